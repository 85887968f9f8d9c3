// io/memory.h — refusing inputs that would not fit in memory: a loader that knows how much a mesh, a
// texture or an image will need asks here before it allocates, so a too-large input is a one-line
// InputError naming the file instead of an allocation failure or the kernel's out-of-memory killer.
#pragma once

#include <cstdint>
#include <string>

namespace symphong {

/// Physical memory of this machine in bytes (sysconf), or 0 when it cannot be told.
std::uint64_t physicalMemoryBytes();

/// The most bytes one input may need: three quarters of physical memory (leaving room for the rest of
/// the render), or 2^46 where physical memory cannot be told.
std::uint64_t memoryBudgetBytes();

/// Throws InputError "<what>: needs N GiB of memory, more than the M GiB symphong allows itself on this
/// machine (3/4 of its P GiB)" when `bytes` exceeds memoryBudgetBytes(). `what` names the file and the
/// thing (e.g. "tex.png: a 100000 x 100000 texture").
void requireMemory(std::uint64_t bytes, const std::string& what);

/// a * b, saturating at UINT64_MAX instead of wrapping (sizes computed from untrusted headers).
std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b);

}  // namespace symphong
