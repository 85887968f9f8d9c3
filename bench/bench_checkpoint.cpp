// Checkpoints of a 4K image (3840 x 2160, render/checkpoint.h): writing one (the state's 464 MB, its
// checksum, fsync, rename, fsync of the directory) and reading one back (with its checksum), in the
// directory given by SYMPHONG_BENCH_DIR (default: the working directory, where checkpoints are written
// beside the output). The state holds arbitrary sums; the cost does not depend on their values.
#include "render/checkpoint.h"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

using namespace symphong;

namespace {

std::string benchPath() {
    const char* dir = std::getenv("SYMPHONG_BENCH_DIR");
    return (std::filesystem::path(dir ? dir : ".") / "bench-4k.ckpt").string();
}

RenderState fourK() {
    RenderState s(3840, 2160, 1024);
    for (std::size_t i = 0; i < s.sum.size(); ++i) {
        const double v = static_cast<double>(i % 977) * 0.001;
        s.sum[i] = Color(v, 2 * v, 3 * v), s.sumSq[i] = Color(v * v), s.sumLuminanceSq[i] = v * v;
    }
    for (auto& n : s.tileSamples) n = 64;
    return s;
}

const RenderIdentity kIdentity{"cornell", "0123456789abcdef", {{"spp", 1024}, {"seed", 1}}};

void BM_WriteCheckpoint4K(benchmark::State& state) {
    const RenderState s = fourK();
    const std::string path = benchPath();
    for (auto _ : state) writeCheckpoint(path, kIdentity, s);
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(std::filesystem::file_size(path)));
    std::filesystem::remove(path);
}

void BM_ReadCheckpoint4K(benchmark::State& state) {
    const std::string path = benchPath();
    writeCheckpoint(path, kIdentity, fourK());
    for (auto _ : state) {
        RenderIdentity id;
        RenderState s;
        readCheckpoint(path, id, s);
        benchmark::DoNotOptimize(s.sum.data());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(std::filesystem::file_size(path)));
    std::filesystem::remove(path);
}

}  // namespace

BENCHMARK(BM_WriteCheckpoint4K)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK(BM_ReadCheckpoint4K)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
