// sampling/sampler.h — samplers: where every random number of a render comes from. A sampler is a pure
// function of (seed, pixel, sample index within the pixel, dimension) to a value in [0,1) or [0,1)^2,
// so an image does not depend on how pixels are scheduled over threads, and any dimension can be
// asked for in any order. Dimensions are handed out in pairs (2D) or singly (1D); the path tracer
// gives each decision of a path (pixel position, light choice and point, the estimator's direction,
// Russian roulette, ...) its own fixed dimension, so decisions never share a number.
//   independent — PCG32: the pixel's stream, its state seeded from (sample, dimension); no stratification.
//   stratified  — correlated multi-jittered strata (Kensler 2013) of every dimension pair, padded: each
//                 pair of each pixel gets its own hashed permutation, any spp (m x n grid, N-rooks in y).
//   sobol       — the first two Sobol' dimensions, a (0,2)-sequence, Owen-scrambled by hashing; padded:
//                 every pair (and every 1D dimension) of every pixel has its own scramble and its own
//                 permutation of the pixel's sample indices (pbrt-v4's PaddedSobolSampler). The pixel's
//                 spp points of a pair are the first spp points of a scrambled (0,2)-sequence.
// docs/sampling.md says why, with measurements.
#pragma once

#include "math/vec3.h"
#include "sampling/lowdiscrepancy.h"
#include "sampling/rng.h"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace symphong {

class Sampler {
public:
    Sampler(std::uint32_t samplesPerPixel, std::uint64_t seed) : spp_(samplesPerPixel ? samplesPerPixel : 1), seed_(seed) {}
    virtual ~Sampler() = default;

    virtual std::string_view name() const = 0;

    /// The pixel's key: (seed, pixel) hashed once, so that a camera sample's many values do not hash
    /// them again. Values depend on (seed, pixel) only through it.
    std::uint64_t pixelKey(std::uint64_t pixel) const { return mixSeed(seed_, pixel); }
    /// Value of dimension `dim` of sample `index` of a pattern of `count` samples (index < count) in
    /// the pixel with key `key`, in [0,1). The pixel's camera samples are the pattern of samplesPerPixel().
    virtual double value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const = 0;
    /// Values of the dimension pair (dim, dim+1), in [0,1)^2.
    virtual Point2 value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const = 0;
    /// The pair (dim, dim+1) as the second half of a 4D pattern whose first half is the pair `partner`:
    /// the samples' points in the two pairs are matched jointly instead of independently (sobol: Sobol'
    /// dimensions 2 and 3 at the index order of the partner pair). Each value stays uniform on its own.
    /// Default (samplers without a 4D pattern): value2D.
    virtual Point2 value2DJoint(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim,
                                std::uint64_t partner) const {
        (void)partner;
        return value2D(key, index, count, dim);
    }
    /// A 3D point: the pair (dim, dim+1) and, as z, the first value of value2DJoint(dim + 2, partner dim)
    /// (matched jointly with the pair where the sampler can). Samplers may compute it at once; the values
    /// are the same as the two calls'.
    virtual Vec3 value3D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {
        const Point2 p = value2D(key, index, count, dim);
        return {p.u, p.v, value2DJoint(key, index, count, dim + 2, dim).u};
    }

    /// Dimension `dim` of camera sample `index` of pixel `pixel`.
    double sample1D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
        return value1D(pixelKey(pixel), index, spp_, dim);
    }
    /// Dimensions (dim, dim+1) of camera sample `index` of pixel `pixel`.
    Point2 sample2D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
        return value2D(pixelKey(pixel), index, spp_, dim);
    }

    std::uint32_t samplesPerPixel() const { return spp_; }
    std::uint64_t seed() const { return seed_; }
    /// Whether value1D and value2D are SobolSampler's: SampleStream then computes them inline
    /// (SobolSampler::pairValue, singleValue), without a virtual call per value.
    bool isSobol() const { return sobol_; }

protected:
    bool sobol_ = false;

