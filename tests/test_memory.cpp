// The memory checks at their boundary (io/memory.h): the budget is three quarters of the machine's
// memory as /proc/meminfo tells it (a second source beside sysconf), a request of exactly the budget
// passes and one byte more is refused naming the input, and the saturating product is exact up to
// 2^64 - 1 and saturates beyond.
#include "io/input_error.h"
#include "io/memory.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

using namespace symphong;

TEST(Memory, TheBudgetIsThreeQuartersOfWhatProcMeminfoSays) {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t kib = 0;
    std::string line;
    while (std::getline(meminfo, line)) {
        std::istringstream in(line);
        in >> key >> kib;
        if (key == "MemTotal:") break;
        kib = 0;
    }
    if (kib == 0) GTEST_SKIP() << "no /proc/meminfo";
    const double total = static_cast<double>(kib) * 1024.0;
    EXPECT_NEAR(static_cast<double>(physicalMemoryBytes()), total, 0.02 * total);
    EXPECT_NEAR(static_cast<double>(memoryBudgetBytes()), 0.75 * total, 0.02 * total);
}

TEST(Memory, ExactlyTheBudgetPassesAndOneByteMoreIsRefused) {
    const std::uint64_t budget = memoryBudgetBytes();
    EXPECT_NO_THROW(requireMemory(budget, "exact"));
    try {
        requireMemory(budget + 1, "big.ply: a mesh of 3 vertices");
        FAIL() << "one byte over the budget was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("big.ply: a mesh of 3 vertices: needs", 0), 0u) << e.what();
    }
}

TEST(Memory, SaturatingMultiplyIsExactUpToTheTopAndSaturatesBeyond) {
    constexpr std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
    EXPECT_EQ(saturatingMultiply((1ull << 32) - 1, (1ull << 32) + 1), top);  // exactly 2^64 - 1
    EXPECT_EQ(saturatingMultiply(1ull << 32, 1ull << 32), top);              // 2^64: saturated
    EXPECT_EQ(saturatingMultiply(3, 5), 15u);
    EXPECT_EQ(saturatingMultiply(0, top), 0u);
    EXPECT_EQ(saturatingMultiply(top, 1), top);
    EXPECT_EQ(saturatingMultiply(top / 2, 3), top);
}
