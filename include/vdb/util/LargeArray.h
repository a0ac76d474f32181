// SPDX-License-Identifier: Apache-2.0
/// @file
/// Large temporary arrays: the per-leaf arrays of a tool that works on every leaf (a mask, an
/// index or a neighbour table per leaf) span hundreds of KiB to many MiB, and their first touch
/// costs one page fault per 4 KiB page, which can cost more than the work done in them (see
/// util/BlockPool.h). From LARGE_ARRAY_MIN bytes up, allocateLargeArray() maps an array on its
/// own, 2 MiB-aligned and rounded up to whole 2 MiB pages, with a request for transparent huge
/// pages (madvise(MADV_HUGEPAGE)); smaller arrays come from operator new. The builds and the
/// VDB_LEAF_POOL setting that turn the leaf pool off (util/BlockPool.h) send every array to
/// operator new.
///
/// Threads: both functions are thread-safe.

#pragma once

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::util {

/// The size from which allocateLargeArray() maps huge pages.
inline constexpr std::size_t LARGE_ARRAY_MIN = std::size_t(128) << 10;

/// An array of `bytes` bytes, aligned to 64, uninitialised. @throw std::bad_alloc
void* allocateLargeArray(std::size_t bytes);
/// Frees an array of allocateLargeArray(); `bytes` is the size it was allocated with.
void freeLargeArray(void* array, std::size_t bytes) noexcept;

/// A standard allocator over allocateLargeArray(), for the large temporary arrays of tools.
template <typename T>
struct LargeArrayAllocator {
    static_assert(alignof(T) <= 64, "LargeArrayAllocator aligns to 64 bytes");
    using value_type = T;
    LargeArrayAllocator() = default;
    template <typename U>
    constexpr LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T))
            throw std::bad_array_new_length();
        return static_cast<T*>(allocateLargeArray(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { freeLargeArray(p, n * sizeof(T)); }
    /// Default-initialises: resize() leaves elements of trivial types (pointers, integers)
    /// unwritten, so that the loop that fills them, in parallel, is their first touch.
    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <typename U>
    constexpr bool operator==(const LargeArrayAllocator<U>&) const noexcept {
        return true;
    }
};

/// A std::vector whose storage comes from allocateLargeArray(). resize(n) leaves new elements
/// of trivial types uninitialised (see LargeArrayAllocator::construct); resize(n, value)
/// writes them.
template <typename T>
using LargeVector = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace vdb::util
