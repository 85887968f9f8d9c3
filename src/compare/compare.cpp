#include "compare/compare.h"

#include "compare/error_map.h"
#include "compare/image_file.h"
#include "compare/metrics.h"
#include "io/image.h"
#include "io/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace symphong {

namespace {

std::vector<std::string> flipKinds() { return {"auto", "hdr", "ldr", "off"}; }

void checkFlipKind(const std::string& v) {
    const auto kinds = flipKinds();
    if (std::find(kinds.begin(), kinds.end(), v) == kinds.end())
        throw std::invalid_argument(fmt::format("'{}' is not one of {}", v, fmt::join(kinds, ", ")));
}

}  // namespace

const schema::Schema<CompareOptions>& compareSchema() {
    using F = schema::Field<CompareOptions>;
    using O = CompareOptions;
    using schema::member;
    static const schema::Schema<CompareOptions> fields = [] {
        schema::Schema<CompareOptions> s;
        s.push_back(F("test", "test", "the image to measure (.exr, .pfm, .hdr, .png, .jpg)", member(&O::test))
                        .noDefaultShown()
                        .only(schema::kCli | schema::kJson));
        s.push_back(F("reference", "reference", "the reference image, same size", member(&O::reference))
                        .noDefaultShown()
                        .only(schema::kCli | schema::kJson));
        s.push_back(F("variance", "--variance",
                      "the test image's per-pixel variance of the mean (EXR or PFM, e.g. `symphong render --variance-output`): "
                      "gives the bias its standard error",
                      member(&O::variance))
                        .noDefaultShown()
                        .orNone());
        s.push_back(F("regions", "--regions",
                      "measure these regions too, separated by ';': rectangles X,Y,W,H (pixels, from the top left) or mask "
                      "images (each grey level above 0 is a region)",
                      member(&O::regions))
                        .noDefaultShown()
                        .orNone());
        s.push_back(F("error_map", "--error-map",
                      "write the signed relative error (Y - Y_ref) / (Y_ref + 0.01) in false colour with a colour bar (PNG)",
                      member(&O::errorMap))
                        .noDefaultShown()
                        .orNone());
        s.push_back(F("flip_map", "--flip-map", "write the FLIP error map (magma) with a colour bar (PNG)", member(&O::flipMap))
                        .noDefaultShown()
                        .orNone());
        s.push_back(F("error_range", "--error-range", "the error map's colour scale: from -R to +R (1 = 100%)", member(&O::errorRange))
                        .mustBePositive());
        s.push_back(F("pixels_per_degree", "--pixels-per-degree",
                      "FLIP's viewing condition (67: a 0.7 m wide 4K monitor seen from 0.7 m)", member(&O::pixelsPerDegree))
                        .mustBePositive());
        s.push_back(F("flip", "--flip", "FLIP kind: auto (LDR-FLIP when both images are 8-bit, HDR-FLIP otherwise), hdr, ldr or off",
                      member(&O::flip))
                        .namedFrom(flipKinds)
                        .checkedBy(checkFlipKind));
        s.push_back(F("json", "--json", "print the results as JSON", member(&O::json)).only(schema::kCli));
        return s;
    }();
    return fields;
}

namespace {

Region rectangleRegion(const std::string& spec, int width, int height) {
    int x = 0, y = 0, w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(spec.c_str(), "%d,%d,%d,%d%c", &x, &y, &w, &h, &tail) != 4)
        throw InputError(fmt::format("--regions: '{}' is neither X,Y,W,H nor an existing mask image", spec));
    if (w <= 0 || h <= 0 || x < 0 || y < 0 || x + w > width || y + h > height)
        throw InputError(fmt::format("--regions: rectangle {} is empty or leaves the {} x {} image", spec, width, height));
    Region r{spec, {}};
    for (int j = y; j < y + h; ++j)
        for (int i = x; i < x + w; ++i) r.pixels.push_back(static_cast<std::size_t>(j) * width + i);
    return r;
}

