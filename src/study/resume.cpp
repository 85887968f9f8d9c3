// A study continued in its output directory (--resume): the finished groups of rows of its results.json,
// when that file is of the same settings, and its reference's checkpoint.
#include "io/files.h"
#include "io/input_error.h"
#include "render/checkpoint.h"
#include "study/config.h"
#include "study/study_parts.h"

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace symphong {

StudyRow rowFromJson(const nlohmann::json& j) {
    StudyRow r;
    r.scene = j.at("scene"), r.estimator = j.at("estimator"), r.variant = j.at("variant"), r.sampler = j.at("sampler");
    r.mode = j.at("mode"), r.spp = j.at("spp"), r.repeat = j.at("repeat"), r.width = j.at("width"), r.height = j.at("height");
    r.seconds = j.at("seconds"), r.rays = j.at("rays"), r.samples = j.at("samples");
    r.meanLuminance = j.at("mean_luminance"), r.meanStdError = j.at("mean_luminance_std_error");
    r.relativeBias = j.at("relative_bias"), r.mseRaw = j.at("mse_raw"), r.mse = j.at("mse"), r.rmse = j.at("rmse");
    r.relMse = j.at("relmse"), r.efficiency = j.at("efficiency"), r.efficiencyRel = j.at("efficiency_relmse");
    r.pixelVarianceWithin = j.at("pixel_variance_within"), r.groupRelativeBias = j.at("group_relative_bias");
    r.groupBiasStdError = j.at("group_bias_std_error"), r.groupBiasZ = j.at("group_bias_z");
    r.groupBiasThreshold = j.at("group_bias_threshold"), r.groupBiasSignificant = j.at("group_bias_significant");
    r.groupPixelVariance = j.at("group_pixel_variance"), r.split = j.at("split");
    r.groupFirstBounceVariance = j.at("group_first_bounce_variance");
    r.cpuSeconds = j.at("cpu_seconds"), r.cost = j.at("cost"), r.paths = j.at("paths"), r.orbit = j.at("orbit");
    r.referenceSd = j.value("reference_sd", 0.0);  // absent from results written before it was kept
    return r;
}

KeptGroups keptGroups(const StudyConfig& c, const fs::path& dir, const std::function<void(const std::string&)>& say) {
    const fs::path file = dir / "results.json";
    std::error_code ec;
    if (!fs::exists(file, ec)) {
        say(fmt::format("no earlier results in {}: starting the study from the beginning", dir.string()));
        return {};
    }
    nlohmann::json saved;
    std::vector<StudyRow> rows;
    try {
        saved = nlohmann::json::parse(readTextFile(file.string()));
        for (const auto& row : saved.at("rows")) rows.push_back(rowFromJson(row));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(fmt::format("{}: cannot be resumed from ({}); remove it or choose another --out", file.string(), e.what()));
    }
    const nlohmann::json now = studyResultSettingsJson(c), before = saved.value("settings", nlohmann::json::object());
    // A setting that the study's build did not have yet (absent from its settings) was its default then.
    const nlohmann::json defaults = studyResultSettingsJson(StudyConfig{});
    const auto unchanged = [&](const std::string& key, const nlohmann::json& value) {
        return before.contains(key) ? before.at(key) == value : defaults.contains(key) && defaults.at(key) == value;
    };
    for (auto it = now.begin(); it != now.end(); ++it)
        if (!unchanged(it.key(), it.value()))
            throw InputError(fmt::format("{}: the earlier study had {} {}, not {}: resume with the same settings, or choose another --out",
                                         file.string(), it.key(), before.contains(it.key()) ? before.at(it.key()).dump() : "(not set)",
                                         it.value().dump()));
    KeptGroups groups;
    for (const StudyRow& r : rows) groups[{r.spp, r.variant}].push_back(r);
    // A group is finished with its first `repeats` rows; rows beyond them (--target-interval's rounds) are kept with it.
    for (auto it = groups.begin(); it != groups.end();)
        it = static_cast<int>(it->second.size()) >= c.repeats ? std::next(it) : groups.erase(it);
    say(fmt::format("resuming the study in {}: {} finished groups of rows kept", dir.string(), groups.size()));
    return groups;
}

void resumeReference(const fs::path& path, const RenderIdentity& identity, RenderState& state) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return;
    RenderIdentity saved;
    readCheckpoint(path.string(), saved, state);
    requireSameRender(path.string(), saved, identity);
    fmt::print(stderr, "symphong: resuming the reference from {}: {} of {} spp\n", path.string(), state.samplesReached(), state.sppBound);
}

}  // namespace symphong
