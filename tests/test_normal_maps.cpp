// Normal and bump maps (scene/shading_normal.h) and tangent frames (scene/tangents.h):
// - closed forms: a diffuse floor under a directional light with a constant tangent-space normal map
//   renders rho/pi E max(0, n'.l) with n' = normalize(x T + y B + z N) for three texture mappings (u along
//   +x; rotated 90 degrees; mirrored, handedness -1), tangents computed or given, scale 1 and 1/2; a
//   height ramp h = b u tilts the normal to normalize(-b, |dp/du|, 0) (dp'/du = dp/du + dh/du n);
// - a second method: a normal map of a smooth field against the same field baked into the vertex normals
//   of a fine grid, region by region within 4 standard errors;
// - computed tangents follow dp/du, keep a mirrored half apart, and equal the tangents Blender wrote;
// - loaders: MTL norm / map_Bump (height map or normal map, by Blender's stamp or the image), glTF
//   normalTexture with its scale, FBX's normal map and BumpFactor, KHR_texture_transform against the
//   extension's own T R S formula; Blender's exports of one normal-mapped scene render alike.
#include "floor_closed_form.h"
#include "stats.h"
#include "test_util.h"

#include "io/image.h"
#include "io/input_error.h"
#include "render/settings.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"
#include "scene/tangents.h"
#include "texture/texture_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <fstream>

using namespace symphong;

namespace {

constexpr double kAlbedo = 0.6, kHalf = 20.0;

/// How the floor's texture coordinates lie on it: Plain: u along +x, v along -z (tangent +x, bitangent
/// -z = cross(n, t), handedness +1); Rotated: u along -z, v along -x (tangent -z, bitangent -x); Mirrored:
/// u along +x, v along +z (bitangent +z = -cross(n, t), handedness -1).
enum class Mapping { Plain, Rotated, Mirrored };

std::array<double, 2> uvAt(Mapping m, const Vec3& p) {
    const double a = (p.x + kHalf) / (2 * kHalf), b = (kHalf - p.z) / (2 * kHalf);
    switch (m) {
        case Mapping::Plain:
            return {a, b};
        case Mapping::Rotated:
            return {b, (kHalf - p.x) / (2 * kHalf)};
        case Mapping::Mirrored:
            return {a, 1 - b};
    }
    return {a, b};
}
Vec3 tangentOf(Mapping m) { return m == Mapping::Rotated ? Vec3(0, 0, -1) : Vec3(1, 0, 0); }
Vec3 bitangentOf(Mapping m) { return m == Mapping::Plain ? Vec3(0, 0, -1) : m == Mapping::Rotated ? Vec3(-1, 0, 0) : Vec3(0, 0, 1); }

/// The floor of floor_closed_form.h with texture coordinates by `mapping`.
Scene mappedFloor(Mapping mapping) {
    Scene s = test::floorScene(kAlbedo, kHalf);
    for (std::size_t i = 0; i < s.positions.size(); ++i) s.uvs.push_back(uvAt(mapping, s.positions[i]));
    for (Triangle& t : s.triangles)
        for (std::size_t k = 0; k < 3; ++k) t.t[k] = static_cast<std::int32_t>(t.v[k]);
    return s;
}

/// A texture of one colour (2 x 2 texels, floats as stored: a data map).
Texture constantTexture(const Color& c) {
    std::vector<float> texels;
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) texels.push_back(static_cast<float>(c[k]));
    return Texture("constant", 2, 2, 3, texels);
}

Light directional(const Vec3& travel, double irradiance) {
    Light l;
    l.type = Light::Type::Directional;
    l.direction = normalize(travel);
    l.intensity = Color(irradiance);
    return l;
}

const Vec3 kTravel = normalize(Vec3(0.5, -1.0, 0.35));  // where the directional light goes
constexpr double kIrradiance = 1.5;

}  // namespace

