#include "render/checkpoint.h"

#include "io/files.h"
#include "io/input_error.h"
#include "render/describe.h"
#include "render/renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace symphong {

namespace {

constexpr char kMagic[] = "symphong checkpoint 1\n";
static_assert(std::endian::native == std::endian::little, "checkpoints are written little-endian");

/// A streaming 64-bit hash of bytes: four lanes of a multiply-xorshift over 8-byte words (32 bytes a
/// step, so the lanes' multiplications overlap), folded at the end; fast enough for a 4K checkpoint's
/// 464 MB, and any damage of a byte changes it. Data is added in blocks that are whole multiples of 32
/// bytes except the last of each section, so the writer and the reader fold identically.
class Hasher {
public:
    void add(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        std::size_t i = 0;
        for (; i + 32 <= n; i += 32) {
            std::uint64_t w[4];
            std::memcpy(w, p + i, 32);
            for (int k = 0; k < 4; ++k) lane_[k] = mix(lane_[k], w[k]);
        }
        for (; i + 8 <= n; i += 8) {
            std::uint64_t w;
            std::memcpy(&w, p + i, 8);
            lane_[0] = mix(lane_[0], w);
        }
        std::uint64_t tail = 0;
        std::memcpy(&tail, p + i, n - i);
        lane_[0] = mix(lane_[0], tail ^ (static_cast<std::uint64_t>(n - i) << 56));
    }
    std::uint64_t value() const {
        std::uint64_t h = 0x243F6A8885A308D3ull;
        for (std::uint64_t l : lane_) h = mix(h, l);
        return h;
    }

private:
    static std::uint64_t mix(std::uint64_t h, std::uint64_t w) {
        h = (h ^ w) * 0x9E3779B97F4A7C15ull;
        return h ^ (h >> 29);
    }
    std::uint64_t lane_[4] = {1, 2, 3, 4};
};

/// Calls fn(pointer, bytes) for [data, data + n) in blocks of at most 64 MiB (a multiple of 32 bytes).
template <class Fn>
void inBlocks(const void* data, std::size_t n, Fn&& fn) {
    constexpr std::size_t kBlock = std::size_t{64} << 20;
    const auto* p = static_cast<const char*>(data);
    for (std::size_t at = 0; at < n; at += kBlock) fn(p + at, std::min(kBlock, n - at));
}

std::string hex(std::uint64_t v) { return fmt::format("{:016x}", v); }

/// The first pixel whose sums no render writes (the renderer discards non-finite samples; a sum of squares
/// is >= 0): a resumed render would carry it into every image. sum.size() when there is none.
std::size_t firstUnwrittenSum(const RenderState& state) {
    for (std::size_t i = 0; i < state.sum.size(); ++i)
        if (!isFinite(state.sum[i]) || !isFinite(state.sumSq[i]) || !(minComponent(state.sumSq[i]) >= 0) ||
            !std::isfinite(state.sumLuminanceSq[i]) || !(state.sumLuminanceSq[i] >= 0))
            return i;
    return state.sum.size();
}

/// --splitting ears's learning (render/render_state.h) as sections: the cells that have factors and the
/// cells that have sums, each cell's number then its values. Empty when the render does not learn.
struct EarsSections {
    std::vector<std::uint32_t> factorCells;
    std::vector<float> factorRatios;                     ///< four a cell: sqrt(v / C_x), sqrt(M / C_x), the first hit's q and MIS share
    std::size_t valuesPerCell = ears::Factors::kTables;  ///< three in checkpoints written before the MIS share (it reads as -1)
    std::vector<std::uint32_t> sumCells;
    std::vector<ears::CellSums> sums;
};
static_assert(sizeof(ears::CellSums) == 48, "CellSums is six packed 64-bit words");

EarsSections packEars(const std::optional<ears::Learning>& learning) {
    EarsSections e;
    if (!learning) return e;
    const ears::Factors& f = learning->factors;
    const auto tables = f.tables();
    for (std::size_t c = 0; c < f.momentRatio.size(); ++c)
        if (std::any_of(tables.begin(), tables.end(), [c](const std::vector<float>* t) { return (*t)[c] >= 0; })) {
            e.factorCells.push_back(static_cast<std::uint32_t>(c));
            for (const std::vector<float>* t : tables) e.factorRatios.push_back((*t)[c]);
        }
    const ears::SumTable& sums = learning->sums();
    for (std::size_t c = 0; c < sums.size(); ++c)
        if (!sums[c].empty()) {
            e.sumCells.push_back(static_cast<std::uint32_t>(c));
            e.sums.push_back(sums[c]);
        }
    return e;
}

/// The sections after the header, in file order: pointer and byte count.
template <class State, class Ears, class Fn>
void forEachSection(State& s, Ears& e, Fn&& fn) {
    fn(s.tileSamples.data(), s.tileSamples.size() * sizeof(std::uint32_t));
    fn(s.sum.data(), s.sum.size() * sizeof(Color));
    fn(s.sumSq.data(), s.sumSq.size() * sizeof(Color));
    fn(s.sumLuminanceSq.data(), s.sumLuminanceSq.size() * sizeof(double));
    fn(e.factorCells.data(), e.factorCells.size() * sizeof(std::uint32_t));
    fn(e.factorRatios.data(), e.factorRatios.size() * sizeof(float));
    fn(e.sumCells.data(), e.sumCells.size() * sizeof(std::uint32_t));
    fn(e.sums.data(), e.sums.size() * sizeof(ears::CellSums));
}

nlohmann::json earsHeader(const ears::Learning& l, const EarsSections& e) {
    return {{"epoch", l.epoch},
            {"probed", l.probed},
            {"lo", {l.grid.lo().x, l.grid.lo().y, l.grid.lo().z}},
            {"hi", {l.grid.hi().x, l.grid.hi().y, l.grid.hi().z}},
            {"scale", l.factors.scale},
            {"has_factors", !l.factors.empty()},
            {"rays_at_start", l.raysAtStart},
            {"samples_at_start", l.samplesAtStart},
            {"paths_at_start", l.pathsAtStart},
            {"resting", l.resting},
            {"variance_at_start", l.varianceAtStart},
            {"factor_cells", e.factorCells.size()},
            {"factor_values", e.valuesPerCell},
            {"sum_cells", e.sumCells.size()}};
}

/// The learning of a checkpoint's "ears" header, its sections sized (read into them next).
ears::Learning earsFromHeader(const nlohmann::json& j, EarsSections& e) {
    const auto vec = [&](const char* key) {
        const auto a = j.at(key).get<std::vector<double>>();
        if (a.size() != 3) throw std::invalid_argument(fmt::format("ears {}: 3 numbers expected", key));
        return Vec3(a[0], a[1], a[2]);
    };
    // Counts are checked against their types before they are converted (as the header's, fuzz finding C1).
    const auto count = [&](const char* key) {
        if (!j.at(key).is_number_unsigned()) throw std::invalid_argument(fmt::format("ears {}: {} is not a count", key, j.at(key).dump()));
        return j.at(key).get<std::uint64_t>();
    };
    const Vec3 lo = vec("lo"), hi = vec("hi");
    if (!isFinite(lo) || !isFinite(hi) || !(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z))
        throw std::invalid_argument("ears: its grid's box is empty or not finite");
    ears::Learning l(ears::Grid::fromBox(lo, hi));
    const std::uint64_t epoch = count("epoch"), factorCells = count("factor_cells"), sumCells = count("sum_cells");
    l.raysAtStart = count("rays_at_start");
    l.samplesAtStart = count("samples_at_start");
    // "paths_at_start" and "resting" are absent from checkpoints written before EARS could rest: it did not,
    // and the epoch of such a checkpoint cannot decide to (its paths at its start unknown).
    l.pathsAtStart = j.contains("paths_at_start") ? count("paths_at_start") : ears::kUnknownPaths;
    if (j.contains("resting")) {
        if (!j.at("resting").is_boolean())
            throw std::invalid_argument(fmt::format("ears resting: {} is not true or false", j.at("resting").dump()));
        l.resting = j.at("resting").get<bool>();
    }
    l.varianceAtStart = j.at("variance_at_start").get<double>();
    if (!std::isfinite(l.varianceAtStart) || l.varianceAtStart < 0) throw std::invalid_argument("ears: variance_at_start is not a finite number >= 0");
    if (epoch > 32 || factorCells > ears::Grid::cellCount() || sumCells > ears::Learning::sumCount())
        throw std::invalid_argument("ears: epoch or cell counts out of range");
    l.epoch = static_cast<int>(epoch);
    // "probed" (the learning pass before the first sample) is absent from checkpoints written before it
    // existed: those renders had none, and a resumed one (past its first sample) runs none.
    if (j.contains("probed")) {
        if (!j.at("probed").is_boolean()) throw std::invalid_argument(fmt::format("ears probed: {} is not true or false", j.at("probed").dump()));
        l.probed = j.at("probed").get<bool>();
    }
    if (j.at("has_factors").get<bool>()) {
        l.factors.scale = j.at("scale").get<double>();
        if (!std::isfinite(l.factors.scale) || l.factors.scale < 0) throw std::invalid_argument("ears: its scale is not a finite number >= 0");
        l.factors.reset(ears::Grid::cellCount());
    }
    // "factor_values" is absent from checkpoints written before the first hit's MIS share: three a cell.
    e.valuesPerCell = j.contains("factor_values") ? count("factor_values") : 3;
    if (e.valuesPerCell != 3 && e.valuesPerCell != ears::Factors::kTables)
        throw std::invalid_argument(fmt::format("ears factor_values: {} is not 3 or {}", e.valuesPerCell, ears::Factors::kTables));
    e.factorCells.resize(factorCells);
    e.factorRatios.resize(e.valuesPerCell * factorCells);
    e.sumCells.resize(sumCells);
    e.sums.resize(sumCells);
    return l;
}

/// The sections read into the learning; what no render writes, or "": a cell number out of range, factors
/// without a table for them, or a factor that learnFactors cannot give (a NaN or an infinity there would
/// reach a resumed render's MIS weights: its samples discarded as bad, a black image).
std::string unpackEars(const EarsSections& e, ears::Learning& l) {
    const std::size_t cells = ears::Grid::cellCount();
    if (!e.factorCells.empty() && l.factors.empty())
        return "its learned splitting lists factor cells, but its header says it has no factors";
    const auto tables = l.factors.tables();  // a three-value checkpoint leaves the last (misShare) at -1
    for (std::size_t i = 0; i < e.factorCells.size(); ++i) {
        if (e.factorCells[i] >= cells) return "its learned splitting names a cell out of range";
        const float* v = &e.factorRatios[e.valuesPerCell * i];
        for (std::size_t k = 0; k < e.valuesPerCell; ++k) {
            if (!l.factors.learnedValue(*tables[k], v[k]))
                return fmt::format("its learned splitting holds a factor that no render writes: {} in cell {}", v[k], e.factorCells[i]);
            (*tables[k])[e.factorCells[i]] = v[k];
        }
    }
    for (std::size_t i = 0; i < e.sumCells.size(); ++i) {
        if (e.sumCells[i] >= l.sums().size()) return "its learned splitting names a cell out of range";
        l.add(e.sumCells[i], e.sums[i]);
    }
    return {};
}

/// The size of the file a stream reads (its position kept): not of whatever its path names now, which
/// another render's checkpoint renamed over it meanwhile would make one file's header and another's size.
std::streamoff sizeOf(std::istream& in) {
    const std::streamoff here = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(here);
    return in ? size : -1;
}

nlohmann::json headerOf(const RenderIdentity& id, const RenderState& s) {
    return {{"scene", id.scene},
            {"scene_hash", id.sceneHash},
            {"settings", id.settings},
            {"width", s.width},
            {"height", s.height},
            {"spp", s.sppBound},
            {"samples_reached", s.samplesReached()},
            {"rays", s.rays},
            {"bad_samples", s.badSamples},
            {"samples", s.samples},
            {"paths", s.paths},
            {"seconds", s.seconds},
            {"cpu_seconds", s.cpuSeconds}};
}

}  // namespace

