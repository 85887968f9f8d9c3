// util/ — low-level helpers that every layer may use and that know nothing of rendering. This file:
// memory for buffers of megabytes that a render allocates and fills at once (EARS's sums of an epoch,
// 5.4 MB; an image's running sums, 15 MB at 512 x 512). Memory fresh from the system costs a page fault
// on its first touch, one per 4 KiB page: in the virtual machines where symphong is measured about 15
// microseconds each, 20 ms for EARS's sums (bench: the first touch of 5.4 MB, 1,318 faults), 4% of a
// 128 x 96 render at 64 spp. Buffers of 2 MiB or more from LargeBufferAllocator start on a 2 MiB boundary
// and are offered to Linux's transparent huge pages (madvise MADV_HUGEPAGE, which the kernel's default
// "madvise" mode honours): one fault per 2 MiB (0.6 ms for the same 5.4 MB). Smaller buffers, or systems
// without it, get ordinary memory; nothing else differs.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace symphong {

/// The huge page of x86-64 Linux.
inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

/// Asks the kernel to back [p, p + bytes) with huge pages (a hint: ignored where unsupported).
inline void adviseHugePages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, bytes, MADV_HUGEPAGE);
#endif
}

template <class T>
struct LargeBufferAllocator {
    using value_type = T;
    LargeBufferAllocator() noexcept = default;
    template <class U>
    LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / 2 / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kHugePage) return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
        const std::size_t whole = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        void* p = ::operator new(whole, std::align_val_t(kHugePage));
        adviseHugePages(p, whole);
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        ::operator delete(p, std::align_val_t(n * sizeof(T) < kHugePage ? alignof(T) : kHugePage));
    }

    template <class U>
    bool operator==(const LargeBufferAllocator<U>&) const noexcept {
        return true;
    }
};

/// A std::vector whose buffer, from 2 MiB on, lies on huge pages where the system offers them.
template <class T>
using LargeBufferVector = std::vector<T, LargeBufferAllocator<T>>;

}  // namespace symphong
