// SPDX-License-Identifier: Apache-2.0
/// @file
/// Spatial bucketing for the geometry-to-level-set tools (mesh scan conversion, particle
/// rasterization; paper section 4.5 and appendix B): primitives are sorted into cubic blocks of
/// voxels by the voxel boxes they can reach, every block is then rasterized by one task into
/// leaves of its own, and the leaves are linked into the tree in block order. Blocks are
/// disjoint, so tasks never share a leaf, and neither the leaves nor the order they are linked
/// in depend on the thread count. Not API.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace vdb::tools::detail {

/// Primitives bucketed by the blocks of 2^log2 voxels per axis that their voxel boxes touch.
/// A primitive appears in every block its box overlaps; within a block the ids ascend.
struct BlockBuckets {
    Index log2 = 6;
    std::vector<Coord> origins;   // block origins, ascending in Coord order (x, then y, then z)
    std::vector<size_t> offsets;  // block b holds ids[offsets[b], offsets[b + 1])
    std::vector<uint32_t> ids;

    size_t size() const { return origins.size(); }
    std::span<const uint32_t> primitives(size_t b) const {
        return {ids.data() + offsets[b], offsets[b + 1] - offsets[b]};
    }
    CoordBBox blockBox(size_t b) const {
        return CoordBBox::createCube(origins[b], Int32(1) << log2);
    }
};

/// The largest index-space coordinate magnitude the tools accept, so that voxel boxes grown by
/// a band width and rounded outwards stay inside the Int32 range.
inline constexpr double MAX_INDEX_COORD = double(1 << 30);

/// Returns the voxels within `margin` of the box [lo, hi] (index space): every integer point
/// whose distance to the box can be below `margin`.
/// @throw ValueError when the box leaves +-MAX_INDEX_COORD or is not finite.
inline CoordBBox voxelReach(const Vec3d& lo, const Vec3d& hi, double margin, const char* who) {
    Coord a, b;
    for (int i = 0; i < 3; ++i) {
        const double l = lo[i] - margin, h = hi[i] + margin;
        if (!(l > -MAX_INDEX_COORD && h < MAX_INDEX_COORD)) {
            throw ValueError(std::string(who) +
                             ": geometry lies too far from the origin in index space (or is "
                             "not finite); at most 2^30 voxels are supported");
        }
        a[i] = Int32(std::ceil(l));
        b[i] = Int32(std::floor(h));
    }
    return CoordBBox(a, b);
}

/// Buckets `count` primitives by block. `boxOf(i, box)` stores the voxel box primitive i can
/// write to and returns false to leave the primitive out. The result is the same for every
/// thread count.
template <typename BoxOfT>
BlockBuckets bucketByBlock(size_t count, Index log2, const BoxOfT& boxOf, bool threaded) {
    struct Entry {
        Coord block;
        uint32_t id;
        bool operator<(const Entry& o) const {
            return block < o.block || (block == o.block && id < o.id);
        }
    };
    // Each chunk of primitives lists its (block, id) entries; chunk sizes depend on count only.
    constexpr size_t CHUNK = 8192;
    const size_t chunkCount = (count + CHUNK - 1) / CHUNK;
    std::vector<std::vector<Entry>> chunks(chunkCount);
    util::parallelFor(
        chunkCount,
        [&](size_t c) {
            auto& out = chunks[c];
            CoordBBox box;
            for (size_t i = c * CHUNK, e = std::min(count, (c + 1) * CHUNK); i < e; ++i) {
                if (!boxOf(i, box) || box.empty())
                    continue;
                const Coord lo = box.min().alignedDown(log2), hi = box.max().alignedDown(log2);
                const Int32 step = Int32(1) << log2;
                for (Int64 x = lo[0]; x <= hi[0]; x += step) {
                    for (Int64 y = lo[1]; y <= hi[1]; y += step) {
                        for (Int64 z = lo[2]; z <= hi[2]; z += step)
                            out.push_back({Coord(Int32(x), Int32(y), Int32(z)), uint32_t(i)});
                    }
                }
            }
        },
        threaded, 1);
    size_t total = 0;
    for (const auto& chunk : chunks)
        total += chunk.size();
    std::vector<Entry> entries;
    entries.reserve(total);
    for (auto& chunk : chunks) {
        entries.insert(entries.end(), chunk.begin(), chunk.end());
        std::vector<Entry>().swap(chunk);
    }
    // Entries are unique, so the sorted order is one and the same however the sort runs.
    if (threaded) {
        tbb::parallel_sort(entries.begin(), entries.end());
    } else {
        std::sort(entries.begin(), entries.end());
    }

    BlockBuckets buckets;
    buckets.log2 = log2;
    buckets.ids.resize(entries.size());
    for (size_t n = 0; n < entries.size(); ++n) {
        if (n == 0 || !(entries[n].block == entries[n - 1].block)) {
            buckets.origins.push_back(entries[n].block);
            buckets.offsets.push_back(n);
        }
        buckets.ids[n] = entries[n].id;
    }
    buckets.offsets.push_back(entries.size());
    return buckets;
}

