// sampling/alias_table.h — a discrete distribution sampled in constant time (Walker's alias method,
// built by Vose's algorithm): light sampling picks an emitter from it on every path vertex.
#pragma once

#include "sampling/rng.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace symphong {

/// Index i with probability p_i = w_i / sum w from one uniform u in [0,1):
///   t = u n,  j = floor(t),  f = t - j;  i = j when f < q_j (f' = f / q_j), else alias_j (f' = (f - q_j) / (1 - q_j)),
/// with n entries whose cell j holds probability q_j / n of j and (1 - q_j) / n of alias_j. f' is uniform
/// on [0,1) given i, so the same u can then choose a point on the chosen item. Zero weights are never chosen.
class AliasTable {
public:
    AliasTable() = default;
    explicit AliasTable(const std::vector<double>& weights) {
        const std::size_t n = weights.size();
        double total = 0;
        for (double w : weights) total += std::max(0.0, w);
        cells_.resize(n);
        if (!(total > 0)) return;
        total_ = total;
        // Vose: scaled probabilities n p_i; pair each entry below 1 with one above until all are 1.
        std::vector<double> scaled(n);
        std::vector<std::uint32_t> small, large;
        for (std::size_t i = 0; i < n; ++i) {
            cells_[i].pmf = std::max(0.0, weights[i]) / total;
            scaled[i] = cells_[i].pmf * static_cast<double>(n);
            (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
        }
        while (!small.empty() && !large.empty()) {
            const std::uint32_t s = small.back(), l = large.back();
            small.pop_back();
            cells_[s].q = scaled[s];
            cells_[s].alias = l;
            scaled[l] -= 1.0 - scaled[s];
            if (scaled[l] < 1.0) {
                large.pop_back();
                small.push_back(l);
            }
        }
        // What is left is 1 up to round-off. A small entry left over (its partner's share rounded away)
        // keeps q = 1 only if it has weight; a zero-weight one sends its whole cell to a chosen entry.
        for (std::uint32_t l : large) cells_[l].q = 1.0, cells_[l].alias = l;
        for (std::uint32_t s : small) {
            cells_[s].q = cells_[s].pmf > 0 ? 1.0 : 0.0;
            cells_[s].alias = s;
            if (cells_[s].pmf > 0) continue;
            for (std::size_t j = 0; j < n; ++j)
                if (cells_[j].pmf > 0) cells_[s].alias = static_cast<std::uint32_t>(j);
        }
    }

    std::size_t size() const { return cells_.size(); }
    /// The sum of the weights (0: nothing can be chosen).
    double total() const { return total_; }
    /// Probability of index i.
    double pmf(std::size_t i) const { return cells_[i].pmf; }

    /// Index i with probability pmf(i) from u in [0,1), and u remapped to [0,1) inside i's share.
    std::size_t sample(double u, double& uRemapped) const {
        const double t = u * static_cast<double>(cells_.size());
        const std::size_t j = std::min(static_cast<std::size_t>(t), cells_.size() - 1);
        const double f = t - static_cast<double>(j);
        const Cell& c = cells_[j];
        if (f < c.q) {
            uRemapped = std::min(f / c.q, kOneBelow);
            return j;
        }
        uRemapped = std::min((f - c.q) / (1.0 - c.q), kOneBelow);
        return c.alias;
    }

private:
    struct Cell {
        double q = 1;             ///< the share of cell j that is j itself
        double pmf = 0;           ///< p_j
        std::uint32_t alias = 0;  ///< who gets the rest of cell j
    };
    std::vector<Cell> cells_;
    double total_ = 0;
};

}  // namespace symphong
