// render/next_event.h — next-event estimation's light sample before its shadow ray (PathTracer::lightSample) and
// its term once the ray is clear (PathTracer::litBy), defined here for the two tracers that call them, each
// inlined where it is called: the recursive tracer's directLight traces the shadow ray between them
// (path_tracer.cpp), the wavefront traces a depth's shadow rays together (wavefront.cpp). Inline, not a call:
// a call between directLight's halves cost the recursive tracer 0.9% more instructions.
#pragma once

#include "render/path_tracer.h"
#include "scene/shading_normal.h"

#include <limits>

namespace symphong {

[[gnu::always_inline]] inline bool PathTracer::lightSample(const Vec3& p, const Vec3& ng, const Frame& frame, const ShadingContext& sc,
                                                           Point2 u, bool shadowed, ShadowRay& ray, LightSample& ls) const {
    EmitterSample s;
    const bool sampled = emitters_.sample(p, u, s);
    return lightSampleOf(sampled, s, p, ng, frame, sc, shadowed, ray, ls);
}

[[gnu::always_inline]] inline bool PathTracer::lightSampleOf(bool sampled, const EmitterSample& s, const Vec3& p, const Vec3& ng,
                                                             const Frame& frame, const ShadingContext& sc, bool shadowed, ShadowRay& ray,
                                                             LightSample& ls) const {
    if (!sampled || dot(s.wi, ng) <= 0) return false;
    const Vec3 wiLocal = frame.toLocal(s.wi);
    if (wiLocal.z <= 0) return false;
    const Color f = evalPhong(*sc.material, sc.wo, wiLocal) * (shadowed ? bumpShadowing(ng, frame.n, s.wi) : 1.0);
    if (isBlack(f)) return false;
    ray.o = p + ng * epsilon_;
    if (s.toInfinity) {
        ray.d = s.wi;
        ray.tfar = std::numeric_limits<double>::infinity();
    } else {
        ray.d = s.target - ray.o;
        ray.tfar = 1.0 - 1e-5;
    }
    DirectLight& out = ls.light;
    ls.later = false;
    if (s.delta) {
        out.unweighted = f * s.radiance * (wiLocal.z / s.pdf);
        out.delta = true;
        return true;
    }
    out.delta = false;  // every field set: a batch's LightSample is written again and again
    ls.wi = s.wi;
    ls.later = s.radianceLater;
    out.unweighted = s.radianceLater ? f : f * s.radiance;
    out.cosine = wiLocal.z;
    out.lightPdf = s.pdf;
    ls.wiLocal = wiLocal;  // the caller sets out.estimatorPdf: estimator_.misPdf(sc, wiLocal)
    return true;
}

[[gnu::always_inline]] inline DirectLight PathTracer::litBy(const LightSample& ls) const {
    if (!ls.later) return ls.light;
    DirectLight out = ls.light;
    out.unweighted = out.unweighted * emitters_.background().backgroundRadiance(ls.wi);
    return out;
}

}  // namespace symphong
