// SPDX-License-Identifier: Apache-2.0
// Oracle: every live block is filled with a pattern of its own (its serial number in every
// 8-byte word) and the set of live blocks is kept beside the pool; after random interleavings
// of allocations and frees, on one thread and across threads, every live block must still
// hold its pattern (no two blocks overlap, no free corrupts a live block), be aligned, and the
// pool's counts must match the oracle's.

#include <vdb/util/BlockPool.h>
#include <vdb/util/LargeArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

namespace vdb::util {
namespace {

struct Live {
    uint64_t* data;
    size_t bytes;
    uint64_t serial;
};

void stamp(const Live& b) {
    for (size_t w = 0; w < b.bytes / 8; ++w)
        b.data[w] = b.serial * 0x9E3779B97F4A7C15ull + w;
}

bool intact(const Live& b) {
    for (size_t w = 0; w < b.bytes / 8; ++w) {
        if (b.data[w] != b.serial * 0x9E3779B97F4A7C15ull + w)
            return false;
    }
    return true;
}

Live allocate(BlockPool& pool, size_t bytes, uint64_t serial) {
    Live b{static_cast<uint64_t*>(pool.allocate(bytes)), bytes, serial};
    EXPECT_EQ(reinterpret_cast<uintptr_t>(b.data) % 64, 0u) << bytes << " bytes";
    stamp(b);
    return b;
}

TEST(BlockPool, RandomAllocationsAndFreesKeepEveryBlockIntact) {
    BlockPool pool(1);
    std::mt19937_64 rng(7);
    // Leaf sizes (float, double, Vec3f and Vec3d leaves with 1 to 3 buffers) and odd ones,
    // beyond MAX_BLOCK too.
    const std::vector<size_t> sizes = {2048,
                                       4096,
                                       6144,
                                       12288,
                                       18432,
                                       36864,
                                       8,
                                       64,
                                       72,
                                       1000,
                                       BlockPool::MAX_BLOCK,
                                       BlockPool::MAX_BLOCK + 8};
    std::vector<Live> live;
    uint64_t serial = 0;
    for (int step = 0; step < 40000; ++step) {
        const bool grow = live.size() < 200 || rng() % 100 < 55;
        if (grow) {
            live.push_back(allocate(pool, sizes[rng() % sizes.size()], ++serial));
        } else {
            const size_t k = rng() % live.size();
            ASSERT_TRUE(intact(live[k])) << "block " << live[k].serial;
            pool.deallocate(live[k].data, live[k].bytes);
            live[k] = live.back();
            live.pop_back();
        }
    }
    for (const Live& b : live)
        ASSERT_TRUE(intact(b)) << "block " << b.serial;
    size_t pooled = 0;
    for (const Live& b : live)
        pooled += b.bytes <= BlockPool::MAX_BLOCK;
    EXPECT_EQ(pool.usage().blocks, pooled);
    for (const Live& b : live)
        pool.deallocate(b.data, b.bytes);
    EXPECT_EQ(pool.usage().blocks, 0u);
    // One spare chunk per pooled size at most.
    EXPECT_LE(pool.usage().chunks, sizes.size() - 1);
}

TEST(BlockPool, EmptyChunksBeyondOneSpareAreReturned) {
    BlockPool pool(1);
    const size_t bytes = 2048;
    const size_t perChunk = (BlockPool::CHUNK_BYTES - 128) / bytes;
    std::vector<void*> blocks;
    for (size_t n = 0; n < 3 * perChunk + 1; ++n)
        blocks.push_back(pool.allocate(bytes));
    EXPECT_EQ(pool.usage().chunks, 4u);
    for (void* p : blocks)
        pool.deallocate(p, bytes);
    EXPECT_EQ(pool.usage().chunks, 1u);
    EXPECT_EQ(pool.usage().blocks, 0u);
    // The spare serves the next allocation.
    void* p = pool.allocate(bytes);
    EXPECT_EQ(pool.usage().chunks, 1u);
    pool.deallocate(p, bytes);
}

TEST(BlockPool, BlocksFreedByOtherThreadsGoBackToTheirChunks) {
    BlockPool pool(3);
    constexpr int THREADS = 4;
    std::mutex handoffMutex;
    std::vector<Live> handoff;  // allocated by one thread, freed by another
    std::vector<std::thread> threads;
    std::vector<int> failures(THREADS, 0);
    for (int t = 0; t < THREADS; ++t) {
        threads.emplace_back([&, t] {
            std::mt19937_64 rng(100 + t);
            std::vector<Live> mine;
            uint64_t serial = uint64_t(t) << 40;
            for (int step = 0; step < 20000; ++step) {
                const int op = int(rng() % 10);
                if (op < 5 || mine.empty()) {
                    mine.push_back(allocate(pool, 2048 * (1 + rng() % 3), ++serial));
                } else if (op < 7) {
                    std::lock_guard lock(handoffMutex);
                    handoff.push_back(mine.back());
                    mine.pop_back();
                } else if (op < 9) {
                    Live b = mine.back();
                    mine.pop_back();
                    failures[t] += !intact(b);
                    pool.deallocate(b.data, b.bytes);
                } else {
                    std::lock_guard lock(handoffMutex);
                    if (!handoff.empty()) {
                        Live b = handoff.back();
                        handoff.pop_back();
                        failures[t] += !intact(b);
                        pool.deallocate(b.data, b.bytes);
                    }
                }
            }
            for (const Live& b : mine) {
                failures[t] += !intact(b);
                pool.deallocate(b.data, b.bytes);
            }
        });
    }
    for (auto& th : threads)
        th.join();
    for (int t = 0; t < THREADS; ++t)
        EXPECT_EQ(failures[t], 0) << "thread " << t;
    for (const Live& b : handoff) {
        EXPECT_TRUE(intact(b));
        pool.deallocate(b.data, b.bytes);
    }
    EXPECT_EQ(pool.usage().blocks, 0u);
    EXPECT_LE(pool.usage().chunks, 3u * 3u);  // one spare per size and shard
}

TEST(BlockPool, ValueBlocksAreAlignedAndWritable) {
    for (size_t bytes : {size_t(2048), size_t(6144), BlockPool::MAX_BLOCK + 1, size_t(1) << 22}) {
        void* p = allocateValueBlock(bytes);
        EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % 64, 0u);
        std::memset(p, 0xAB, bytes);
        freeValueBlock(p, bytes);
    }
}

// Large arrays below, at and above LARGE_ARRAY_MIN, several live at once and freed out of
// order: each keeps its own pattern, so no two overlap and no free touches a live one.
TEST(LargeArray, ArraysAreAlignedDisjointAndKeepTheirContents) {
    const std::vector<size_t> sizes = {8,
                                       4096,
                                       LARGE_ARRAY_MIN - 8,
                                       LARGE_ARRAY_MIN,
                                       BlockPool::CHUNK_BYTES,
                                       BlockPool::CHUNK_BYTES + 8,
                                       3 * BlockPool::CHUNK_BYTES + 4096};
    std::vector<Live> live;
    uint64_t serial = 0;
    for (int round = 0; round < 2; ++round) {
        for (size_t bytes : sizes) {
            Live b{static_cast<uint64_t*>(allocateLargeArray(bytes)), bytes, ++serial};
            EXPECT_EQ(reinterpret_cast<uintptr_t>(b.data) % 64, 0u) << bytes << " bytes";
            stamp(b);
            live.push_back(b);
        }
    }
    for (size_t k = 0; k < live.size(); k += 2) {
        EXPECT_TRUE(intact(live[k])) << live[k].bytes << " bytes";
        freeLargeArray(live[k].data, live[k].bytes);
    }
    for (size_t k = 1; k < live.size(); k += 2) {
        EXPECT_TRUE(intact(live[k])) << live[k].bytes << " bytes";
        freeLargeArray(live[k].data, live[k].bytes);
    }
    freeLargeArray(nullptr, LARGE_ARRAY_MIN);  // like delete of null: nothing
}

TEST(LargeArray, VectorGrowsAcrossTheThresholdAndKeepsItsElements) {
    LargeVector<uint64_t> v;
    const size_t n = 3 * LARGE_ARRAY_MIN / sizeof(uint64_t) + 5;
    for (size_t i = 0; i < n; ++i)
        v.push_back(i * 3);  // reallocates from operator new into mappings
    ASSERT_EQ(v.size(), n);
    for (size_t i = 0; i < n; ++i)
        ASSERT_EQ(v[i], i * 3) << i;
    LargeVector<uint64_t> copy(v);
    v.clear();
    v.shrink_to_fit();
    EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), uint64_t(0)), 3 * (n * (n - 1) / 2));
}

TEST(LargeArray, ImpossibleCountsThrowBeforeAllocating) {
    LargeArrayAllocator<std::array<uint64_t, 8>> alloc;
    EXPECT_THROW((void)alloc.allocate(std::numeric_limits<size_t>::max() / 8),
                 std::bad_array_new_length);
}

}  // namespace
}  // namespace vdb::util