TEST(NormalMaps, ConstantMapTiltsTheLambertCosineInItsTangentFrame) {
    const Vec3 mapNormal = normalize(Vec3(0.45, -0.3, 1.0));  // tangent space
    const Vec3 l = -kTravel;
    for (Mapping mapping : {Mapping::Plain, Mapping::Rotated, Mapping::Mirrored})
        for (double scale : {1.0, 0.5})
            for (bool given : {false, true}) {
                if (scale != 1 && (given || mapping != Mapping::Plain)) continue;  // the strength once is enough
                // Sanitized (test::kSanitized): four of the seven cases (each mapping, given and computed
                // tangents, the strength), each at its full sample count.
                if (test::kSanitized && scale == 1 && given != (mapping != Mapping::Rotated)) continue;
                Scene s = mappedFloor(mapping);
                s.textures.push_back(constantTexture((mapNormal + Vec3(1.0)) * 0.5));
                s.materials[0].textures.normal.index = 0;
                s.materials[0].textures.normalScale = scale;
                if (given) {  // the file's tangents (these are what computeTangents would find)
                    const double sign = mapping == Mapping::Mirrored ? -1 : 1;
                    s.tangents.push_back({tangentOf(mapping), sign});
                    for (Triangle& t : s.triangles) t.tg = {0, 0, 0};
                }
                s.lights = {directional(kTravel, kIrradiance)};
                finalizeScene(s, "test", false);
                const Vec3 local(mapNormal.x * scale, mapNormal.y * scale, mapNormal.z);
                const Vec3 n = normalize(tangentOf(mapping) * local.x + bitangentOf(mapping) * local.y + Vec3(0, 1, 0) * local.z);
                // The map changes the picture: its cosine differs from the flat floor's by 0.02 or more, some 25
                // times the comparison's tolerance (0.1% of the radiance).
                ASSERT_GT(std::abs(dot(n, l) - l.y), 0.02);
                const std::string what =
                    fmt::format("mapping {}, scale {}, tangents {}", static_cast<int>(mapping), scale, given ? "given" : "computed");
                // Where the viewer would be behind the bent normal (far along the floor), the unbent one is used.
                test::expectFloorMatchesClosedForm(
                    s, kHalf,
                    [&](const Vec3&, const Vec3& ray) -> std::optional<double> {
                        const Vec3 used = dot(n, -ray) > 0 ? n : Vec3(0, 1, 0);
                        return kAlbedo / kPi * kIrradiance * std::max(0.0, dot(used, l));
                    },
                    what, 40);
            }
}

TEST(NormalMaps, HeightRampTiltsTheNormalAgainstItsSlope) {
    // h(u) = b u: the ramp's texels (i + 1/2) / 64 read exactly u by bilinear lookup away from the edges
    // (clamped there). dp/du = 2 kHalf x, so dp'/du = (2 kHalf, b, 0), dp'/dv = (0, 0, -2 kHalf) and
    // n' = normalize(-b, 2 kHalf, 0).
    constexpr int kTexels = 64;
    for (double b : {10.0, 25.0}) {
        Scene s = mappedFloor(Mapping::Plain);
        std::vector<float> ramp;
        for (int i = 0; i < kTexels; ++i) ramp.push_back(static_cast<float>((i + 0.5) / kTexels));
        Texture t("ramp", kTexels, 1, 1, ramp);
        t.wrapU = t.wrapV = WrapMode::Clamp;
        s.textures.push_back(t);
        s.materials[0].textures.bump.index = 0;
        s.materials[0].textures.bumpScale = b;
        s.lights = {directional(kTravel, kIrradiance)};
        finalizeScene(s, "test", false);
        const Vec3 n = normalize(Vec3(-b, 2 * kHalf, 0));
        const Vec3 l = -kTravel;
        ASSERT_GT(std::abs(dot(n, l) - l.y), 0.05);
        test::expectFloorMatchesClosedForm(
            s, kHalf,
            [&](const Vec3&, const Vec3& ray) -> std::optional<double> {
                const Vec3 used = dot(n, -ray) > 0 ? n : Vec3(0, 1, 0);
                return kAlbedo / kPi * kIrradiance * std::max(0.0, dot(used, l));
            },
            fmt::format("bump scale {}", b), 40);
    }
}

namespace {

/// A smooth field of tangent-space normals over [0,1]^2 (tilts up to about 27 degrees).
Vec3 field(double u, double v) { return normalize(Vec3(0.5 * std::sin(2 * kPi * 1.5 * u), 0.4 * std::cos(2 * kPi * v), 1.0)); }

/// A square patch of the floor (x in [-2, 2], z in [-3, 1]) with Plain-like texture coordinates over it,
/// lit by an emissive quad; either one quad with a normal map of `field`, or a grid of cells x cells
/// quads whose vertex normals are the field's normals in world space.
Scene fieldPatch(bool baked, int cells, int texels) {
    Scene s;
    PhongMaterial floor, lamp;
    floor.name = "floor", floor.rhoD = Color(kAlbedo);
    lamp.name = "lamp", lamp.rhoD = Color(0.0), lamp.emission = Color(4.0);
    s.materials = {floor, lamp};
    const double x0 = -2, x1 = 2, z0 = -3, z1 = 1;
    const auto world = [](const Vec3& t) { return normalize(Vec3(t.x, t.z, -t.y)); };  // T = +x, B = -z, N = +y
    const int n = baked ? cells : 1;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
            s.positions.emplace_back(x0 + (x1 - x0) * u, 0.0, z1 - (z1 - z0) * v);
            s.uvs.push_back({u, v});
            if (baked) s.normals.push_back(world(field(u, v)));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
            const std::array<std::uint32_t, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            for (const auto& tri : {std::array<std::uint32_t, 3>{q[0], q[1], q[2]}, std::array<std::uint32_t, 3>{q[0], q[2], q[3]}}) {
                Triangle t;
                t.v = tri;
                for (std::size_t k = 0; k < 3; ++k) {
                    t.t[k] = static_cast<std::int32_t>(tri[k]);
                    if (baked) t.n[k] = static_cast<std::int32_t>(tri[k]);
                }
                s.triangles.push_back(t);
            }
        }
    if (!baked) {  // the field at texel centres (u = (i + 1/2) / W, v = 1 - (j + 1/2) / H, row 0 at the top)
        std::vector<float> data;
        for (int j = 0; j < texels; ++j)
            for (int i = 0; i < texels; ++i) {
                const Vec3 f = field((i + 0.5) / texels, 1.0 - (j + 0.5) / texels);
                for (int k = 0; k < 3; ++k) data.push_back(static_cast<float>((f[k] + 1) / 2));
            }
        Texture t("field", texels, texels, 3, data);
        t.wrapU = t.wrapV = WrapMode::Clamp;
        s.textures.push_back(t);
        s.materials[0].textures.normal.index = 0;
    }
    test::addQuad(s, Vec3(1, 2, -1.5), Vec3(2, 2, -1.5), Vec3(2, 2, -0.5), Vec3(1, 2, -0.5), 1);  // facing -y
    s.camera.position = Vec3(0, 3.5, 2.5);
    s.camera.target = Vec3(0, 0, -1);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 60;
    finalizeScene(s, "test", false);
    return s;
}

