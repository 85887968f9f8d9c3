// sampling/sampler_registry.h — the table of samplers: one entry per sampler with its name, its --help
// line, its traits and its factory. The CLI, the Python module and the study list, check and create
// samplers from it, so adding a sampler is its own class (sampler.h or a file of its own) plus one entry
// here (sampler_registry.cpp).
#pragma once

#include "sampling/sampler.h"

#include <span>
#include <string_view>

namespace symphong {

struct SamplerTraits {
    /// Independent values (no stratification): the baseline the study compares the other samplers with.
    bool independentValues = false;
};

struct SamplerEntry {
    std::string_view name;
    std::string_view help;  ///< its --help text, after "name - "
    SamplerTraits traits;
    std::unique_ptr<Sampler> (*create)(std::uint32_t samplesPerPixel, std::uint64_t seed);
};

/// Every sampler, in the order --help lists them.
std::span<const SamplerEntry> samplerTable();

/// The entry of the named sampler, or nullptr.
const SamplerEntry* findSampler(std::string_view name);

/// Whether the named sampler is a baseline of independent values (traits.independentValues).
bool isIndependentSampler(std::string_view name);

}  // namespace symphong
