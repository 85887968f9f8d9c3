// accel/ — ray queries. Owns the Intel Embree 3 device and scene built from a Scene's triangles, and
// answers closest-hit and any-hit (shadow) queries for single rays, and for batches of them as 16-wide
// packets: closest hits of bundles of rays from one origin (a set estimator's directions, a tile's camera
// rays), and closest hits and shadow queries of rays that do not share one (a wavefront's depth). Geometry
// crosses into float here; everything above it stays in double. On request it records every query as
// Embree was given it (RayQuery), so that bench/ can trace a render's own rays again with Embree alone.
#pragma once

#include "math/vec3.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace symphong {

struct Hit {
    double t = 0;
    std::uint32_t prim = 0;  ///< triangle index in Scene::triangles
    double u = 0, v = 0;     ///< barycentrics of vertices 1 and 2
};

/// One query as it reached Embree (float, as the ray structures hold it): a closest-hit ray, or a shadow
/// (any-hit) ray. A bundle's rays are recorded one by one, as closest-hit rays.
struct RayQuery {
    float org[3], dir[3];
    float tnear, tfar;
    bool shadow;
};

/// A shadow (any-hit) query: o + t d for t in (0, tfar).
struct ShadowRay {
    Vec3 o, d;
    double tfar = 0;
};

class Accel {
public:
    /// Builds the BVH of the scene's triangles. A scene with cut-out materials keeps a pointer to
    /// `scene` (its filter reads the alpha textures during queries), so it must outlive the Accel.
    /// `packets`: batches of rays (bundles, intersectEach, occludedEach) go to Embree as 16-wide packets where
    /// the device supports them; false: one by one, so that every query answers exactly as intersect() and
    /// occluded() do (a packet's kernels can differ from them in float round-off: a grazing ray's answer).
    explicit Accel(const Scene& scene, bool packets = true);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    /// Closest hit along o + t d, t in (tnear, tfar). d need not be unit length.
    bool intersect(const Vec3& o, const Vec3& d, double tnear, double tfar, Hit& hit) const;
    /// Closest hits of n rays o[i] + t d[i], t in (tnear, inf), that do not share an origin (a wavefront's bounce
    /// rays): found[i] whether ray i hit, hits[i] its hit. As 16-wide packets (rtcIntersect16) where the device
    /// supports them and n > kSingleRaysUpTo (the answers of intersect() to float round-off), else one by one
    /// with its own copy of intersect()'s query (bit for bit; its own copy so that the path tracer's single
    /// call of intersect() stays inlined there).
    void intersectEach(const Vec3* o, const Vec3* d, std::size_t n, double tnear, Hit* hits, bool* found) const;
    /// Closest hits of n rays o + t dirs[i], t in (tnear, inf), sharing the origin o: traced as 16-wide
    /// Embree packets (rtcIntersect16) where the device supports them, else one by one. found[i] says
    /// whether ray i hit; hits[i] is its hit. The same answers as intersect() ray by ray, to float
    /// round-off of the packet kernels. `coherent`: the rays point nearly the same way (neighbouring camera
    /// rays), which Embree's packet traversal can exploit (RTC_INTERSECT_CONTEXT_FLAG_COHERENT).
    void intersectBundle(const Vec3& o, const Vec3* dirs, std::size_t n, double tnear, Hit* hits, bool* found, bool coherent = false) const;
    /// Bundles of at most this many rays go ray by ray (rtcIntersect1): a packet costs about what a full one
    /// does however few of its lanes are active. Larger ones go as 16-wide packets.
    static constexpr std::size_t kSingleRaysUpTo = 4;
    /// Whether anything blocks o + t d for t in (tnear, tfar).
    bool occluded(const Vec3& o, const Vec3& d, double tnear, double tfar) const;
    /// occluded() of n shadow rays that do not share an origin (a wavefront's light samples of one depth),
    /// t in (0, tfar): blocked[i] whether ray i is blocked. As 16-wide packets (rtcOccluded16) where the device
    /// supports them and n > kSingleRaysUpTo, else one by one. A packet can answer a rare ray according to the
    /// other rays in it (as intersectEach's can): callers that promise the same image in any passes give it
    /// the same rays together whatever the passes (the renderer's batches: render/renderer.cpp).
    void occludedEach(const ShadowRay* rays, std::size_t n, bool* blocked) const;

    RTCSceneTy* handle() const { return scene_; }

    /// Appends every later query to `log` (nullptr: stops). Not synchronised: record a render with one
    /// thread. For bench/'s replay; a render that records nothing pays one untaken branch per query.
    void record(std::vector<RayQuery>* log) { log_ = log; }

private:
    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* scene_ = nullptr;
    bool packets_ = false;  ///< the device has native or emulated 16-wide packets
    std::vector<RayQuery>* log_ = nullptr;
};

/// The version of Embree this program was built with.
std::string embreeVersion();

}  // namespace symphong
