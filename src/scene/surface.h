// scene/surface.h — what a surface is at one point of a triangle: its texture coordinates (interpolated
// from the triangle's uvs, or its barycentrics where it has none), the Phong parameters that its
// material's textures give there, its emission, and whether a cut-out (alpha) texture makes a hole
// there. Also the texture table that the loaders fill (one decoded image per file and encoding).
#pragma once

#include "scene/scene.h"

#include <functional>
#include <map>
#include <set>
#include <tuple>
#include <string>
#include <utility>

namespace symphong {

struct TexCoord {
    double u = 0, v = 0;
};

/// Texture coordinates at barycentrics (b1, b2) of vertices 1 and 2 (Embree's u, v).
TexCoord texcoordAt(const Scene& scene, const Triangle& tri, double b1, double b2);

/// The Phong parameters of material m at uv: m itself when its textures leave rho_d, rho_s and n alone,
/// else `scratch` with its rhoD, rhoS, exponent and emission set (its name is not touched) and
/// rho_d + rho_s scaled down per channel to at most 1.
const PhongMaterial& materialAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv, PhongMaterial& scratch);

/// Emitted radiance of material m at uv (Ke, times its emission texture).
Color emissionAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv);

/// Whether material m's cut-out texture makes a hole at uv (coverage below 1/2).
bool cutOutAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv);

/// The loaders' texture table: loads each (file, encoding) once into Scene::textures. A missing file is
/// a warning (the material keeps its constant); an unreadable one is an InputError naming the file.
class TextureTable {
public:
    explicit TextureTable(Scene& scene) : scene_(scene) {}
    /// Index of the texture at `path` (loaded on first use), or -1 with a warning naming `where` (the
    /// material file and its line or element) when the file does not exist.
    std::int32_t file(const std::string& path, TextureEncoding encoding, const std::string& where);
    /// Adds an already decoded texture under a key (embedded images of a glTF binary); the same key
    /// returns the same index.
    std::int32_t add(const std::string& key, TextureEncoding encoding, const std::function<Texture()>& decode);
    /// The texture `index` sampled with these wrap modes: the same index for the first material that uses
    /// it (or any with the same modes), a copy of the decoded image for a material that wraps it otherwise
    /// (one image file, two MTL entries, one with -clamp on). -1 stays -1.
    std::int32_t withWrap(std::int32_t index, WrapMode u, WrapMode v);

private:
    Scene& scene_;
    std::map<std::pair<std::string, int>, std::int32_t> loaded_;
    std::map<std::tuple<std::int32_t, int, int>, std::int32_t> wrapped_;  ///< (image, u, v) -> texture with those modes
    std::set<std::int32_t> wrapSet_;                                      ///< images whose own modes a material has set
};

}  // namespace symphong
