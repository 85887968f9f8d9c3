// accel/: the bundle query (16-wide packets) and the queries of rays of their own origins (intersectEach,
// occludedEach) answer as the single-ray queries do, ray by ray, at every bundle size around the packet width, for rays
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

// intersectEach and occludedEach take rays of their own origins: one by one (an Accel without packets, or a
// batch of at most kSingleRaysUpTo) with their own copy of the single-ray query, the same answers bit for bit;
// as 16-wide packets otherwise, the same answers to float round-off. Rays that hit (or are blocked) and rays
// that leave the box (or are clear) alike, at batch sizes around the packet width.
void expectEachMatchesSingleRays(bool packets) {
    Scene s = makeCornellBox();
    finalizeScene(s, "cornell", false);
    const Accel accel(s, packets);
    Vec3 lo, hi;
    s.bounds(lo, hi);
    Rng rng(4, 3);
    std::size_t hitsSeen = 0, raysSeen = 0, blockedSeen = 0, clearSeen = 0;
    for (std::size_t n : {1u, 4u, 5u, 15u, 16u, 17u, 40u, 200u}) {
        std::vector<Vec3> origins(n), dirs(n);
        std::vector<ShadowRay> shadows(n);
        for (std::size_t i = 0; i < n; ++i) {
            origins[i] = pointInside(rng, lo, hi);
            dirs[i] = directionOnSphere(rng);
            // A segment to another point inside, or a ray to infinity.
            shadows[i].o = origins[i];
            if (i % 3 == 0) {
                shadows[i].d = dirs[i];
                shadows[i].tfar = std::numeric_limits<double>::infinity();
            } else {
                shadows[i].d = pointInside(rng, lo, hi) - origins[i];
                shadows[i].tfar = 1.0 - 1e-5;
            }
        }
        const bool exact = !packets || n <= Accel::kSingleRaysUpTo;
        std::vector<Hit> hits(n);
        auto found = std::make_unique<bool[]>(n);
        auto blocked = std::make_unique<bool[]>(n);
        accel.intersectEach(origins.data(), dirs.data(), n, 1e-4, hits.data(), found.get());
        accel.occludedEach(shadows.data(), n, blocked.get());
        for (std::size_t i = 0; i < n; ++i) {
            ++raysSeen;
            ASSERT_EQ(blocked[i], accel.occluded(shadows[i].o, shadows[i].d, 0.0, shadows[i].tfar)) << "n = " << n << ", shadow ray " << i;
            ++(blocked[i] ? blockedSeen : clearSeen);
            Hit single;
            const bool f = accel.intersect(origins[i], dirs[i], 1e-4, std::numeric_limits<double>::infinity(), single);
            ASSERT_EQ(found[i], f) << "n = " << n << ", ray " << i;
            if (!f) continue;
            ++hitsSeen;
            EXPECT_EQ(hits[i].prim, single.prim) << "n = " << n << ", ray " << i;
            if (exact) {
                EXPECT_EQ(hits[i].t, single.t) << "n = " << n << ", ray " << i;
                EXPECT_EQ(hits[i].u, single.u) << "n = " << n << ", ray " << i;
                EXPECT_EQ(hits[i].v, single.v) << "n = " << n << ", ray " << i;
            } else {
                EXPECT_NEAR(hits[i].t, single.t, 1e-5 * single.t) << "n = " << n << ", ray " << i;
                EXPECT_NEAR(hits[i].u, single.u, 1e-5);
                EXPECT_NEAR(hits[i].v, single.v, 1e-5);
            }
        }
    }
    EXPECT_GT(hitsSeen, raysSeen / 2);  // the open box: most rays from inside hit a wall
    EXPECT_LT(hitsSeen, raysSeen) << "and some leave it";
    EXPECT_GT(blockedSeen, raysSeen / 20) << "the blocks and walls stop some shadow rays";
    EXPECT_GT(clearSeen, raysSeen / 5);
}

TEST(Accel, EachRayOfItsOwnOriginAnswersAsTheSingleRayQueriesDo) {
    expectEachMatchesSingleRays(false);
    expectEachMatchesSingleRays(true);
}

}  // namespace
}  // namespace symphong
