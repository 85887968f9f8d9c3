// sampling/distribution1d.h — a discrete distribution proportional to non-negative weights, sampled
// by inverting its CDF (used to pick an emitter triangle in proportion to its power).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace symphong {

class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(const std::vector<double>& weights) : cdf_(weights.size() + 1, 0.0) {
        for (std::size_t i = 0; i < weights.size(); ++i) cdf_[i + 1] = cdf_[i] + std::max(0.0, weights[i]);
        total_ = cdf_.back();
        if (total_ > 0)
            for (double& c : cdf_) c /= total_;
    }

    std::size_t size() const { return cdf_.empty() ? 0 : cdf_.size() - 1; }
    double total() const { return total_; }
    /// The CDF below index i: the sum of the probabilities of 0..i-1.
    double cdf(std::size_t i) const { return cdf_[i]; }
    /// Probability of index i.
    double pmf(std::size_t i) const { return cdf_[i + 1] - cdf_[i]; }

    /// Index i with probability pmf(i), from u in [0,1).
    std::size_t sample(double u) const {
        const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
        const std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - cdf_.begin()) - 1));
        std::size_t idx = std::min(i, size() - 1);
        while (idx > 0 && pmf(idx) == 0) --idx;  // never return a zero-weight entry
        while (pmf(idx) == 0 && idx + 1 < size()) ++idx;
        return idx;
    }

private:
    std::vector<double> cdf_;
    double total_ = 0;
};

}  // namespace symphong
