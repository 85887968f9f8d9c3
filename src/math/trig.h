// math/trig.h — sine and cosine together, of the angles that sampling warps take: a fraction of a turn
// (phi = 2 pi v) or an angle within [-pi/4, pi/4] (the concentric disk's). Polynomials instead of libm's
// sincos, which reduces any double argument (tables, branches, a call): here the reduction is one
// rounding to the nearest quarter turn, exact, and the rest is two short Horner chains that run side by
// side. Accurate to a few units in the last place (tests/test_warps.cpp compares with std::sin and
// std::cos over the whole range).
#pragma once

#include "math/branchless.h"
#include "math/vec3.h"

#include <cmath>

namespace symphong {

struct SinCos {
    double sin, cos;
};

/// sin x and cos x for |x| <= pi/4 by their Taylor series to x^17 and x^16 (the first omitted terms,
/// x^19/19! and x^18/18!, are below 1.1e-17 and 2.6e-16 x^2 there: under the rounding of the sums).
inline SinCos sinCosQuarter(double x) {
    const double x2 = x * x;
    const double s = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800 +
                     x2 * (1.0 / 6227020800.0 + x2 * (-1.0 / 1307674368000.0 + x2 * (1.0 / 355687428096000.0)))))))));
    const double c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800 +
                     x2 * (1.0 / 479001600.0 + x2 * (-1.0 / 87178291200.0 + x2 * (1.0 / 20922789888000.0))))))));
    return {s, c};
}

/// sin(2 pi v) and cos(2 pi v) for v in [0, 1] (a turn's fraction, as phi = 2 pi v of a warp): q = the
/// nearest quarter turn to v (4v - q is exact: Sterbenz), x = (4v - q) pi/2 in [-pi/4, pi/4], then
/// sin(q pi/2 + x), cos(q pi/2 + x) by exchanging and negating sin x and cos x:
///   q mod 4 = 0: (sin x, cos x);  1: (cos x, -sin x);  2: (-sin x, -cos x);  3: (-cos x, sin x),
/// i.e. an odd q exchanges them (negating the new cosine) and q mod 4 >= 2 negates both. The quarter is
/// uniform over the samples: chosen by masks, not by a branch (math/branchless.h).
inline SinCos sinCosTurn(double v) {
    const double w = 4.0 * v;
    const int q = static_cast<int>(w + 0.5);  // w >= 0: truncation of w + 1/2 rounds to nearest
    const SinCos r = sinCosQuarter((w - q) * (0.5 * kPi));
    const bool exchange = (q & 1) != 0, negate = (q & 2) != 0;
    return {negateIf(negate, choose(exchange, r.cos, r.sin)), negateIf(negate, choose(exchange, -r.sin, r.cos))};
}

}  // namespace symphong
