#include "io/memory.h"

#include "io/input_error.h"

#include <fmt/format.h>
#include <unistd.h>

#include <limits>

namespace symphong {

std::uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || pageSize <= 0) return 0;
    return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize);
}

std::uint64_t memoryBudgetBytes() {
    const std::uint64_t physical = physicalMemoryBytes();
    return physical > 0 ? physical / 4 * 3 : (std::uint64_t{1} << 46);
}

std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
    return a * b;
}

void requireMemory(std::uint64_t bytes, const std::string& what) {
    const std::uint64_t budget = memoryBudgetBytes();
    if (bytes <= budget) return;
    constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
    const double need = static_cast<double>(bytes) / kGiB;
    throw InputError(
        fmt::format("{}: needs {:.3g} GiB of memory, more than the {:.3g} GiB symphong allows itself on this machine "
                    "(3/4 of its {:.3g} GiB)",
                    what, need, static_cast<double>(budget) / kGiB, static_cast<double>(physicalMemoryBytes()) / kGiB));
}

}  // namespace symphong
