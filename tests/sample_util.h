// Sample streams for tests that call estimators directly: each call gets a stream of its own (a new
// pixel of a sampler), so calls are independent unless a test groups them as one pixel's samples.
#pragma once

#include "sampling/sampler.h"

#include <cstdint>
#include <memory>
#include <string>

namespace symphong::test {

/// Camera sample `index` of consecutive pixels of a sampler: next() moves to a new pixel.
class Streams {
public:
    explicit Streams(std::uint64_t seed, const std::string& sampler = "independent", std::uint32_t spp = 1)
        : sampler_(makeSampler(sampler, spp, seed)) {}
    /// A stream for sample `index` of the current pixel.
    SampleStream at(std::uint32_t index, std::uint64_t dim = 0) const { return SampleStream(*sampler_, pixel_, index, dim); }
    /// Moves to the next pixel and returns a stream for its sample 0.
    SampleStream next() {
        ++pixel_;
        return at(0);
    }
    void nextPixel() { ++pixel_; }

private:
    std::unique_ptr<Sampler> sampler_;
    std::uint64_t pixel_ = 0;
};

}  // namespace symphong::test
