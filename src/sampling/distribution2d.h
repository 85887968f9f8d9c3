// sampling/distribution2d.h — a piecewise-constant density on [0,1)^2 proportional to a grid of
// non-negative weights (W columns x H rows), sampled by inverting a marginal CDF over rows and then the
// chosen row's conditional CDF over columns (pbrt-v4's PiecewiseConstant2D, in our own code). Used to
// importance-sample environment maps by luminance x sin(theta).
#pragma once

#include "sampling/rng.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace symphong {

class Distribution2D {
public:
    Distribution2D() = default;
    /// weights: row-major, rows x columns, each >= 0 (negative values count as 0).
    Distribution2D(const std::vector<double>& weights, std::size_t columns, std::size_t rows)
        : columns_(columns), rows_(rows), conditional_(rows * (columns + 1), 0.0), marginal_(rows + 1, 0.0) {
        for (std::size_t y = 0; y < rows; ++y) {
            double* cdf = &conditional_[y * (columns + 1)];
            for (std::size_t x = 0; x < columns; ++x) cdf[x + 1] = cdf[x] + std::max(0.0, weights[y * columns + x]);
            const double sum = cdf[columns];
            marginal_[y + 1] = marginal_[y] + sum;
            if (sum > 0)
                for (std::size_t x = 0; x <= columns; ++x) cdf[x] /= sum;
        }
        total_ = marginal_[rows];
        if (total_ > 0)
            for (double& m : marginal_) m /= total_;
    }

    std::size_t columns() const { return columns_; }
    std::size_t rows() const { return rows_; }
    /// Sum of the weights (0: nothing can be sampled).
    double total() const { return total_; }

    /// Density over [0,1)^2 of cell (x, y): P(row y) P(column x | y) W H.
    double cellPdf(std::size_t x, std::size_t y) const {
        const double pRow = marginal_[y + 1] - marginal_[y];
        const double* cdf = &conditional_[y * (columns_ + 1)];
        return pRow * (cdf[x + 1] - cdf[x]) * static_cast<double>(columns_ * rows_);
    }

    /// A point of [0,1)^2 (p.u across the columns, p.v down the rows) with density cellPdf of its cell,
    /// from uniform u; also the cell. Requires total() > 0.
    Point2 sample(Point2 u, std::size_t& x, std::size_t& y, double& pdf) const {
        double dv = 0, du = 0;
        y = invert(marginal_.data(), rows_, u.v, dv);
        x = invert(&conditional_[y * (columns_ + 1)], columns_, u.u, du);
        pdf = cellPdf(x, y);
        return {std::min((static_cast<double>(x) + du) / static_cast<double>(columns_), kOneBelow),
                std::min((static_cast<double>(y) + dv) / static_cast<double>(rows_), kOneBelow)};
    }

private:
    /// The cell i of an n-cell CDF (cdf[0] = 0, cdf[n] = 1) with cdf[i] <= u < cdf[i+1] and a non-zero
    /// share, and u's offset inside it in [0,1).
    static std::size_t invert(const double* cdf, std::size_t n, double u, double& offset) {
        std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf, cdf + n + 1, u) - cdf);
        i = i == 0 ? 0 : std::min(i - 1, n - 1);
        while (i > 0 && cdf[i + 1] - cdf[i] <= 0) --i;  // never a zero-weight cell
        while (cdf[i + 1] - cdf[i] <= 0 && i + 1 < n) ++i;
        const double width = cdf[i + 1] - cdf[i];
        offset = width > 0 ? std::clamp((u - cdf[i]) / width, 0.0, kOneBelow) : 0.0;
        return i;
    }

    std::size_t columns_ = 0, rows_ = 0;
    std::vector<double> conditional_;  ///< per row: its columns+1 CDF values
    std::vector<double> marginal_;     ///< rows+1 CDF values over rows
    double total_ = 0;
};

}  // namespace symphong