RenderResult renderDirect(const Scene& s, std::uint64_t seed, int size = 48, std::uint32_t spp = 64) {
    return test::renderTiny(s, "cosine", size, spp, seed, 0, true, 1, "independent");
}

/// Whether two independent renders agree region by region (size x size pixels) within 4 standard
/// errors; counts the regions where either differs from `flat` by more than 4 standard errors too (what
/// shows that the comparison could fail).
void expectRendersAgree(const RenderResult& a, const RenderResult& b, const RenderResult* flat, int block, const std::string& what) {
    int regions = 0, changed = 0;
    for (int by = 0; by + block <= a.image.height; by += block)
        for (int bx = 0; bx + block <= a.image.width; bx += block) {
            double ma = 0, mb = 0, va = 0, vb = 0, mf = 0, vf = 0;
            for (int y = by; y < by + block; ++y)
                for (int x = bx; x < bx + block; ++x) {
                    ma += luminance(a.image.at(x, y)), va += luminanceVariance(a.variance.at(x, y));
                    mb += luminance(b.image.at(x, y)), vb += luminanceVariance(b.variance.at(x, y));
                    if (flat) mf += luminance(flat->image.at(x, y)), vf += luminanceVariance(flat->variance.at(x, y));
                }
            const double n = block * block;
            ma /= n, mb /= n, mf /= n;
            const double se = std::sqrt(va + vb) / n;
            ++regions;
            EXPECT_LE(std::abs(ma - mb), 4 * se + 1e-12) << what << ": region (" << bx << ", " << by << "): " << ma << " against " << mb
                                                         << " (standard error of the difference " << se << ")";
            if (flat && std::abs(ma - mf) > 4 * std::sqrt(va + vf) / n) ++changed;
        }
    EXPECT_GT(regions, 0);
    if (flat) {
        EXPECT_GE(changed, regions / 3) << what << ": the map should change many regions beyond their noise";
    }
}

}  // namespace

TEST(NormalMaps, MapOfAFieldMatchesTheSameFieldBakedIntoVertexNormals) {
    const Scene mapped = fieldPatch(false, 0, 192), baked = fieldPatch(true, 96, 0);
    Scene flat = mapped;
    flat.materials[0].textures.normal = TextureRef{};
    const RenderResult a = renderDirect(mapped, 11), b = renderDirect(baked, 12), f = renderDirect(flat, 13);
    expectRendersAgree(a, b, &f, 6, "normal map against baked normals");
}

TEST(Tangents, FollowDpDuAndKeepAMirroredHalfApart) {
    // Two unit quads in z = 0 facing +z that share the edge x = 0 (positions and texture coordinates):
    // u = 1 + x on the left (dp/du = +x, handedness +1), u = 1 - x on the right (dp/du = -x, mirrored).
    Scene s;
    s.materials = {PhongMaterial{}};
    s.textures.push_back(constantTexture(Color(0.5, 0.5, 1.0)));
    s.materials[0].textures.normal.index = 0;
    for (double y : {0.0, 1.0})
        for (double x : {-1.0, 0.0, 1.0}) {
            s.positions.emplace_back(x, y, 0.0);
            s.uvs.push_back({1 - std::abs(x), y});
        }
    // vertices: 0 (-1,0) 1 (0,0) 2 (1,0) 3 (-1,1) 4 (0,1) 5 (1,1)
    for (const auto& v : {std::array<std::uint32_t, 3>{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}}) {
        Triangle t;
        t.v = v;
        for (std::size_t k = 0; k < 3; ++k) t.t[k] = static_cast<std::int32_t>(v[k]);
        s.triangles.push_back(t);
    }
    EXPECT_EQ(computeTangents(s), 4u);
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
        const bool left = i < 2;
        for (std::size_t k = 0; k < 3; ++k) {
            const Tangent& t = s.tangents[static_cast<std::size_t>(s.triangles[i].tg[k])];
            EXPECT_NEAR(t.t.x, left ? 1.0 : -1.0, 1e-12) << "triangle " << i << " corner " << k;
            EXPECT_NEAR(std::abs(t.t.y) + std::abs(t.t.z), 0.0, 1e-12);
            EXPECT_EQ(t.sign, left ? 1.0 : -1.0);
            // The bitangent sign x cross(n, t) runs along increasing v (+y) on both halves.
            EXPECT_NEAR(dot(cross(Vec3(0, 0, 1), t.t) * t.sign, Vec3(0, 1, 0)), 1.0, 1e-12);
        }
    }
    // The shared vertices 1 and 4 have one tangent per half.
    EXPECT_NE(s.triangles[0].tg[1], s.triangles[2].tg[0]);
}

