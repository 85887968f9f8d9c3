#include "sampling/sampler_registry.h"

#include <fmt/format.h>

#include <stdexcept>

namespace symphong {

namespace {

template <class S>
std::unique_ptr<Sampler> create(std::uint32_t samplesPerPixel, std::uint64_t seed) {
    return std::make_unique<S>(samplesPerPixel, seed);
}

// The table: one entry per sampler.
const SamplerEntry kSamplers[] = {
    {"independent", "independent uniform numbers (PCG32 streams)", SamplerTraits{true}, create<IndependentSampler>},
    {"stratified", "jittered strata (correlated multi-jittered) in every dimension pair, any spp", {}, create<StratifiedSampler>},
    {"sobol", "Owen-scrambled Sobol' (0,2)-sequence in every dimension pair (the default)", {}, create<SobolSampler>},
};

}  // namespace

std::span<const SamplerEntry> samplerTable() { return kSamplers; }

const SamplerEntry* findSampler(std::string_view name) {
    for (const SamplerEntry& e : kSamplers)
        if (e.name == name) return &e;
    return nullptr;
}

bool isIndependentSampler(std::string_view name) {
    const SamplerEntry* e = findSampler(name);
    return e && e->traits.independentValues;
}

const std::vector<std::string>& samplerNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const SamplerEntry& e : kSamplers) out.emplace_back(e.name);
        return out;
    }();
    return names;
}

std::string samplerHelp() {
    std::string out;
    for (const SamplerEntry& e : kSamplers) out += fmt::format("{}{:<11} - {}", out.empty() ? "" : "\n", e.name, e.help);
    return out;
}

std::unique_ptr<Sampler> makeSampler(std::string_view name, std::uint32_t samplesPerPixel, std::uint64_t seed) {
    if (const SamplerEntry* e = findSampler(name)) return e->create(samplesPerPixel, seed);
    throw std::invalid_argument(fmt::format("unknown sampler '{}' (valid: {})", name, fmt::join(samplerNames(), ", ")));
}

}  // namespace symphong