std::vector<Region> maskRegions(const std::string& path, int width, int height) {
    const Image mask = readImageFile(path).image;
    if (mask.width != width || mask.height != height)
        throw InputError(fmt::format("--regions: mask {} is {} x {}, the images {} x {}", path, mask.width, mask.height, width, height));
    std::map<int, Region> levels;  // by grey level, 0..255 of the mask's first channel as stored
    for (std::size_t i = 0; i < mask.pixels.size(); ++i) {
        const int level = static_cast<int>(std::lround(255 * std::clamp(mask.pixels[i].x, 0.0, 1.0)));
        if (level == 0) continue;
        Region& r = levels[level];
        if (r.name.empty()) r.name = fmt::format("{}={}", path, level);
        r.pixels.push_back(i);
    }
    if (levels.empty()) throw InputError(fmt::format("--regions: mask {} has no pixel above 0", path));
    std::vector<Region> out;
    for (auto& [level, r] : levels) out.push_back(std::move(r));
    return out;
}

RegionMetrics measureRegion(const Region& region, const Image& test, const Image& ref, const Image* variance, const FlipResult& flip) {
    RegionMetrics m;
    m.name = region.name;
    m.pixels = region.pixels.size();
    const double n = static_cast<double>(m.pixels);
    double varianceSum = 0;
    double flipSum = 0;
    for (std::size_t i : region.pixels) {
        const Color& t = test.pixels[i];
        const Color& r = ref.pixels[i];
        const double yt = luminance(t), yr = luminance(r), d = yt - yr;
        m.mse += d * d / n;
        m.relMse += d * d / (yr * yr + 0.01) / n;  // relMSE (Rousselle et al. 2011), as the study's
        for (int c = 0; c < 3; ++c) m.mseChannel[c] += (t[c] - r[c]) * (t[c] - r[c]) / n;
        m.meanTest += yt / n;
        m.meanReference += yr / n;
        if (variance) varianceSum += luminanceVariance(variance->pixels[i]);
        if (!flip.map.empty()) flipSum += flip.map[i];
    }
    m.rmse = std::sqrt(m.mse);
    for (int c = 0; c < 3; ++c) m.rmseChannel[c] = std::sqrt(m.mseChannel[c]);
    m.meanRatio = m.meanReference > 0 ? m.meanTest / m.meanReference : 0.0;
    // The mean of independent pixels: Var(mean) = sum of the pixels' variances / n^2.
    if (variance) m.biasStdError = std::sqrt(varianceSum) / n;
    if (!flip.map.empty()) m.flipMean = flipSum / n;
    return m;
}

void requireSameSize(const Image& a, const Image& b, const std::string& what) {
    if (a.width != b.width || a.height != b.height)
        throw InputError(fmt::format("{} is {} x {}, the reference {} x {}", what, a.width, a.height, b.width, b.height));
}

}  // namespace

std::vector<Region> parseRegions(const std::string& specs, int width, int height) {
    std::vector<Region> out;
    std::size_t start = 0;
    while (start <= specs.size() && !specs.empty()) {
        const std::size_t end = std::min(specs.find(';', start), specs.size());
        const std::string spec = specs.substr(start, end - start);
        start = end + 1;
        if (spec.empty()) continue;
        std::error_code ec;
        if (std::filesystem::is_regular_file(spec, ec)) {
            for (Region& r : maskRegions(spec, width, height)) out.push_back(std::move(r));
        } else {
            out.push_back(rectangleRegion(spec, width, height));
        }
    }
    return out;
}

Comparison compareImages(const Image& test, const Image& reference, const Image* variance, const std::vector<Region>& regions,
                         const std::string& flipKind, double pixelsPerDegree) {
    requireSameSize(test, reference, "the test image");
    if (variance) requireSameSize(*variance, reference, "the variance image");
    Comparison c;
    c.width = reference.width;
    c.height = reference.height;
    c.flipKind = flipKind;
    if (flipKind == "hdr") {
        HdrFlipOptions fo;
        fo.pixelsPerDegree = pixelsPerDegree;
        c.flip = hdrFlip(reference, test, fo);
    } else if (flipKind == "ldr") {
        c.flip = ldrFlip(reference, test, pixelsPerDegree);
    }
    Region whole{"image", {}};
    whole.pixels.resize(reference.pixels.size());
    for (std::size_t i = 0; i < whole.pixels.size(); ++i) whole.pixels[i] = i;
    c.regions.push_back(measureRegion(whole, test, reference, variance, c.flip));
    for (const Region& r : regions) c.regions.push_back(measureRegion(r, test, reference, variance, c.flip));
    return c;
}