TEST(Tangents, SmoothSphereTangentsAreUnitAndOrthogonalToTheNormals) {
    Scene s;
    s.materials = {PhongMaterial{}};
    s.textures.push_back(constantTexture(Color(0.5, 0.5, 1.0)));
    s.materials[0].textures.normal.index = 0;
    test::addUvSphere(s, 0, true, 12, 24);
    for (const Vec3& p : s.positions) {  // smooth normals, and longitude / latitude as texture coordinates
        s.normals.push_back(p);
        s.uvs.push_back({std::atan2(p.z, p.x) / kTwoPi + 0.5, 1 - std::acos(std::clamp(p.y, -1.0, 1.0)) / kPi});
    }
    for (Triangle& t : s.triangles)
        for (std::size_t k = 0; k < 3; ++k) t.n[k] = t.t[k] = static_cast<std::int32_t>(t.v[k]);
    computeTangents(s);
    for (const Triangle& t : s.triangles)
        for (std::size_t k = 0; k < 3; ++k) {
            ASSERT_GE(t.tg[k], 0);
            const Tangent& tg = s.tangents[static_cast<std::size_t>(t.tg[k])];
            const Vec3 n = cornerNormal(s, t, static_cast<int>(k));
            EXPECT_NEAR(length(tg.t), 1.0, 1e-9);
            EXPECT_NEAR(dot(tg.t, n), 0.0, 1e-9);
        }
}

namespace {

std::string blenderNormalMapFile(const std::string& name) {
    return std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/blender/normalmap/" + name;
}

Vec3 centroid(const Scene& s, const Triangle& t) { return (s.positions[t.v[0]] + s.positions[t.v[1]] + s.positions[t.v[2]]) / 3.0; }

}  // namespace

TEST(Tangents, ComputedTangentsEqualTheOnesBlenderWrote) {
    // Blender 3.4 wrote the same plane (two quads, one mirrored in v) with its MikkTSpace tangents
    // (scene_tangents.glb) and without (scene.glb): the tangents we compute for the second are the
    // first's, with the same handedness, at every corner.
    EXPECT_FALSE(loadAssimp(blenderNormalMapFile("scene_tangents.glb")).tangents.empty()) << "the file's TANGENT is read";
    EXPECT_TRUE(loadAssimp(blenderNormalMapFile("scene.glb")).tangents.empty());
    const Scene file = loadScene(blenderNormalMapFile("scene_tangents.glb")), computed = loadScene(blenderNormalMapFile("scene.glb"));
    int corners = 0, mirrored = 0;
    for (const Triangle& a : file.triangles) {
        if (a.tg[0] < 0) continue;
        const Triangle* match = nullptr;
        for (const Triangle& b : computed.triangles)
            if (length(centroid(file, a) - centroid(computed, b)) < 1e-5) match = &b;
        ASSERT_NE(match, nullptr);
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3 p = file.positions[a.v[k]];
            std::size_t j = 0;
            while (j < 3 && length(computed.positions[match->v[j]] - p) > 1e-5) ++j;
            ASSERT_LT(j, 3u);
            const Tangent& want = file.tangents[static_cast<std::size_t>(a.tg[k])];
            const Tangent& got = computed.tangents[static_cast<std::size_t>(match->tg[j])];
            EXPECT_NEAR(length(want.t - got.t), 0.0, 1e-5) << "corner at (" << p.x << ", " << p.y << ", " << p.z << ")";
            EXPECT_EQ(want.sign, got.sign);
            ++corners;
            mirrored += want.sign < 0;
        }
    }
    EXPECT_EQ(corners, 12);
    EXPECT_EQ(mirrored, 6) << "one of the two quads is mirrored";
}

