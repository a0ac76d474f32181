// SPDX-License-Identifier: Apache-2.0
/// @file
/// BlockPool: the memory of leaf value buffers (DESIGN.md: "allocate leaves from a pool").
///
/// Every tool that builds a grid makes thousands to millions of leaves, each with one value
/// block of a few KiB (2 KiB for a float leaf). Taken one by one from malloc, a fresh block is
/// a first touch of new 4 KiB pages: the page faults, not the work, then dominate building a
/// grid from a dense array, dilation, CSG copies and scan conversion. The pool carves blocks
/// of one size out of 2 MiB chunks that the kernel may back with transparent huge pages
/// (madvise(MADV_HUGEPAGE)), so a chunk costs one fault instead of 512, and reuses freed
/// blocks in place.
///
/// - Blocks of up to MAX_BLOCK bytes come from the pool, rounded up to 64 bytes and aligned to
///   64; larger ones from operator new (aligned to 64 as well).
/// - The pool has shards; a thread allocates from the shard it was assigned on first use, and
///   a block goes back to the shard of its chunk, whichever thread frees it. So threads that
///   build leaves in parallel do not share a lock, and results never depend on which thread
///   allocated what.
/// - A shard keeps at most one empty chunk per block size; further chunks are unmapped as soon
///   as they are empty.
/// - The first chunk of each block size in a shard keeps 4 KiB pages: a small grid does not
///   cost a 2 MiB page per thread and value type. The chunks after it ask for huge pages.
/// - allocateValueBlock() and freeValueBlock() use the process-wide pool, except in builds with
///   AddressSanitizer or ThreadSanitizer (which must see every block) and when the environment
///   variable VDB_LEAF_POOL is 0 at the first allocation: then plain operator new and delete.
///
/// Threads: every member is thread-safe.

#pragma once

#include <cstddef>
#include <memory>

namespace vdb::util {

class BlockPool {
public:
    /// The largest block the pool serves itself.
    static constexpr std::size_t MAX_BLOCK = 32 * 1024;
    /// The size of a chunk, and its alignment.
    static constexpr std::size_t CHUNK_BYTES = std::size_t(2) << 20;

    /// A pool with `shards` shards; 0 picks one per hardware thread (at most 64).
    explicit BlockPool(unsigned shards = 0);
    /// Unmaps every chunk. @pre every block allocated from the pool has been freed.
    ~BlockPool();
    BlockPool(const BlockPool&) = delete;
    BlockPool& operator=(const BlockPool&) = delete;

    /// A block of at least `bytes` bytes, aligned to 64 bytes, uninitialised.
    /// @throw std::bad_alloc when no memory can be had.
    void* allocate(std::size_t bytes);
    /// Returns a block of this pool; `bytes` is the size it was allocated with.
    void deallocate(void* block, std::size_t bytes) noexcept;

    /// The chunks the pool holds (empty spares included) and the blocks in use.
    struct Usage {
        std::size_t chunks = 0;
        std::size_t blocks = 0;
    };
    Usage usage() const;

    /// The pool the leaves of every tree use. Never destroyed, so that trees in static
    /// storage may free their leaves at exit.
    static BlockPool& leafValues();

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

/// A leaf value block of `bytes` bytes, aligned to 64 (see the file comment for where it comes
/// from). @throw std::bad_alloc
void* allocateValueBlock(std::size_t bytes);
/// Frees a block of allocateValueBlock(); `bytes` is the size it was allocated with.
void freeValueBlock(void* block, std::size_t bytes) noexcept;

}  // namespace vdb::util
