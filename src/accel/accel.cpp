#include "accel/accel.h"

#include "scene/surface.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace symphong {

namespace {

void onEmbreeError(void*, RTCError code, const char* message) {
    // Embree calls this on its own threads; we cannot throw through it, so report and abort the query.
    fmt::print(stderr, "symphong: Embree error {}: {}\n", static_cast<int>(code), message ? message : "");
}

/// Embree filter for cut-out materials (intersection and occlusion alike): a candidate hit where the
/// material's alpha texture reads below 1/2 is rejected, so the ray goes on through the hole.
void cutOutFilter(const RTCFilterFunctionNArguments* args) {
    const auto& scene = *static_cast<const Scene*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const Triangle& tri = scene.triangles[prim];
        const PhongMaterial& m = scene.materials[tri.material];
        if (!m.textures.alpha.present()) continue;
        const TexCoord uv = texcoordAt(scene, tri, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
        if (cutOutAt(scene, m, uv)) args->valid[i] = 0;
    }
}

}  // namespace

Accel::Accel(const Scene& scene, bool packets) {
    device_ = rtcNewDevice(nullptr);
    if (!device_)
        throw std::runtime_error(fmt::format("cannot create the Embree device (error {})", static_cast<int>(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(device_, onEmbreeError, nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_NONE);
    // Embree's default (medium) build: the high one (spatial splits) traced no faster on the boxes, the textured
    // scene or a 2M-triangle sphere (bench_limit's Embree-alone rays/s), and built a 1M-triangle mesh 4% slower.
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);

    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* verts = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.positions.size()));
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) verts[3 * i + c] = static_cast<float>(scene.positions[i][c]);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), scene.triangles.size()));
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
        for (int c = 0; c < 3; ++c) idx[3 * i + c] = scene.triangles[i].v[c];
    if (scene.hasCutOuts()) {
        rtcSetGeometryUserData(geom, const_cast<Scene*>(&scene));
        rtcSetGeometryIntersectFilterFunction(geom, cutOutFilter);
        rtcSetGeometryOccludedFilterFunction(geom, cutOutFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree failed to build the scene");
    packets_ = packets && (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0 ||
                           rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED) != 0);
}

Accel::~Accel() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

namespace {

[[gnu::always_inline]] inline bool closestHit(RTCScene scene, std::vector<RayQuery>* log, const Vec3& o, const Vec3& d, double tnear,
                                              double tfar, Hit& hit) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(o.x);
    rh.ray.org_y = static_cast<float>(o.y);
    rh.ray.org_z = static_cast<float>(o.z);
    rh.ray.dir_x = static_cast<float>(d.x);
    rh.ray.dir_y = static_cast<float>(d.y);
    rh.ray.dir_z = static_cast<float>(d.z);
    rh.ray.tnear = static_cast<float>(tnear);
    rh.ray.tfar = tfar == std::numeric_limits<double>::infinity() ? std::numeric_limits<float>::infinity() : static_cast<float>(tfar);
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    if (log) [[unlikely]]
        log->push_back(
            {{rh.ray.org_x, rh.ray.org_y, rh.ray.org_z}, {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z}, rh.ray.tnear, rh.ray.tfar, false});
    rtcIntersect1(scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.prim = rh.hit.primID;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    return true;
}

}  // namespace

bool Accel::intersect(const Vec3& o, const Vec3& d, double tnear, double tfar, Hit& hit) const {
    return closestHit(scene_, log_, o, d, tnear, tfar, hit);
}