TEST(NormalMaps, NormalMapImagesAreToldFromHeightMaps) {
    const Texture bumps = loadTextureFile(blenderNormalMapFile("bumps.png"), TextureEncoding::Linear);
    EXPECT_TRUE(looksLikeNormalMap(bumps));
    EXPECT_TRUE(looksLikeNormalMap(constantTexture(Color(0.5, 0.5, 1.0))));
    std::vector<float> ramp;
    for (int i = 0; i < 64; ++i)
        for (int k = 0; k < 3; ++k) ramp.push_back(static_cast<float>(i / 63.0));
    EXPECT_FALSE(looksLikeNormalMap(Texture("grey ramp", 64, 1, 3, ramp)));
    EXPECT_FALSE(looksLikeNormalMap(Texture("one channel", 2, 1, 1, {0.5f, 1.0f})));
    EXPECT_FALSE(looksLikeNormalMap(constantTexture(Color(0.8, 0.3, 0.1))));  // a colour: (2c - 1) has z < 0
}

namespace {

/// An 8-bit PNG of one colour (bytes as given).
std::string writeSolidPng(const std::string& path, int size, std::array<unsigned char, 3> rgb) {
    std::vector<unsigned char> px;
    for (int i = 0; i < size * size; ++i) px.insert(px.end(), rgb.begin(), rgb.end());
    EXPECT_NE(stbi_write_png(path.c_str(), size, size, 3, px.data(), size * 3), 0);
    return path;
}

}  // namespace

TEST(NormalMaps, MtlNormAndBumpMapsAreReadAsTheyAreMeant) {
    test::TempDir dir;
    writeSolidPng(dir.file("normal.png"), 4, {160, 110, 240});
    writeSolidPng(dir.file("height.png"), 4, {90, 90, 90});
    const std::string obj =
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
        "usemtl a\nf 1/1/1 2/2/1 3/3/1\nusemtl b\nf 1/1/1 3/3/1 2/2/1\nusemtl c\nf 2/2/1 1/1/1 3/3/1\n"
        "usemtl d\nf 2/2/1 3/3/1 1/1/1\n";
    const std::string mtl =
        "newmtl a\nKd 0.5 0.5 0.5\nnorm -bm 0.7 normal.png\n"
        "newmtl b\nKd 0.5 0.5 0.5\nmap_Bump -bm 0.25 height.png\n"
        "newmtl c\nKd 0.5 0.5 0.5\nbump normal.png\n"
        "newmtl d\nKd 0.5 0.5 0.5\nmap_Bump -bm 1e999 height.png\n";
    dir.write("s.obj", obj);
    dir.write("m.mtl", mtl.substr(0, mtl.find("newmtl d")) + "newmtl d\nKd 0.5 0.5 0.5\n");
    const Scene s = loadScene(dir.file("s.obj"));
    const auto& a = s.materials[static_cast<std::size_t>(s.findMaterial("a"))].textures;
    const auto& b = s.materials[static_cast<std::size_t>(s.findMaterial("b"))].textures;
    const auto& c = s.materials[static_cast<std::size_t>(s.findMaterial("c"))].textures;
    EXPECT_TRUE(a.normal.present() && !a.bump.present());
    EXPECT_NEAR(a.normalScale, 0.7, 1e-7);  // tinyobjloader reads it in single precision
    EXPECT_TRUE(b.bump.present() && !b.normal.present()) << "a grey image under map_Bump is a height map";
    EXPECT_NEAR(b.bumpScale, 0.25, 1e-7);
    EXPECT_TRUE(c.normal.present() && !c.bump.present()) << "a normal-map image under bump is a normal map";
    for (const std::string& w : s.warnings) EXPECT_EQ(w.find("not supported"), std::string::npos) << w;
    // The same grey image in an MTL that Blender wrote: Blender writes its normal maps as map_Bump.
    dir.write("m.mtl", "# Blender 3.4.1 MTL File: 'x.blend'\nnewmtl a\nKd 0.5 0.5 0.5\nmap_Bump -bm 1.000000 height.png\n");
    const Scene blender = loadScene(dir.file("s.obj"));
    EXPECT_TRUE(blender.materials[static_cast<std::size_t>(blender.findMaterial("a"))].textures.normal.present());
    // A -bm that is not a number is bad input naming the file.
    dir.write("m.mtl", mtl);
    try {
        loadScene(dir.file("s.obj"));
        ADD_FAILURE() << "-bm 1e999 was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("m.mtl"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("-bm"), std::string::npos) << e.what();
    }
}

TEST(NormalMaps, BlenderExportsCarryTheNormalMapAndItsStrength) {
    for (const char* file : {"scene.glb", "scene_tangents.glb", "scene.fbx", "scene_tspace.fbx", "scene.obj", "scene_strength05.glb",
                             "scene_strength05.fbx", "scene_strength05.obj"}) {
        const Scene s = loadScene(blenderNormalMapFile(file));
        const int m = s.findMaterial("bumpy");
        ASSERT_GE(m, 0) << file;
        const MaterialTextures& tx = s.materials[static_cast<std::size_t>(m)].textures;
        EXPECT_TRUE(tx.normal.present()) << file;
        EXPECT_FALSE(tx.bump.present()) << file;
        EXPECT_DOUBLE_EQ(tx.normalScale, std::string(file).find("strength05") != std::string::npos ? 0.5 : 1.0) << file;
        for (const std::string& w : s.warnings) EXPECT_EQ(w.find("not supported"), std::string::npos) << file << ": " << w;
    }
}