private:
    std::uint32_t spp_;
    std::uint64_t seed_;
};

/// Independent uniform values: PCG32, stream = the pixel key, state seeded from (sample index,
/// dimension); a 2D value is the first two doubles of its dimension's generator. Values of different
/// dimensions, samples or pixels are independent.
class IndependentSampler final : public Sampler {
public:
    using Sampler::Sampler;
    std::string_view name() const override { return "independent"; }
    double value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override;
    Point2 value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override;
};

/// Jittered strata in every dimension pair: Kensler's correlated multi-jittered pattern with an
/// m x n grid, m = floor(sqrt(N)), n = ceil(N/m). Every sample is alone in its y stratum of 1/N and in
/// its x sub-column of 1/(m n); for N = m n each of the m x n cells holds exactly one sample
/// (multi-jittered), otherwise the columns hold floor(N/m) or floor(N/m)+1 samples and a cell may hold
/// two. 1D dimensions: a permuted, jittered stratum of 1/N each. Permutations: permuteAny.
class StratifiedSampler final : public Sampler {
public:
    using Sampler::Sampler;
    std::string_view name() const override { return "stratified"; }
    double value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override;
    Point2 value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override;
};

/// Padded, Owen-scrambled Sobol' (0,2)-sequence: pair (dim, dim+1) of sample i is
///   (owen(sobol0(j), s0), owen(sobol1(j), s1)),  j = permute(i, spp, s2),
/// with s0, s1 the two halves of one 64-bit hash h of (pixel key, dim) and s2 the high half of h times
/// an odd constant; a 1D dimension is owen(sobol0(j), s0) with its own hash.
class SobolSampler final : public Sampler {
public:
    SobolSampler(std::uint32_t samplesPerPixel, std::uint64_t seed) : Sampler(samplesPerPixel, seed) { sobol_ = true; }
    std::string_view name() const override { return "sobol"; }
    double value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override {
        return singleValue(key, index, count, dim);
    }
    Point2 value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override {
        return pairValue(key, index, count, dim);
    }
    /// value1D: h = mixSeed(key, 2 dim + 1); owen(sobol_0(permute(index, count, high32(h))), low32(h)).
    static double singleValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) {
        const std::uint64_t h = mixSeed(key, 2 * dim + 1);
        const std::uint32_t j = permuteSamples(index, count, static_cast<std::uint32_t>(h >> 32));
        return fixedToUnit(owenScrambledSobol0(j, static_cast<std::uint32_t>(h)));
    }
    /// value2D: h = mixSeed(key, 2 dim), j = permute(index, count, pairPermutationSeed(h));
    /// (owen(sobol_0(j), low32(h)), owen(sobol_1(j), high32(h))).
    static Point2 pairValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) {
        const std::uint64_t h = mixSeed(key, 2 * dim);
        const std::uint32_t j = permuteSamples(index, count, pairPermutationSeed(h));
        return {fixedToUnit(owenScrambledSobol0(j, static_cast<std::uint32_t>(h))),
                fixedToUnit(owenScrambledSobol1(j, static_cast<std::uint32_t>(h >> 32)))};
    }
    /// Continuation j (< kBlockSize) of sample `index` as a block point (lowdiscrepancy.h blockPoint): the
    /// same scrambles and permutation as singleValue and pairValue, point blockPoint(permuted index, k, j)
    /// of the pattern of kBlockSize x count, k = the bits of count - 1.
    static double blockSingleValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim, std::uint32_t j) {
        const std::uint64_t h = mixSeed(key, 2 * dim + 1);
        const std::uint32_t a = permuteSamples(index, count, static_cast<std::uint32_t>(h >> 32));
        return fixedToUnit(owenScrambledSobol0(blockPoint(a, blockBits(count), j), static_cast<std::uint32_t>(h)));
    }
    static Point2 blockPairValue(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim, std::uint32_t j) {
        const std::uint64_t h = mixSeed(key, 2 * dim);
        const std::uint32_t point = blockPoint(permuteSamples(index, count, pairPermutationSeed(h)), blockBits(count), j);
        return {fixedToUnit(owenScrambledSobol0(point, static_cast<std::uint32_t>(h))),
                fixedToUnit(owenScrambledSobol1(point, static_cast<std::uint32_t>(h >> 32)))};
    }
    static std::uint32_t blockBits(std::uint32_t count) { return count <= 1 ? 0u : static_cast<std::uint32_t>(std::bit_width(count - 1)); }
    /// The seed of a pair's permutation of the pixel's sample indices, from its hash: the high half of h times an odd constant.
    static std::uint32_t pairPermutationSeed(std::uint64_t h) { return static_cast<std::uint32_t>((h * 0xD6E8FEB86659FD93ull) >> 32); }
    /// (owen(sobol_2(j), s_0'), owen(sobol_3(j), s_1')), j the partner pair's permuted index, s' hashed from dim.
    Point2 value2DJoint(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim,
                        std::uint64_t partner) const override;
    /// Sobol' dimensions 0, 1 and 2 at one permuted index: one permutation instead of two.
    Vec3 value3D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override;
};

