// Textures (texture/, scene/surface.h): wrap modes and bilinear lookup; decoding PNG (8 and 16 bit,
// sRGB to linear), HDR and EXR; corrupt, truncated and too-large images as bad input naming the file;
// MTL maps (map_Kd with and without Kd, map_d cut-outs, -clamp, a missing file as a warning) and glTF
// base-colour textures (from a file and embedded as a data URI) rendered against the mean their
// texels give, within the render's own standard error.
#include "test_util.h"

#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "scene/surface.h"
#include "texture/texture_io.h"

#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include <cmath>
#include <cstring>
#include <fstream>

using namespace symphong;

namespace {

/// A checkerboard of `cells` x `cells` squares, `size` pixels a side, grey levels a (top-left) and b,
/// written as an 8-bit PNG with `channels` channels (the alpha channel, when there is one, is 255 on
/// a-squares and 0 on b-squares).
std::string writeChecker(const std::string& path, int size, int cells, unsigned char a, unsigned char b, int channels = 3) {
    std::vector<unsigned char> px(static_cast<std::size_t>(size * size * channels));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const bool first = ((x * cells / size) + (y * cells / size)) % 2 == 0;
            for (int c = 0; c < channels; ++c) {
                const bool alpha = (channels == 2 || channels == 4) && c == channels - 1;
                px[static_cast<std::size_t>((y * size + x) * channels + c)] = alpha ? (first ? 255 : 0) : (first ? a : b);
            }
        }
    EXPECT_NE(stbi_write_png(path.c_str(), size, size, channels, px.data(), size * channels), 0);
    return path;
}

double linear8(unsigned char v) { return srgbToLinear(v / 255.0); }

/// A unit square in the z = 0 plane facing +z with uvs 0..1, filling exactly the view of a camera at
/// z = d with a 40 degree field of view (so each pixel sees an equal share of the texture).
std::string squareObj(const test::TempDir& dir, const std::string& mtl, const std::string& material) {
    return dir.write("square.obj", "mtllib " + mtl + "\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl " +
                                       material + "\nf 1/1 2/2 3/3 4/4\n");
}

std::string squareJson(const test::TempDir& dir, const std::string& mesh, const std::string& environment) {
    const double d = 1.0 / std::tan(20.0 * kPi / 180.0);
    return dir.write("square.json", "{\"mesh\": \"" + mesh + "\", \"camera\": {\"position\": [0, 0, " + std::to_string(d) +
                                        "], \"target\": [0, 0, 0], \"fov\": 40}, \"environment\": " + environment + "}");
}

}  // namespace

