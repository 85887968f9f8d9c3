// sampling/ — random numbers and the pure warps that turn uniform points of [0,1)^2 into directions
// and points with known densities. Every warp here is a small function whose comment gives the formula
// it implements and the density it produces; sampling/ knows nothing of scenes, materials or images.
#pragma once

#include <pcg_random.hpp>

#include <cstdint>

namespace symphong {

struct Point2 {
    double u = 0, v = 0;
};

/// The largest double below 1: a value rescaled into [0,1) is clamped to it, so no warp sees u = 1.
inline constexpr double kOneBelow = 0x1.fffffffffffffp-1;

/// PCG32 stream (O'Neill 2014) returning doubles in [0,1) with 53 random bits.
/// Render code seeds one stream per pixel, so an image does not depend on how pixels are scheduled.
class Rng {
public:
    Rng(std::uint64_t seed, std::uint64_t stream) : gen_(seed, stream) {}

    double uniform() {
        const std::uint64_t hi = gen_() >> 5;                                      // 27 bits
        const std::uint64_t lo = gen_() >> 6;                                      // 26 bits
        return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);  // / 2^53
    }
    Point2 uniform2() {
        const double a = uniform();
        return {a, uniform()};
    }
    std::uint32_t bits() { return gen_(); }
    /// Skips `draws` 32-bit outputs (two per uniform()) in O(log draws) steps.
    void advance(std::uint64_t draws) { gen_.advance(draws); }

private:
    pcg32 gen_;
};

/// Mixes a seed and a pixel (or any other) index into a well-spread 64-bit seed (SplitMix64 finaliser).
constexpr std::uint64_t mixSeed(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + index + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

}  // namespace symphong