/// Another sampler seen with one pair made joint: its pair (dim, dim+1) reads value2DJoint(dim, partner),
/// every other value is the sampler's own (the same seed, so the same pixel keys). The path tracer reads
/// the first hit's estimator through it for --joint-first-bounce, so that SampleStream::get2D stays a
/// plain call on the hot path.
class JointPairView final : public Sampler {
public:
    JointPairView(const Sampler& inner, std::uint64_t dim, std::uint64_t partner)
        : Sampler(inner.samplesPerPixel(), inner.seed()), inner_(inner), dim_(dim), partner_(partner) {}
    std::string_view name() const override { return inner_.name(); }
    double value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override {
        return inner_.value1D(key, index, count, dim);
    }
    Point2 value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override {
        return dim == dim_ ? inner_.value2DJoint(key, index, count, dim, partner_) : inner_.value2D(key, index, count, dim);
    }
    Point2 value2DJoint(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim,
                        std::uint64_t partner) const override {
        return inner_.value2DJoint(key, index, count, dim, partner);
    }
    Vec3 value3D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const override {
        return inner_.value3D(key, index, count, dim);
    }

private:
    const Sampler& inner_;
    std::uint64_t dim_, partner_;
};

/// Names accepted by makeSampler, in the order --help lists them.
const std::vector<std::string>& samplerNames();
/// One line per sampler for --help.
std::string samplerHelp();
/// The sampler used when none is named.
inline constexpr std::string_view kDefaultSampler = "sobol";
/// Creates a sampler; throws std::invalid_argument listing the valid names.
std::unique_ptr<Sampler> makeSampler(std::string_view name, std::uint32_t samplesPerPixel, std::uint64_t seed);

/// Values of a camera sample computed ahead of its stream's reads (the wavefront tracer's, in the lanes of
/// sobol_lanes.h): up to two pairs and one single dimension, each at its dimension number. A sobol stream
/// reading through them (SampleStream::readAhead) takes a value from here when its dimension is one of
/// these and computes it as usual otherwise: the same values either way.
struct AheadValues {
    static constexpr std::uint64_t kNone = ~std::uint64_t{0};
    std::uint64_t pairDims[2] = {kNone, kNone};
    Point2 pairs[2];
    std::uint64_t singleDim = kNone;
    double single = 0;
};

/// One camera sample's view of a sampler: the pixel and sample index fixed, dimensions handed out in
/// order from a position the caller sets. What estimators and the path tracer draw from.
class SampleStream {
public:
    /// No stream yet: a place in an array of streams, to be assigned one before it is read.
    SampleStream() = default;
    SampleStream(const Sampler& sampler, std::uint64_t pixel, std::uint32_t index, std::uint64_t dim = 0)
        : sampler_(&sampler),
          pixel_(pixel),
          key_(sampler.pixelKey(pixel)),
          index_(index),
          count_(sampler.samplesPerPixel()),
          sobol_(sampler.isSobol()),
          dim_(dim) {}