static_assert(sizeof(Color) == 3 * sizeof(double), "Color is three packed doubles");

std::string sceneFingerprint(const Scene& scene, const std::string& spec) {
    Hasher h;
    std::error_code ec;
    if (std::filesystem::is_regular_file(spec, ec)) {
        std::ifstream in(spec, std::ios::binary);
        std::vector<char> buffer(1 << 20);
        while (in) {
            in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
            h.add(buffer.data(), static_cast<std::size_t>(in.gcount()));
        }
    } else {
        h.add(spec.data(), spec.size());
    }
    const std::string description = describeScene(scene, spec);
    h.add(description.data(), description.size());
    return hex(h.value());
}

void writeCheckpoint(const std::string& path, const RenderIdentity& identity, const RenderState& state) {
    writeDurably(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        Hasher h;
        const auto put = [&](const void* data, std::size_t n) {
            inBlocks(data, n, [&](const char* block, std::size_t size) {
                out.write(block, static_cast<std::streamsize>(size));
                h.add(block, size);
            });
        };
        const EarsSections ears = packEars(state.ears);
        nlohmann::json head = headerOf(identity, state);
        if (state.ears) head["ears"] = earsHeader(*state.ears, ears);
        const std::string header = head.dump() + "\n";
        put(kMagic, sizeof kMagic - 1);
        put(header.data(), header.size());
        forEachSection(state, ears, put);
        const std::uint64_t checksum = h.value();
        out.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
        out.close();
        if (!out) throw std::runtime_error("write failed (disk full?)");
    });
}

