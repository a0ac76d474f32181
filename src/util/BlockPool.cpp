// SPDX-License-Identifier: Apache-2.0

#include <vdb/util/BlockPool.h>
#include <vdb/util/LargeArray.h>

#include <sys/mman.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VDB_POOL_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define VDB_POOL_SANITIZED 1
#endif
#endif
#ifndef VDB_POOL_SANITIZED
#define VDB_POOL_SANITIZED 0
#endif

namespace vdb::util {

namespace {

constexpr std::size_t GRAIN = 64;
constexpr std::size_t CLASSES = BlockPool::MAX_BLOCK / GRAIN;
constexpr std::align_val_t BLOCK_ALIGN{GRAIN};

struct Shard;

// At the start of every chunk; the blocks follow it. Guarded by its shard's mutex.
struct alignas(GRAIN) Chunk {
    Shard* shard = nullptr;
    std::size_t sizeClass = 0;
    std::size_t blockBytes = 0;
    std::size_t capacity = 0;  // blocks in the chunk
    std::size_t bumped = 0;    // blocks ever handed out from the untouched end
    std::size_t live = 0;      // blocks in use
    void* freeList = nullptr;  // freed blocks, linked through their first bytes
    Chunk* prev = nullptr;     // in the shard's list of chunks with room for this class
    Chunk* next = nullptr;
    bool listed = false;

    std::byte* blocks() { return reinterpret_cast<std::byte*>(this) + sizeof(Chunk); }
};

struct Shard {
    std::mutex mutex;
    std::array<Chunk*, CLASSES> room{};              // chunks that have room, not empty
    std::array<Chunk*, CLASSES> spare{};             // at most one empty chunk per class
    std::array<std::size_t, CLASSES> classChunks{};  // chunks mapped per class
    std::size_t chunks = 0;
    std::size_t blocks = 0;

    void link(Chunk* c) {
        c->prev = nullptr;
        c->next = room[c->sizeClass];
        if (c->next)
            c->next->prev = c;
        room[c->sizeClass] = c;
        c->listed = true;
    }
    void unlink(Chunk* c) {
        if (c->prev)
            c->prev->next = c->next;
        else
            room[c->sizeClass] = c->next;
        if (c->next)
            c->next->prev = c->prev;
        c->prev = c->next = nullptr;
        c->listed = false;
    }
};

// A mapping of `bytes` (a multiple of CHUNK_BYTES), aligned to CHUNK_BYTES, with a request for
// huge pages when `huge`.
void* mapAligned(std::size_t bytes, bool huge) {
    constexpr std::size_t align = BlockPool::CHUNK_BYTES;
    if (bytes > std::size_t(-1) - align)
        throw std::bad_alloc();
    const std::size_t span = bytes + align;
    void* raw = ::mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED)
        throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (start + align - 1) & ~std::uintptr_t(align - 1);
    if (aligned > start)
        ::munmap(raw, aligned - start);
    if (aligned + bytes < start + span)
        ::munmap(reinterpret_cast<void*>(aligned + bytes), start + span - aligned - bytes);
    void* mapped = reinterpret_cast<void*>(aligned);
#ifdef MADV_HUGEPAGE
    if (huge)
        ::madvise(mapped, bytes, MADV_HUGEPAGE);  // a hint: 4 KiB pages work as well
#endif
    return mapped;
}

void* mapChunk(bool huge) {
    return mapAligned(BlockPool::CHUNK_BYTES, huge);
}

void unmapChunk(Chunk* c) {
    ::munmap(c, BlockPool::CHUNK_BYTES);
}

// The mapped size of a large array of `bytes` bytes: whole chunks.
std::size_t largeArrayMapping(std::size_t bytes) {
    constexpr std::size_t chunk = BlockPool::CHUNK_BYTES;
    if (bytes > std::size_t(-1) - chunk)
        throw std::bad_alloc();
    return (bytes + chunk - 1) & ~(chunk - 1);
}

}  // namespace

// Threads get consecutive tickets on first use; a thread's shard in a pool of n shards is its
// ticket modulo n.
namespace {
std::atomic<unsigned> gNextTicket{0};
}  // namespace

struct BlockPool::Impl {
    std::vector<std::unique_ptr<Shard>> shards;

    Shard& shardOfThisThread() {
        thread_local const unsigned ticket = gNextTicket.fetch_add(1, std::memory_order_relaxed);
        return *shards[ticket % shards.size()];
    }
};

BlockPool::BlockPool(unsigned shards) : mImpl(std::make_unique<Impl>()) {
    if (shards == 0)
        shards = std::clamp(std::thread::hardware_concurrency(), 1u, 64u);
    for (unsigned s = 0; s < shards; ++s)
        mImpl->shards.push_back(std::make_unique<Shard>());
}

