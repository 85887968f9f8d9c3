// math/branchless.h — choosing between two values without a branch, for the choices that a random
// number makes (which half of the square a sampling warp's point fell in, which quarter turn an angle is
// in) and the clamps of values that change from path vertex to path vertex: a branch on such a condition
// is mispredicted about as often as it is taken, each a pipeline flush, while a choice by bit masks costs
// a few integer instructions and always the same.
// The compiler turns a plain `c ? x : y` on doubles into a branch at x86-64's baseline (there is no
// blend instruction before SSE4.1), so the masks are written out. The values chosen are bit for bit
// those of the branch.
#pragma once

#include <bit>
#include <cstdint>

namespace symphong {

/// c ? x : y, by masks: every bit of x where c holds, of y where it does not.
inline double choose(bool c, double x, double y) {
    const std::uint64_t mask = std::uint64_t{0} - static_cast<std::uint64_t>(c);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(x) & mask) | (std::bit_cast<std::uint64_t>(y) & ~mask));
}

/// v clamped to [lo, hi] (lo <= hi) by masks: lo below it, hi above it, v itself (a NaN too) between. The
/// values of std::clamp, which GCC compiles to branches (as it does std::min(std::max(...)) when it can
/// prove the result's range).
inline double clampByMasks(double v, double lo, double hi) {
    const double atLeast = choose(v < lo, lo, v);
    return choose(atLeast > hi, hi, atLeast);
}

/// x with its sign flipped where c holds (-x, exactly, as a negation gives it), else x.
inline double negateIf(bool c, double x) {
    return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) ^ (static_cast<std::uint64_t>(c) << 63));
}

}  // namespace symphong