Comparison compareLoaded(const Image& test, const Image& reference, const Image* variance, bool bothLowDynamicRange,
                         const CompareOptions& o) {
    if (test.width != reference.width || test.height != reference.height)
        throw InputError(fmt::format("{} is {} x {} but the reference {} is {} x {}", o.test, test.width, test.height, o.reference,
                                     reference.width, reference.height));
    if (variance && (variance->width != reference.width || variance->height != reference.height))
        throw InputError(fmt::format("--variance {} is {} x {}, the images {} x {}", o.variance, variance->width, variance->height,
                                     reference.width, reference.height));
    // Check the outputs before the work, so that a bad path fails now.
    if (!o.errorMap.empty()) checkErrorMapPath(o.errorMap, "--error-map");
    if (!o.flipMap.empty()) checkErrorMapPath(o.flipMap, "--flip-map");
    try {
        checkFlipKind(o.flip);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("--flip: {}", e.what()));
    }
    std::string kind = o.flip;
    if (kind == "auto") kind = bothLowDynamicRange ? "ldr" : "hdr";
    if (kind == "off" && !o.flipMap.empty()) throw InputError("--flip-map needs FLIP (--flip is off)");
    const std::vector<Region> regions = parseRegions(o.regions, reference.width, reference.height);
    Comparison c = compareImages(test, reference, variance, regions, kind, o.pixelsPerDegree);
    if (!o.errorMap.empty()) writeRelativeErrorMap(test, reference, o.errorRange, o.errorMap);
    if (!o.flipMap.empty()) writeFlipMap(c.flip, o.flipMap);
    return c;
}

Comparison runComparison(const CompareOptions& o) {
    const ImageFile test = readImageFile(o.test);
    const ImageFile ref = readImageFile(o.reference);
    std::optional<Image> variance;
    if (!o.variance.empty()) variance = readImageFile(o.variance).image;
    return compareLoaded(test.image, ref.image, variance ? &*variance : nullptr, test.lowDynamicRange && ref.lowDynamicRange, o);
}

namespace {

nlohmann::json metricsJson(const RegionMetrics& m) {
    nlohmann::json j = {{"name", m.name},
                        {"pixels", m.pixels},
                        {"mse", m.mse},
                        {"rmse", m.rmse},
                        {"relmse", m.relMse},
                        {"mse_rgb", {m.mseChannel.x, m.mseChannel.y, m.mseChannel.z}},
                        {"rmse_rgb", {m.rmseChannel.x, m.rmseChannel.y, m.rmseChannel.z}},
                        {"mean_test", m.meanTest},
                        {"mean_reference", m.meanReference},
                        {"mean_ratio", m.meanRatio},
                        {"bias", m.meanTest - m.meanReference},
                        {"relative_bias", m.meanReference > 0 ? (m.meanTest - m.meanReference) / m.meanReference : 0.0}};
    j["bias_std_error"] = m.biasStdError ? nlohmann::json(*m.biasStdError) : nlohmann::json();
    j["bias_z"] = m.biasStdError && *m.biasStdError > 0 ? nlohmann::json((m.meanTest - m.meanReference) / *m.biasStdError)
                                                         : nlohmann::json();
    j["flip"] = m.flipMean >= 0 ? nlohmann::json(m.flipMean) : nlohmann::json();
    return j;
}

}  // namespace

