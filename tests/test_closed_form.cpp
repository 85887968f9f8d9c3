// Renders against closed forms that owe nothing to our code: the direct irradiance that a Lambertian
// polygon emitter gives a point of a plane (Lambert's formula), unoccluded and partly occluded (the
// occluder's shadow clipped out of the emitter polygon), against --max-depth 1 renders, region by region,
// within 4 standard errors. The formula is checked first against the rectangle form factor of the
// heat-transfer tables, an independent derivation.
#include "stats.h"
#include "test_util.h"

#include "compare/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

using namespace symphong;

namespace {

constexpr double kPiD = 3.14159265358979323846;

/// Irradiance at p (unit normal n) from a planar polygon of uniform radiance L whose emitting side
/// faces p and which lies wholly above p's tangent plane. Lambert (1760), as in Arvo, "Applications of
/// irradiance tensors", SIGGRAPH 1995, Eq. (5)-(8):
///   E = L/2 * |sum_i theta_i n . normalize(r_i x r_(i+1))|,  r_i = v_i - p,  theta_i = angle(r_i, r_(i+1)).
double polygonIrradiance(const std::vector<Vec3>& polygon, const Vec3& p, const Vec3& n, double L) {
    double sum = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Vec3 a = normalize(polygon[i] - p), b = normalize(polygon[(i + 1) % polygon.size()] - p);
        const Vec3 c = cross(a, b);
        const double s = length(c);
        if (s < 1e-15) continue;
        sum += std::atan2(s, dot(a, b)) * dot(n, c / s);
    }
    return 0.5 * L * std::abs(sum);
}

/// Form factor from a differential area to a parallel X x Y rectangle at distance h with one corner
/// straight above it (Howell, "A catalog of radiation heat transfer configuration factors", B-3):
///   F = 1/(2 pi) [x/sqrt(1+x^2) atan(y/sqrt(1+x^2)) + y/sqrt(1+y^2) atan(x/sqrt(1+y^2))], x = X/h, y = Y/h.
double cornerRectangleFormFactor(double X, double Y, double h) {
    const double x = X / h, y = Y / h;
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2 * kPiD);
}

/// An axis-aligned rectangle [x0, x1] x [z0, z1] of the plane y = const.
struct Rect {
    double x0, x1, z0, z1;
    std::optional<Rect> intersect(const Rect& o) const {
        const Rect r{std::max(x0, o.x0), std::min(x1, o.x1), std::max(z0, o.z0), std::min(z1, o.z1)};
        if (r.x0 >= r.x1 || r.z0 >= r.z1) return std::nullopt;
        return r;
    }
    std::vector<Vec3> polygon(double y) const { return {Vec3(x0, y, z0), Vec3(x1, y, z0), Vec3(x1, y, z1), Vec3(x0, y, z1)}; }
    bool contains(double x, double z) const { return x >= x0 && x <= x1 && z >= z0 && z <= z1; }
};

using test::addQuad;

/// A grey diffuse floor (y = 0) under a square emitter facing down (y = kLightY), optionally with a
/// black square occluder between them (y = kOccluderY); the camera, below the emitter, looks down at
/// the floor, so it sees the emitter's light only through the floor.
constexpr double kLightY = 1.0, kOccluderY = 0.5, kAlbedo = 0.5, kRadiance = 2.0, kFloor = 20.0;
const Rect kLight{-0.5, 0.5, -0.5, 0.5};
const Rect kOccluder{0.05, 0.55, -0.15, 0.35};

Scene lambertScene(bool occluded) {
    Scene s;
    PhongMaterial floor, light, black;
    floor.name = "floor", floor.rhoD = Color(kAlbedo);
    light.name = "light", light.rhoD = Color(0.0), light.emission = Color(kRadiance);
    black.name = "occluder", black.rhoD = Color(0.0);
    s.materials = {floor, light, black};
    addQuad(s, Vec3(-kFloor, 0, -kFloor), Vec3(-kFloor, 0, kFloor), Vec3(kFloor, 0, kFloor), Vec3(kFloor, 0, -kFloor), 0);  // normal +y
    const auto L = kLight.polygon(kLightY);
    addQuad(s, L[0], L[1], L[2], L[3], 1);  // (x0,z0) (x1,z0) (x1,z1) (x0,z1): normal -y, facing the floor
    if (occluded) {
        const auto O = kOccluder.polygon(kOccluderY);
        addQuad(s, O[0], O[1], O[2], O[3], 2);
    }
    s.camera.position = Vec3(0.1, 0.95, 1.0);
    s.camera.target = Vec3(0.1, 0, -0.2);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 50;
    return s;
}

