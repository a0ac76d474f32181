// SPDX-License-Identifier: Apache-2.0
/// @file
/// prefetchRead(): a hint that bytes will be read soon, so that a walk over scattered blocks
/// (a tree's leaves, each value buffer allocated on its own) overlaps the next block's cache
/// misses with work on the current one.

#pragma once

#include <cstddef>

#if defined(_MSC_VER) && !defined(__clang__)
#include <xmmintrin.h>
#endif

namespace vdb::util {

/// Size of the cache line the hints are issued for.
inline constexpr std::size_t CACHE_LINE_BYTES = 64;

/// Asks for every cache line of `[p, p + bytes)` to be brought towards the core, for reading.
/// A hint only: it never faults, never blocks and changes no value.
[[gnu::always_inline]] inline void prefetchRead(const void* p, std::size_t bytes) {
    const char* begin = static_cast<const char*>(p);
    for (std::size_t offset = 0; offset < bytes; offset += CACHE_LINE_BYTES) {
#if defined(_MSC_VER) && !defined(__clang__)
        _mm_prefetch(begin + offset, _MM_HINT_T0);
#else
        __builtin_prefetch(begin + offset, 0, 3);
#endif
    }
}

}  // namespace vdb::util
