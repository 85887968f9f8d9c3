// estimators/options.h — the schema of the estimators' parameters (EstimatorOptions): each with its
// name, flag, range and help, defined here beside the estimators that read them (their factories in the
// table of estimators/registry.cpp check the values they use). Render, furnace and study settings embed
// it (util/schema.h).
#pragma once

#include "estimators/estimator.h"
#include "util/schema.h"

namespace symphong {

/// symmetric_n (--symmetric-n), paper_refined (--paper-refined), symmetric_orbit (--symmetric-orbit) and
/// symmetric_mode (--symmetric-mode).
const schema::Schema<EstimatorOptions>& estimatorOptionsSchema();

}  // namespace symphong