TEST(NormalMaps, BlenderExportsOfANormalMappedPlaneRenderAlike) {
    // glTF with and without tangents, FBX with and without, and OBJ (through a JSON scene with the same
    // camera) of one plane under one emitter: each within 4 standard errors of the glTF, region by region;
    // the plane without its map differs in many regions.
    const Scene reference = loadScene(blenderNormalMapFile("scene.glb"));
    const RenderResult ref = renderDirect(reference, 1, 48, 64);
    Scene flat = reference;
    for (PhongMaterial& m : flat.materials) m.textures.normal = TextureRef{};
    const RenderResult f = renderDirect(flat, 2, 48, 64);
    std::uint64_t seed = 3;
    for (const char* file : {"scene_tangents.glb", "scene.fbx", "scene_tspace.fbx", "obj_camera.json"})
        expectRendersAgree(renderDirect(loadScene(blenderNormalMapFile(file)), seed++, 48, 64), ref, &f, 6, file);
}

TEST(NormalMaps, KhrTextureTransformFollowsTheExtensionsFormula) {
    // A 64 x 64 image of four solid quadrants and a quad whose base colour texture has offset, rotation
    // and scale. For each point of a grid the texture must read the quadrant that the extension's own
    // formula (uv' = T R S uv in glTF's coordinates, t = 1 - v) points to.
    test::TempDir dir;
    const std::array<std::array<unsigned char, 3>, 4> colours{{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}}};
    std::vector<unsigned char> px;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const auto& c = colours[static_cast<std::size_t>((y >= 32) * 2 + (x >= 32))];  // top-left, top-right, bottom-left, bottom-right
            px.insert(px.end(), c.begin(), c.end());
        }
    ASSERT_NE(stbi_write_png(dir.file("quadrants.png").c_str(), 64, 64, 3, px.data(), 64 * 3), 0);
    // Positions (4 x vec3) then texture coordinates (4 x vec2) then indices (6 x uint16), little-endian.
    std::string bin;
    const auto put = [&](const auto& v) { bin.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
    for (float p : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) put(p);
    for (float t : {0.f, 1.f, 1.f, 1.f, 1.f, 0.f, 0.f, 0.f}) put(t);
    for (std::uint16_t i : {0, 1, 2, 0, 2, 3}) put(i);
    std::ofstream(dir.file("q.bin"), std::ios::binary) << bin;
    const double offset[2] = {0.3, 0.1}, rotation = 0.4, scale[2] = {1.5, 0.8};
    dir.write("q.gltf", fmt::format(R"({{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_texture_transform"],
  "buffers": [{{"uri": "q.bin", "byteLength": {}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "images": [{{"uri": "quadrants.png"}}], "textures": [{{"source": 0}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0, "extensions": {{"KHR_texture_transform":
      {{"offset": [{}, {}], "rotation": {}, "scale": [{}, {}]}}}}}}, "metallicFactor": 0}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2, "material": 0}}]}}],
  "nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}], "scene": 0}})",
                                    bin.size(), offset[0], offset[1], rotation, scale[0], scale[1]));
    const Scene s = loadScene(dir.file("q.gltf"));
    const TextureRef& ref = s.materials[0].textures.diffuse;
    ASSERT_TRUE(ref.present());
    const Texture& tex = s.textures[static_cast<std::size_t>(ref.index)];
    int checked = 0;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) {
            const double u = (i + 0.5) / 20, v = (j + 0.5) / 20;
            // The extension's formula in glTF's coordinates: translation * rotation * scale.
            const double sx = u * scale[0], sy = (1 - v) * scale[1];
            const double rx = std::cos(rotation) * sx - std::sin(rotation) * sy, ry = std::sin(rotation) * sx + std::cos(rotation) * sy;
            const double gx = rx + offset[0], gy = ry + offset[1];
            const double fx = gx - std::floor(gx), fy = gy - std::floor(gy);  // the sampler repeats
            const auto nearEdge = [](double f) { return std::min({std::abs(f), std::abs(f - 0.5), std::abs(f - 1)}) < 2.0 / 64; };
            if (nearEdge(fx) || nearEdge(fy)) continue;
            const auto& want = colours[static_cast<std::size_t>((fy >= 0.5) * 2 + (fx >= 0.5))];
            const Color got = tex.rgb(ref.u(u, v), ref.v(u, v));
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(got[k], want[static_cast<std::size_t>(k)] / 255.0, 1e-6) << "at uv (" << u << ", " << v << ")";
            ++checked;
        }
    EXPECT_GT(checked, 150);
}

