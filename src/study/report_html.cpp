#include "study/report_html.h"

#include "compare/flip.h"
#include "compare/metrics.h"
#include "io/files.h"
#include "study/answer.h"
#include "study/report_viewer.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>

namespace fs = std::filesystem;

namespace symphong {

std::uint16_t halfOf(float v) {
    const std::uint32_t f = std::bit_cast<std::uint32_t>(v);
    const auto sign = static_cast<std::uint16_t>((f >> 16) & 0x8000u);
    const std::uint32_t a = f & 0x7fffffffu;
    if (a >= 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7c00u | (a > 0x7f800000u ? 0x200u : 0u));  // inf, NaN
    if (a >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // >= 65520 rounds to infinity
    if (a < 0x38800000u) {  // below 2^-14: a subnormal half m * 2^-24 (the scaling by 2^24 is exact)
        const float m = std::nearbyint(std::bit_cast<float>(a) * 16777216.0f);  // ties to even
        return static_cast<std::uint16_t>(sign | static_cast<std::uint16_t>(m));
    }
    std::uint32_t h = ((((a >> 23) - 127 + 15) << 10) | ((a & 0x7fffffu) >> 13));
    const std::uint32_t rest = a & 0x1fffu;  // the 13 bits dropped: round to nearest, ties to even
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;
    return static_cast<std::uint16_t>(sign | h);
}

float floatOfHalf(std::uint16_t h) {
    const int e = (h >> 10) & 0x1f, m = h & 0x3ff;
    const float s = (h & 0x8000) ? -1.0f : 1.0f;
    if (e == 0) return s * std::ldexp(static_cast<float>(m), -24);
    if (e == 31) return m ? std::numeric_limits<float>::quiet_NaN() : s * std::numeric_limits<float>::infinity();
    return s * std::ldexp(static_cast<float>(1024 + m), e - 25);
}

std::string base64(const unsigned char* data, std::size_t size) {
    static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((size + 2) / 3 * 4);
    for (std::size_t i = 0; i < size; i += 3) {
        const std::uint32_t n = (static_cast<std::uint32_t>(data[i]) << 16) | (i + 1 < size ? data[i + 1] << 8 : 0) |
                                (i + 2 < size ? data[i + 2] : 0);
        out += kDigits[(n >> 18) & 63];
        out += kDigits[(n >> 12) & 63];
        out += i + 1 < size ? kDigits[(n >> 6) & 63] : '=';
        out += i + 2 < size ? kDigits[n & 63] : '=';
    }
    return out;
}

std::string halfImageBase64(const Image& img) {
    std::vector<unsigned char> bytes;
    bytes.reserve(img.pixels.size() * 6);
    for (const Color& c : img.pixels)
        for (int k = 0; k < 3; ++k) {
            const std::uint16_t h = halfOf(static_cast<float>(c[k]));
            bytes.push_back(static_cast<unsigned char>(h & 0xff));
            bytes.push_back(static_cast<unsigned char>(h >> 8));
        }
    return base64(bytes.data(), bytes.size());
}

fs::path sppRenderPath(const fs::path& dir, const std::string& label, std::uint32_t spp) {
    return dir / "renders" / fmt::format("{}@{}spp.exr", label, spp);
}

namespace {

/// A variant's first repeat at one spp against the reference: the image, its FLIP map and errors.
nlohmann::json renderEntry(const fs::path& file, std::uint32_t spp, const Image& reference) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return nullptr;
    const Image img = readExr(file.string());
    if (img.width != reference.width || img.height != reference.height) return nullptr;
    const FlipResult flip = hdrFlip(reference, img);
    std::vector<unsigned char> bytes(flip.map.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<unsigned char>(std::lround(255 * std::clamp(flip.map[i], 0.0f, 1.0f)));
    const ImageError e = imageError(img, reference);
    return {{"spp", spp},
            {"image", halfImageBase64(img)},
            {"flip", base64(bytes.data(), bytes.size())},
            {"flip_mean", flip.mean},
            {"rmse", e.rmse},
            {"relmse", e.relMse}};
}

/// "**a** `b`" -> "a `b`": the page shows code spans but not Markdown's emphasis.
std::string withoutEmphasis(std::string s) {
    for (std::size_t p = s.find("**"); p != std::string::npos; p = s.find("**", p)) s.erase(p, 2);
    return s;
}

nlohmann::json tablesJson(const std::vector<ReportTable>& tables) {
    nlohmann::json out = nlohmann::json::array();
    for (const ReportTable& t : tables) {
        nlohmann::json rows = nlohmann::json::array();
        for (const auto& row : t.rows) {
            nlohmann::json cells = nlohmann::json::array();
            for (const ReportCell& c : row)
                cells.push_back({{"text", c.text}, {"value", c.value ? nlohmann::json(*c.value) : nlohmann::json()}});
            rows.push_back(cells);
        }
        out.push_back({{"title", t.title}, {"note", t.note}, {"columns", t.columns}, {"rows", rows}});
    }
    return out;
}

nlohmann::json plotsJson(const fs::path& dir) {
    static const std::pair<const char*, const char*> kPlots[] = {{"convergence_spp.png", "RMSE against samples per pixel"},
                                                                  {"convergence_time.png", "RMSE against render time"},
                                                                  {"efficiency.png", "Efficiency relative to the yardstick"}};
    // Not heatmaps.png and crops.png: the viewer shows every render's error map and zooms itself, and they
    // were a third of a page's size (details.md links them).
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [file, title] : kPlots) {
        std::error_code ec;
        if (!fs::is_regular_file(dir / file, ec)) continue;
        const std::string bytes = readTextFile((dir / file).string());
        out.push_back({{"title", title}, {"png", base64(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size())}});
    }
    return out;
}

}  // namespace

nlohmann::json reportHtmlData(const ReportInputs& in, const fs::path& dir) {
    const StudyConfig& c = in.config;
    nlohmann::json d;
    d["title"] = fmt::format("Estimator study: {}", in.sceneName);
    d["subtitle"] = fmt::format("{}x{} pixels, max depth {}, {} repeat(s) per variant and spp, seed {}{}. The viewer shows each variant's first repeat.",
                                c.width, c.height, c.maxDepth, c.repeats, c.seed, in.cancelled ? "; interrupted: the finished rows only" : "");
    nlohmann::json answer = nlohmann::json::array();
    for (const std::string& line : in.answer) answer.push_back(withoutEmphasis(line));
    d["answer"] = answer;
    d["width"] = c.width;
    d["height"] = c.height;
    d["spp"] = c.spps;
    d["reference"] = {{"label", c.referencePath.empty() ? fmt::format("reference ({}, {} spp)", referenceMethod(c), c.referenceSpp)
                                                        : fmt::format("reference ({})", c.referencePath)},
                      {"image", halfImageBase64(in.reference.image)}};
    nlohmann::json variants = nlohmann::json::array();
    for (const StudyVariant& v : studyVariants(c)) {
        nlohmann::json images = nlohmann::json::array();
        for (std::uint32_t spp : c.spps) images.push_back(renderEntry(sppRenderPath(dir, v.label, spp), spp, in.reference.image));
        variants.push_back({{"label", v.label}, {"images", images}});
    }
    d["variants"] = variants;
    d["plots"] = plotsJson(dir);
    d["tables"] = tablesJson(in.tables);
    return d;
}

std::string reportHtml(const nlohmann::json& data) {
    std::string json = data.dump();
    // Every "<" as its JSON escape: no text in the data can end the script or open a comment inside it.
    for (std::size_t p = json.find('<'); p != std::string::npos; p = json.find('<', p + 6)) json.replace(p, 1, "\\u003c");
    std::string page = kReportViewerHtml;
    const std::string marker = "@STUDY_DATA@";
    const std::size_t at = page.find(marker);
    if (at == std::string::npos) throw std::logic_error("report_viewer.html has no @STUDY_DATA@ marker");
    page.replace(at, marker.size(), json);
    return page;
}

}  // namespace symphong
