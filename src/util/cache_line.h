// util/ — low-level helpers that every layer may use and that know nothing of rendering. This file:
// memory for data that one thread writes while other threads read their own data nearby. Two cores
// that touch the same cache line, one of them writing, pass the line back and forth on every write
// ("false sharing"), whatever the program's logic. The path tracer's per-thread scratch buffers are
// written on every sample; allocated by malloc they may share a line with the read-only scene and
// emitter tables (the main thread's scratch comes from the same heap arena as those tables), and the
// default render measured 15-20% slower in builds whose heap layout put them together
// (docs/performance.md). Buffers from CacheLineAllocator start on a line boundary and fill whole lines,
// so their writes never touch a line that holds anything else.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

namespace symphong {

/// Twice the x86 line: adjacent-line prefetch moves lines in pairs, so a pair is the unit of sharing.
inline constexpr std::size_t kCacheLinePair = 128;

/// Bytes rounded up to whole kCacheLinePair units.
constexpr std::size_t roundUpToCacheLinePair(std::size_t bytes) { return (bytes + kCacheLinePair - 1) / kCacheLinePair * kCacheLinePair; }

template <class T>
struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() noexcept = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / 2 / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(::operator new(roundUpToCacheLinePair(n * sizeof(T)), std::align_val_t(kCacheLinePair)));
    }
    void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kCacheLinePair)); }

    template <class U>
    bool operator==(const CacheLineAllocator<U>&) const noexcept {
        return true;
    }
};

/// A std::vector whose buffer is alone on its cache lines. (Not for bool: std::vector<bool> packs bits.)
template <class T>
using CacheLineVector = std::vector<T, CacheLineAllocator<T>>;

struct CacheLineDelete {
    template <class T>
    void operator()(T* p) const noexcept {
        ::operator delete(p, std::align_val_t(kCacheLinePair));
    }
};

/// An array of n value-initialised trivial T alone on its cache lines; for the element types that
/// std::vector treats specially (bool).
template <class T>
using CacheLineArray = std::unique_ptr<T[], CacheLineDelete>;

template <class T>
CacheLineArray<T> makeCacheLineArray(std::size_t n) {
    static_assert(std::is_trivial_v<T>);
    T* p = CacheLineAllocator<T>().allocate(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = T{};
    return CacheLineArray<T>(p);
}

}  // namespace symphong
