// util/large_buffer.h: a buffer of 2 MiB or more starts on a 2 MiB boundary and is freed with the
// alignment it was allocated with (the sanitizer build reports a mismatched aligned delete); a smaller one
// gets ordinary memory, aligned for its type; an impossible size is refused with std::bad_array_new_length;
// and the kernel's transparent huge pages back a large buffer where the system offers them (read from
// /proc/self/smaps: AnonHugePages of the buffer's mapping), which is why the allocator exists.
#include "util/large_buffer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

using namespace symphong;

namespace {

std::uintptr_t address(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

/// A transparent-huge-page setting of the kernel ("enabled": always, madvise or never; "defrag": whether a
/// fault in a region that asked for huge pages compacts memory to find one), empty where it has none.
std::string hugePageMode(const std::string& setting = "enabled") {
    std::ifstream f("/sys/kernel/mm/transparent_hugepage/" + setting);
    std::string line;
    std::getline(f, line);
    const auto open = line.find('['), close = line.find(']');
    return open == std::string::npos || close == std::string::npos ? "" : line.substr(open + 1, close - open - 1);
}

/// AnonHugePages (kB) of the mapping of /proc/self/smaps that holds address p.
long anonHugePagesKb(const void* p) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
            inside = address(p) >= lo && address(p) < hi;
            continue;
        }
        if (inside && line.rfind("AnonHugePages:", 0) == 0) return std::stol(line.substr(14));
    }
    return -1;
}

}  // namespace

TEST(LargeBuffer, LargeBuffersStartOnAHugePageAndSmallOnesOnTheirType) {
    for (const std::size_t bytes : {kHugePage, kHugePage + 8, 3 * kHugePage - 8, 5'400'000ul}) {
        LargeBufferVector<double> v(bytes / sizeof(double), 1.5);
        EXPECT_EQ(address(v.data()) % kHugePage, 0u) << bytes;
        EXPECT_EQ(v.back(), 1.5);
        v.resize(v.size() * 2, 2.5);  // the old buffer freed as allocated, the new one aligned too
        EXPECT_EQ(address(v.data()) % kHugePage, 0u) << bytes;
        EXPECT_EQ(v[v.size() / 2 - 1], 1.5);
        EXPECT_EQ(v.back(), 2.5);
    }
    struct alignas(64) Wide {
        char bytes[64];
    };
    for (const std::size_t n : {1ul, 7ul, kHugePage / sizeof(Wide) - 1}) {
        LargeBufferVector<Wide> v(n);
        EXPECT_EQ(address(v.data()) % alignof(Wide), 0u) << n;
    }
    LargeBufferAllocator<double> allocator;
    EXPECT_THROW((void)allocator.allocate(static_cast<std::size_t>(-1) / 4), std::bad_array_new_length);
}

TEST(LargeBuffer, HugePagesBackALargeBufferWhereTheKernelOffersThem) {
    const std::string mode = hugePageMode();
    if (mode != "always" && mode != "madvise") GTEST_SKIP() << "no transparent huge pages here (mode '" << mode << "')";
    // Without compaction at the fault a fragmented machine may have no free 2 MiB page to give.
    const std::string defrag = hugePageMode("defrag");
    if (defrag != "always" && defrag != "madvise" && defrag != "defer+madvise")
        GTEST_SKIP() << "huge pages only when free ones happen to exist here (defrag '" << defrag << "')";
    LargeBufferVector<char> v(4 * kHugePage);
    std::memset(v.data(), 1, v.size());  // first touch: the faults that huge pages make 512 times fewer
    const long kb = anonHugePagesKb(v.data());
    ASSERT_GE(kb, 0) << "no mapping in /proc/self/smaps holds the buffer";
    // The kernel may decline (memory fragmented, khugepaged's limits): at least one huge page is what the
    // hint gets on a machine that offers them; none at all means the hint was not given.
    EXPECT_GE(kb, 2048) << "mode " << mode;
}
