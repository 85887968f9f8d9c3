#include "texture/texture_io.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"

#include <ImfIO.h>
#include <ImfRgbaFile.h>
#include <fmt/format.h>
#include <stb/stb_image.h>

#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <memory>

namespace symphong {

namespace {

/// An OpenEXR input stream over bytes in memory (OpenEXR reads files through IStream).
class MemoryStream : public Imf::IStream {
public:
    MemoryStream(const std::string& name, const unsigned char* data, std::size_t size)
        : Imf::IStream(name.c_str()), data_(data), size_(size) {}
    bool read(char c[], int n) override {
        if (n < 0 || pos_ > size_ || static_cast<std::size_t>(n) > size_ - pos_) throw std::runtime_error("the file ends early");
        std::memcpy(c, data_ + pos_, static_cast<std::size_t>(n));
        pos_ += static_cast<std::size_t>(n);
        return pos_ < size_;
    }
    std::uint64_t tellg() override { return pos_; }
    void seekg(std::uint64_t pos) override { pos_ = static_cast<std::size_t>(std::min<std::uint64_t>(pos, size_ + 1)); }

private:
    const unsigned char* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
};

void checkTexels(const std::string& name, const std::vector<float>& texels, int width, int channels) {
    for (std::size_t i = 0; i < texels.size(); ++i)
        if (!(texels[i] >= 0) || !std::isfinite(texels[i])) {
            const std::size_t pixel = i / static_cast<std::size_t>(channels);
            throw InputError(fmt::format("{}: texel ({}, {}) channel {} is {} (texels must be finite and >= 0)", name,
                                         pixel % static_cast<std::size_t>(width), pixel / static_cast<std::size_t>(width),
                                         i % static_cast<std::size_t>(channels), texels[i]));
        }
}

void requireTexelMemory(const std::string& name, std::uint64_t width, std::uint64_t height, std::uint64_t channels,
                        std::uint64_t decodeBytesPerTexel) {
    // The float texels we keep plus the decoder's own buffer.
    const std::uint64_t texels = saturatingMultiply(saturatingMultiply(width, height), channels);
    requireMemory(saturatingMultiply(texels, sizeof(float) + decodeBytesPerTexel),
                  fmt::format("{}: a {} x {} texture", name, width, height));
}

/// stb_image decodes a truncated file as if its missing bytes were zeros, so a 31-byte header can claim
/// gigabytes. No real image holds more than about 8,256 texels a byte (a one-colour 1-bit PNG:
/// deflate's 1032:1 times 8 pixels a byte): a header (`what`) claiming more than 16,384 texels per byte
/// of the file is truncated (found by fuzzing, docs/reliability.md).
void checkClaimedTexels(const std::string& name, std::uint64_t width, std::uint64_t height, std::size_t size, const char* what) {
    if (saturatingMultiply(width, height) > saturatingMultiply(size, 16384) + (std::uint64_t{1} << 16))
        throw InputError(fmt::format("{}: truncated image: its {} claims {} x {} texels, more than its {} bytes can hold", name, what,
                                     width, height, size));
}

Texture decodeExr(const std::string& name, const unsigned char* data, std::size_t size) {
    try {
        MemoryStream stream(name, data, size);
        Imf::RgbaInputFile file(stream);
        const Imath::Box2i dw = file.dataWindow();
        const std::int64_t w64 = static_cast<std::int64_t>(dw.max.x) - dw.min.x + 1,
                           h64 = static_cast<std::int64_t>(dw.max.y) - dw.min.y + 1;
        if (w64 <= 0 || h64 <= 0 || w64 > INT_MAX / 4 || h64 > INT_MAX / 4)
            throw InputError(fmt::format("{}: OpenEXR data window {} x {} is empty or too large", name, w64, h64));
        const int channels = (file.channels() & Imf::WRITE_A) ? 4 : 3;
        checkClaimedTexels(name, static_cast<std::uint64_t>(w64), static_cast<std::uint64_t>(h64), size, "data window");
        requireTexelMemory(name, static_cast<std::uint64_t>(w64), static_cast<std::uint64_t>(h64), 4, sizeof(Imf::Rgba) / 4);
        const int w = static_cast<int>(w64), h = static_cast<int>(h64);
        std::vector<Imf::Rgba> pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
        // The frame buffer is addressed by absolute pixel coordinates: shift by the data window's corner.
        const std::ptrdiff_t shift = -static_cast<std::ptrdiff_t>(dw.min.x) - static_cast<std::ptrdiff_t>(dw.min.y) * w;
        file.setFrameBuffer(reinterpret_cast<Imf::Rgba*>(reinterpret_cast<std::uintptr_t>(pixels.data()) +
                                                         shift * static_cast<std::ptrdiff_t>(sizeof(Imf::Rgba))),
                            1, static_cast<std::size_t>(w));
        file.readPixels(dw.min.y, dw.max.y);
        std::vector<float> texels(pixels.size() * static_cast<std::size_t>(channels));
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            float* t = &texels[i * static_cast<std::size_t>(channels)];
            t[0] = pixels[i].r, t[1] = pixels[i].g, t[2] = pixels[i].b;
            if (channels == 4) t[3] = pixels[i].a;
        }
        checkTexels(name, texels, w, channels);
        return Texture(name, w, h, channels, std::move(texels));
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(fmt::format("{}: cannot read it as OpenEXR: {}", name, e.what()));
    }
}

/// The image formats Debian's stb_image decodes that symphong does not document (PNM, GIF, PSD, PIC),
/// by their signatures: refused before stb_image sees them (its PNM header parser overflows a signed
/// integer on a long width; found by fuzzing, docs/reliability.md). No TGA can begin with these bytes
/// (its second byte, the colour-map type, is 0 or 1).
const char* undocumentedFormat(const unsigned char* data, std::size_t size) {
    if (size >= 2 && data[0] == 'P' && data[1] >= '1' && data[1] <= '7') return "PNM (portable anymap)";
    if (size >= 4 && std::memcmp(data, "GIF8", 4) == 0) return "GIF";
    if (size >= 4 && std::memcmp(data, "8BPS", 4) == 0) return "Photoshop (PSD)";
    if (size >= 4 && std::memcmp(data, "\x53\x80\xF6\x34", 4) == 0) return "Softimage PIC";
    return nullptr;
}

/// Walks a JPEG's markers as stb_image 2.27 reads them (segments by their length, entropy-coded data
/// after a scan up to the next marker, bytes past the end reading as 0) and refuses a Huffman table
/// (DHT) whose 16 code counts add up to more than 256: stb_image 2.27 does not check it and writes past
/// its tables (stb_image 2.28 does; found by fuzzing, docs/reliability.md).
void checkJpegHuffmanTables(const std::string& name, const unsigned char* data, std::size_t size) {
    if (size < 2 || data[0] != 0xFF || data[1] != 0xD8) return;
    const auto byte = [&](std::size_t i) -> unsigned { return i < size ? data[i] : 0u; };
    std::size_t pos = 2;
    while (pos + 1 < size) {
        if (byte(pos) != 0xFF) {
            ++pos;  // not at a marker (entropy-coded data): look further
            continue;
        }
        const unsigned marker = byte(pos + 1);
        if (marker == 0xFF || marker == 0x00 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01 || marker == 0xD8) {
            pos += marker == 0xFF ? 1 : 2;  // fill byte, stuffed zero, or a marker without a segment
            continue;
        }
        if (marker == 0xD9) return;  // end of image
        const std::size_t length = (byte(pos + 2) << 8) | byte(pos + 3);
        if (length < 2) return;  // stb_image rejects it
        if (marker == 0xC4) {
            std::size_t at = pos + 4, left = length - 2;
            while (left >= 17) {
                std::size_t codes = 0;
                for (std::size_t k = 0; k < 16; ++k) codes += byte(at + 1 + k);
                if (codes > 256)
                    throw InputError(fmt::format("{}: corrupt JPEG: a Huffman table declares {} codes (at most 256)", name, codes));
                if (17 + codes > left) break;
                at += 17 + codes;
                left -= 17 + codes;
            }
        }
        pos += 2 + length;
    }
}

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

Texture decodeTexture(const std::string& name, const unsigned char* data, std::size_t size, TextureEncoding encoding) {
    static constexpr unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (size >= 4 && std::memcmp(data, kExrMagic, 4) == 0) return decodeExr(name, data, size);
    if (size > static_cast<std::size_t>(INT_MAX)) throw InputError(fmt::format("{}: the file is over 2 GiB", name));
    const int len = static_cast<int>(size);
    if (const char* format = undocumentedFormat(data, size))
        throw InputError(fmt::format("{}: a {} image; symphong reads PNG, JPEG, BMP, TGA, HDR and EXR textures", name, format));
    checkJpegHuffmanTables(name, data, size);
    int w = 0, h = 0, comp = 0;
    static constexpr unsigned char kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (size >= 24 && std::memcmp(data, kPngMagic, 8) == 0 && std::memcmp(data + 12, "IHDR", 4) == 0) {
        // stb_image refuses images over 2^30 bytes as "unknown": read the PNG's size to say why.
        const auto be32 = [&](std::size_t at) {
            return (std::uint64_t{data[at]} << 24) | (std::uint64_t{data[at + 1]} << 16) | (std::uint64_t{data[at + 2]} << 8) |
                   data[at + 3];
        };
        const std::uint64_t pw = be32(16), ph = be32(20);
        requireTexelMemory(name, pw, ph, 4, 1);
        if (saturatingMultiply(saturatingMultiply(pw, ph), 4) > (std::uint64_t{1} << 30))
            throw InputError(fmt::format("{}: a {} x {} PNG is larger than stb_image decodes (2^30 bytes)", name, pw, ph));
    }
    if (!stbi_info_from_memory(data, len, &w, &h, &comp) || w <= 0 || h <= 0 || comp < 1 || comp > 4) {
        const char* why = stbi_failure_reason();
        throw InputError(
            fmt::format("{}: not an image symphong reads (PNG, JPEG, BMP, TGA, HDR or EXR){}{}", name, why ? ": " : "", why ? why : ""));
    }
    checkClaimedTexels(name, static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), size, "header");
    const bool hdr = stbi_is_hdr_from_memory(data, len) != 0;
    const bool sixteen = !hdr && stbi_is_16_bit_from_memory(data, len) != 0;
    requireTexelMemory(name, static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), static_cast<std::uint64_t>(comp),
                       hdr ? 4 : (sixteen ? 2 : 1));

    int dw = 0, dh = 0, dc = 0;
    std::unique_ptr<void, StbFree> decoded;
    if (hdr)
        decoded.reset(stbi_loadf_from_memory(data, len, &dw, &dh, &dc, 0));
    else if (sixteen)
        decoded.reset(stbi_load_16_from_memory(data, len, &dw, &dh, &dc, 0));
    else
        decoded.reset(stbi_load_from_memory(data, len, &dw, &dh, &dc, 0));
    if (!decoded || dw != w || dh != h || dc != comp) {
        const char* why = stbi_failure_reason();
        throw InputError(fmt::format("{}: corrupt or truncated image{}{}", name, why ? ": " : "", why ? why : ""));
    }
    if (!hdr && !sixteen) return textureFrom8Bit(name, w, h, comp, static_cast<const unsigned char*>(decoded.get()), encoding);
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(comp);
    std::vector<float> texels(n);
    if (hdr) {
        const float* f = static_cast<const float*>(decoded.get());
        std::copy(f, f + n, texels.begin());
        checkTexels(name, texels, w, comp);
    } else {
        // 16-bit: colour channels (all but the alpha of a grey+alpha or RGBA image) through the sRGB curve.
        const int colourChannels = comp == 2 || comp == 4 ? comp - 1 : comp;
        const bool srgb = encoding == TextureEncoding::Srgb;
        const auto* s = static_cast<const std::uint16_t*>(decoded.get());
        for (std::size_t i = 0; i < n; ++i) {
            const double v = s[i] / 65535.0;
            texels[i] =
                static_cast<float>(srgb && static_cast<int>(i % static_cast<std::size_t>(comp)) < colourChannels ? srgbToLinear(v) : v);
        }
    }
    return Texture(name, w, h, comp, std::move(texels));
}

Texture textureFrom8Bit(const std::string& name, int width, int height, int channels, const unsigned char* bytes,
                        TextureEncoding encoding) {
    std::array<float, 256> linear{}, srgbTable{};
    for (int i = 0; i < 256; ++i) {
        linear[static_cast<std::size_t>(i)] = static_cast<float>(i / 255.0);
        srgbTable[static_cast<std::size_t>(i)] = static_cast<float>(srgbToLinear(i / 255.0));
    }
    // Colour channels: all but the alpha of a grey+alpha or RGBA image.
    const int colourChannels = channels == 2 || channels == 4 ? channels - 1 : channels;
    const bool srgb = encoding == TextureEncoding::Srgb;
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels);
    std::vector<float> texels(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool colour = srgb && static_cast<int>(i % static_cast<std::size_t>(channels)) < colourChannels;
        texels[i] = (colour ? srgbTable : linear)[bytes[i]];
    }
    return Texture(name, width, height, channels, std::move(texels));
}

Texture loadTextureFile(const std::string& path, TextureEncoding encoding) {
    const std::string bytes = readTextFile(path);
    return decodeTexture(path, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), encoding);
}

}  // namespace symphong
