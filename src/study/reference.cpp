// The study's reference: given (--reference), read from the cache in the output directory when its key
// matches, or made from a render and cached.
#include "io/files.h"
#include "io/input_error.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <cmath>

namespace fs = std::filesystem;

namespace symphong {

Reference existingReference(const StudyConfig& c, const fs::path& dir, const nlohmann::json& key) {
    Reference ref;
    const fs::path exr = dir / "reference.exr", json = dir / "reference.json";
    if (!c.referencePath.empty()) {
        ref.image = readExr(c.referencePath);
        if (ref.image.width != c.width || ref.image.height != c.height)
            throw InputError(fmt::format("--reference {}: {}x{} does not match the study's {}x{}", c.referencePath, ref.image.width,
                                         ref.image.height, c.width, c.height));
        ref.mean = meanLuminance(ref.image);
        ref.note = fmt::format("Reference: `{}` (given; its own noise is unknown and taken as zero).", c.referencePath);
        ref.have = true;
    } else if (fs::exists(exr) && fs::exists(json)) {
        try {
            const auto cached = nlohmann::json::parse(readTextFile(json.string()));
            if (cached.value("key", nlohmann::json()) == key) {
                ref.image = readExr(exr.string());
                ref.mean = {cached.at("mean_luminance").get<double>(), cached.at("mean_std_error").get<double>()};
                ref.noise = cached.at("pixel_variance").get<double>();
                ref.noiseSd = cached.at("noise_sd").get<double>();  // a cache written before it was kept: rendered again
                ref.have = ref.image.width == c.width && ref.image.height == c.height;
                ref.note = fmt::format("Reference: `{}` at {} spp, cached in reference.exr.", referenceMethod(c), c.referenceSpp);
            }
        } catch (const std::exception&) {
            ref = Reference{};  // a damaged cache is re-rendered
        }
    }
    return ref;
}

Reference referenceFromRender(const StudyConfig& c, const RenderResult& r, std::uint32_t spp) {
    Reference ref;
    ref.image = r.image;
    for (Color& p : ref.image.pixels)
        for (int ch = 0; ch < 3; ++ch) p[ch] = static_cast<float>(p[ch]);
    ref.mean = meanLuminance(ref.image, &r.variance);
    const auto pixels = static_cast<double>(r.variance.pixels.size());
    double fourth = 0;  // sum of sigma_p^4
    for (const Color& v : r.variance.pixels) {
        const double s2 = luminanceVariance(v);
        ref.noise += s2 / pixels;
        fourth += s2 * s2;
    }
    ref.noiseSd = pixels > 0 ? std::sqrt(2 * fourth) / pixels : 0.0;
    ref.note = fmt::format(
        "Reference: `{}` at {} spp{} ({:.1f} s), cached in reference.exr.", referenceMethod(c), spp,
        c.referenceError > 0 ? fmt::format(" (stopped at a relative error of its mean of {:.3g}%)", 100 * c.referenceError) : "",
        r.stats.seconds);
    ref.have = true;
    return ref;
}

void writeReferenceCache(const Reference& ref, const nlohmann::json& key, double seconds, const fs::path& dir) {
    writeExr(ref.image, (dir / "reference.exr").string(), false);
    writeFile((dir / "reference.json").string(), nlohmann::json{{"key", key},
                                                                {"mean_luminance", ref.mean.mean},
                                                                {"mean_std_error", ref.mean.stdError},
                                                                {"pixel_variance", ref.noise},
                                                                {"noise_sd", ref.noiseSd},
                                                                {"seconds", seconds}}
                                                         .dump(2) +
                                                     "\n");
}

}  // namespace symphong
