// compare/flip.cpp — LDR-FLIP and HDR-FLIP (see flip.h). "The FLIP paper" is Andersson et al., HPG 2020
// (with its erratum: the achromatic channel is normalised by dividing by 116, not 100); "the HDR-FLIP
// paper" is Andersson et al., Eurographics 2021 short paper. The constants and the separation of the
// filters follow NVIDIA's reference implementation (github.com/NVlabs/flip, FLIP.h, v1.6, and its
// misc/separatedConvolutions.pdf); the code is ours. Images are held as float planes (as the reference
// does), per-pixel colour arithmetic is done in double; tests/test_flip.cpp checks the agreement.
#include "compare/flip.h"

#include "io/input_error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace symphong {

namespace {

using Plane = std::vector<float>;  // one channel of an image, row-major, row 0 at the top

// --- Constants -----------------------------------------------------------------------------------

// FLIP paper, colour pipeline: the HyAB distance is raised to qc; the share pc of the largest distance
// cmax is mapped to [0, pt], the rest to (pt, 1].
constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95;
// FLIP paper, feature pipeline: edge detectors of width w degrees (Gaussian sigma = w/2); the feature
// difference is raised to qf.
constexpr double kW = 0.082, kQf = 0.5;

// FLIP paper, colour pipeline, spatial filtering: the contrast sensitivity functions as sums of
// Gaussians a sqrt(pi/b) exp(-pi^2 x^2 / b), x in degrees: one term for the achromatic channel Y and for
// the red-green channel Cx, two for the blue-yellow channel Cz.
struct GaussianTerm {
    double a, b;
};
constexpr GaussianTerm kCsfY{1.0, 0.0047}, kCsfCx{1.0, 0.0053}, kCsfCz1{34.1, 0.04}, kCsfCz2{13.5, 0.025};
constexpr double kCsfLargestB = 0.04;

// HDR-FLIP paper: the ACES filmic curve (Narkowicz's fit, (x (a x + b)) / (x (c x + d) + e)) on 0.6 x, the
// 0.6 undoing the fit's built-in exposure, as the reference tool applies it.
constexpr double kAcesPre = 0.6, kAcesA = 2.51, kAcesB = 0.03, kAcesC = 2.43, kAcesD = 0.59, kAcesE = 0.14;
// HDR-FLIP paper, exposure range: the start exposure maps the reference's largest luminance, the stop
// exposure its median luminance, to this tone-mapped value.
constexpr double kExposureTarget = 0.85;

// Linear sRGB (Rec. 709 primaries, D65) -> CIE XYZ, the exact fractions of the standard's matrix.
constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                                    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                                    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};

struct Mat3 {
    double m[3][3];
};

