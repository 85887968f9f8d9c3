// render/renderer.h — the image loop: pixels in 16x16 tiles spread over oneTBB; every random number of
// camera sample i of pixel p comes from the sampler as a pure function of (seed, p, i, dimension), so
// the same seed gives the same image bit for bit at any thread count. Also keeps the per-pixel variance
// of the mean for statistical comparisons.
#pragma once

#include "io/image.h"
#include "render/path_tracer.h"
#include "render/render_state.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace symphong {

/// The most pixels an image may have (its three double buffers then take 4.5 GiB); the command line
/// and the Python module refuse larger sizes as bad input.
inline constexpr long kMaxImagePixels = 64L * 1024 * 1024;

/// What an image takes while it renders: its running sums (RenderState, 56 bytes a pixel) and the mean
/// and variance images made from them (48).
inline constexpr std::uint64_t kImageBytesPerPixel = 104;

/// Refuses (InputError) an image whose render buffers (kImageBytesPerPixel) would need more than
/// io/memory.h allows.
void requireImageMemory(int width, int height);

/// Images are rendered in square tiles of this many pixels, numbered row by row from the top left.
inline constexpr int kRenderTile = 16;

/// Number of tiles of a width x height image.
int tileCount(int width, int height);

/// Pixels [x0, x1) x [y0, y1) of tile `tile` (edge tiles are cut at the image's border).
void tileRect(int tile, int width, int height, int& x0, int& y0, int& x1, int& y1);

/// Calls fn(x, y, pixel) for every pixel of tile `tile` of a width x height image, row by row, with
/// pixel = y width + x its index in the image: the one loop over a tile's pixels (the render, the
/// state's images, the MPI messages).
template <class Fn>
void forEachTilePixel(int tile, int width, int height, Fn&& fn) {
    int x0, y0, x1, y1;
    tileRect(tile, width, height, x0, y0, x1, y1);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) fn(x, y, static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
}

/// Where a render's tiles come from when a render is shared with other processes (distrib/): every
/// worker thread calls next() until it returns false, so next() must be thread-safe. A tile's pixels
/// depend only on its number, never on who renders it or when.
class TileSource {
public:
    virtual ~TileSource() = default;
    virtual bool next(int& tile) = 0;
};

struct RenderSettings {
    int width = 512, height = 512;
    std::uint32_t spp = 64;
    std::uint64_t seed = 1;
    std::string sampler = std::string(kDefaultSampler);  ///< unless the estimator requires its own
    int threads = 0;                                     ///< 0: all hardware threads
    TraceSettings trace;
    /// --splitting ears's roulette floor (TraceSettings::earsRouletteFloor) forced on or off (tests);
    /// unset, the renderer decides: on unless the render's sampler is one of independent values.
    std::optional<bool> earsRouletteFloor;
    /// When set and it becomes true, remaining tiles are skipped and the result is marked cancelled.
    const std::atomic<bool>* cancel = nullptr;
    /// Called on the worker thread after each finished tile (cancelled tiles are not finished); tests
    /// use it to cancel after a known number of tiles.
    std::function<void()> onTileDone;
    /// Null: every tile, shared among this process's threads. Otherwise only the tiles it gives out;
    /// the other pixels of the result stay zero.
    TileSource* tiles = nullptr;
};

struct RenderStats {
    double seconds = 0;     ///< wall time
    double cpuSeconds = 0;  ///< CPU time of the process's threads while it rendered (under MPI: summed over the ranks)
    std::uint64_t rays = 0;
    std::uint64_t samples = 0;     ///< camera samples
    std::uint64_t paths = 0;       ///< paths started: one per camera sample, plus each further ray a first-hit split or set traces
    std::uint64_t badSamples = 0;  ///< non-finite contributions discarded
};

struct RenderResult {
    Image image;     ///< per-pixel mean radiance
    Image variance;  ///< per-pixel variance of that mean (sample variance / spp), per channel
    RenderStats stats;
    std::string sampler;     ///< the sampler used (the estimator's own where it requires one)
    bool cancelled = false;  ///< stopped early through RenderSettings::cancel: the image is incomplete
};

/// The primary rays of a camera for a w x h image: its basis and scale computed once, so that each ray
/// costs one normalisation (the render's loop makes one per camera sample).
struct CameraRays {
    CameraRays(const Camera& cam, int width, int height);
    /// The ray through image point (px, py) (pixels, origin top-left):
    ///   d = normalize(forward + right x sx + up x sy),  sx = (2 px / w - 1) tan(fovY/2) w/h,  sy = (1 - 2 py / h) tan(fovY/2).
    void operator()(double px, double py, Vec3& origin, Vec3& dir) const {
        const double sx = (2.0 * px / width - 1.0) * tanHalf * aspect;
        const double sy = (1.0 - 2.0 * py / height) * tanHalf;
        origin = position;
        dir = normalize(forward + right * sx + up * sy);
    }
    Vec3 position, forward, right, up;
    double tanHalf, aspect;
    int width, height;
};