TEST(Assimp, BlenderPortraitCameraKeepsItsVerticalFieldOfView) {
    // Blender 3.4, 60 x 80 pixels, 50 mm lens on a 36 mm sensor, sensor fit AUTO: the 36 mm span the
    // longer (vertical) side, so the vertical field of view is 2 atan(18 / 50); its FBX and Collada
    // exporters write that angle as the horizontal one.
    const double vertical = 2 * std::atan(18.0 / 50.0) * 180 / kPi;
    for (const char* file : {"scene.glb", "scene.fbx", "scene.dae"}) {
        const Scene s = loadScene(std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/blender/portrait/" + file);
        EXPECT_NEAR(s.camera.fovY, vertical, 0.01) << file;
    }
}

TEST(NormalMaps, PerturbedNormalIsTheMapsVectorInTheTangentFrame) {
    const Vec3 mapNormal = normalize(Vec3(0.45, -0.3, 1.0));
    for (Mapping mapping : {Mapping::Plain, Mapping::Rotated, Mapping::Mirrored})
        for (bool flipped : {false, true}) {
            Scene s = mappedFloor(mapping);
            s.textures.push_back(constantTexture((mapNormal + Vec3(1.0)) * 0.5));
            s.materials[0].textures.normal.index = 0;
            // Wound clockwise but with vertex normals +y: the handedness follows the normals, not the winding.
            if (flipped) {
                s.normals = {Vec3(0, 1, 0)};
                for (Triangle& t : s.triangles) {
                    std::swap(t.v[1], t.v[2]);
                    std::swap(t.t[1], t.t[2]);
                    t.n = {0, 0, 0};
                }
            }
            computeTangents(s);
            const Vec3 want =
                normalize(tangentOf(mapping) * mapNormal.x + bitangentOf(mapping) * mapNormal.y + Vec3(0, 1, 0) * mapNormal.z);
            for (const Triangle& t : s.triangles) {
                const TexCoord uv = texcoordAt(s, t, 0.3, 0.3);
                const Vec3 got = perturbedNormal(s, t, s.materials[0].textures, 0.3, 0.3, uv, Vec3(0, 1, 0));
                EXPECT_NEAR(length(got - want), 0.0, 1e-6)
                    << "mapping " << static_cast<int>(mapping) << (flipped ? ", wound clockwise" : "") << ": (" << got.x << ", " << got.y
                    << ", " << got.z << ") against (" << want.x << ", " << want.y << ", " << want.z << ")";
            }
        }
}

TEST(NormalMaps, MatchesCyclesWithBumpShadowingAndItsDarkHalfWithout) {
    // Blender Cycles' own picture of the normal-mapped plane (256 spp) against symphong's of its glTF
    // export (64 spp). As it is, over the pixels darker than their neighbourhood (a 3x3 mean below the
    // 17x17 mean: the half of each bump that the map turns away from the light) the sums agree within 4
    // standard errors (Cycles' variance taken as ours times 64/256: same scene, four times the samples),
    // while on the bright half Cycles is darker by some 10%: it multiplies a bent normal's shading by the
    // shadowing term of Chiang et al. 2019, below 1 only where the bent normal faces the light more than
    // the surface does. With --bump-shadowing, which applies that term, both halves agree.
    const Scene s = loadScene(blenderNormalMapFile("scene.glb"));
    const Image cycles = readExr(blenderNormalMapFile("cycles_reference.exr"));
    ASSERT_EQ(cycles.width, 96);
    for (bool shadowing : {false, true}) {
        const Accel accel(s);
        const auto est = makeEstimator("phong");
        RenderSettings rs;
        rs.width = rs.height = 96;
        rs.spp = 64;
        rs.seed = 7;
        rs.trace.bumpShadowing = shadowing;
        const RenderResult r = render(s, accel, *est, rs);
        const auto mean = [&](int x, int y, int k) {
            double sum = 0;
            int n = 0;
            for (int j = std::max(0, y - k); j <= std::min(95, y + k); ++j)
                for (int i = std::max(0, x - k); i <= std::min(95, x + k); ++i) sum += luminance(r.image.at(i, j)), ++n;
            return sum / n;
        };
        double ours[2] = {0, 0}, theirs[2] = {0, 0}, variance[2] = {0, 0};
        int pixels[2] = {0, 0};
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 96; ++x) {
                const double a = luminance(r.image.at(x, y)), b = luminance(cycles.at(x, y));
                if (a < 0.005 || b < 0.005) continue;  // off the plane
                const int half = mean(x, y, 1) < mean(x, y, 8) ? 0 : 1;  // 0: dark, 1: bright
                ours[half] += a, theirs[half] += b, variance[half] += 1.25 * luminanceVariance(r.variance.at(x, y));
                ++pixels[half];
            }
        ASSERT_GT(pixels[0], 1000);
        ASSERT_GT(pixels[1], 1000);
        for (int half : {0, 1}) {
            const double ratio = ours[half] / theirs[half], se = std::sqrt(variance[half]) / theirs[half];
            std::printf("%s, %s half: symphong / Cycles = %.4f +- %.4f over %d pixels\n", shadowing ? "--bump-shadowing" : "as it is",
                        half ? "bright" : "dark", ratio, se, pixels[half]);
            if (half == 0 || shadowing)
                EXPECT_NEAR(ratio, 1.0, 4 * se) << (shadowing ? "--bump-shadowing, " : "") << (half ? "bright" : "dark") << " half";
            else
                EXPECT_GT(ratio, 1.05) << "without the shadowing term the bright half is brighter than Cycles'";
        }
    }
}