constexpr Mat3 inverse(const double (&a)[3][3]) {
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
                 c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    return {{{c00 / det, (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det, (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det},
             {c01 / det, (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det, (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det},
             {c02 / det, (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det, (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det}}};
}
constexpr Mat3 kXyzToRgb = inverse(kRgbToXyz);

constexpr Vec3 apply(const double (&m)[3][3], const Vec3& v) {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

// The reference white of YCxCz and L*a*b*: D65, the XYZ of RGB white.
constexpr Vec3 kWhite = apply(kRgbToXyz, Vec3(1.0));

// --- Colour spaces (FLIP paper, colour pipeline) -------------------------------------------------

// YCxCz (Zhang and Wandell's opponent space, linear in XYZ): Y = 116 y - 16, Cx = 500 (x - y),
// Cz = 200 (y - z), with x, y, z the XYZ over the white's.
Vec3 linearRgbToYcxcz(const Color& rgb) {
    const Vec3 xyz = apply(kRgbToXyz, rgb);
    const double x = xyz.x / kWhite.x, y = xyz.y / kWhite.y, z = xyz.z / kWhite.z;
    return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Color ycxczToLinearRgb(const Vec3& ycc) {
    const double y = (ycc.x + 16.0) / 116.0, x = y + ycc.y / 500.0, z = y - ycc.z / 200.0;
    return apply(kXyzToRgb.m, Vec3(x * kWhite.x, y * kWhite.y, z * kWhite.z));
}

// CIE L*a*b* (D65): f(t) = t^(1/3) above (6/29)^3, t / (3 (6/29)^2) + 4/29 below.
double labF(double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// L*a*b* with the Hunt adjustment (FLIP paper, colour pipeline): a and b scaled by 0.01 L, so that
// dark colours' chroma counts for less.
Vec3 huntLab(const Color& rgb) {
    const Vec3 xyz = apply(kRgbToXyz, rgb);
    const double fx = labF(xyz.x / kWhite.x), fy = labF(xyz.y / kWhite.y), fz = labF(xyz.z / kWhite.z);
    const double l = 116.0 * fy - 16.0;
    return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

// HyAB (Abasi et al.): city-block distance in L, Euclidean in (a, b).
double hyab(const Vec3& p, const Vec3& q) {
    const double da = p.y - q.y, db = p.z - q.z;
    return std::abs(p.x - q.x) + std::sqrt(da * da + db * db);
}

// cmax: the HyAB^qc distance between the Hunt-adjusted L*a*b* of pure green and pure blue, the largest
// between two colours of the gamut.
double maxColourDistance() { return std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), kQc); }

// FLIP paper, colour pipeline, the redistribution of errors: distances below pc cmax compressed
// linearly to [0, pt], those above to (pt, 1].
double redistribute(double e, double cmax) {
    const double pccmax = kPc * cmax;
    return e < pccmax ? e * kPt / pccmax : kPt + (e - pccmax) / (cmax - pccmax) * (1.0 - kPt);
}

// --- Separable filters --------------------------------------------------------------------------

using Kernel = std::vector<float>;  // 2r + 1 weights, offset -r first

template <class Fn>
void forEachRow(int h, const Fn& fn) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) fn(y);
    });
}

// The 2D filters are separable, kx(x) ky(y), and applied one output row at a time, columns first: the
// column pass of row y into a row buffer padded by r on each side (edge pixels repeated, as beyond the
// image's border), then the row pass. No intermediate image; the reference filters rows first, which
// changes only the rounding (tests/test_flip.cpp).
struct PaddedRow {
    int w, r;
    std::vector<float> v;  // w + 2r values, pixel x at v[x + r]
    PaddedRow(int width, int radius) : w(width), r(radius), v(static_cast<std::size_t>(width) + 2 * radius) {}
};

// row.v[x + r] = sum_t ky[t] in(x, y + t - r), rows outside the image replaced by the nearest one.
void columnPass(const Plane& in, int h, int y, const Kernel& ky, PaddedRow& row) {
    const int w = row.w, r = static_cast<int>(ky.size()) / 2;
    float* o = row.v.data() + row.r;
    std::fill(o, o + w, 0.0f);
    for (int t = 0; t < static_cast<int>(ky.size()); ++t) {  // taps outside, pixels inside: vectorises
        const float* src = &in[static_cast<std::size_t>(std::clamp(y + t - r, 0, h - 1)) * w];
        for (int x = 0; x < w; ++x) o[x] += ky[t] * src[x];
    }
    std::fill(row.v.begin(), row.v.begin() + row.r, o[0]);
    std::fill(row.v.end() - row.r, row.v.end(), o[w - 1]);
}

// out[x] = sum_t kx[t] row(x + t - r), x in [0, w); kx's radius at most the row's padding.
void rowPass(const PaddedRow& row, const Kernel& kx, float* out) {
    const float* in = row.v.data() + row.r - static_cast<int>(kx.size()) / 2;
    std::fill(out, out + row.w, 0.0f);
    for (std::size_t t = 0; t < kx.size(); ++t)
        for (int x = 0; x < row.w; ++x) out[x] += kx[t] * in[x + t];
}

// The contrast sensitivity filters, separated (separatedConvolutions.pdf): Y and Cx are one Gaussian each,
// g(x) g(y), normalised to sum 1. Cz is a sum of two, each the product of two 1D factors
// sqrt(a sqrt(pi/b)) exp(-pi^2 x^2 / b), all four factors divided by sqrt(S1^2 + S2^2) (S_i: the 1D sum of
// term i) so that the 2D filter sums to 1. Radius: three standard deviations, sqrt(b / (2 pi^2)) degrees,
// of the widest term.
struct CsfKernels {
    Kernel y, cx, cz1, cz2;
};

CsfKernels csfKernels(double ppd) {
    const int r = static_cast<int>(std::ceil(3.0 * std::sqrt(kCsfLargestB / (2.0 * kPi * kPi)) * ppd));
    const auto term = [&](const GaussianTerm& g, bool root, double& sum) {
        std::vector<double> v(2 * r + 1);
        for (int i = -r; i <= r; ++i) {
            const double x = i / ppd, amplitude = g.a * std::sqrt(kPi / g.b);
            v[i + r] = (root ? std::sqrt(amplitude) : amplitude) * std::exp(-kPi * kPi * x * x / g.b);
            sum += v[i + r];
        }
        return v;
    };
    const auto scaled = [](const std::vector<double>& v, double s) {
        Kernel k(v.size());
        for (std::size_t i = 0; i < v.size(); ++i) k[i] = static_cast<float>(v[i] / s);
        return k;
    };
    double sy = 0, scx = 0, s1 = 0, s2 = 0;
    const auto y = term(kCsfY, false, sy), cx = term(kCsfCx, false, scx);
    const auto cz1 = term(kCsfCz1, true, s1), cz2 = term(kCsfCz2, true, s2);
    const double sz = std::sqrt(s1 * s1 + s2 * s2);
    return {scaled(y, sy), scaled(cx, scx), scaled(cz1, sz), scaled(cz2, sz)};
}

// FLIP paper, feature pipeline: a Gaussian of sigma = w/2 degrees (in pixels here), radius 3 sigma, and
// its first and second derivatives, -x g(x) and (x^2 / sigma^2 - 1) g(x). The Gaussian sums to 1; each
// derivative's positive weights sum to 1 and its negative ones to -1.
struct FeatureKernels {
    Kernel g, dg, ddg;
};

FeatureKernels featureKernels(double ppd) {
    const double sigma = 0.5 * kW * ppd;
    const int r = static_cast<int>(std::ceil(3.0 * sigma));
    std::vector<double> g(2 * r + 1), dg(g.size()), ddg(g.size());
    double sum = 0, dgPos = 0, dgNeg = 0, ddgPos = 0, ddgNeg = 0;
    for (int i = -r; i <= r; ++i) {
        const double gi = std::exp(-i * i / (2.0 * sigma * sigma));
        g[i + r] = gi;
        dg[i + r] = -i * gi;
        ddg[i + r] = (i * i / (sigma * sigma) - 1.0) * gi;
        sum += gi;
        (dg[i + r] > 0 ? dgPos : dgNeg) += std::abs(dg[i + r]);
        (ddg[i + r] > 0 ? ddgPos : ddgNeg) += std::abs(ddg[i + r]);
    }
    const auto ratio = [](double v, double s) { return static_cast<float>(s > 0 ? v / s : 0.0); };  // 0/0: ppd < 0.7
    FeatureKernels k{Kernel(g.size()), Kernel(g.size()), Kernel(g.size())};
    for (std::size_t i = 0; i < g.size(); ++i) {
        k.g[i] = ratio(g[i], sum);
        k.dg[i] = ratio(dg[i], dg[i] > 0 ? dgPos : dgNeg);
        k.ddg[i] = ratio(ddg[i], ddg[i] > 0 ? ddgPos : ddgNeg);
    }
    return k;
}

struct Filters {
    CsfKernels csf;
    FeatureKernels feature;
    double cmax;
};

// --- The two pipelines --------------------------------------------------------------------------

struct Ycxcz {
    int w = 0, h = 0;
    Plane y, cx, cz;
    Plane achromatic;  // (Y + 16) / 116, in [0,1], for the feature pipeline
};

// `out` := the image in YCxCz, each pixel first mapped to display linear RGB in [0,1] by `display`.
// Its planes are reused when it is refilled (HDR-FLIP: one refill per exposure).
template <class Display>
void toYcxcz(const Image& img, const Display& display, Ycxcz& out) {
    const std::size_t n = img.pixels.size();
    out.w = img.width;
    out.h = img.height;
    for (Plane* p : {&out.y, &out.cx, &out.cz, &out.achromatic}) p->resize(n);
    forEachRow(img.height, [&](int y) {
        for (std::size_t i = static_cast<std::size_t>(y) * img.width, e = i + img.width; i < e; ++i) {
            const Vec3 c = linearRgbToYcxcz(display(img.pixels[i]));
            out.y[i] = static_cast<float>(c.x);
            out.cx[i] = static_cast<float>(c.y);
            out.cz[i] = static_cast<float>(c.z);
            out.achromatic[i] = static_cast<float>((c.x + 16.0) / 116.0);
        }
    });
}

// FLIP paper, colour pipeline, spatial filtering: row y of each channel filtered by its contrast
// sensitivity function, as Hunt-adjusted L*a*b* after clamping to the RGB gamut.
struct CsfRows {
    PaddedRow padded;
    std::vector<float> y, cx, cz1, cz2;
    CsfRows(int w, int r) : padded(w, r), y(w), cx(w), cz1(w), cz2(w) {}

    void filter(const Ycxcz& img, int row, const CsfKernels& k) {
        const std::pair<const Plane*, std::pair<const Kernel*, float*>> passes[] = {
            {&img.y, {&k.y, y.data()}}, {&img.cx, {&k.cx, cx.data()}}, {&img.cz, {&k.cz1, cz1.data()}}, {&img.cz, {&k.cz2, cz2.data()}}};
        for (const auto& [plane, kernel] : passes) {
            columnPass(*plane, img.h, row, *kernel.first, padded);
            rowPass(padded, *kernel.first, kernel.second);
        }
    }
    Vec3 lab(int x) const {
        const Color rgb = ycxczToLinearRgb({y[x], cx[x], cz1[x] + cz2[x]});
        return huntLab(vmin(vmax(rgb, Vec3(0.0)), Vec3(1.0)));
    }
};

// FLIP paper, colour pipeline: the HyAB distance of the filtered colours raised to qc and redistributed
// to [0,1].
Plane colourDifference(const Ycxcz& reference, const Ycxcz& test, const Filters& f) {
    Plane out(reference.y.size());
    const int w = reference.w, r = static_cast<int>(f.csf.y.size()) / 2;
    forEachRow(reference.h, [&](int y) {
        CsfRows ref(w, r), tst(w, r);
        ref.filter(reference, y, f.csf);
        tst.filter(test, y, f.csf);
        float* o = &out[static_cast<std::size_t>(y) * w];
        for (int x = 0; x < w; ++x) o[x] = static_cast<float>(redistribute(std::pow(hyab(ref.lab(x), tst.lab(x)), kQc), f.cmax));
    });
    return out;
}

// FLIP paper, feature pipeline: in row y of the normalised achromatic channel, the gradient magnitude of
// the Gaussian-smoothed image (edges) and the magnitude of its second derivatives (points), from the
// separated filters dg(x) g(y), g(x) dg(y), ddg(x) g(y), g(x) ddg(y).
struct FeatureRows {
    PaddedRow g, dg, ddg;
    std::vector<float> dx, dy, ddx, ddy;
    FeatureRows(int w, int r) : g(w, r), dg(w, r), ddg(w, r), dx(w), dy(w), ddx(w), ddy(w) {}

    void filter(const Ycxcz& img, int row, const FeatureKernels& k) {
        columnPass(img.achromatic, img.h, row, k.g, g);
        columnPass(img.achromatic, img.h, row, k.dg, dg);
        columnPass(img.achromatic, img.h, row, k.ddg, ddg);
        rowPass(g, k.dg, dx.data());
        rowPass(dg, k.g, dy.data());
        rowPass(g, k.ddg, ddx.data());
        rowPass(ddg, k.g, ddy.data());
    }
    double edge(int x) const { return std::sqrt(double(dx[x]) * dx[x] + double(dy[x]) * dy[x]); }
    double point(int x) const { return std::sqrt(double(ddx[x]) * ddx[x] + double(ddy[x]) * ddy[x]); }
};

// FLIP paper, final difference: the feature difference ((1/sqrt 2) max(edge, point difference))^qf,
// and the error colour^(1 - feature).
Plane ldrFlipMap(const Ycxcz& reference, const Ycxcz& test, const Filters& f) {
    if (reference.y.empty()) return {};
    Plane map = colourDifference(reference, test, f);
    const int w = reference.w, r = static_cast<int>(f.feature.g.size()) / 2;
    forEachRow(reference.h, [&](int y) {
        FeatureRows ref(w, r), tst(w, r);
        ref.filter(reference, y, f.feature);
        tst.filter(test, y, f.feature);
        float* m = &map[static_cast<std::size_t>(y) * w];
        for (int x = 0; x < w; ++x) {
            const double edge = std::abs(ref.edge(x) - tst.edge(x)), point = std::abs(ref.point(x) - tst.point(x));
            const double feature = std::pow(std::max(edge, point) / std::sqrt(2.0), kQf);
            m[x] = static_cast<float>(std::pow(static_cast<double>(m[x]), 1.0 - feature));
        }
    });
    return map;
}

// --- Shared checks and results ------------------------------------------------------------------

void checkInputs(const Image& reference, const Image& test, double ppd) {
    for (const Image* img : {&reference, &test})
        if (img->width < 0 || img->height < 0 || img->pixels.size() != static_cast<std::size_t>(img->width) * img->height)
            throw InputError("FLIP: an image's pixel count does not match its size");
    if (reference.width != test.width || reference.height != test.height)
        throw InputError("FLIP: the images differ in size: reference " + std::to_string(reference.width) + "x" +
                         std::to_string(reference.height) + ", test " + std::to_string(test.width) + "x" + std::to_string(test.height));
    if (!(ppd > 0) || !std::isfinite(ppd)) throw InputError("FLIP: pixels per degree must be positive, not " + std::to_string(ppd));
}

Filters filtersFor(double ppd) { return {csfKernels(ppd), featureKernels(ppd), maxColourDistance()}; }

FlipResult resultFrom(const Image& reference, Plane map) {
    FlipResult out;
    out.width = reference.width;
    out.height = reference.height;
    double sum = 0;
    for (float v : map) sum += v;
    out.mean = map.empty() ? 0.0 : sum / static_cast<double>(map.size());
    out.map = std::move(map);
    return out;
}

// --- HDR ----------------------------------------------------------------------------------------

// HDR input: negative and non-finite channels count as 0 (the reference tool passes them to the tone mapper).
Color radiance(const Color& c) {
    const auto v = [](double x) { return std::isfinite(x) && x > 0 ? x : 0.0; };
    return {v(c.x), v(c.y), v(c.z)};
}

double aces(double x) {
    const double s = std::min(kAcesPre * x, 1e100);  // flat (a/c) long before; s^2 must not overflow
    return s * (kAcesA * s + kAcesB) / (s * (kAcesC * s + kAcesD) + kAcesE);
}

// The input x >= 0 at which aces(x) = kExposureTarget: the larger root of
// (a p^2 - t c p^2) x^2 + (b p - t d p) x - t e = 0, p = 0.6, t = 0.85.
double acesInverseOfTarget() {
    const double p = kAcesPre, t = kExposureTarget;
    const double a = (kAcesA - t * kAcesC) * p * p, b = (kAcesB - t * kAcesD) * p, c = -t * kAcesE;
    return (-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

// HDR-FLIP paper, exposure range: start = log2(x_t / Y_max), stop = log2(x_t / Y_median), x_t the input the
// tone mapper takes to 0.85, Y the reference's luminances; the median is the element n/2 of the sorted
// luminances, as in the reference tool. Our choices where the reference's would be infinite: a median of 0
// is replaced by the smallest positive luminance, an all-black reference gives start = stop = 0.
std::pair<double, double> automaticExposures(const Image& reference) {
    std::vector<double> lum(reference.pixels.size());
    double smallest = INFINITY;
    for (std::size_t i = 0; i < lum.size(); ++i) {
        lum[i] = luminance(radiance(reference.pixels[i]));
        if (lum[i] > 0) smallest = std::min(smallest, lum[i]);
    }
    if (lum.empty() || !(smallest < INFINITY)) return {0.0, 0.0};
    const double largest = *std::max_element(lum.begin(), lum.end());
    const auto mid = lum.begin() + static_cast<std::ptrdiff_t>(lum.size() / 2);
    std::nth_element(lum.begin(), mid, lum.end());
    const double median = *mid > 0 ? *mid : smallest, xt = acesInverseOfTarget();
    return {std::log2(xt / largest), std::log2(xt / median)};
}

}  // namespace

// FLIP paper, viewing conditions: the pixels in one degree of visual angle, d (N / W) (pi / 180).
double flipPixelsPerDegree(double distance, double monitorWidth, double monitorPixels) {
    return distance * (monitorPixels / monitorWidth) * (kPi / 180.0);
}

FlipResult ldrFlip(const Image& reference, const Image& test, double pixelsPerDegree) {
    checkInputs(reference, test, pixelsPerDegree);
    const auto display = [](const Color& c) {
        const auto v = [](double x) { return x > 0 ? (x < 1 ? x : 1.0) : 0.0; };  // NaN -> 0
        return Color(v(c.x), v(c.y), v(c.z));
    };
    Ycxcz r, t;
    toYcxcz(reference, display, r);
    toYcxcz(test, display, t);
    return resultFrom(reference, ldrFlipMap(r, t, filtersFor(pixelsPerDegree)));
}

// HDR-FLIP paper: both images exposed by 2^c for c from start to stop in equal steps, tone-mapped (ACES)
// and clamped to [0,1]; per pixel the largest LDR-FLIP over the exposures.
FlipResult hdrFlip(const Image& reference, const Image& test, const HdrFlipOptions& options) {
    checkInputs(reference, test, options.pixelsPerDegree);
    double start = options.startExposure.value_or(0), stop = options.stopExposure.value_or(0);
    if (!options.startExposure || !options.stopExposure) {
        const auto [autoStart, autoStop] = automaticExposures(reference);
        start = options.startExposure.value_or(autoStart);
        stop = options.stopExposure.value_or(autoStop);
    }
    if (!std::isfinite(start) || !std::isfinite(stop) || start > stop)
        throw InputError("HDR-FLIP: the start exposure " + std::to_string(start) + " must not exceed the stop exposure " + std::to_string(stop));
    const int count = options.exposures.value_or(std::max(2, static_cast<int>(std::ceil(stop - start))));
    if (count < 1) throw InputError("HDR-FLIP: the number of exposures must be at least 1, not " + std::to_string(count));

    const Filters f = filtersFor(options.pixelsPerDegree);
    const double step = count > 1 ? (stop - start) / (count - 1) : 0.0;
    Plane map(reference.pixels.size(), 0.0f);
    Ycxcz r, t;
    for (int i = 0; i < count; ++i) {
        const double scale = std::exp2(start + i * step);
        const auto display = [scale](const Color& c) {
            const Color e = radiance(c) * scale;
            return vmin(Color(aces(e.x), aces(e.y), aces(e.z)), Color(1.0));
        };
        toYcxcz(reference, display, r);
        toYcxcz(test, display, t);
        const Plane ldr = ldrFlipMap(r, t, f);
        for (std::size_t p = 0; p < map.size(); ++p) map[p] = std::max(map[p], ldr[p]);
    }
    FlipResult out = resultFrom(reference, std::move(map));
    out.startExposure = start;
    out.stopExposure = stop;
    out.exposures = count;
    return out;
}

}  // namespace symphong