/// Runs `op(b, leaves)` for every block b, in parallel when `threaded`; op appends the leaves
/// it makes (all inside block b, at distinct origins) to `leaves`. Then links every leaf into
/// the empty region of `tree` it belongs to, block by block.
template <typename TreeT, typename OpT>
void buildLeavesByBlock(TreeT& tree, size_t blockCount, const OpT& op, bool threaded) {
    using LeafT = typename TreeT::LeafNodeType;
    std::vector<std::vector<std::unique_ptr<LeafT>>> leaves(blockCount);
    util::parallelFor(
        blockCount, [&](size_t b) { op(b, leaves[b]); }, threaded, 1);
    for (auto& block : leaves) {
        for (auto& leaf : block)
            tree.addLeaf(std::move(leaf));
    }
}

/// The leaves of one block: their local indices (x-major), origins and centres.
template <typename LeafT, Index BlockLog2>
struct BlockLeaves {
    static constexpr Index PER_AXIS = Index(1) << (BlockLog2 - LeafT::LOG2DIM);
    static constexpr Int32 DIM = Int32(LeafT::DIM);

    /// Calls `op(index, center)` for every leaf of the block at `origin` that `box` (clipped
    /// to the block) touches; `center` is the middle of the leaf's voxel centres.
    template <typename OpT>
    static void forEachTouched(const Coord& origin, CoordBBox box, const OpT& op) {
        const CoordBBox block = CoordBBox::createCube(origin, Int32(1) << BlockLog2);
        box.min() = Coord::maxComponent(box.min(), block.min());
        box.max() = Coord::minComponent(box.max(), block.max());
        if (box.empty())
            return;
        const Coord lo = (box.min() - origin) >> LeafT::LOG2DIM;
        const Coord hi = (box.max() - origin) >> LeafT::LOG2DIM;
        for (Int32 x = lo[0]; x <= hi[0]; ++x) {
            for (Int32 y = lo[1]; y <= hi[1]; ++y) {
                for (Int32 z = lo[2]; z <= hi[2]; ++z) {
                    const Vec3d center =
                        Vec3d(origin.offsetBy(x * DIM, y * DIM, z * DIM)) + 0.5 * double(DIM - 1);
                    op((uint32_t(x) * PER_AXIS + uint32_t(y)) * PER_AXIS + uint32_t(z), center);
                }
            }
        }
    }

    /// The origin of the leaf with local `index` in the block at `origin`.
    static Coord leafOrigin(const Coord& origin, uint32_t index) {
        return origin.offsetBy(Int32(index / (PER_AXIS * PER_AXIS)) * DIM,
                               Int32((index / PER_AXIS) % PER_AXIS) * DIM,
                               Int32(index % PER_AXIS) * DIM);
    }
};

/// The block edge (log2, in voxels) the tools use: 64 voxels, or one leaf if leaves are larger.
template <typename TreeT>
constexpr Index blockLog2() {
    return std::max<Index>(6, TreeT::LeafNodeType::LOG2DIM);
}

}  // namespace vdb::tools::detail