nlohmann::json comparisonJson(const Comparison& c, const CompareOptions& o) {
    nlohmann::json j = {{"test", o.test}, {"reference", o.reference}, {"width", c.width}, {"height", c.height}};
    j["variance"] = o.variance.empty() ? nlohmann::json() : nlohmann::json(o.variance);
    nlohmann::json flip = {{"kind", c.flipKind}, {"pixels_per_degree", o.pixelsPerDegree}};
    if (c.flipKind == "hdr")
        flip.update({{"start_exposure", c.flip.startExposure}, {"stop_exposure", c.flip.stopExposure}, {"exposures", c.flip.exposures}});
    j["flip"] = flip;
    j["image"] = metricsJson(c.regions.front());
    j["regions"] = nlohmann::json::array();
    for (std::size_t i = 1; i < c.regions.size(); ++i) j["regions"].push_back(metricsJson(c.regions[i]));
    j["error_map"] = o.errorMap.empty() ? nlohmann::json() : nlohmann::json(o.errorMap);
    j["flip_map"] = o.flipMap.empty() ? nlohmann::json() : nlohmann::json(o.flipMap);
    return j;
}

namespace {

std::string biasText(const RegionMetrics& m) {
    const double bias = m.meanTest - m.meanReference;
    const double rel = m.meanReference > 0 ? 100 * bias / m.meanReference : 0.0;
    if (!m.biasStdError) return fmt::format("{:+.4g} ({:+.3g}%)", bias, rel);
    const double z = *m.biasStdError > 0 ? bias / *m.biasStdError : 0.0;
    return fmt::format("{:+.4g} ({:+.3g}%) +- {:.2g}, z = {:+.2f}{}", bias, rel, *m.biasStdError, z,
                       std::abs(z) > 4 ? "  biased (|z| > 4)" : "");
}

}  // namespace

std::string comparisonText(const Comparison& c, const CompareOptions& o) {
    const RegionMetrics& m = c.regions.front();
    std::string out = fmt::format("{} against {} ({} x {} pixels)\n", o.test, o.reference, c.width, c.height);
    out += fmt::format("{:<22}{:>12}{:>12}{:>12}{:>12}\n", "", "luminance", "R", "G", "B");
    out += fmt::format("{:<22}{:>12.4g}{:>12.4g}{:>12.4g}{:>12.4g}\n", "MSE", m.mse, m.mseChannel.x, m.mseChannel.y, m.mseChannel.z);
    out += fmt::format("{:<22}{:>12.4g}{:>12.4g}{:>12.4g}{:>12.4g}\n", "RMSE", m.rmse, m.rmseChannel.x, m.rmseChannel.y, m.rmseChannel.z);
    out += fmt::format("{:<22}{:>12.4g}\n", "relMSE", m.relMse);
    out += fmt::format("{:<22}{:.6g} / {:.6g} = {:.4f}\n", "mean test / reference", m.meanTest, m.meanReference, m.meanRatio);
    out += fmt::format("{:<22}{}\n", "bias of the mean", biasText(m));
    if (c.flipKind == "hdr")
        out += fmt::format("{:<22}{:.4f}  (HDR-FLIP, {} exposures from {:+.2f} to {:+.2f} stops, {:g} pixels per degree)\n", "FLIP", m.flipMean,
                           c.flip.exposures, c.flip.startExposure, c.flip.stopExposure, o.pixelsPerDegree);
    else if (c.flipKind == "ldr")
        out += fmt::format("{:<22}{:.4f}  (LDR-FLIP, {:g} pixels per degree)\n", "FLIP", m.flipMean, o.pixelsPerDegree);
    if (c.regions.size() > 1) {
        out += fmt::format("\n{:<28}{:>9}{:>11}{:>11}{:>11}{:>9}{:>9}  {}\n", "region", "pixels", "RMSE", "relMSE", "mean", "ratio", "FLIP",
                           "bias");
        for (std::size_t i = 1; i < c.regions.size(); ++i) {
            const RegionMetrics& r = c.regions[i];
            out += fmt::format("{:<28}{:>9}{:>11.4g}{:>11.4g}{:>11.4g}{:>9.4f}{:>9}  {}\n", r.name, r.pixels, r.rmse, r.relMse, r.meanTest,
                               r.meanRatio, r.flipMean >= 0 ? fmt::format("{:.4f}", r.flipMean) : "-", biasText(r));
        }
    }
    if (!o.errorMap.empty()) out += fmt::format("error map: {}\n", o.errorMap);
    if (!o.flipMap.empty()) out += fmt::format("FLIP map: {}\n", o.flipMap);
    return out;
}

}  // namespace symphong
