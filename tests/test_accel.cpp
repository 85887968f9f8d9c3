// accel/: the bundle query (16-wide packets) and the query of rays of their own origins (intersectEach)
// answer as the single-ray query does, ray by ray, at every bundle size around the packet width, for rays
// that hit and rays that leave the scene.
#include "accel/accel.h"
#include "sampling/rng.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace symphong {
namespace {

/// A point inside the box [lo, hi].
Vec3 pointInside(Rng& rng, const Vec3& lo, const Vec3& hi) {
    return {lo.x + (hi.x - lo.x) * rng.uniform(), lo.y + (hi.y - lo.y) * rng.uniform(), lo.z + (hi.z - lo.z) * rng.uniform()};
}

/// A unit direction uniform on the sphere.
Vec3 directionOnSphere(Rng& rng) {
    const double z = 1 - 2 * rng.uniform(), phi = kTwoPi * rng.uniform(), r = std::sqrt(1 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
}

void expectBundleMatchesSingleRays(const Scene& scene, std::uint64_t seed, bool coherent) {
    const Accel accel(scene);
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    Rng rng(seed, 3);
    std::size_t hitsSeen = 0, missesSeen = 0;
    for (std::size_t n : {1u, 2u, 15u, 16u, 17u, 24u, 32u, 33u, 40u}) {
        for (int trial = 0; trial < 20; ++trial) {
            // An origin inside the bounds, directions over the whole sphere (some leave the scene).
            const Vec3 o = pointInside(rng, lo, hi);
            std::vector<Vec3> dirs(n);
            for (Vec3& d : dirs) d = directionOnSphere(rng) * (0.5 + rng.uniform());  // lengths 0.5 to 1.5: need not be unit
            std::vector<Hit> hits(n);
            auto found = std::make_unique<bool[]>(n);
            accel.intersectBundle(o, dirs.data(), n, 1e-4, hits.data(), found.get(), coherent);
            for (std::size_t i = 0; i < n; ++i) {
                Hit single;
                const bool f = accel.intersect(o, dirs[i], 1e-4, std::numeric_limits<double>::infinity(), single);
                ASSERT_EQ(found[i], f) << "n = " << n << ", ray " << i;
                if (!f) {
                    ++missesSeen;
                    continue;
                }
                ++hitsSeen;
                EXPECT_EQ(hits[i].prim, single.prim) << "n = " << n << ", ray " << i;
                EXPECT_NEAR(hits[i].t, single.t, 1e-5 * single.t) << "n = " << n << ", ray " << i;
                EXPECT_NEAR(hits[i].u, single.u, 1e-5);
                EXPECT_NEAR(hits[i].v, single.v, 1e-5);
            }
        }
    }
    // The comparison covered both answers.
    EXPECT_GT(hitsSeen, 100u);
    EXPECT_GT(missesSeen, 100u);
}

TEST(Accel, BundleMatchesSingleRaysInTheCornellBox) {
    Scene s = makeCornellBox();
    finalizeScene(s, "cornell", false);
    expectBundleMatchesSingleRays(s, 1, false);
    expectBundleMatchesSingleRays(s, 1, true);  // the flag of camera packets: a hint, the same answers
}

TEST(Accel, BundleMatchesSingleRaysOnTheBunny) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene bunny = loadScene(test::scenesDir() + "/bunny/stanford-bunny.obj");
    expectBundleMatchesSingleRays(bunny, 2, false);
    expectBundleMatchesSingleRays(bunny, 2, true);
}

// intersectEach traces rays of their own origins one by one with its own copy of intersect()'s query: the same
// answers bit for bit, rays that hit and rays that leave the box alike.
TEST(Accel, EachRayOfItsOwnOriginAnswersAsIntersectDoes) {
    Scene s = makeCornellBox();
    finalizeScene(s, "cornell", false);
    const Accel accel(s);
    Vec3 lo, hi;
    s.bounds(lo, hi);
    Rng rng(4, 3);
    const std::size_t n = 200;
    std::vector<Vec3> origins(n), dirs(n);
    for (std::size_t i = 0; i < n; ++i) {
        origins[i] = pointInside(rng, lo, hi);
        dirs[i] = directionOnSphere(rng);
    }
    std::vector<Hit> hits(n);
    auto found = std::make_unique<bool[]>(n);
    accel.intersectEach(origins.data(), dirs.data(), n, 1e-4, hits.data(), found.get());
    std::size_t hitsSeen = 0;
    for (std::size_t i = 0; i < n; ++i) {
        Hit single;
        const bool f = accel.intersect(origins[i], dirs[i], 1e-4, std::numeric_limits<double>::infinity(), single);
        ASSERT_EQ(found[i], f) << "ray " << i;
        if (!f) continue;
        ++hitsSeen;
        EXPECT_EQ(hits[i].prim, single.prim) << "ray " << i;
        EXPECT_EQ(hits[i].t, single.t) << "ray " << i;
        EXPECT_EQ(hits[i].u, single.u) << "ray " << i;
        EXPECT_EQ(hits[i].v, single.v) << "ray " << i;
    }
    EXPECT_GT(hitsSeen, n / 2);  // the open box: most rays from inside hit a wall
    EXPECT_LT(hitsSeen, n) << "and some leave it";
}

}  // namespace
}  // namespace symphong