TEST(Texture, WrapModes) {
    EXPECT_EQ(wrapIndex(-1, 4, WrapMode::Repeat), 3);
    EXPECT_EQ(wrapIndex(9, 4, WrapMode::Repeat), 1);
    EXPECT_EQ(wrapIndex(-3, 4, WrapMode::Clamp), 0);
    EXPECT_EQ(wrapIndex(7, 4, WrapMode::Clamp), 3);
    // Mirror: 0 1 2 3 | 3 2 1 0 | 0 1 ...
    EXPECT_EQ(wrapIndex(4, 4, WrapMode::Mirror), 3);
    EXPECT_EQ(wrapIndex(7, 4, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapIndex(8, 4, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapIndex(-1, 4, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapIndex(-2, 4, WrapMode::Mirror), 1);
}

// One image, two MTL entries: one clamps it (-clamp on), the other repeats it. Each material keeps its
// own wrap mode (the image is decoded once; the second mode gets a copy), and a lookup outside [0,1)
// reads the edge for the first and the wrapped texel for the second; two entries with the same mode
// share one texture.
TEST(Texture, OneImageUnderTwoWrapModesKeepsEach) {
    test::TempDir dir;
    writeChecker(dir.file("checker.png"), 4, 4, 255, 0);  // 4 x 4 pixels, each its own cell
    dir.write("m.mtl", "newmtl clamped\nmap_Kd -clamp on checker.png\nnewmtl repeated\nmap_Kd checker.png\n"
                       "newmtl repeated2\nmap_Kd checker.png\n");
    dir.write("s.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl clamped\nf 1/1 2/2 3/3\n"
                       "usemtl repeated\nf 1/1 2/2 3/3\nusemtl repeated2\nf 1/1 2/2 3/3\n");
    const Scene s = loadObj(dir.file("s.obj"));
    ASSERT_EQ(s.textures.size(), 2u);
    const auto& clamped = s.materials[static_cast<std::size_t>(s.findMaterial("clamped"))].textures.diffuse;
    const auto& repeated = s.materials[static_cast<std::size_t>(s.findMaterial("repeated"))].textures.diffuse;
    const auto& repeated2 = s.materials[static_cast<std::size_t>(s.findMaterial("repeated2"))].textures.diffuse;
    ASSERT_NE(clamped.index, repeated.index);
    EXPECT_EQ(repeated.index, repeated2.index);
    const Texture& c = s.textures[static_cast<std::size_t>(clamped.index)];
    const Texture& r = s.textures[static_cast<std::size_t>(repeated.index)];
    EXPECT_EQ(c.wrapU, WrapMode::Clamp);
    EXPECT_EQ(r.wrapU, WrapMode::Repeat);
    // At u = 1.125, v = 0.125 (the bottom row's texel centres, row 3): clamped reads the last column
    // (x = 3, x + y even: white), repeated the first (x = 0, odd: black).
    const double clampedValue = c.rgb(1.125, 0.125).x, repeatedValue = r.rgb(1.125, 0.125).x;
    EXPECT_DOUBLE_EQ(clampedValue, c.rgb(0.875, 0.125).x);   // the edge texel
    EXPECT_DOUBLE_EQ(repeatedValue, r.rgb(0.125, 0.125).x);  // the first column again
    EXPECT_NE(clampedValue, repeatedValue);
}

TEST(Texture, BilinearLookupBetweenTexelCentres) {
    // 2 x 2 grey: top row 0, 1; bottom row 2, 3. Texel centres at u = 1/4, 3/4 and v = 3/4 (top), 1/4.
    Texture t("t", 2, 2, 1, {0, 1, 2, 3});
    t.wrapU = t.wrapV = WrapMode::Clamp;
    EXPECT_DOUBLE_EQ(t.channel(0.25, 0.75, 0), 0.0);
    EXPECT_DOUBLE_EQ(t.channel(0.75, 0.25, 0), 3.0);
    EXPECT_DOUBLE_EQ(t.channel(0.5, 0.5, 0), 1.5);
    EXPECT_DOUBLE_EQ(t.channel(0.5, 0.75, 0), 0.5);
    EXPECT_DOUBLE_EQ(t.channel(0.0, 0.75, 0), 0.0);  // clamped at the edge
    t.wrapU = WrapMode::Repeat;
    EXPECT_DOUBLE_EQ(t.channel(0.0, 0.75, 0), 0.5);  // halfway between the last and the first column
    EXPECT_DOUBLE_EQ(t.rgb(0.75, 0.25).y, 3.0);      // grey reads as (g, g, g)
    EXPECT_DOUBLE_EQ(t.channel(0.5, 0.5, 3), 1.0);   // no alpha: opaque
    int x, y;
    t.nearestTexel(0.9, 0.1, x, y);
    EXPECT_EQ(x, 1);
    EXPECT_EQ(y, 1);
}

TEST(TextureIo, PngIsDecodedFromSrgbToLinearAndAlphaStaysLinear) {
    test::TempDir dir;
    const std::string png = writeChecker(dir.file("c.png"), 8, 2, 200, 50, 4);
    const Texture srgb = loadTextureFile(png, TextureEncoding::Srgb);
    ASSERT_EQ(srgb.width(), 8);
    ASSERT_EQ(srgb.channels(), 4);
    EXPECT_NEAR(srgb.texel(0, 0, 0), linear8(200), 1e-6);
    EXPECT_NEAR(srgb.texel(7, 0, 1), linear8(50), 1e-6);
    EXPECT_FLOAT_EQ(srgb.texel(0, 0, 3), 1.0f);
    EXPECT_FLOAT_EQ(srgb.texel(7, 0, 3), 0.0f);
    const Texture lin = loadTextureFile(png, TextureEncoding::Linear);
    EXPECT_NEAR(lin.texel(0, 0, 0), 200 / 255.0, 1e-6);
}

TEST(TextureIo, SixteenBitHdrAndExr) {
    test::TempDir dir;
    // 16-bit grey PNG: stb writes only 8-bit, so a hand-made one: 1 x 1, value 0x8000 (0.50001 linear).
    const Image img = [] {
        Image i(3, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) i.at(x, y) = Color(0.5 * x, 2.0 * y, 10.0);
        return i;
    }();
    writeExr(img, dir.file("e.exr"));
    const Texture exr = loadTextureFile(dir.file("e.exr"), TextureEncoding::Srgb);  // EXR is linear whatever is asked
    ASSERT_EQ(exr.width(), 3);
    ASSERT_EQ(exr.height(), 2);
    EXPECT_FLOAT_EQ(exr.texel(2, 1, 0), 1.0f);
    EXPECT_FLOAT_EQ(exr.texel(2, 1, 1), 2.0f);
    EXPECT_FLOAT_EQ(exr.texel(0, 0, 2), 10.0f);
    std::vector<float> hdr = {4.0f, 0.25f, 1.0f, 0.5f, 8.0f, 2.0f};
    ASSERT_NE(stbi_write_hdr(dir.file("h.hdr").c_str(), 2, 1, 3, hdr.data()), 0);
    const Texture h = loadTextureFile(dir.file("h.hdr"), TextureEncoding::Srgb);
    EXPECT_NEAR(h.texel(0, 0, 0), 4.0f, 4.0 * 0.01);  // RGBE keeps about 1% precision
    EXPECT_NEAR(h.texel(1, 0, 1), 8.0f, 8.0 * 0.01);
}

TEST(TextureIo, CorruptTruncatedAndHugeImagesAreBadInputNamingTheFile) {
    test::TempDir dir;
    const std::string png = writeChecker(dir.file("c.png"), 32, 4, 200, 50);
    std::string bytes = readTextFile(png);
    const auto expectError = [&](const std::string& name, const std::string& data, const std::string& needle) {
        const std::string path = dir.write(name, data);
        try {
            loadTextureFile(path, TextureEncoding::Srgb);
            ADD_FAILURE() << name << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError("text.png", "this is not an image", "not an image");
    expectError("cut.png", bytes.substr(0, bytes.size() / 2), "corrupt or truncated");
    // A valid PNG header that claims 100000 x 100000 pixels: refused before decoding.
    std::string huge = bytes;
    const unsigned char dims[8] = {0, 1, 0x86, 0xA0, 0, 1, 0x86, 0xA0};
    huge.replace(16, 8, reinterpret_cast<const char*>(dims), 8);
    expectError("huge.png", huge, "GiB of memory");
    expectError("bad.exr", std::string("\x76\x2f\x31\x01", 4) + "garbage", "OpenEXR");
    // Formats stb_image decodes but symphong does not document are refused by name.
    expectError("grey.pgm", "P5\n2 2\n255\n" + std::string(4, '\x80'), "a PNM (portable anymap) image");
    expectError("anim.gif", "GIF89a" + std::string(20, '\0'), "a GIF image");
    // A JPEG Huffman table declaring 510 codes (stb_image 2.27 would write past its tables).
    std::string jpeg("\xFF\xD8\xFF\xC4\x00\x13\x00", 7);
    jpeg += std::string("\xFF\xFF", 2) + std::string(14, '\0');
    expectError("dht.jpg", jpeg, "a Huffman table declares 510 codes");
    // A BMP header that claims 4000 x 4000 pixels in 70 bytes: truncated, not decoded into zeros.
    std::string bmp = "BM" + std::string(52, '\0');
    const auto put32 = [&](std::size_t at, std::uint32_t v) { std::memcpy(&bmp[at], &v, 4); };
    const auto put16 = [&](std::size_t at, std::uint16_t v) { std::memcpy(&bmp[at], &v, 2); };
    put32(2, 70), put32(10, 54), put32(14, 40), put32(18, 4000), put32(22, 4000), put16(26, 1), put16(28, 24);
    bmp += std::string(16, '\x7f');
    expectError("short.bmp", bmp, "truncated image");
    EXPECT_THROW(loadTextureFile(dir.file("absent.png"), TextureEncoding::Srgb), MissingFileError);
}

TEST(Memory, RefusesWhatExceedsTheBudget) {
    EXPECT_NO_THROW(requireMemory(1 << 20, "small"));
    try {
        requireMemory(saturatingMultiply(1ull << 40, 1ull << 40), "x.obj: a mesh");
        ADD_FAILURE() << "an impossible size was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("x.obj: a mesh: needs"), std::string::npos) << e.what();
    }
}

// A diffuse square under a constant environment L: each point sends back rho_d(uv) L exactly, so the
// image's mean is L times the mean of the texture's linear values over the square.
TEST(TexturedRender, MapKdCheckerboardRendersItsLinearMean) {
    test::TempDir dir;
    writeChecker(dir.file("checker.png"), 64, 8, 200, 50);
    dir.write("m.mtl", "newmtl checker\nKd 0.8 0.8 0.8\nKs 0 0 0\nmap_Kd checker.png\nnewmtl bare\nmap_Kd checker.png\n");
    for (const std::string material : {"checker", "bare"}) {
        squareObj(dir, "m.mtl", material);
        const Scene s = loadScene(squareJson(dir, "square.obj", "1.5"));
        ASSERT_EQ(s.textures.size(), 1u);
        const double kd = material == "checker" ? 0.8 : 1.0;  // no Kd: the map alone
        const double expected = 1.5 * kd * 0.5 * (linear8(200) + linear8(50));
        const RenderResult r = test::renderIndependent(s, "cosine", 32, 16, 7);
        const auto [mean, se] = test::imageMeanAndError(r);
        // Each 4 x 4 block of pixels sees one checker square exactly; the noise is the pixel jitter
        // across the squares' edges, and a little from round-off.
        EXPECT_NEAR(mean, expected, 4 * se + 1e-3 * expected) << material << ": se " << se;
        // Decoded as linear values instead, the mean would be 0.49 kd L: far off.
        EXPECT_GT(std::abs(1.5 * kd * (200 + 50) / 510.0 - expected), 0.2);
    }
}

TEST(TexturedRender, MapDCutOutShowsTheEnvironmentThroughItsHoles) {
    test::TempDir dir;
    // Black square (Kd 0) with a cut-out checker: alpha 1 on half the squares. Behind it, only the
    // environment L = 2: the image mean is L times the share of holes, 1/2.
    writeChecker(dir.file("mask.png"), 64, 8, 255, 0, 2);
    dir.write("m.mtl", "newmtl cut\nKd 0 0 0\nmap_d -clamp on mask.png\n");
    squareObj(dir, "m.mtl", "cut");
    const Scene s = loadScene(squareJson(dir, "square.obj", "2"));
    ASSERT_TRUE(s.hasCutOuts());
    EXPECT_EQ(s.textures[0].wrapU, WrapMode::Clamp);
    const RenderResult r = test::renderIndependent(s, "cosine", 32, 16, 3);
    const auto [mean, se] = test::imageMeanAndError(r);
    // (The pixel grid lines up with the checker's squares, so the estimate is exact here: se = 0.)
    EXPECT_NEAR(mean, 1.0, 4 * se + 1e-3) << "se " << se;
    // Every pixel is wholly a hole (2) or wholly the square (0), but for those on an edge.
    int holes = 0;
    for (const Color& c : r.image.pixels) holes += luminance(c) > 1.9;
    EXPECT_GT(holes, 32 * 32 / 4);
}

TEST(TexturedRender, MissingTextureIsAWarningAndTheConstantIsUsed) {
    test::TempDir dir;
    dir.write("m.mtl", "newmtl m\nKd 0.25 0.25 0.25\nmap_Kd nowhere.png\n");
    squareObj(dir, "m.mtl", "m");
    const Scene s = loadScene(squareJson(dir, "square.obj", "1"));
    EXPECT_TRUE(s.textures.empty());
    bool warned = false;
    for (const auto& w : s.warnings)
        warned = warned || (w.find("nowhere.png") != std::string::npos && w.find("m.mtl:3") != std::string::npos);
    EXPECT_TRUE(warned) << "no warning naming the texture and its MTL line";
    // Maps symphong does not have (displacement, reflection) are ignored with a warning, not silently.
    dir.write("b.mtl", "newmtl m\nKd 0.25 0.25 0.25\ndisp height.png\n");
    squareObj(dir, "b.mtl", "m");
    const Scene displaced = loadScene(squareJson(dir, "square.obj", "1"));
    bool dispWarned = false;
    for (const auto& w : displaced.warnings) dispWarned = dispWarned || w.find("disp map 'height.png' is not supported") != std::string::npos;
    EXPECT_TRUE(dispWarned);
    const auto [mean, se] = test::imageMeanAndError(test::renderIndependent(s, "cosine", 16, 4, 1));
    EXPECT_NEAR(mean, 0.25, 1e-6 + 4 * se);
}

TEST(TexturedRender, CorruptTextureIsAnErrorNamingTheFile) {
    test::TempDir dir;
    dir.write("bad.png", "\x89PNG\r\n\x1a\n not really");
    dir.write("m.mtl", "newmtl m\nmap_Kd bad.png\n");
    const std::string obj = squareObj(dir, "m.mtl", "m");
    try {
        loadScene(obj);
        ADD_FAILURE() << "a corrupt texture was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos) << e.what();
    }
}

// glTF: base colour texture, metallic 0, roughness 1: rho_d = 0.96 x texture, rho_s = 0.04, n = 0 (the
// table in docs/scene-format.md). The same material as an MTL with Kd 0.96, map_Kd, Ks 0.04, Ns 0; the two
// render the same mean within statistics, from a file, from a data URI and embedded in a .glb.
TEST(TexturedRender, GltfBaseColourTextureMatchesTheObjVersion) {
    test::TempDir dir;
    writeChecker(dir.file("checker.png"), 64, 8, 180, 60);
    dir.write("m.mtl", "newmtl checker\nKd 0.96 0.96 0.96\nKs 0.04 0.04 0.04\nNs 0\nmap_Kd checker.png\n");
    squareObj(dir, "m.mtl", "checker");
    const Scene obj = loadScene(squareJson(dir, "square.obj", "1"));
    const auto [objMean, objSe] = test::imageMeanAndError(test::renderIndependent(obj, "phong", 32, 32, 5));

    // The same square as glTF: positions, uvs (glTF's v runs down the image: v_gltf = 1 - v_obj).
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const std::uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(pos), sizeof pos);
    bin += std::string(reinterpret_cast<const char*>(uv), sizeof uv);
    bin += std::string(reinterpret_cast<const char*>(idx), sizeof idx);
    std::ofstream(dir.file("square.bin"), std::ios::binary) << bin;
    const auto base64 = [](const std::string& in) {
        static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::string out;
        for (std::size_t i = 0; i < in.size(); i += 3) {
            const unsigned n = (static_cast<unsigned char>(in[i]) << 16) |
                               (i + 1 < in.size() ? static_cast<unsigned char>(in[i + 1]) << 8 : 0) |
                               (i + 2 < in.size() ? static_cast<unsigned char>(in[i + 2]) : 0);
            out += t[(n >> 18) & 63];
            out += t[(n >> 12) & 63];
            out += i + 1 < in.size() ? t[(n >> 6) & 63] : '=';
            out += i + 2 < in.size() ? t[n & 63] : '=';
        }
        return out;
    };
    for (const std::string& image :
         {std::string("checker.png"), "data:image/png;base64," + base64(readTextFile(dir.file("checker.png")))}) {
        dir.write("square.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
  "materials": [{"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 1}}],
  "textures": [{"source": 0, "sampler": 0}], "samplers": [{"wrapS": 10497, "wrapT": 33071}], "images": [{"uri": ")" +
                                     image + R"("}],
  "buffers": [{"uri": "square.bin", "byteLength": 92}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32}, {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})");
        const Scene g = loadScene(squareJson(dir, "square.gltf", "1"));
        ASSERT_EQ(g.textures.size(), 1u) << image.substr(0, 20);
        const MaterialTextures& tx = g.materials[0].textures;
        EXPECT_EQ(tx.model, MaterialTextures::Model::MetallicRoughness);
        EXPECT_EQ(g.textures[0].wrapU, WrapMode::Repeat);
        EXPECT_EQ(g.textures[0].wrapV, WrapMode::Clamp);
        // At the top-left square's centre: rho_d = 0.96 x the texel (1 - F0), rho_s = 0.04, n = 0.
        PhongMaterial scratch;
        const PhongMaterial& at = materialAt(g, g.materials[0], {1.0 / 16, 1.0 - 1.0 / 16}, scratch);
        EXPECT_NEAR(at.rhoD.x, 0.96 * linear8(180), 1e-6);
        EXPECT_NEAR(at.rhoS.x, 0.04, 1e-12);
        EXPECT_NEAR(at.exponent, 0.0, 1e-9);
        const auto [mean, se] = test::imageMeanAndError(test::renderIndependent(g, "phong", 32, 32, 6));
        EXPECT_NEAR(mean, objMean, 4 * std::hypot(se, objSe)) << image.substr(0, 20) << ": se " << se << ", " << objSe;
    }

    // The same as a binary .glb: geometry and the PNG in its BIN chunk, the image named by a buffer view.
    const std::string png = readTextFile(dir.file("checker.png"));
    std::string body = bin + png;
    while (body.size() % 4) body += '\0';
    std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
  "materials": [{"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 1}}],
  "textures": [{"source": 0}], "images": [{"bufferView": 3, "mimeType": "image/png"}],
  "buffers": [{"byteLength": )" +
                       std::to_string(body.size()) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32}, {"buffer": 0, "byteOffset": 80, "byteLength": 12},
                  {"buffer": 0, "byteOffset": 92, "byteLength": )" +
                       std::to_string(png.size()) + R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
    while (json.size() % 4) json += ' ';
    const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::string glb = "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + body.size())) +
                            u32(static_cast<std::uint32_t>(json.size())) + "JSON" + json + u32(static_cast<std::uint32_t>(body.size())) +
                            std::string("BIN\0", 4) + body;
    std::ofstream(dir.file("square.glb"), std::ios::binary) << glb;
    const Scene g = loadScene(squareJson(dir, "square.glb", "1"));
    ASSERT_EQ(g.textures.size(), 1u);
    EXPECT_NE(g.textures[0].name().find("embedded"), std::string::npos) << g.textures[0].name();
    const auto [mean, se] = test::imageMeanAndError(test::renderIndependent(g, "phong", 32, 32, 8));
    EXPECT_NEAR(mean, objMean, 4 * std::hypot(se, objSe)) << "glb: se " << se << ", " << objSe;
}

// An emitter with a cut-out emits only where it is solid: light sampling (which picks points on the
// whole triangle) and paths that hit it (which pass through its holes) must agree.
TEST(TexturedRender, CutOutEmitterLightsAsMuchThroughLightSamplingAsThroughPaths) {
    test::TempDir dir;
    writeChecker(dir.file("mask.png"), 64, 4, 255, 0, 2);
    dir.write("m.mtl", "newmtl floor\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\nmap_d mask.png\n");
    dir.write("s.obj",
              "mtllib m.mtl\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
              "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
              "usemtl floor\nf 1 4 3 2\nusemtl lamp\nf 5/1 6/2 7/3 8/4\n");
    const Scene s = loadScene(dir.write(
        "s.json", R"({"obj": "s.obj", "camera": {"position": [0, 0.9, 0.01], "target": [0, 0, 0], "fov": 60}, "environment": 0})"));
    ASSERT_TRUE(s.hasCutOuts());
    const auto [nee, seNee] = test::imageMeanAndError(test::renderIndependent(s, "cosine", 16, 64, 41, true));
    const auto [paths, sePaths] = test::imageMeanAndError(test::renderIndependent(s, "cosine", 16, 64, 42, false));
    EXPECT_NEAR(nee, paths, 4 * std::hypot(seNee, sePaths)) << "se " << seNee << ", " << sePaths;
    EXPECT_GT(nee, 0.1);
}

// Collada through Assimp: the checkerboard square written by Assimp's own Collada exporter from the OBJ
// (its map_Kd becomes a <texture>) loads with the texture and renders the OBJ's mean.
TEST(TexturedRender, ColladaDiffuseTextureMatchesTheObjVersion) {
    test::TempDir dir;
    writeChecker(dir.file("checker.png"), 64, 8, 200, 50);
    dir.write("m.mtl", "newmtl checker\nKd 1 1 1\nKs 0 0 0\nmap_Kd checker.png\n");
    const std::string obj = squareObj(dir, "m.mtl", "checker");
    Assimp::Importer importer;
    const aiScene* ai = importer.ReadFile(obj, 0);
    ASSERT_NE(ai, nullptr) << importer.GetErrorString();
    Assimp::Exporter exporter;
    ASSERT_EQ(exporter.Export(ai, "collada", dir.file("square.dae")), AI_SUCCESS) << exporter.GetErrorString();
    const Scene fromObj = loadScene(squareJson(dir, "square.obj", "1"));
    const Scene fromDae = loadScene(squareJson(dir, "square.dae", "1"));
    ASSERT_EQ(fromDae.textures.size(), 1u);
    EXPECT_TRUE(fromDae.materials[0].textures.diffuse.present() || fromDae.materials.back().textures.diffuse.present());
    const auto [a, sa] = test::imageMeanAndError(test::renderIndependent(fromObj, "cosine", 32, 16, 9));
    const auto [b, sb] = test::imageMeanAndError(test::renderIndependent(fromDae, "cosine", 32, 16, 10));
    EXPECT_NEAR(a, b, 4 * std::hypot(sa, sb) + 1e-3 * a) << "se " << sa << ", " << sb;
    EXPECT_NEAR(a, 0.5 * (linear8(200) + linear8(50)), 1e-2);
}