/// Direct irradiance at floor point (x, 0, z): the emitter, less the part of it that the occluder hides.
/// Seen from p the occluder covers, on the emitter's plane, its own square scaled about p by
/// kLightY / kOccluderY (p is at height 0); irradiance is additive over the emitter's area, so the
/// hidden part's irradiance is subtracted (the clipping).
double floorIrradiance(double x, double z, bool occluded) {
    const Vec3 p(x, 0, z), n(0, 1, 0);
    double E = polygonIrradiance(kLight.polygon(kLightY), p, n, kRadiance);
    if (occluded) {
        const double k = kLightY / kOccluderY;
        const Rect shadow{x + (kOccluder.x0 - x) * k, x + (kOccluder.x1 - x) * k, z + (kOccluder.z0 - z) * k, z + (kOccluder.z1 - z) * k};
        if (const auto hidden = kLight.intersect(shadow)) E -= polygonIrradiance(hidden->polygon(kLightY), p, n, kRadiance);
    }
    return E;
}

/// The exact expected value of pixel (px, py): the floor's reflected radiance albedo/pi * E averaged over
/// the pixel's area (16 x 16 points), or nothing when some ray of the pixel would see the occluder or
/// miss the floor.
std::optional<double> exactPixel(const Scene& s, int width, int height, int px, int py, bool occluded) {
    constexpr int kSub = 16;
    double sum = 0;
    for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
            Vec3 o, d;
            cameraRay(s.camera, width, height, px + (i + 0.5) / kSub, py + (j + 0.5) / kSub, o, d);
            if (occluded) {
                const double t = (kOccluderY - o.y) / d.y;
                const Vec3 q = o + d * t;
                if (t > 0 && kOccluder.contains(q.x, q.z)) return std::nullopt;
            }
            const Vec3 q = o + d * (-o.y / d.y);
            if (d.y >= 0 || std::abs(q.x) > kFloor || std::abs(q.z) > kFloor) return std::nullopt;  // past the floor
            sum += kAlbedo / kPiD * floorIrradiance(q.x, q.z, occluded);
        }
    return sum / (kSub * kSub);
}

}  // namespace

// Lambert's polygon formula against the corner-rectangle form factor (E = pi L F), split into four
// corner rectangles for a point under a rectangle's interior, and against a point far away (E -> L A cos^2 / d^2).
TEST(LambertFormula, AgreesWithTheRectangleFormFactor) {
    const double L = 1.7, h = 0.8;
    const Rect r{-0.3, 0.9, -0.5, 0.2};
    const Vec3 p(0, 0, 0), n(0, 1, 0);
    const double table = kPiD * L *
                         (cornerRectangleFormFactor(0.3, 0.5, h) + cornerRectangleFormFactor(0.9, 0.5, h) +
                          cornerRectangleFormFactor(0.3, 0.2, h) + cornerRectangleFormFactor(0.9, 0.2, h));
    EXPECT_NEAR(polygonIrradiance(r.polygon(h), p, n, L), table, 1e-12 * table);
    // Far away and straight below, a small square is a point source: E = L A / d^2.
    const Rect tiny{-1e-3, 1e-3, -1e-3, 1e-3};
    EXPECT_NEAR(polygonIrradiance(tiny.polygon(50.0), p, n, L), L * 4e-6 / 2500.0, 1e-9 * L * 4e-6 / 2500.0);
    // The whole plane above: E = pi L.
    const Rect huge{-1e6, 1e6, -1e6, 1e6};
    EXPECT_NEAR(polygonIrradiance(huge.polygon(1.0), p, n, L), kPiD * L, 1e-5);
}

