// render/direct_light.h — next-event estimation's result at a vertex (DirectLight: its contribution before
// the MIS weight that waits for the vertex's number of continuations) and a light sample whose shadow ray is
// still to be traced (LightSample: the wavefront traces a depth's shadow rays together). PathTracer makes them
// (path_tracer.cpp: directLight, lightSample, litBy).
#pragma once

#include "math/vec3.h"

namespace symphong {

/// Next-event estimation's contribution at a vertex before its MIS weight (PathTracer::directLight). As
/// made, nothing: f L = 0 at a density of 1, which value() weighs to an exact 0 by the same formula as a
/// sample that arrived (whether the shadow ray got through is a coin toss per vertex: no branch on it).
struct DirectLight {
    Color unweighted{0.0};    ///< f L (a delta emitter: the whole contribution)
    double cosine = 0;        ///< cos theta of the light's direction
    double lightPdf = 1;      ///< the light sample's density (solid angle), > 0
    double estimatorPdf = 0;  ///< the estimator's MIS density of that direction for one call
    bool delta = false;       ///< from a delta emitter: `unweighted` is the contribution, nothing to weigh

    /// The contribution with MIS against `misScale` estimator calls at the vertex (the first hit's split
    /// count k, EARS's q, else 1): f L cos w / p, w the power heuristic of the light's density against the
    /// density of all of those calls together.
    Color value(double misScale) const;
};

/// A light sample before its shadow ray (PathTracer::lightSample): what next-event estimation contributes
/// once the ray is clear (PathTracer::litBy): `light`, whose `unweighted` still lacks the environment's
/// radiance along `wi` when `later` (looked up only for a clear ray), and whose `estimatorPdf` the caller
/// sets (the estimator's MIS density of `wiLocal`; not for a delta emitter): the recursive tracer for a clear
/// ray only, the wavefront before the vertex's material is gone.
struct LightSample {
    DirectLight light;
    Vec3 wi, wiLocal;
    bool later = false;
};

}  // namespace symphong
