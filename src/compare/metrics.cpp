#include "compare/metrics.h"

#include <cmath>
#include <stdexcept>

namespace symphong {

namespace {

void checkSameSize(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size())
        throw std::invalid_argument("images differ in size");
}

}  // namespace

double luminanceVariance(const Color& v) {
    const double sd = 0.2126 * std::sqrt(v.x) + 0.7152 * std::sqrt(v.y) + 0.0722 * std::sqrt(v.z);
    return sd * sd;
}

ImageError imageError(const Image& img, const Image& ref) {
    checkSameSize(img, ref);
    ImageError e;
    const std::size_t n = img.pixels.size();
    if (n == 0) return e;
    double se = 0, rel = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double y = luminance(img.pixels[i]), yr = luminance(ref.pixels[i]);
        const double d2 = (y - yr) * (y - yr);
        se += d2;
        rel += d2 / (yr * yr + 0.01);
    }
    e.mse = se / n;
    e.rmse = std::sqrt(e.mse);
    e.relMse = rel / n;
    return e;
}

MeanWithError meanLuminance(const Image& img, const Image* varianceOfMean) {
    MeanWithError m;
    const std::size_t n = img.pixels.size();
    if (n == 0) return m;
    double sum = 0, var = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sum += luminance(img.pixels[i]);
        if (varianceOfMean) var += luminanceVariance(varianceOfMean->pixels[i]);
    }
    m.mean = sum / n;
    m.stdError = std::sqrt(var) / n;
    return m;
}

double studentCritical(int dof) {
    // Solved numerically for P(|T| > t) = 6.334e-5, the normal distribution's two-sided tail at 4.
    static constexpr double kTable[30] = {10000.82, 125.65, 32.62, 17.45, 12.28, 9.84, 8.47, 7.6,  7.0,  6.57,
                                          6.24,     5.99,   5.78,  5.62,  5.48,  5.36, 5.26, 5.18, 5.1,  5.04,
                                          4.98,     4.92,   4.88,  4.83,  4.8,   4.76, 4.73, 4.7,  4.67, 4.65};
    if (dof < 1) return INFINITY;
    if (dof <= 30) return kTable[dof - 1];
    return 4.0 + 0.65 * 30.0 / dof;
}

BiasEstimate relativeBias(const std::vector<MeanWithError>& repeats, const MeanWithError& reference) {
    BiasEstimate b;
    if (repeats.empty() || reference.mean == 0) return b;
    const double R = static_cast<double>(repeats.size());
    double mean = 0, within = 0;
    bool allKnown = true;
    for (const auto& r : repeats) {
        mean += r.mean / R;
        within += r.stdError * r.stdError / (R * R);
        allKnown = allKnown && r.stdError > 0;
    }
    double spread = 0;
    if (repeats.size() >= 2) {
        for (const auto& r : repeats) spread += (r.mean - mean) * (r.mean - mean);
        spread /= (R - 1) * R;
    }
    double var;
    if (allKnown) {
        // Many pixels make each render's own error reliable; the spread guards against heavy tails.
        var = std::max(within, spread);
        b.threshold = 4.0;
    } else {
        var = spread;
        b.threshold = studentCritical(static_cast<int>(repeats.size()) - 1);
    }
    const double diff = mean - reference.mean;
    b.relative = diff / reference.mean;
    const double se = std::sqrt(var + reference.stdError * reference.stdError);
    b.stdError = se / std::abs(reference.mean);
    b.z = se > 0 ? diff / se : 0.0;
    b.significant = se > 0 && std::isfinite(b.threshold) && std::abs(b.z) > b.threshold;
    return b;
}

double pixelVarianceAcrossRepeats(const std::vector<const Image*>& repeats) {
    if (repeats.size() < 2) return 0.0;
    const std::size_t n = repeats[0]->pixels.size();
    for (const Image* r : repeats) checkSameSize(*r, *repeats[0]);
    const double R = static_cast<double>(repeats.size());
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double s = 0, ss = 0;
        for (const Image* r : repeats) {
            const double y = luminance(r->pixels[i]);
            s += y;
            ss += y * y;
        }
        total += std::max(0.0, (ss - s * s / R) / (R - 1));
    }
    return n ? total / n : 0.0;
}

double halfSquaredDifference(const Image& a, const Image& b) {
    checkSameSize(a, b);
    double total = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const double d = luminance(a.pixels[i]) - luminance(b.pixels[i]);
        total += 0.5 * d * d;
    }
    return a.pixels.empty() ? 0.0 : total / static_cast<double>(a.pixels.size());
}

std::vector<float> relativeErrorMap(const Image& img, const Image& ref) {
    checkSameSize(img, ref);
    std::vector<float> out(img.pixels.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double y = luminance(img.pixels[i]), yr = luminance(ref.pixels[i]);
        out[i] = static_cast<float>(std::abs(y - yr) / (yr + 0.01));
    }
    return out;
}

}  // namespace symphong
