// fuzz/fuzz_checkpoint.cpp — libFuzzer target for the checkpoint reader (render/checkpoint.cpp,
// readCheckpoint: the magic line, the JSON header with the image size, spp and statistics, the size the
// header calls for against the file's, the tile counts and sums, the checksum). The input is one byte of
// flags, then the file; with bit 0 of the flags set the harness first makes the checksum right
// (fuzz_common.h, withFixedChecksum), so that mutations of the sections reach what is checked after the
// checksum and what a resumed render does with the state (requireSameRender, the image, its variance).
// InputError is the expected rejection; anything else escaping, a crash, a sanitizer report or an
// accepted checkpoint that breaks fuzz_common.h's checkpointProblem is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return readCheckpointInput(scratchDir("checkpoint"), input); });
}