namespace {

/// Lane k of a 16-wide packet: o + t d, t in (tnear, tfar), in float as Embree takes it.
void setLane(RTCRay16& ray, std::size_t k, const Vec3& o, const Vec3& d, double tnear, float tfar) {
    ray.org_x[k] = static_cast<float>(o.x);
    ray.org_y[k] = static_cast<float>(o.y);
    ray.org_z[k] = static_cast<float>(o.z);
    ray.dir_x[k] = static_cast<float>(d.x);
    ray.dir_y[k] = static_cast<float>(d.y);
    ray.dir_z[k] = static_cast<float>(d.z);
    ray.tnear[k] = static_cast<float>(tnear);
    ray.tfar[k] = tfar;
    ray.time[k] = 0;
    ray.mask[k] = 0xFFFFFFFFu;
    ray.id[k] = static_cast<unsigned>(k);
    ray.flags[k] = 0;
}

/// Records a packet's first `count` lanes as Embree got them (Accel::record).
void logPacket(std::vector<RayQuery>& log, const RTCRay16& ray, std::size_t count, bool shadow) {
    for (std::size_t k = 0; k < count; ++k)
        log.push_back(
            {{ray.org_x[k], ray.org_y[k], ray.org_z[k]}, {ray.dir_x[k], ray.dir_y[k], ray.dir_z[k]}, ray.tnear[k], ray.tfar[k], shadow});
}

/// Closest hits of `count` <= 16 rays as one 16-wide packet (rtcIntersect16): ray k from origin(k) along
/// direction(k), t in (tnear, inf); inactive lanes repeat the last valid ray.
template <class Origin, class Direction>
void closestHits16(RTCScene scene, std::vector<RayQuery>* log, std::size_t count, const Origin& origin, const Direction& direction,
                   double tnear, bool coherent, Hit* hits, bool* found) {
    alignas(64) int valid[16];
    alignas(64) RTCRayHit16 rh;
    for (std::size_t k = 0; k < 16; ++k) {
        valid[k] = k < count ? -1 : 0;
        const std::size_t i = std::min(k, count - 1);
        setLane(rh.ray, k, origin(i), direction(i), tnear, std::numeric_limits<float>::infinity());
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    if (log) [[unlikely]]
        logPacket(*log, rh.ray, count, false);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect16(valid, scene, &ctx, &rh);
    for (std::size_t k = 0; k < count; ++k) {
        found[k] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        if (!found[k]) continue;
        hits[k].t = rh.ray.tfar[k];
        hits[k].prim = rh.hit.primID[k];
        hits[k].u = rh.hit.u[k];
        hits[k].v = rh.hit.v[k];
    }
}

}  // namespace

void Accel::intersectEach(const Vec3* o, const Vec3* d, std::size_t n, double tnear, Hit* hits, bool* found) const {
    if (!packets_ || n <= kSingleRaysUpTo) {
        for (std::size_t i = 0; i < n; ++i)
            found[i] = closestHit(scene_, log_, o[i], d[i], tnear, std::numeric_limits<double>::infinity(), hits[i]);
        return;
    }
    for (std::size_t first = 0; first < n; first += 16)
        closestHits16(
            scene_, log_, std::min<std::size_t>(16, n - first), [&](std::size_t k) -> const Vec3& { return o[first + k]; },
            [&](std::size_t k) -> const Vec3& { return d[first + k]; }, tnear, false, hits + first, found + first);
}

void Accel::intersectBundle(const Vec3& o, const Vec3* dirs, std::size_t n, double tnear, Hit* hits, bool* found, bool coherent) const {
    // A packet costs about what a full one does however few of its lanes are active: a small bundle (the
    // two rays of --split 2) goes ray by ray (bench_limit --split 2; docs/performance.md, "The limit").
    if (!packets_ || n <= kSingleRaysUpTo) {
        for (std::size_t i = 0; i < n; ++i) found[i] = intersect(o, dirs[i], tnear, std::numeric_limits<double>::infinity(), hits[i]);
        return;
    }
    for (std::size_t first = 0; first < n; first += 16)
        closestHits16(
            scene_, log_, std::min<std::size_t>(16, n - first), [&](std::size_t) -> const Vec3& { return o; },
            [&](std::size_t k) -> const Vec3& { return dirs[first + k]; }, tnear, coherent, hits + first, found + first);
}

bool Accel::occluded(const Vec3& o, const Vec3& d, double tnear, double tfar) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray;
    ray.org_x = static_cast<float>(o.x);
    ray.org_y = static_cast<float>(o.y);
    ray.org_z = static_cast<float>(o.z);
    ray.dir_x = static_cast<float>(d.x);
    ray.dir_y = static_cast<float>(d.y);
    ray.dir_z = static_cast<float>(d.z);
    ray.tnear = static_cast<float>(tnear);
    ray.tfar = static_cast<float>(tfar);
    ray.time = 0;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    if (log_) [[unlikely]]
        log_->push_back({{ray.org_x, ray.org_y, ray.org_z}, {ray.dir_x, ray.dir_y, ray.dir_z}, ray.tnear, ray.tfar, true});
    rtcOccluded1(scene_, &ctx, &ray);
    return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

// Embree's occlusion packets (rtcOccluded16) answer a rare shadow ray according to the other rays of its packet
// (its traversal goes ray by ray once few of them are active): the renderer keeps its images independent of
// their passes by batching the same camera samples together in any pass (render/renderer.cpp, CameraPackets).
void Accel::occludedEach(const ShadowRay* rays, std::size_t n, bool* blocked) const {
    if (!packets_ || n <= kSingleRaysUpTo) {
        for (std::size_t i = 0; i < n; ++i) blocked[i] = occluded(rays[i].o, rays[i].d, 0.0, rays[i].tfar);
        return;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t first = 0; first < n; first += 16) {
        const std::size_t count = std::min<std::size_t>(16, n - first);
        alignas(64) int valid[16];
        alignas(64) RTCRay16 ray;
        for (std::size_t k = 0; k < 16; ++k) {
            valid[k] = k < count ? -1 : 0;
            const ShadowRay& r = rays[first + std::min(k, count - 1)];  // inactive lanes repeat a valid ray
            setLane(ray, k, r.o, r.d, 0.0, static_cast<float>(r.tfar));
        }
        if (log_) [[unlikely]]
            logPacket(*log_, ray, count, true);
        rtcOccluded16(valid, scene_, &ctx, &ray);
        for (std::size_t k = 0; k < count; ++k) blocked[first + k] = ray.tfar[k] < 0;  // Embree sets tfar to -inf on a hit
    }
}

std::string embreeVersion() { return RTC_VERSION_STRING; }

}  // namespace symphong