    /// Sub-sample j of k of this sample (first-hit splitting): sample index x k + j of a pattern of
    /// count x k samples of the same pixel, at the current dimension. The k sub-samples of the pixel's
    /// count samples are together one pattern of count x k (a stratified or low-discrepancy sampler
    /// stratifies them jointly), and each sub-sample's values are as uniform as a camera sample's.
    SampleStream split(std::uint32_t j, std::uint32_t k) const {
        SampleStream s = *this;
        s.index_ = subSampleIndex(index_, j, k);
        s.count_ = subSampleCount(count_, k);
        if (s.mode_ == kAheadMode) s.readAhead(nullptr);  // values ahead are this sample's, not a sub-sample's
        return s;
    }

    /// split's numbering, for a caller that reads the sub-samples' values itself (the wavefront's lanes):
    /// sub-sample j of k of sample `index` is sample index x k + j of a pattern of count x k.
    static std::uint32_t subSampleIndex(std::uint32_t index, std::uint32_t j, std::uint32_t k) { return index * k + j; }
    static std::uint32_t subSampleCount(std::uint32_t count, std::uint32_t k) { return count * k; }

    /// Continuation j (< kBlockSize) of this sample (--splitting ears at the first hit): sub-sample j of
    /// kBlockSize (split), except that under sobol get1D and get2D read point blockPoint(a, k, j) of the
    /// pattern of kBlockSize x count (a the dimension's permuted index of this sample): a sample's first 2^p
    /// continuations are then a net among themselves, and continuation j of the pixel's samples one net
    /// too (lowdiscrepancy.h). Everything else (get3D, the spread patterns) reads the split sub-sample.
    SampleStream blockContinuation(std::uint32_t j) const {
        SampleStream s = split(j, kBlockSize);
        s.mode_ = sobol_ ? kBlockMode : kPlainMode;
        return s;
    }

    void setDimension(std::uint64_t dim) { dim_ = dim; }
    /// Reads from now on take the values in `ahead` at their dimensions (a sobol stream that is not a
    /// block continuation; other streams ignore it); `ahead` must outlive the reads. nullptr: no longer.
    void readAhead(const AheadValues* ahead) {
        if (!sobol_ || mode_ == kBlockMode) return;
        ahead_ = ahead;
        mode_ = ahead ? kAheadMode : kPlainMode;
    }
    /// The same sample of the same pixel read through another sampler (e.g. a JointPairView of this one).
    SampleStream through(const Sampler& sampler) const {
        SampleStream s = *this;
        s.sampler_ = &sampler;
        s.sobol_ = sampler.isSobol();
        return s;
    }
    const Sampler& sampler() const { return *sampler_; }
    std::uint64_t dimension() const { return dim_; }
    double get1D() {
        const std::uint64_t d = dim_++;
        if (!sobol_) return sampler_->value1D(key_, index_, count_, d);
        if (mode_ == kBlockMode)
            return SobolSampler::blockSingleValue(key_, index_ / kBlockSize, count_ / kBlockSize, d, index_ % kBlockSize);
        if (mode_ == kAheadMode && ahead_->singleDim == d) return ahead_->single;
        return SobolSampler::singleValue(key_, index_, count_, d);  // one call each (GCC then inlines them)
    }
    Point2 get2D() {
        Point2 p;
        if (!sobol_)
            p = sampler_->value2D(key_, index_, count_, dim_);
        else if (mode_ == kBlockMode)
            p = SobolSampler::blockPairValue(key_, index_ / kBlockSize, count_ / kBlockSize, dim_, index_ % kBlockSize);
        else if (mode_ == kAheadMode && ahead_->pairDims[0] == dim_)
            p = ahead_->pairs[0];
        else if (mode_ == kAheadMode && ahead_->pairDims[1] == dim_)
            p = ahead_->pairs[1];
        else
            p = SobolSampler::pairValue(key_, index_, count_, dim_);
        dim_ += 2;
        return p;
    }
    /// The next pair's values for sample `index` of a pattern of `count` samples of this pixel
    /// (index < count): values shared by a group of camera samples.
    Point2 get2DOf(std::uint32_t index, std::uint32_t count) {
        const Point2 p = sampler_->value2D(key_, index, count, dim_);
        dim_ += 2;
        return p;
    }

