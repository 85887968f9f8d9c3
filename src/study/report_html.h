// study/report_html.h — report.html: one self-contained page (no network, images inside it) with a viewer
// that flips between the reference and each variant's first repeat at each spp, their error and FLIP
// maps, the plots and the tables of report.md. The page itself is src/study/report_viewer.html (embedded
// at build time); this file fills its data: the images as base64 half floats, FLIP maps as bytes.
#pragma once

#include "io/image.h"
#include "study/study_parts.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace symphong {

/// IEEE 754 binary16 nearest to `v` (ties to even; overflow to infinity, NaN kept).
std::uint16_t halfOf(float v);
/// The inverse of halfOf for every binary16 value.
float floatOfHalf(std::uint16_t h);

/// Standard base64 (RFC 4648, with padding).
std::string base64(const unsigned char* data, std::size_t size);

/// A linear RGB image as base64 of little-endian half floats, R, G, B interleaved, row 0 at the top.
std::string halfImageBase64(const Image& img);

/// The path of a variant's first repeat at `spp` among the study's renders.
std::filesystem::path sppRenderPath(const std::filesystem::path& dir, const std::string& label, std::uint32_t spp);

/// The page's data (the contract at the top of report_viewer.html) from the study's files in `dir`.
nlohmann::json reportHtmlData(const ReportInputs& in, const std::filesystem::path& dir);

/// The page: the viewer with `data` in it (every "<" written as \u003c, so that no text can close the script).
std::string reportHtml(const nlohmann::json& data);

}  // namespace symphong
