#include "io/image.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"

#include <ImfArray.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <OpenEXRConfig.h>
#include <fmt/format.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

namespace fs = std::filesystem;

namespace symphong {

ImageFormat imageFormatFor(const std::string& path) {
    const std::string ext = lowerExtension(path);
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".exr") return ImageFormat::Exr;
    throw InputError(fmt::format("{}: output must end in .png or .exr", path));
}

void checkWritable(const std::string& path) {
    imageFormatFor(path);
    checkCanCreate(path);
}

unsigned char toSrgb8(double linear, double exposure) {
    double v = linear * exposure;
    if (!(v > 0)) v = 0;  // also maps NaN to 0
    v = std::min(v, 1.0);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<unsigned char>(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
}

void writePng(const Image& img, const std::string& path, double exposure) {
    std::vector<unsigned char> bytes(static_cast<std::size_t>(img.width) * img.height * 3);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) bytes[3 * i + c] = toSrgb8(img.pixels[i][c], exposure);
    writeAtomically(path, [&](const std::string& tmp) {
        png_image pi{};
        pi.version = PNG_IMAGE_VERSION;
        pi.width = static_cast<png_uint_32>(img.width);
        pi.height = static_cast<png_uint_32>(img.height);
        pi.format = PNG_FORMAT_RGB;
        if (!png_image_write_to_file(&pi, tmp.c_str(), 0, bytes.data(), 0, nullptr)) throw std::runtime_error(pi.message);
    });
}

void writeExr(const Image& img, const std::string& path, bool half) {
    writeAtomically(path, [&](const std::string& tmp) {
        const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
        Imf::Header header(img.width, img.height);
        for (const char* ch : {"R", "G", "B"}) header.channels().insert(ch, Imf::Channel(type));
        Imf::OutputFile file(tmp.c_str(), header);
        Imf::FrameBuffer fb;
        const std::size_t n = img.pixels.size();
        std::vector<float> planes(3 * n);
        std::vector<Imath::half> halves(half ? 3 * n : 0);
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                planes[c * n + i] = static_cast<float>(img.pixels[i][c]);
                if (half) halves[c * n + i] = Imath::half(planes[c * n + i]);
            }
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            char* base = half ? reinterpret_cast<char*>(halves.data() + c * n) : reinterpret_cast<char*>(planes.data() + c * n);
            const std::size_t elem = half ? sizeof(Imath::half) : sizeof(float);
            fb.insert(names[c], Imf::Slice(type, base, elem, elem * img.width));
        }
        file.setFrameBuffer(fb);
        file.writePixels(img.height);
    });
}

void writeImage(const Image& img, const std::string& path, double exposure, bool exrHalf) {
    if (imageFormatFor(path) == ImageFormat::Png)
        writePng(img, path, exposure);
    else
        writeExr(img, path, exrHalf);
}

Image readExr(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw MissingFileError(fmt::format("{}: no such file", path));
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        const std::int64_t w64 = static_cast<std::int64_t>(dw.max.x) - dw.min.x + 1,
                           h64 = static_cast<std::int64_t>(dw.max.y) - dw.min.y + 1;
        if (w64 <= 0 || h64 <= 0 || w64 > (1 << 24) || h64 > (1 << 24))
            throw InputError(fmt::format("{}: EXR data window {} x {} is empty or too large", path, w64, h64));
        requireMemory(static_cast<std::uint64_t>(w64) * static_cast<std::uint64_t>(h64) * 36,
                      fmt::format("{}: a {} x {} image", path, w64, h64));
        const int w = static_cast<int>(w64), h = static_cast<int>(h64);
        const std::size_t n = static_cast<std::size_t>(w) * h;
        std::vector<float> planes(3 * n, 0.0f);
        Imf::FrameBuffer fb;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            if (!file.header().channels().findChannel(names[c])) throw InputError(fmt::format("{}: EXR has no {} channel", path, names[c]));
            char* base = reinterpret_cast<char*>(planes.data() + c * n) -
                         (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * w) *
                             static_cast<std::ptrdiff_t>(sizeof(float));
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * w));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        Image img(w, h);
        for (std::size_t i = 0; i < n; ++i) img.pixels[i] = {planes[i], planes[n + i], planes[2 * n + i]};
        return img;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(fmt::format("{}: cannot read EXR: {}", path, e.what()));
    }
}

std::string openexrVersion() { return OPENEXR_VERSION_STRING; }
std::string libpngVersion() { return PNG_LIBPNG_VER_STRING; }

}  // namespace symphong
