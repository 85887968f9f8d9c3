// Cut-outs stop nothing, for shadow rays as for camera rays: a floor lit by a sun straight above, under a
// perforated (map_d-style) black screen, against the same floor under a screen built of the solid squares
// alone (a second code path: geometry instead of the alpha test). The camera sits under the screen and
// sees only the floor, so every difference between the two is in the shadow rays. A shadow ray that
// ignored the holes would leave the floor dark (half the light), one that ignored the screen would light
// it all (twice).
#include "test_util.h"

#include "scene/surface.h"

#include <gtest/gtest.h>

using namespace symphong;

namespace {

constexpr double kHalf = 4.0;     // the floor and the screen span [-4, 4]^2
constexpr double kScreenY = 1.0;  // the screen's height over the floor

Scene floorUnderTheSun() {
    Scene s;
    PhongMaterial floor, screen;
    floor.name = "floor", floor.rhoD = Color(0.8);
    screen.name = "screen", screen.rhoD = Color(0.0);
    s.materials = {floor, screen};
    test::addQuad(s, Vec3(-kHalf, 0, -kHalf), Vec3(-kHalf, 0, kHalf), Vec3(kHalf, 0, kHalf), Vec3(kHalf, 0, -kHalf), 0);
    Light sun;
    sun.type = Light::Type::Directional, sun.direction = Vec3(0, -1, 0), sun.intensity = Color(2.0);
    s.lights = {sun};
    s.camera.position = Vec3(0, 0.7, 3.5);  // under the screen, looking down at the floor
    s.camera.target = Vec3(0, 0, 0);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 50;
    return s;
}

/// A square [x0,x1] x [z0,z1] of the screen, facing down, with texture coordinates (u, v) = ((x + 4) / 2, (z + 4) / 2).
void addScreenSquare(Scene& s, double x0, double x1, double z0, double z1) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    const auto uvBase = static_cast<std::int32_t>(s.uvs.size());
    for (const auto& [x, z] : {std::pair{x0, z0}, std::pair{x1, z0}, std::pair{x1, z1}, std::pair{x0, z1}}) {
        s.positions.emplace_back(x, kScreenY, z);
        s.uvs.push_back({(x + kHalf) / 2, (z + kHalf) / 2});
    }
    for (const auto& tri : {std::array<std::uint32_t, 3>{0, 1, 2}, std::array<std::uint32_t, 3>{0, 2, 3}}) {
        Triangle t;
        t.v = {base + tri[0], base + tri[1], base + tri[2]};
        t.t = {uvBase + static_cast<std::int32_t>(tri[0]), uvBase + static_cast<std::int32_t>(tri[1]), uvBase + static_cast<std::int32_t>(tri[2])};
        t.material = 1;
        s.triangles.push_back(t);
    }
}

}  // namespace

TEST(CutOutShadows, APerforatedScreenCastsTheShadowOfItsSolidParts) {
    // The perforated screen: one square, a 2 x 2 checker of coverage repeated 4 times in u and v.
    Scene perforated = floorUnderTheSun();
    perforated.textures.emplace_back("checker", 2, 2, 1, std::vector<float>{1, 0, 0, 1});
    perforated.materials[1].textures.alpha.index = 0;
    addScreenSquare(perforated, -kHalf, kHalf, -kHalf, kHalf);
    ASSERT_TRUE(perforated.hasCutOuts());
    // The same screen as geometry: the 0.5 x 0.5 (in uv) cells that the alpha test keeps, each a square.
    Scene solid = floorUnderTheSun();
    int kept = 0;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const TexCoord centre{0.25 + 0.5 * i, 0.25 + 0.5 * j};
            if (cutOutAt(perforated, perforated.materials[1], centre)) continue;
            addScreenSquare(solid, -kHalf + i, -kHalf + i + 1, -kHalf + j, -kHalf + j + 1);
            ++kept;
        }
    ASSERT_EQ(kept, 32) << "a checker keeps half of its cells";
    // Both renders from the same samples: paired, so their difference is the shadow rays' alone.
    const RenderResult a = test::renderIndependent(perforated, "cosine", 48, 16, 5, 1);
    const RenderResult b = test::renderIndependent(solid, "cosine", 48, 16, 5, 1);
    double sum = 0, sum2 = 0, lit = 0;
    const double n = static_cast<double>(a.image.pixels.size());
    for (std::size_t i = 0; i < a.image.pixels.size(); ++i) {
        const double d = luminance(a.image.pixels[i]) - luminance(b.image.pixels[i]);
        sum += d, sum2 += d * d;
        lit += luminance(b.image.pixels[i]) / n;
    }
    const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, 0.0, 4 * se + 1e-3 * lit) << "perforated vs solid squares: se " << se << ", image mean " << lit;
    // And the shadow is there: about half of the sun's rho/pi E reaches the floor on average.
    EXPECT_GT(lit, 0.3 * 0.8 / kPi * 2.0);
    EXPECT_LT(lit, 0.7 * 0.8 / kPi * 2.0);
}
