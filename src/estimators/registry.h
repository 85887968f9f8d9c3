// estimators/registry.h — the table of estimators: one entry per estimator with its name, its --help
// line, its traits and its factory. Everything that lists, checks, creates or compares estimators (the
// CLI, the Python module, the study and its conclusion) reads this table, so adding an estimator is its
// own file (the class and its factory) plus one entry here (registry.cpp). The traits say what an
// estimator is, so that callers decide by them instead of by names.
#pragma once

#include "estimators/estimator.h"

#include <span>
#include <string_view>

namespace symphong {

/// What the study does with an estimator's variants.
enum class EstimatorRole {
    Other,      ///< measured, not singled out
    Baseline,   ///< a standard strategy the candidates are compared with (cosine, stratified, phong)
    Candidate,  ///< a symmetric-sampling estimator, the subject of the comparison
};

struct EstimatorTraits {
    /// Its directions have a density (misPdf): it combines with light sampling by MIS and is unbiased.
    /// Without one (the paper's, as printed) it must account for all reflected light itself.
    bool hasDensity = true;
    /// It uses a whole set of directions per estimate (branch and spread modes, --symmetric-mode).
    bool setEstimator = false;
    /// The sampler it is defined with, overriding the one asked for; empty: the one asked for.
    std::string_view ownSampler;
    EstimatorRole role = EstimatorRole::Other;
    /// The yardstick of the study's tables ("efficiency vs phong"), its fair pairs and its equal-time table.
    bool yardstick = false;
    /// It reads EstimatorOptions::symmetricOrbit: R copies of one point used together (`symmetric-mix`).
    bool takesOrbit = false;
};

struct EstimatorEntry {
    std::string_view name;
    /// Its --help text, after "name - "; a line break continues under it.
    std::string_view help;
    EstimatorTraits traits;
    /// Creates it; reads the parameters of EstimatorOptions it has and checks their ranges (throws
    /// std::invalid_argument naming the option).
    std::unique_ptr<Estimator> (*create)(const EstimatorOptions& options);
};

/// Every estimator, in the order --help lists them.
std::span<const EstimatorEntry> estimatorTable();

/// The entry of the named estimator, or nullptr.
const EstimatorEntry* findEstimator(std::string_view name);

/// The entry of the named estimator; throws std::invalid_argument listing the valid names otherwise.
const EstimatorEntry& estimatorEntry(std::string_view name);

/// The study's yardstick estimator (the first entry with traits.yardstick).
std::string_view yardstickEstimator();

}  // namespace symphong