// --max-depth 1 renders of the floor under the emitter against Lambert's formula, in 6x6-pixel regions
// (those that see the occluder are left out): every estimator that samples directions, with and
// without light sampling, and the occluded scene, whose regions include the penumbra. Independent
// sampler: the pixels are independent, so a region's standard error comes from its pixels' variances.
TEST(LambertFormula, DirectLightOnAPlaneMatchesRegionByRegion) {
    constexpr int kSize = 48, kBlock = 6;
    for (bool occluded : {false, true}) {
        const Scene scene = lambertScene(occluded);
        const Accel accel(scene);
        std::vector<std::optional<double>> exact(kSize * kSize);
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                exact[static_cast<std::size_t>(y * kSize + x)] = exactPixel(scene, kSize, kSize, x, y, occluded);
        for (const char* estimator : {"cosine", "phong", "uniform"})
            for (bool nee : {true, false}) {
                // Sanitized (test::kSanitized): half the renders, each at its full spp, so that every
                // estimator runs with and without light sampling and on both scenes.
                if (test::kSanitized && (std::string(estimator) == "phong") == (nee == occluded)) continue;
                const auto est = makeEstimator(estimator);
                RenderSettings rs;
                rs.width = rs.height = kSize;
                rs.spp = nee ? 256 : 2048;
                rs.seed = 17;
                rs.sampler = "independent";
                rs.trace.maxDepth = 1;
                rs.trace.nextEvent = nee;
                const RenderResult r = render(scene, accel, *est, rs);
                int regions = 0, penumbra = 0;
                double worstRelError = 0;
                for (int by = 0; by < kSize; by += kBlock)
                    for (int bx = 0; bx < kSize; bx += kBlock) {
                        double sum = 0, want = 0, var = 0;
                        bool usable = true;
                        for (int y = by; y < by + kBlock && usable; ++y)
                            for (int x = bx; x < bx + kBlock; ++x) {
                                const auto& e = exact[static_cast<std::size_t>(y * kSize + x)];
                                if (!e) {
                                    usable = false;
                                    break;
                                }
                                want += *e;
                                sum += r.image.at(x, y).x;  // grey scene: every channel alike
                                var += r.variance.at(x, y).x;
                            }
                        const double n = kBlock * kBlock, mean = sum / n, expected = want / n, se = std::sqrt(var) / n;
                        // The lit part of the floor: far away it receives almost nothing, and its relative
                        // noise says little.
                        if (!usable || expected < 0.1 * kAlbedo / kPiD * floorIrradiance(0, 0, false)) continue;
                        ++regions;
                        if (occluded) {
                            // A region in the penumbra: its closed form differs from the unoccluded one.
                            const double centreX = bx + kBlock / 2.0, centreY = by + kBlock / 2.0;
                            Vec3 o, d;
                            cameraRay(scene.camera, kSize, kSize, centreX, centreY, o, d);
                            const Vec3 q = o + d * (-o.y / d.y);
                            const double open = floorIrradiance(q.x, q.z, false), lit = floorIrradiance(q.x, q.z, true);
                            if (lit > 0.05 * open && lit < 0.95 * open) ++penumbra;
                        }
                        ASSERT_GT(expected, 0);
                        EXPECT_LT(se, 0.05 * expected) << "the test must be able to see a few-percent error";
                        EXPECT_LT(std::abs(mean - expected), 4 * se)
                            << estimator << (nee ? " with" : " without") << " light sampling" << (occluded ? ", occluded" : "")
                            << ": region at (" << bx << ", " << by << ") renders " << mean << " +- " << se << ", Lambert's formula gives "
                            << expected;
                        worstRelError = std::max(worstRelError, std::abs(mean - expected) / expected);
                    }
                EXPECT_GE(regions, occluded ? 25 : 35) << "most of the image is lit floor";
                if (occluded) {
                    EXPECT_GE(penumbra, 3) << "some regions must be in the penumbra, where the clipping matters";
                }
                RecordProperty(std::string(estimator) + (nee ? "_nee" : "_bsdf") + (occluded ? "_occluded" : ""),
                               std::to_string(worstRelError));
            }
    }
}

