// tests/floor_closed_form.h — a diffuse floor seen from above at an angle, rendered at --max-depth 1 and
// compared region by region with a closed form of its radiance (test_lights, test_normal_maps).
#pragma once

#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>

namespace symphong::test {

/// A grey diffuse floor (y = 0, +-half in x and z, material 0, albedo `albedo`, facing +y) seen from
/// above at an angle, and a black material 1 for occluders; the scene's lights are added by the test.
inline Scene floorScene(double albedo, double half) {
    Scene s;
    PhongMaterial floor, black;
    floor.name = "floor", floor.rhoD = Color(albedo);
    black.name = "black", black.rhoD = Color(0.0);
    s.materials = {floor, black};
    addQuad(s, Vec3(-half, 0, -half), Vec3(-half, 0, half), Vec3(half, 0, half), Vec3(half, 0, -half), 0);
    s.camera.position = Vec3(0.2, 1.6, 2.0);
    s.camera.target = Vec3(0, 0, -0.2);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 55;
    return s;
}

/// Renders `scene` at depth 1 (with and without NEE) and compares 6x6-pixel regions with `exact` (the
/// floor's radiance at a floor point y = 0 within +-half; nullopt where the pixel must be left out),
/// averaged over each pixel's area, within 4 standard errors (and at least 0.1% of the value).
inline void expectFloorMatchesClosedForm(const Scene& scene, double half, const std::function<std::optional<double>(const Vec3& floorPoint, const Vec3& ray)>& exact,
                             const std::string& what, int minRegions) {
    constexpr int kSize = 48, kBlock = 6, kSub = 8;
    std::vector<std::optional<double>> want(kSize * kSize);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            double sum = 0;
            bool usable = true;
            for (int j = 0; j < kSub && usable; ++j)
                for (int i = 0; i < kSub; ++i) {
                    Vec3 o, d;
                    cameraRay(scene.camera, kSize, kSize, x + (i + 0.5) / kSub, y + (j + 0.5) / kSub, o, d);
                    const Vec3 q = o + d * (-o.y / d.y);
                    const auto v = d.y < 0 && std::abs(q.x) < half && std::abs(q.z) < half ? exact(q, d) : std::nullopt;
                    if (!v) {
                        usable = false;
                        break;
                    }
                    sum += *v;
                }
            if (usable) want[static_cast<std::size_t>(y * kSize + x)] = sum / (kSub * kSub);
        }
    const Accel accel(scene);
    for (bool nee : {true, false}) {
        const auto est = makeEstimator("cosine");
        RenderSettings rs;
        rs.width = rs.height = kSize;
        rs.spp = 64;
        rs.seed = 5;
        rs.sampler = "independent";
        rs.trace.maxDepth = 1;
        rs.trace.nextEvent = nee;
        const RenderResult r = render(scene, accel, *est, rs);
        int regions = 0;
        for (int by = 0; by < kSize; by += kBlock)
            for (int bx = 0; bx < kSize; bx += kBlock) {
                double sum = 0, expected = 0, var = 0;
                bool usable = true;
                for (int y = by; y < by + kBlock; ++y)
                    for (int x = bx; x < bx + kBlock; ++x) {
                        const auto& w = want[static_cast<std::size_t>(y * kSize + x)];
                        usable = usable && w.has_value();
                        if (!w) continue;
                        expected += *w;
                        sum += r.image.at(x, y).x;
                        var += r.variance.at(x, y).x;
                    }
                if (!usable) continue;
                const double n = kBlock * kBlock;
                const double mean = sum / n, exp = expected / n, se = std::sqrt(var) / n;
                ++regions;
                // Within the pixel-position noise, and at least as close as 0.1% of the value (a region
                // where the closed form is smooth has almost no noise: one sample per light per pixel).
                EXPECT_LE(std::abs(mean - exp), std::max(4 * se, 1e-3 * exp))
                    << what << (nee ? "" : " (--no-nee)") << ": region at (" << bx << ", " << by << ") renders " << mean << " +- " << se
                    << ", closed form " << exp;
            }
        EXPECT_GE(regions, minRegions) << what;
    }
}

}  // namespace symphong::test
