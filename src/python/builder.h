// python/builder.h — what python/builder.cpp (Scene.from_arrays) and python/builder_materials.cpp (its
// materials and texture maps) share: arrays and numbers checked as the loaders check files, each problem a
// ValueError (InputError) naming the array and element, or the dict key ("materials[2].rho_d[1] = -0.5 is
// negative").
#pragma once

#include "python/common.h"
#include "scene/surface.h"

#include <cstdint>
#include <string>

namespace symphong::pybuild {

/// "(4, 2)": an array's shape as Python prints it.
std::string shapeText(const py::array& a);
/// A C-ordered float64 array of shape (N, cols), (N,) when cols == 0; ValueError naming it for another shape
/// or a value that is not finite, TypeError for a non-numeric one.
py::array_t<double, py::array::c_style> floatRows(const py::handle& obj, const std::string& name, py::ssize_t cols);
/// An integer array of shape (N, cols), (N,) when cols == 0, each value in [0, limit); ValueError naming
/// the element and `limitName` for one out of range.
py::array_t<std::int64_t, py::array::c_style> indexRows(const py::handle& obj, const std::string& name, py::ssize_t cols,
                                                        std::int64_t limit, const std::string& limitName);
double finiteNumber(const py::handle& v, const std::string& where);
double nonNegative(const py::handle& v, const std::string& where);
/// A colour: one number (grey) or 3 (a 4th, alpha, as Blender's RGBA sockets give it, is not read), each finite, >= 0.
Color colour(const py::handle& v, const std::string& where);
Vec3 vector3(const py::handle& v, const std::string& where);
/// A texture from an image array: (H, W) or (H, W, C), C in 1..4, row 0 at the top. uint8 texels scaled to
/// [0,1] (colour channels through the sRGB curve under TextureEncoding::Srgb, as an 8-bit PNG's); float texels
/// are linear values, each finite and >= 0.
Texture textureFromArray(const py::array& raw, TextureEncoding encoding, const std::string& where);
/// Material `index` of from_arrays' `materials` list, its textures loaded into `table`.
PhongMaterial material(const py::handle& spec, std::size_t index, TextureTable& table);

}  // namespace symphong::pybuild