/// Primary ray through image point (px, py) (pixels, origin top-left) of a w x h image (CameraRays made
/// for one ray: the same values).
void cameraRay(const Camera& cam, int width, int height, double px, double py, Vec3& origin, Vec3& dir);

/// Takes every tile of `state` (or those settings.tiles gives out) from its own count of samples up to
/// `upTo` (at most state.sppBound, the sampler's pattern size), adding each sample to its pixel's sums in
/// the order of its index; adds the rays, samples and time to the state. A cancellation
/// (settings.cancel) skips the tiles not yet begun: each tile is either taken to `upTo` or left as it was.
/// settings.width and height must be the state's; settings.spp is not used (state.sppBound is).
/// With --splitting ears it goes epoch by epoch (splitting/learning.h): every tile to the end of the
/// epoch, then the next epoch's factors (endEpochIfDone), and so on up to `upTo`.
void renderSamples(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state,
                   std::uint32_t upTo, std::atomic<std::uint64_t>* progress = nullptr);

/// The path tracer for renders of `state` with these settings, to be kept for many calls of the
/// renderSamples below (passes: making one goes over every triangle, its area and normal and the emitters,
/// 0.2 s on a 2M-triangle mesh). With --splitting ears it starts the state's learning. Its time counts in
/// the state's.
std::unique_ptr<PathTracer> makeTracer(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                       RenderState& state);
/// renderSamples with a tracer from makeTracer for this state, scene and settings (the same result).
void renderSamples(PathTracer& tracer, const Estimator& estimator, const RenderSettings& settings, RenderState& state, std::uint32_t upTo,
                   std::atomic<std::uint64_t>* progress = nullptr);

/// renderSamples within one epoch of --splitting ears (`upTo` at most the end of the epoch the state is
/// in): the tiles' continuations are added to the epoch's sums in state.ears. What distrib/ runs on
/// each rank between two exchanges of what was learned.
void renderSegment(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state,
                   std::uint32_t upTo, std::atomic<std::uint64_t>* progress = nullptr);

/// --splitting ears: the state's learning, made over the scene's bounds when it has none yet.
void startLearning(const Scene& scene, RenderState& state);

/// --splitting ears: the learning pass before the image's first sample (splitting/learning.h "probe"),
/// once per render (state.ears->probed; a checkpoint carries it): ears::kProbeSamples camera samples of
/// another seed's pattern in one pixel of every 2 x 2, traced with the unlearned factors and recorded,
/// never added to the image. Its records, rays and per-pixel variance give the factors of the image's
/// epoch 0 (ears::Learning::learnFromProbe); its rays and paths count in the state's. Nothing when the
/// render has fewer than ears::kProbeMinSpp samples a pixel (epoch 0 then renders unlearned) or the
/// probe already ran. Deterministic: the same factors at any thread count. Cancelled (settings.cancel)
/// part way, it learns nothing and leaves the probe to be run again.
void probeLearning(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state);

/// --splitting ears: when every tile has finished the state's epoch, learns the next epoch's factors
/// (from the epoch's sums, the rays and samples since it began and the image's variance per sample) and
/// returns true. `mayRest` (earsMayRest): an epoch that split nothing lets EARS rest for the rest of the
/// render (ears::kRestBelowExtraPaths). False, and nothing learned, once it rests.
bool endEpochIfDone(RenderState& state, bool mayRest = false);
/// Whether a render's EARS may rest: its roulette is floored at plain roulette's (TraceSettings::
/// earsRouletteFloor: a low-discrepancy sampler), so that factors that split nothing differ from plain
/// roulette only by keeping a few more paths (under the independent sampler their roulette may be harder).
bool earsMayRest(const Estimator& estimator, const RenderSettings& settings);

/// The image, variance and statistics of a state (the sampler's name recorded as given).
RenderResult resultOf(const RenderState& state, const std::string& sampler);

/// Renders the scene in one pass of settings.spp samples. `progress`, when given, is advanced by the
/// number of camera samples finished.
RenderResult render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                    std::atomic<std::uint64_t>* progress = nullptr);

/// The version of oneTBB this program was built with, and the one loaded at run time.
std::string tbbVersion();

}  // namespace symphong