// Light arriving at grazing angles: a wall under the edge of a ceiling-like emitter (the upper back wall
// of a Cornell box, where Blender Cycles 3.4 renders up to 2% too dark: docs/validation.md). The wall
// z = -1 faces +z; the emitter, 0.1 below the wall's top, faces down and reaches to 0.2 in front of the
// wall, so the wall's upper rows see it edge-on. Regions of 4x4 pixels within 4 standard errors.
TEST(LambertFormula, GrazingLightOnAWallUnderTheEmitter) {
    constexpr int kSize = 40, kBlock = 4, kSub = 16;
    constexpr double kWallZ = -1.0, kTop = 2.0, kEmitterY = 1.9;
    const Rect emitter{-0.5, 0.5, -0.8, 0.2};
    Scene s;
    PhongMaterial wall, light;
    wall.name = "wall", wall.rhoD = Color(kAlbedo);
    light.name = "light", light.rhoD = Color(0.0), light.emission = Color(kRadiance);
    s.materials = {wall, light};
    addQuad(s, Vec3(-2, 0, kWallZ), Vec3(2, 0, kWallZ), Vec3(2, kTop, kWallZ), Vec3(-2, kTop, kWallZ), 0);  // normal +z
    const auto L = emitter.polygon(kEmitterY);
    addQuad(s, L[0], L[1], L[2], L[3], 1);  // normal -y
    // Just under the emitter's plane, close in on the wall's top: it sees the wall up to that plane.
    s.camera.position = Vec3(0, 1.85, 1.5);
    s.camera.target = Vec3(0, 1.8, kWallZ);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 8;
    const Accel accel(s);
    // The exact radiance of each pixel (nothing where a ray of the pixel sees the emitter or misses the wall).
    std::vector<std::optional<double>> exact(kSize * kSize);
    double brightest = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            double sum = 0;
            bool usable = true;
            for (int j = 0; j < kSub && usable; ++j)
                for (int i = 0; i < kSub && usable; ++i) {
                    Vec3 o, d;
                    cameraRay(s.camera, kSize, kSize, x + (i + 0.5) / kSub, y + (j + 0.5) / kSub, o, d);
                    const double te = (kEmitterY - o.y) / d.y;
                    const Vec3 e = o + d * te;
                    if (te > 0 && emitter.contains(e.x, e.z)) usable = false;
                    const Vec3 q = o + d * ((kWallZ - o.z) / d.z);
                    if (std::abs(q.x) > 2 || q.y < 0 || q.y > kTop) usable = false;
                    // Above the emitter's plane the wall sees only its back: no light.
                    if (usable && q.y < kEmitterY) sum += kAlbedo / kPiD * polygonIrradiance(L, q, Vec3(0, 0, 1), kRadiance);
                }
            if (!usable) continue;
            exact[static_cast<std::size_t>(y * kSize + x)] = sum / (kSub * kSub);
            brightest = std::max(brightest, sum / (kSub * kSub));
        }
    for (const auto& [estimator, nee] : {std::pair{"cosine", true}, std::pair{"phong", true}, std::pair{"cosine", false}}) {
        // Sanitized (test::kSanitized): the two renders with light sampling, each at its full spp; the
        // one without (two thirds of the cost, at 16384 spp) is left to the release build, and paths
        // without light sampling run sanitized in DirectLightOnAPlaneMatchesRegionByRegion.
        if (test::kSanitized && !nee) continue;
        const auto est = makeEstimator(estimator);
        RenderSettings rs;
        rs.width = rs.height = kSize;
        rs.spp = nee ? 4096 : 16384;  // enough for a 1% error in the grazing rows to stand out
        rs.seed = 23;
        rs.sampler = "independent";
        rs.trace.maxDepth = 1;
        rs.trace.nextEvent = nee;
        const RenderResult r = render(s, accel, *est, rs);
        int regions = 0, grazing = 0;
        std::array<double, kSize / kBlock> rowSum{}, rowWant{}, rowVar{};
        for (int by = 0; by < kSize; by += kBlock)
            for (int bx = 0; bx < kSize; bx += kBlock) {
                double sum = 0, want = 0, var = 0;
                bool usable = true;
                for (int y = by; y < by + kBlock; ++y)
                    for (int x = bx; x < bx + kBlock; ++x) {
                        const auto& e = exact[static_cast<std::size_t>(y * kSize + x)];
                        usable = usable && e.has_value();
                        if (!e) continue;
                        want += *e, sum += r.image.at(x, y).x, var += r.variance.at(x, y).x;
                    }
                const double n = kBlock * kBlock, mean = sum / n, expected = want / n, se = std::sqrt(var) / n;
                if (!usable || expected < 0.05 * brightest) continue;
                ++regions;
                // The rows where the emitter is seen nearly edge-on: the wall within 0.15 below its plane.
                Vec3 o, d;
                cameraRay(s.camera, kSize, kSize, bx + kBlock / 2.0, by + kBlock / 2.0, o, d);
                grazing += (o + d * ((kWallZ - o.z) / d.z)).y > kEmitterY - 0.15;
                rowSum[by / kBlock] += sum, rowWant[by / kBlock] += want, rowVar[by / kBlock] += var;
                EXPECT_LT(se, 0.01 * expected);
                EXPECT_LT(std::abs(mean - expected), 4 * se)
                    << estimator << (nee ? " with" : " without") << " light sampling: region at (" << bx << ", " << by << ") renders "
                    << mean << " +- " << se << ", Lambert's formula gives " << expected;
            }
        // Each row of regions as a whole (its standard error a third of a region's): a 1% error
        // confined to the rows lit at grazing angles fails here (checked by mutation).
        for (std::size_t row = 0; row < rowSum.size(); ++row) {
            if (rowWant[row] <= 0) continue;
            EXPECT_LT(std::abs(rowSum[row] - rowWant[row]), 4 * std::sqrt(rowVar[row]))
                << estimator << (nee ? " with" : " without") << " light sampling: row of regions " << row << " renders " << rowSum[row]
                << " +- " << std::sqrt(rowVar[row]) << " in all, Lambert's formula gives " << rowWant[row];
        }
        EXPECT_GE(regions, 30);
        EXPECT_GE(grazing, 10) << "the test must cover the rows lit at grazing angles";
    }
}
