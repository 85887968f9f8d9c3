// fuzz/fuzz_settings.cpp — libFuzzer target for the render settings read from a JSON scene's "render"
// object (render/settings.cpp applySceneSettings through util/schema.h fromJson: every field's type,
// range and allowed names, estimator options, the progressive fields; then checkRenderOptions, the
// estimator, stopRules and renderSettings, as `symphong render scene.json` does). The input is the value
// of "render" in {"builtin": "cornell", "render": INPUT}. InputError is the expected rejection; anything
// else escaping, a crash, a sanitizer report, or accepted options outside their ranges or that do not
// read back the same through toJson/fromJson (fuzz_common.h, settingsProblem) is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadSettingsInput(scratchDir("settings"), input); });
}