BlockPool::~BlockPool() {
    for (auto& shard : mImpl->shards) {
        for (std::size_t c = 0; c < CLASSES; ++c) {
            for (Chunk* chunk = shard->room[c]; chunk;) {
                Chunk* next = chunk->next;
                unmapChunk(chunk);
                chunk = next;
            }
            if (shard->spare[c])
                unmapChunk(shard->spare[c]);
        }
    }
}

void* BlockPool::allocate(std::size_t bytes) {
    if (bytes > MAX_BLOCK)
        return ::operator new(bytes, BLOCK_ALIGN);
    const std::size_t sizeClass = bytes == 0 ? 0 : (bytes - 1) / GRAIN;
    Shard& shard = mImpl->shardOfThisThread();
    std::lock_guard lock(shard.mutex);
    Chunk* c = shard.room[sizeClass];
    if (!c) {
        if (shard.spare[sizeClass]) {
            c = shard.spare[sizeClass];
            shard.spare[sizeClass] = nullptr;
        } else {
            // The first chunk of a class in a shard keeps 4 KiB pages, so that a small grid
            // costs no 2 MiB page per thread and value type; the chunks of larger ones after
            // it ask for huge pages.
            c = new (mapChunk(shard.classChunks[sizeClass] > 0)) Chunk;
            ++shard.classChunks[sizeClass];
            c->shard = &shard;
            c->sizeClass = sizeClass;
            c->blockBytes = (sizeClass + 1) * GRAIN;
            c->capacity = (CHUNK_BYTES - sizeof(Chunk)) / c->blockBytes;
            ++shard.chunks;
        }
        shard.link(c);
    }
    void* block;
    if (c->freeList) {
        block = c->freeList;
        std::memcpy(&c->freeList, block, sizeof(void*));
    } else {
        block = c->blocks() + c->bumped * c->blockBytes;
        ++c->bumped;
    }
    ++c->live;
    ++shard.blocks;
    if (c->live == c->capacity)
        shard.unlink(c);
    return block;
}

void BlockPool::deallocate(void* block, std::size_t bytes) noexcept {
    if (!block)
        return;
    if (bytes > MAX_BLOCK) {
        ::operator delete(block, BLOCK_ALIGN);
        return;
    }
    auto* c = reinterpret_cast<Chunk*>(reinterpret_cast<std::uintptr_t>(block) &
                                       ~std::uintptr_t(CHUNK_BYTES - 1));
    Shard& shard = *c->shard;
    Chunk* release = nullptr;
    {
        std::lock_guard lock(shard.mutex);
        std::memcpy(block, &c->freeList, sizeof(void*));
        c->freeList = block;
        --c->live;
        --shard.blocks;
        if (!c->listed)
            shard.link(c);  // it was full
        if (c->live == 0) {
            shard.unlink(c);
            if (!shard.spare[c->sizeClass]) {
                shard.spare[c->sizeClass] = c;
            } else {
                release = c;
                --shard.chunks;
                --shard.classChunks[c->sizeClass];
            }
        }
    }
    if (release)
        unmapChunk(release);
}

BlockPool::Usage BlockPool::usage() const {
    Usage u;
    for (const auto& shard : mImpl->shards) {
        std::lock_guard lock(shard->mutex);
        u.chunks += shard->chunks;
        u.blocks += shard->blocks;
    }
    return u;
}

BlockPool& BlockPool::leafValues() {
    static BlockPool* pool = new BlockPool();
    return *pool;
}

namespace {

bool poolEnabled() {
    static const bool enabled = [] {
        if (VDB_POOL_SANITIZED)
            return false;
        const char* env = std::getenv("VDB_LEAF_POOL");
        return !(env && std::strcmp(env, "0") == 0);
    }();
    return enabled;
}

}  // namespace

void* allocateValueBlock(std::size_t bytes) {
    if (poolEnabled())
        return BlockPool::leafValues().allocate(bytes);
    return ::operator new(bytes, BLOCK_ALIGN);
}

void freeValueBlock(void* block, std::size_t bytes) noexcept {
    if (poolEnabled())
        BlockPool::leafValues().deallocate(block, bytes);
    else
        ::operator delete(block, BLOCK_ALIGN);
}

void* allocateLargeArray(std::size_t bytes) {
    if (bytes < LARGE_ARRAY_MIN || !poolEnabled())
        return ::operator new(bytes, BLOCK_ALIGN);
    return mapAligned(largeArrayMapping(bytes), /*huge=*/true);
}

void freeLargeArray(void* array, std::size_t bytes) noexcept {
    if (!array)
        return;
    if (bytes < LARGE_ARRAY_MIN || !poolEnabled())
        ::operator delete(array, BLOCK_ALIGN);
    else
        ::munmap(array, largeArrayMapping(bytes));
}

}  // namespace vdb::util
