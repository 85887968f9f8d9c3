// Images as NumPy arrays: the conversions, write_image and read_image.
#include "io/input_error.h"
#include "python/common.h"
#include "render/renderer.h"

#include <fmt/format.h>

#include <cmath>

namespace symphong {

/// (H, W, 3) float32 copy of an image: the values the EXR writer stores, bit for bit.
py::array_t<float> toArray(const Image& img) {
    py::array_t<float> a({static_cast<py::ssize_t>(img.height), static_cast<py::ssize_t>(img.width), static_cast<py::ssize_t>(3)});
    float* out = a.mutable_data();
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = static_cast<float>(img.pixels[i][c]);
    return a;
}

Image fromArray(const py::array& input) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(input);
    if (!a) throw InputError("image: expected a numeric array of shape (H, W, 3) or (H, W)");
    const bool grey = a.ndim() == 2;
    if (!(grey || (a.ndim() == 3 && a.shape(2) == 3)))
        throw InputError(fmt::format("image: shape must be (H, W, 3) or (H, W), got {}", py::str(input.attr("shape")).cast<std::string>()));
    const long h = static_cast<long>(a.shape(0)), w = static_cast<long>(a.shape(1));
    if (w < 1 || h < 1) throw InputError(fmt::format("image: {}x{} has no pixels", w, h));
    if (w * h > kMaxImagePixels) throw InputError(fmt::format("image: {}x{} is too large (at most {} pixels)", w, h, kMaxImagePixels));
    Image img(static_cast<int>(w), static_cast<int>(h));
    const double* in = a.data();
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double v = in[grey ? i : 3 * i + c];
            if (!std::isfinite(v))
                throw InputError(fmt::format("image: pixel (x {}, y {}) has the non-finite value {}", i % img.width, i / img.width, v));
            img.pixels[i][c] = v;
        }
    return img;
}

void registerArrays(py::module_& m) {
    m.def(
        "write_image",
        [](const std::string& path, const py::array& image, double exposure, bool exrHalf) {
            if (!(exposure > 0) || !std::isfinite(exposure))
                throw InputError(fmt::format("exposure = {} must be a positive number", exposure));
            imageFormatFor(path);  // the extension first: no work for a name that cannot be written
            const Image img = fromArray(image);
            py::gil_scoped_release release;
            checkWritable(path);
            writeImage(img, path, exposure, exrHalf);
        },
        R"(write_image(path, image, exposure=1.0, exr_half=False)

Writes a linear RGB array of shape (H, W, 3) (or (H, W), grey) as .png (8-bit sRGB after multiplying by
exposure and clamping to [0, 1]) or .exr (32-bit float; 16-bit half with exr_half=True), atomically: the
file is either the complete image or untouched. Non-finite values raise ValueError.)",
        py::arg("path"), py::arg("image"), py::kw_only(), py::arg("exposure") = 1.0, py::arg("exr_half") = false);

    m.def(
        "read_image",
        [](const std::string& path) {
            Image img;
            {
                py::gil_scoped_release release;
                img = readExr(path);
            }
            return toArray(img);
        },
        R"(read_image(path) -> float32 array (H, W, 3)

Reads a linear RGB OpenEXR file (half or float), e.g. a reference image written by `symphong render -o x.exr`.)",
        py::arg("path"));
}

}  // namespace symphong