    /// Spread pattern: the pixel's samples come in rounds of `entries`; this sample is entry
    /// perm(i mod entries) of round i / entries, with perm a hashed permutation (a random rotation of a
    /// scrambled order) of {0..entries-1} per (seed, pixel, dimension, round). Over a whole round every
    /// entry is taken once; for a random seed each sample's entry is uniform on its own. Uses one
    /// dimension (as a hash key).
    std::uint32_t patternEntry(std::uint32_t entries);
    /// Number of rounds of `entries` samples in the pixel: ceil(spp / entries).
    std::uint32_t patternRounds(std::uint32_t entries) const { return (samplesPerPixel() + entries - 1) / entries; }
    /// This sample's round.
    std::uint32_t patternRound(std::uint32_t entries) const { return index_ / entries; }
    /// The next pair's values shared by every sample of this sample's round: sample `round` of a
    /// pattern of patternRounds(entries) samples, so the rounds' points are themselves stratified.
    Point2 roundPoint(std::uint32_t entries) { return get2DOf(patternRound(entries), patternRounds(entries)); }
    /// Sampler::value3D at the next two pairs (x, y: the first pair; z: the joint third coordinate).
    Vec3 get3D() {
        const Vec3 p = sampler_->value3D(key_, index_, count_, dim_);
        dim_ += 4;
        return p;
    }
    /// The same, shared by every sample of this sample's round (a pattern over the rounds, as roundPoint).
    Vec3 roundPoint3D(std::uint32_t entries) {
        const Vec3 p = sampler_->value3D(key_, patternRound(entries), patternRounds(entries), dim_);
        dim_ += 4;
        return p;
    }
    /// The point of a pattern entry that uses point `pointIndex` of its set: with `shared`, the
    /// round's point from the pointIndex-th pair after the current dimension (roundPoint); otherwise this
    /// sample's own next pair.
    Point2 entryPoint(std::uint32_t entries, std::uint32_t pointIndex, bool shared) {
        if (!shared) return get2D();
        dim_ += 2 * static_cast<std::uint64_t>(pointIndex);
        return roundPoint(entries);
    }

    std::uint64_t pixel() const { return pixel_; }
    /// The pixel's key (Sampler::pixelKey): what the sampler hashes with each dimension.
    std::uint64_t pixelKey() const { return key_; }
    std::uint32_t sampleIndex() const { return index_; }
    /// Samples of the pattern this stream's sample belongs to: the pixel's spp, or spp x k for a split one.
    std::uint32_t samplesPerPixel() const { return count_; }
    std::uint64_t seed() const { return sampler_->seed(); }

private:
    const Sampler* sampler_ = nullptr;
    std::uint64_t pixel_ = 0, key_ = 0;
    std::uint32_t index_ = 0;
    std::uint32_t count_ = 0;  ///< samples of the pattern: the pixel's spp, or spp x k for a split stream
    bool sobol_ = false;       ///< sampler_ is a SobolSampler: its values inline
    static constexpr std::uint8_t kPlainMode = 0, kBlockMode = 1, kAheadMode = 2;
    /// How a sobol stream reads: its values as such; a blockContinuation's block points; or the values in
    /// ahead_ where their dimensions come (readAhead).
    std::uint8_t mode_ = kPlainMode;
    const AheadValues* ahead_ = nullptr;
    std::uint64_t dim_ = 0;
};

}  // namespace symphong