void readCheckpoint(const std::string& path, RenderIdentity& identity, RenderState& state) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open the checkpoint", path));
    readCheckpoint(in, path, identity, state);
}

void readCheckpoint(std::istream& in, const std::string& path, RenderIdentity& identity, RenderState& state) {
    const auto damaged = [&](const std::string& why) {
        return InputError(fmt::format("{}: not a usable checkpoint ({}); delete it to start the render again", path, why));
    };
    Hasher h;
    std::string magic(sizeof kMagic - 1, '\0');
    in.read(magic.data(), static_cast<std::streamsize>(magic.size()));
    if (!in || magic != kMagic) throw damaged("it does not start with \"symphong checkpoint 1\"");
    h.add(magic.data(), magic.size());
    std::string line;
    if (!std::getline(in, line)) throw damaged("no header");
    line += "\n";
    h.add(line.data(), line.size());
    nlohmann::json header;
    EarsSections ears;
    try {
        header = nlohmann::json::parse(line);
        // The header's numbers are checked against their types before they are converted (a 1e30 read
        // as an integer is undefined behaviour, a -1 read as unsigned a wrapped count; fuzz finding C1).
        const auto count = [&](const char* key, std::uint64_t max) {
            const nlohmann::json& v = header.at(key);
            if (!v.is_number_unsigned() || v.get<std::uint64_t>() > max)
                throw damaged(fmt::format("its header's {} is {}, not an integer from 0 to {}", key, v.dump(), max));
            return v.get<std::uint64_t>();
        };
        const auto seconds = [&](const char* key) {
            const nlohmann::json& v = header.at(key);
            if (!v.is_number() || !(v.get<double>() >= 0) || !std::isfinite(v.get<double>()))
                throw damaged(fmt::format("its header's {} is {}, not a number of seconds", key, v.dump()));
            return v.get<double>();
        };
        identity = {header.at("scene").get<std::string>(), header.at("scene_hash").get<std::string>(), header.at("settings")};
        const auto w = static_cast<int>(count("width", std::numeric_limits<int>::max()));
        const auto ht = static_cast<int>(count("height", std::numeric_limits<int>::max()));
        const auto spp = static_cast<std::uint32_t>(count("spp", std::numeric_limits<std::uint32_t>::max()));
        if (w < 1 || ht < 1 || static_cast<long>(w) * ht > kMaxImagePixels || spp < 1)
            throw damaged("its image size or spp is out of range");
        requireImageMemory(w, ht);
        state = RenderState(w, ht, spp);
        constexpr std::uint64_t kAny = std::numeric_limits<std::uint64_t>::max();
        state.rays = count("rays", kAny);
        state.badSamples = count("bad_samples", kAny);
        state.samples = count("samples", kAny);
        state.seconds = seconds("seconds");
        // Written since the study measured cost by CPU time; an older checkpoint has neither.
        state.paths = header.contains("paths") ? count("paths", kAny) : state.samples;
        state.cpuSeconds = header.contains("cpu_seconds") ? seconds("cpu_seconds") : 0.0;
        if (header.contains("ears")) state.ears = earsFromHeader(header.at("ears"), ears);
    } catch (const nlohmann::json::exception& e) {
        throw damaged(fmt::format("its header: {}", e.what()));
    } catch (const std::invalid_argument& e) {
        throw damaged(fmt::format("its header: {}", e.what()));
    }
    std::uint64_t expected = 0;
    forEachSection(state, ears, [&](void*, std::size_t n) { expected += n; });
    const std::streamoff start = in.tellg(), size = sizeOf(in);
    if (start < 0 || size < 0 || static_cast<std::uint64_t>(size) != static_cast<std::uint64_t>(start) + expected + sizeof(std::uint64_t))
        throw damaged(fmt::format("{} bytes where its header needs {}: truncated or overwritten", size, start + expected + 8));
    forEachSection(state, ears, [&](void* data, std::size_t n) {
        inBlocks(data, n, [&](const char* block, std::size_t size) {
            in.read(const_cast<char*>(block), static_cast<std::streamsize>(size));
            h.add(block, size);
        });
    });
    std::uint64_t checksum = 0;
    in.read(reinterpret_cast<char*>(&checksum), sizeof checksum);
    if (!in || checksum != h.value()) throw damaged("its checksum does not match its contents");
    for (std::uint32_t n : state.tileSamples)
        if (n > state.sppBound) throw damaged("a tile has more samples than the render's spp");
    if (state.ears)
        if (const std::string why = unpackEars(ears, *state.ears); !why.empty()) throw damaged(why);
    // What no render writes, even under a matching checksum (fuzz finding C2).
    if (const std::size_t i = firstUnwrittenSum(state); i < state.sum.size())
        throw damaged(fmt::format("pixel ({}, {}) holds a sum that no render writes: not finite, or a negative sum of squares",
                                  i % static_cast<std::size_t>(state.width), i / static_cast<std::size_t>(state.width)));
}

void requireSameRender(const std::string& path, const RenderIdentity& saved, const RenderIdentity& now) {
    if (saved.sceneHash != now.sceneHash)
        throw InputError(
            fmt::format("{}: the checkpoint is of another scene ({}, fingerprint {}), not of {} (fingerprint {}) as it is "
                        "now; render the same scene, or delete the checkpoint to start again",
                        path, saved.scene, saved.sceneHash, now.scene, now.sceneHash));
    const auto text = [](const nlohmann::json& j, const std::string& key) { return j.contains(key) ? j.at(key).dump() : "(not set)"; };
    for (const auto& source : {now.settings, saved.settings})
        for (auto it = source.begin(); it != source.end(); ++it)
            if (text(saved.settings, it.key()) != text(now.settings, it.key()))
                throw InputError(
                    fmt::format("{}: the checkpoint was made with {} {}, not {}: resume with the same settings, or delete it to "
                                "start again",
                                path, it.key(), text(saved.settings, it.key()), text(now.settings, it.key())));
}

}  // namespace symphong
