#include "compare/image_file.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "texture/texture_io.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace symphong {

namespace {

/// The header of a PFM file: "PF" or "Pf", width height, scale (negative: little-endian), each token
/// separated by white space, the last followed by exactly one white-space character.
struct PfmHeader {
    int channels = 0, width = 0, height = 0;
    bool littleEndian = true;
};

PfmHeader readPfmHeader(std::istream& in, const std::string& path) {
    std::string magic;
    double scale = 0;
    PfmHeader h;
    in >> magic >> h.width >> h.height >> scale;
    if (!in || (magic != "PF" && magic != "Pf"))
        throw InputError(fmt::format("{}: not a PFM file (expected 'PF' or 'Pf', width, height and scale)", path));
    in.get();  // the single white-space character before the data
    if (h.width <= 0 || h.height <= 0 || h.width > (1 << 24) || h.height > (1 << 24))
        throw InputError(fmt::format("{}: PFM size {} x {} is empty or too large", path, h.width, h.height));
    if (scale == 0 || !std::isfinite(scale)) throw InputError(fmt::format("{}: PFM scale {} must be a non-zero number", path, scale));
    h.channels = magic == "PF" ? 3 : 1;
    h.littleEndian = scale < 0;
    return h;
}

float pfmValue(const unsigned char* p, bool littleEndian) {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= static_cast<std::uint32_t>(p[littleEndian ? i : 3 - i]) << (8 * i);
    return std::bit_cast<float>(bits);
}

void requireFinite(const Image& img, const std::string& path) {
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(img.pixels[i][c]))
                throw InputError(fmt::format("{}: pixel ({}, {}) has a value that is not finite ({})", path, i % img.width, i / img.width,
                                             img.pixels[i][c]));
}

}  // namespace

Image readPfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open", path));
    const PfmHeader h = readPfmHeader(in, path);
    const std::size_t n = static_cast<std::size_t>(h.width) * h.height;
    requireMemory(static_cast<std::uint64_t>(n) * 28, fmt::format("{}: a {} x {} image", path, h.width, h.height));
    std::vector<unsigned char> data(n * h.channels * 4);
    in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size()));
    if (static_cast<std::size_t>(in.gcount()) != data.size())
        throw InputError(fmt::format("{}: PFM data truncated ({} of {} bytes for {} x {} x {})", path, in.gcount(), data.size(), h.width,
                                     h.height, h.channels));
    Image img(h.width, h.height);
    for (int row = 0; row < h.height; ++row)  // stored bottom to top
        for (int x = 0; x < h.width; ++x) {
            const unsigned char* p = data.data() + (static_cast<std::size_t>(row) * h.width + x) * h.channels * 4;
            Color& c = img.at(x, h.height - 1 - row);
            for (int k = 0; k < 3; ++k) c[k] = pfmValue(p + 4 * (h.channels == 3 ? k : 0), h.littleEndian);
        }
    return img;
}

ImageFile readImageFile(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw MissingFileError(fmt::format("{}: no such file", path));
    const std::string ext = lowerExtension(path);
    ImageFile out;
    out.format = ext.empty() ? std::string() : ext.substr(1);
    if (ext == ".exr") {
        out.image = readExr(path);
    } else if (ext == ".pfm") {
        out.image = readPfm(path);
    } else if (ext == ".hdr" || ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga") {
        const Texture t = loadTextureFile(path, TextureEncoding::Srgb);
        out.image = Image(t.width(), t.height());
        for (int y = 0; y < t.height(); ++y)
            for (int x = 0; x < t.width(); ++x) out.image.at(x, y) = t.texelRgb(x, y);
        out.lowDynamicRange = ext != ".hdr";
    } else {
        throw InputError(fmt::format("{}: unknown image format '{}' (expected .exr, .pfm, .hdr, .png, .jpg, .bmp or .tga)", path, ext));
    }
    requireFinite(out.image, path);
    return out;
}

}  // namespace symphong
