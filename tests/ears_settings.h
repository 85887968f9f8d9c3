// Render settings for the --splitting ears tests (test_ears.cpp, test_ears_mis.cpp): a render of
// width x height pixels and spp samples with the learned factors on.
#pragma once

#include "render/renderer.h"

#include <cstdint>
#include <string>

namespace symphong::test {

inline RenderSettings earsSettings(int width, int height, std::uint32_t spp, std::uint64_t seed, const std::string& sampler = "sobol") {
    RenderSettings rs;
    rs.width = width, rs.height = height, rs.spp = spp, rs.seed = seed, rs.sampler = sampler;
    rs.trace.splitting = SplittingMode::Ears;
    return rs;
}

}  // namespace symphong::test