TEST(NormalMaps, BumpShadowingTermFollowsItsFormula) {
    const Vec3 ng(0, 0, 1);
    EXPECT_EQ(bumpShadowing(ng, ng, normalize(Vec3(1, 0, 1))), 1.0);  // no bend: no shadowing
    // The bent normal faces the light less than the surface does: g > 1, no shadowing.
    EXPECT_EQ(bumpShadowing(ng, normalize(Vec3(-0.3, 0, 1)), normalize(Vec3(1, 0, 1))), 1.0);
    // Faces it more: g = (ng.l) / ((ns.l)(ns.ng)) in (0, 1), G = -g^3 + g^2 + g.
    const Vec3 ns = normalize(Vec3(0.6, 0, 1)), l = normalize(Vec3(1, 0, 0.3));
    const double g = dot(ng, l) / (dot(ns, l) * dot(ns, ng));
    ASSERT_GT(g, 0);
    ASSERT_LT(g, 1);
    EXPECT_NEAR(bumpShadowing(ng, ns, l), -g * g * g + g * g + g, 1e-15);
    EXPECT_LT(bumpShadowing(ng, ns, l), 1.0);
    // Light below the surface but above the bent normal: fully shadowed.
    EXPECT_EQ(bumpShadowing(ng, ns, normalize(Vec3(1, 0, -0.1))), 0.0);
}

TEST(NormalMaps, BumpShadowingUnderADirectionalLightGivesTheClosedForm) {
    // The constant map of the first test (plain mapping) with --bump-shadowing: rho/pi E (n'.l) G(n_g, n', l)
    // (about 0.71 of the unshadowed value for this light).
    const Vec3 mapNormal = normalize(Vec3(0.45, -0.3, 1.0));
    const Vec3 travel = normalize(Vec3(-1, -0.5, -0.6));  // low light from +x +z, which the bent normal faces
    const Vec3 l = -travel;
    Scene s = mappedFloor(Mapping::Plain);
    s.textures.push_back(constantTexture((mapNormal + Vec3(1.0)) * 0.5));
    s.materials[0].textures.normal.index = 0;
    s.lights = {directional(travel, kIrradiance)};
    finalizeScene(s, "test", false);
    const Vec3 n = normalize(Vec3(mapNormal.x, mapNormal.z, -mapNormal.y));  // T = +x, B = -z, N = +y
    const Vec3 up(0, 1, 0);
    ASSERT_LT(bumpShadowing(up, n, l), 0.98) << "the light must be one the bent normal faces more than the floor";
    // The test helper renders with default settings; the term is switched on here through the schema's
    // settings as a user would (RenderOptions -> RenderSettings).
    RenderOptions o;
    o.bumpShadowing = true;
    ASSERT_TRUE(renderSettings(o).trace.bumpShadowing);
    const Accel accel(s);
    const auto est = makeEstimator("cosine");
    RenderSettings rs = renderSettings(o);
    rs.width = rs.height = 32;
    rs.spp = 16;
    rs.trace.maxDepth = 1;
    const RenderResult r = render(s, accel, *est, rs);
    int checked = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            Vec3 o2, d;
            cameraRay(s.camera, 32, 32, x + 0.5, y + 0.5, o2, d);
            if (dot(n, -d) <= 0.05 || d.y >= 0) continue;  // the bent normal is not used where the viewer is behind it
            const double want = kAlbedo / kPi * kIrradiance * dot(n, l) * bumpShadowing(up, n, l);
            EXPECT_NEAR(r.image.at(x, y).x, want, 1e-6 * want) << "pixel (" << x << ", " << y << ")";
            ++checked;
        }
    EXPECT_GT(checked, 500);
}

TEST(NormalMaps, StrengthThatIsNotFiniteIsBadInput) {
    for (bool bump : {false, true}) {
        Scene s = mappedFloor(Mapping::Plain);
        s.textures.push_back(constantTexture(Color(0.5, 0.5, 1.0)));
        (bump ? s.materials[0].textures.bump : s.materials[0].textures.normal).index = 0;
        (bump ? s.materials[0].textures.bumpScale : s.materials[0].textures.normalScale) = std::nan("");
        try {
            finalizeScene(s, "scene.fbx", false);
            ADD_FAILURE() << "a NaN strength was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("scene.fbx: material 'floor'"), std::string::npos) << e.what();
        }
    }
}
