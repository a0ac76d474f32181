// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery behind tools/Morphology.h (not API; included by that header, after the
/// NearestNeighbors and TilePolicy enums): word kernels on leaf value masks, a sparse set of
/// leaf-sized mask regions that the kernels run over, and the drivers that move masks between
/// a tree and such a set for each tile policy.
///
/// A region set copies the masks out of the tree, so that every step reads a snapshot and
/// writes fresh masks: each region's new mask is a pure function of its own old mask and its
/// neighbours' (a gather), computed in parallel without locks, and the result does not depend
/// on the number of threads. Regions that dilation reaches for the first time are collected
/// per task, sorted and created serially before the gather of each step.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tools/detail/LeafBuild.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/BitMask.h>
#include <vdb/util/LargeArray.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

// ---- Word kernels -----------------------------------------------------------------------------

/// Shifts and face masks for the value mask of a leaf of edge DIM = 2^Log2Dim.
///
/// The mask is read as one NUM_VALUES-bit integer whose bit (x * DIM + y) * DIM + z is voxel
/// (x, y, z), word 0 holding the lowest bits. One step of +1 along z, y or x is then a left
/// shift by 1, DIM or DIM^2 bits: in-word shifts for z and y, whole-word moves for x once
/// DIM^2 >= 64 (an 8^3 leaf has one 64-bit word per x-slab). The face masks cut what a shift
/// carries across a row or slab boundary and splice in the neighbour leaf's opposite face.
template <Index Log2Dim>
struct LeafMaskOps {
    using Word = uint64_t;
    static constexpr Index DIM = Index(1) << Log2Dim;
    static constexpr Index NUM_VALUES = Index(1) << (3 * Log2Dim);
    using Mask = util::BitMask<NUM_VALUES>;
    static constexpr Index WORDS = Mask::WORD_COUNT;

    /// log2 of the bit stride of one voxel step along `axis` (0 = x, 1 = y, 2 = z).
    static constexpr Index strideLog2(int axis) { return Log2Dim * Index(2 - axis); }

    /// Word `w` of the mask of the voxels whose coordinate along `axis` is 0, or DIM - 1 when
    /// `high`. Along an axis of stride s, such voxels form runs of s bits every s * DIM bits.
    static constexpr Word faceWord(int axis, bool high, Index w) {
        const Index64 run = Index64(1) << strideLog2(axis);
        const Index64 period = run << Log2Dim;
        if (period <= 64) {
            // Whole periods per word; run < period <= 64, so run <= 32.
            const Word ones = (Word(1) << run) - 1;
            const Word pattern =
                period == 64 ? ones : (~Word(0) / ((Word(1) << period) - 1)) * ones;
            return high ? pattern << (period - run) : pattern;
        }
        // A word lies inside one period; `offset` is its first bit within that period.
        const Index64 offset = (Index64(w) << 6) & (period - 1);
        if (run >= 64)
            return (high ? offset >= period - run : offset < run) ? ~Word(0) : Word(0);
        const Word ones = (Word(1) << run) - 1;
        if (high)
            return offset == period - 64 ? ones << (64 - run) : Word(0);
        return offset == 0 ? ones : Word(0);
    }

    /// True when a step along `axis` can move bits across a word boundary into positions that
    /// the face masks keep, so the shifts must carry bits between words.
    static constexpr bool carries(int axis) {
        return (Index64(1) << (strideLog2(axis) + Log2Dim)) > 64;
    }

    /// Word `w` of `v << S`: the voxels moved S bit positions up.
    template <Index S, bool Carry>
    static Word up(const Word* v, Index w) {
        constexpr Index WS = S >> 6, BS = S & 63;
        if (w < WS)
            return 0;
        Word r = v[w - WS] << BS;
        if constexpr (Carry && BS != 0) {
            if (w > WS)
                r |= v[w - WS - 1] >> (64 - BS);
        }
        return r;
    }
    /// Word `w` of `v >> S`: the voxels moved S bit positions down.
    template <Index S, bool Carry>
    static Word down(const Word* v, Index w) {
        constexpr Index WS = S >> 6, BS = S & 63;
        if (w + WS >= WORDS)
            return 0;
        Word r = v[w + WS] >> BS;
        if constexpr (Carry && BS != 0) {
            if (w + WS + 1 < WORDS)
                r |= v[w + WS + 1] << (64 - BS);
        }
        return r;
    }

    /// Word `w` of the masks of voxel (x, y, z)'s neighbour at -1 along `Axis` (`below`) and
    /// at +1 (`above`), with `prev` and `next` the masks of the leaves at -DIM and +DIM.
    template <int Axis>
    static void neighbourWords(const Word* self, const Word* prev, const Word* next, Index w,
                               Word& below, Word& above) {
        constexpr Index S = Index(1) << strideLog2(Axis);
        constexpr Index NS = S * (DIM - 1);
        constexpr bool C = carries(Axis);
        const Word fromBelow = up<S, C>(self, w), fromAbove = down<S, C>(self, w);
        const Word fromPrev = down<NS, C>(prev, w), fromNext = up<NS, C>(next, w);
        if constexpr (Axis == 0) {
            // x is the most significant coordinate: what crosses the leaf falls off the end.
            below = fromBelow | fromPrev;
            above = fromAbove | fromNext;
        } else {
            const Word lo = faceWord(Axis, false, w), hi = faceWord(Axis, true, w);
            below = (fromBelow & ~lo) | (fromPrev & lo);
            above = (fromAbove & ~hi) | (fromNext & hi);
        }
    }

    /// Word `w` of the one-voxel dilation of `self` along `Axis`.
    template <int Axis>
    static Word dilateWord(const Word* self, const Word* prev, const Word* next, Index w) {
        Word below, above;
        neighbourWords<Axis>(self, prev, next, w, below, above);
        return self[w] | below | above;
    }
    /// Word `w` of the one-voxel erosion of `self` along `Axis`.
    template <int Axis>
    static Word erodeWord(const Word* self, const Word* prev, const Word* next, Index w) {
        Word below, above;
        neighbourWords<Axis>(self, prev, next, w, below, above);
        return self[w] & below & above;
    }

    /// True when `mask` holds a voxel on side `d` of every axis (-1: coordinate 0, +1:
    /// coordinate DIM - 1, 0: any), i.e. when one step in direction `d` leaves the leaf.
    static bool touches(const Mask& mask, int dx, int dy, int dz) {
        const Word* v = mask.words();
        for (Index w = 0; w < WORDS; ++w) {
            Word bits = v[w];
            if (dx != 0)
                bits &= faceWord(0, dx > 0, w);
            if (dy != 0)
                bits &= faceWord(1, dy > 0, w);
            if (dz != 0)
                bits &= faceWord(2, dz > 0, w);
            if (bits != 0)
                return true;
        }
        return false;
    }
};

// ---- Neighbourhoods ---------------------------------------------------------------------------

/// A leaf-sized step to one of the 26 neighbouring regions.
struct RegionStep {
    int x, y, z;
};

/// The 26 steps, faces first, then edges, then corners, so that the first 6, 18 or 26 are the
/// regions one voxel step of NN_FACE, NN_FACE_EDGE or NN_FACE_EDGE_VERTEX can reach.
inline constexpr std::array<RegionStep, 26> REGION_STEPS = [] {
    std::array<RegionStep, 26> steps{};
    size_t n = 0;
    for (int nonzero = 1; nonzero <= 3; ++nonzero) {
        for (int x = -1; x <= 1; ++x)
            for (int y = -1; y <= 1; ++y)
                for (int z = -1; z <= 1; ++z)
                    if ((x != 0) + (y != 0) + (z != 0) == nonzero)
                        steps[n++] = RegionStep{x, y, z};
    }
    return steps;
}();

/// Number of leading REGION_STEPS that one step of `nn` can reach (6, 18 or 26).
inline constexpr size_t regionStepCount(NearestNeighbors nn) {
    return nn == NN_FACE ? 6 : nn == NN_FACE_EDGE ? 18 : 26;
}

/// `origin + step * dim` when every component stays within 32 bits.
inline bool offsetOrigin(const Coord& origin, Int64 dx, Int64 dy, Int64 dz, Int64 dim,
                         Coord& result) {
    const Int64 x = origin[0] + dx * dim, y = origin[1] + dy * dim, z = origin[2] + dz * dim;
    constexpr Int64 lo = std::numeric_limits<Int32>::min(), hi = std::numeric_limits<Int32>::max();
    if (x < lo || x > hi || y < lo || y > hi || z < lo || z > hi)
        return false;
    result = Coord(Int32(x), Int32(y), Int32(z));
    return true;
}

// ---- Region set -------------------------------------------------------------------------------

/// A sparse set of leaf-sized regions of index space, each with a value mask, and one step of
/// dilation or erosion over all of them.
///
/// Regions are numbered in the order they were added. A block index finds a region from its
/// origin: 8^3 regions per block, each block a dense table of region numbers plus the numbers
/// of its 26 neighbour blocks, so that a region's neighbours are found with array reads.
/// The mask array keeps two extra entries past the last region, an all-off and an all-on mask,
/// which stand for absent neighbours (inactive space, or space under an active tile).
///
/// Threads: assign() and the steps run in parallel over regions, add() is serial; the region
/// numbers and the masks are the same for any number of threads.
template <Index Log2Dim>
class MaskRegionSet {
public:
    using Ops = LeafMaskOps<Log2Dim>;
    using Mask = typename Ops::Mask;
    using Word = typename Ops::Word;
    static constexpr uint32_t NONE = ~uint32_t(0);
    static constexpr Int32 DIM = Int32(Ops::DIM);
    static constexpr Index WORDS = Ops::WORDS;

    MaskRegionSet() : mMasks{Mask(), Mask(true)} {}

    size_t size() const { return mOrigins.size(); }

    /// Makes an empty set the `n` regions `originOf(i)` with masks `maskOf(i)`, numbered i,
    /// building the arrays in parallel when `threaded`. @pre the set is empty; the origins are
    /// distinct multiples of DIM
    template <typename OriginT, typename MaskT>
    void assign(size_t n, const OriginT& originOf, const MaskT& maskOf, bool threaded);
    const Coord& origin(size_t i) const { return mOrigins[i]; }
    const Mask& mask(size_t i) const { return mMasks[i]; }

    /// Appends a region. @pre no region has this origin; origin is a multiple of DIM
    uint32_t add(const Coord& origin, const Mask& mask) {
        const uint32_t id = uint32_t(mOrigins.size());
        const Coord r = origin >> Log2Dim;
        const uint32_t block = findOrAddBlock(blockKey(origin));
        const uint16_t local = localIndex(r[0], r[1], r[2]);
        VDB_ASSERT(mSlots[block][local] == NONE);
        mSlots[block][local] = id;
        mOrigins.push_back(origin);
        mBlock.push_back(block);
        mLocal.push_back(local);
        mMasks.insert(mMasks.end() - 2, mask);
        return id;
    }
    /// Marks region `i` as pinned: erode() resets it to all-on after every step.
    void pin(uint32_t i) { mPinned.push_back(i); }

    /// The region one region-step from region `i`, or NONE. @pre each step in [-1, 1]
    uint32_t neighbour(size_t i, int dx, int dy, int dz) const {
        const uint16_t local = mLocal[i];
        const int x = (local >> 6) + dx, y = ((local >> 3) & 7) + dy, z = (local & 7) + dz;
        // Block step per axis: -1 below 0, +1 above 7 (x >> 3 is -1, 0 or 1 here).
        const int bx = x >> 3, by = y >> 3, bz = z >> 3;
        const uint32_t block =
            mNeighbourBlocks[mBlock[i]][size_t((bx + 1) * 9 + (by + 1) * 3 + (bz + 1))];
        if (block == NONE)
            return NONE;
        return mSlots[block][localIndex(x, y, z)];
    }

    /// Adds, for every region with a voxel on a face (edge, corner) that one step of `nn`
    /// crosses, the neighbour region beyond it if it is absent, inside `domain` and
    /// `makeAccept()(origin)` allows it. New regions are added in sorted origin order.
    template <typename MakeAcceptT>
    void addReachedRegions(NearestNeighbors nn, const CoordBBox& domain,
                           const MakeAcceptT& makeAccept, bool threaded);

    /// Records, for every region, its six face neighbours for the steps. An absent neighbour
    /// stands for the all-on mask when `useFill` and `makeFill()(origin)` says its region is
    /// covered, else for the all-off mask.
    template <typename MakeFillT>
    void buildFaceTable(bool useFill, const MakeFillT& makeFill, bool threaded);

    /// One dilation (`Erode` false) or erosion step of every region by `nn`, reading the
    /// face table built since the last add(). Pinned regions are reset to all-on afterwards.
    template <bool Erode>
    void step(NearestNeighbors nn, bool threaded);

private:
    static constexpr Index BLOCK_LOG2 = 3;
    static constexpr size_t BLOCK_SIZE = size_t(1) << (3 * BLOCK_LOG2);
    using Slots = std::array<uint32_t, BLOCK_SIZE>;

    struct KeyHash {
        size_t operator()(const Coord& k) const noexcept {
            const uint64_t x = static_cast<uint32_t>(k[0]), y = static_cast<uint32_t>(k[1]),
                           z = static_cast<uint32_t>(k[2]);
            uint64_t h = ((x << 32) | y) * 0x9e3779b97f4a7c15ull;
            h ^= z * 0xc2b2ae3d27d4eb4full;
            return size_t(h ^ (h >> 29));
        }
    };

    static uint16_t localIndex(int x, int y, int z) {
        return uint16_t(((x & 7) << 6) | ((y & 7) << 3) | (z & 7));
    }
    static Coord blockKey(const Coord& origin) { return (origin >> Log2Dim) >> BLOCK_LOG2; }

    /// Links block `id` (at `key`) to its existing neighbours, and them to it when `both`.
    void linkBlock(uint32_t id, const Coord& key, bool both) {
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dz = -1; dz <= 1; ++dz) {
                    const size_t slot = size_t((dx + 1) * 9 + (dy + 1) * 3 + (dz + 1));
                    const auto other = mBlockMap.find(key.offsetBy(dx, dy, dz));
                    if (other == mBlockMap.end())
                        continue;
                    mNeighbourBlocks[id][slot] = other->second;
                    if (both)
                        mNeighbourBlocks[other->second][26 - slot] = id;
                }
            }
        }
    }

    uint32_t findOrAddBlock(const Coord& key) {
        const auto [it, added] = mBlockMap.try_emplace(key, uint32_t(mSlots.size()));
        if (!added)
            return it->second;
        const uint32_t id = it->second;
        mSlots.emplace_back();
        mSlots.back().fill(NONE);
        mNeighbourBlocks.emplace_back();
        mNeighbourBlocks.back().fill(NONE);
        linkBlock(id, key, /*both=*/true);
        return id;
    }

    // Scratch mask arrays sized for the current regions, with the two sentinels at the end.
    void prepare(util::LargeVector<Mask>& buffer) const {
        buffer.resize(mOrigins.size() + 2);
        buffer[mOrigins.size()] = Mask();
        buffer[mOrigins.size() + 1] = Mask(true);
    }

    template <bool Erode, int Axis>
    static Word axisWord(const util::LargeVector<Mask>& in, const std::array<uint32_t, 6>& face,
                         size_t i, Index w) {
        const Word* self = in[i].words();
        const Word* prev = in[face[2 * Axis]].words();
        const Word* next = in[face[2 * Axis + 1]].words();
        if constexpr (Erode) {
            return Ops::template erodeWord<Axis>(self, prev, next, w);
        } else {
            return Ops::template dilateWord<Axis>(self, prev, next, w);
        }
    }

    // The arrays with an entry per region or block are large for large grids: they come from
    // util::LargeVector, whose huge pages make their first touch cheap.
    util::LargeVector<Coord> mOrigins;
    util::LargeVector<uint32_t> mBlock;  // block of each region
    util::LargeVector<uint16_t> mLocal;  // slot of each region in its block
    util::LargeVector<Mask> mMasks;      // one per region, then the all-off and all-on sentinels
    std::vector<uint32_t> mPinned;
    util::LargeVector<std::array<uint32_t, 6>> mFace;  // -x, +x, -y, +y, -z, +z; into mMasks
    util::LargeVector<Mask> mScratchA, mScratchB, mScratchC;
    std::unordered_map<Coord, uint32_t, KeyHash> mBlockMap;
    util::LargeVector<Slots> mSlots;  // region of each block slot, or NONE
    util::LargeVector<std::array<uint32_t, 27>> mNeighbourBlocks;  // (dx+1)*9+(dy+1)*3+(dz+1)
};

template <Index Log2Dim>
template <typename OriginT, typename MaskT>
void MaskRegionSet<Log2Dim>::assign(size_t n, const OriginT& originOf, const MaskT& maskOf,
                                    bool threaded) {
    VDB_ASSERT(size() == 0);
    constexpr size_t grain = 256;
    mOrigins.resize(n);
    mBlock.resize(n);
    mLocal.resize(n);
    mMasks.resize(n + 2);
    mMasks[n] = Mask();
    mMasks[n + 1] = Mask(true);

    // The regions, and the keys of their blocks per task (consecutive regions mostly share a
    // block); sorted afterwards, so that block numbers do not depend on how the range was split.
    std::vector<Coord> keys;
    std::mutex mutex;
    util::parallelForRange(
        n,
        [&](size_t begin, size_t end) {
            std::vector<Coord> local;
            for (size_t i = begin; i < end; ++i) {
                const Coord origin = originOf(i);
                const Coord r = origin >> Log2Dim;
                mOrigins[i] = origin;
                mMasks[i] = maskOf(i);
                mLocal[i] = localIndex(r[0], r[1], r[2]);
                const Coord key = r >> BLOCK_LOG2;
                if (local.empty() || local.back() != key)
                    local.push_back(key);
            }
            std::lock_guard<std::mutex> lock(mutex);
            keys.insert(keys.end(), local.begin(), local.end());
        },
        threaded, grain);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());

    const size_t blocks = keys.size();
    mBlockMap.reserve(blocks);
    for (size_t b = 0; b < blocks; ++b)
        mBlockMap.emplace(keys[b], uint32_t(b));
    mSlots.resize(blocks);
    mNeighbourBlocks.resize(blocks);
    util::parallelFor(
        blocks,
        [&](size_t b) {
            mSlots[b].fill(NONE);
            mNeighbourBlocks[b].fill(NONE);
            linkBlock(uint32_t(b), keys[b], /*both=*/false);
        },
        threaded, 16);
    util::parallelFor(
        n,
        [&](size_t i) {
            const uint32_t block = mBlockMap.find(blockKey(mOrigins[i]))->second;
            VDB_ASSERT(mSlots[block][mLocal[i]] == NONE);
            mBlock[i] = block;
            mSlots[block][mLocal[i]] = uint32_t(i);
        },
        threaded, grain);
}

template <Index Log2Dim>
template <typename MakeAcceptT>
void MaskRegionSet<Log2Dim>::addReachedRegions(NearestNeighbors nn, const CoordBBox& domain,
                                               const MakeAcceptT& makeAccept, bool threaded) {
    const size_t stepCount = regionStepCount(nn);
    std::vector<Coord> reached;
    std::mutex mutex;
    // Collect per task, then sort: the result does not depend on how the range was split.
    util::parallelForRange(
        size(),
        [&](size_t begin, size_t end) {
            auto accept = makeAccept();
            std::vector<Coord> local;
            for (size_t i = begin; i < end; ++i) {
                const Mask& m = mMasks[i];
                if (m.isOff())
                    continue;
                for (size_t s = 0; s < stepCount; ++s) {
                    const RegionStep d = REGION_STEPS[s];
                    if (neighbour(i, d.x, d.y, d.z) != NONE || !Ops::touches(m, d.x, d.y, d.z))
                        continue;
                    Coord o;
                    if (!offsetOrigin(mOrigins[i], d.x, d.y, d.z, DIM, o) || !domain.isInside(o))
                        continue;
                    if (accept(o))
                        local.push_back(o);
                }
            }
            if (!local.empty()) {
                std::lock_guard<std::mutex> lock(mutex);
                reached.insert(reached.end(), local.begin(), local.end());
            }
        },
        threaded, 256);
    std::sort(reached.begin(), reached.end());
    reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
    mMasks.reserve(mMasks.size() + reached.size());
    for (const Coord& o : reached)
        add(o, Mask());
}

template <Index Log2Dim>
template <typename MakeFillT>
void MaskRegionSet<Log2Dim>::buildFaceTable(bool useFill, const MakeFillT& makeFill,
                                            bool threaded) {
    const size_t n = size();
    const uint32_t off = uint32_t(n), on = uint32_t(n + 1);
    mFace.resize(n);
    util::parallelForRange(
        n,
        [&](size_t begin, size_t end) {
            auto fill = makeFill();
            for (size_t i = begin; i < end; ++i) {
                for (int axis = 0; axis < 3; ++axis) {
                    for (int side = 0; side < 2; ++side) {
                        const int d = side == 0 ? -1 : 1;
                        const int dx = axis == 0 ? d : 0, dy = axis == 1 ? d : 0,
                                  dz = axis == 2 ? d : 0;
                        uint32_t id = neighbour(i, dx, dy, dz);
                        if (id == NONE) {
                            Coord o;
                            id = useFill && offsetOrigin(mOrigins[i], dx, dy, dz, DIM, o) && fill(o)
                                     ? on
                                     : off;
                        }
                        mFace[i][size_t(2 * axis + side)] = id;
                    }
                }
            }
        },
        threaded, 256);
}

template <Index Log2Dim>
template <bool Erode>
void MaskRegionSet<Log2Dim>::step(NearestNeighbors nn, bool threaded) {
    const size_t n = size();
    constexpr size_t grain = 128;
    if (nn == NN_FACE) {
        // A voxel and its six face neighbours: the three axis steps of the same input.
        prepare(mScratchA);
        util::parallelFor(
            n,
            [&](size_t i) {
                const auto& face = mFace[i];
                Word* out = mScratchA[i].words();
                for (Index w = 0; w < WORDS; ++w) {
                    const Word x = axisWord<Erode, 0>(mMasks, face, i, w);
                    const Word y = axisWord<Erode, 1>(mMasks, face, i, w);
                    const Word z = axisWord<Erode, 2>(mMasks, face, i, w);
                    out[w] = Erode ? (x & y & z) : (x | y | z);
                }
            },
            threaded, grain);
        mMasks.swap(mScratchA);
    } else if (nn == NN_FACE_EDGE) {
        // The 18-neighbourhood is the union of the three axis-aligned 3x3 squares, each the
        // composition of two axis steps: xy, xz and yz.
        prepare(mScratchA);
        prepare(mScratchB);
        util::parallelFor(
            n,
            [&](size_t i) {
                const auto& face = mFace[i];
                Word* xs = mScratchA[i].words();
                Word* ys = mScratchB[i].words();
                for (Index w = 0; w < WORDS; ++w) {
                    xs[w] = axisWord<Erode, 0>(mMasks, face, i, w);
                    ys[w] = axisWord<Erode, 1>(mMasks, face, i, w);
                }
            },
            threaded, grain);
        prepare(mScratchC);
        util::parallelFor(
            n,
            [&](size_t i) {
                const auto& face = mFace[i];
                Word* out = mScratchC[i].words();
                for (Index w = 0; w < WORDS; ++w) {
                    const Word xy = axisWord<Erode, 1>(mScratchA, face, i, w);
                    const Word xz = axisWord<Erode, 2>(mScratchA, face, i, w);
                    const Word yz = axisWord<Erode, 2>(mScratchB, face, i, w);
                    out[w] = Erode ? (xy & xz & yz) : (xy | xz | yz);
                }
            },
            threaded, grain);
        mMasks.swap(mScratchC);
    } else {
        // The 3x3x3 cube is the composition of the three axis steps.
        prepare(mScratchA);
        util::parallelFor(
            n,
            [&](size_t i) {
                Word* out = mScratchA[i].words();
                for (Index w = 0; w < WORDS; ++w)
                    out[w] = axisWord<Erode, 0>(mMasks, mFace[i], i, w);
            },
            threaded, grain);
        prepare(mScratchB);
        util::parallelFor(
            n,
            [&](size_t i) {
                Word* out = mScratchB[i].words();
                for (Index w = 0; w < WORDS; ++w)
                    out[w] = axisWord<Erode, 1>(mScratchA, mFace[i], i, w);
            },
            threaded, grain);
        util::parallelFor(
            n,
            [&](size_t i) {
                Word* out = mScratchA[i].words();
                for (Index w = 0; w < WORDS; ++w)
                    out[w] = axisWord<Erode, 2>(mScratchB, mFace[i], i, w);
            },
            threaded, grain);
        mMasks.swap(mScratchA);
    }
    for (uint32_t i : mPinned)
        mMasks[i].setOn();
}

// ---- Tree walks -------------------------------------------------------------------------------

/// An active tile: its first voxel, its edge in voxels and the level of the node holding it.
struct TileRef {
    Coord origin;
    Int32 dim;
    Index level;
    bool operator<(const TileRef& o) const {
        return level != o.level ? level < o.level : origin < o.origin;
    }
};

/// Tree walks over tiles and branches shared by the morphology drivers.
template <typename TreeT>
struct TreeTileOps {
    using TopT = typename TreeT::TopNodeType;
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    static constexpr bool IS_MASK = tree::IS_MASK_NODE<LeafT>;

    /// The value of a tile switched off: in a mask tree a tile's value is its state.
    static ValueT offValue(const ValueT& value) {
        if constexpr (IS_MASK) {
            return ValueT(false);
        } else {
            return value;
        }
    }

    template <typename NodeT>
    static void collectIn(const NodeT& node, std::vector<TileRef>& tiles) {
        using ChildT = typename NodeT::ChildNodeType;
        tree::forEachTile<ValueFilter::On>(node, [&](const auto& tile) {
            tiles.push_back({tile.origin, Int32(ChildT::DIM), NodeT::LEVEL});
        });
        if constexpr (ChildT::LEVEL > 0)
            tree::forEachChild(node, [&](const ChildT& child) { collectIn(child, tiles); });
    }
    /// Every active tile of the tree, sorted by level and origin.
    static std::vector<TileRef> activeTiles(const TreeT& tree) {
        std::vector<TileRef> tiles;
        collectIn(tree.topNode(), tiles);
        std::sort(tiles.begin(), tiles.end());
        return tiles;
    }

    template <typename NodeT>
    static bool hasActiveTilesIn(const NodeT& node) {
        using ChildT = typename NodeT::ChildNodeType;
        bool any = false;
        tree::forEachTile<ValueFilter::On>(node, [&](const auto&) { any = true; });
        if constexpr (ChildT::LEVEL > 0) {
            tree::forEachChild(node,
                               [&](const ChildT& child) { any = any || hasActiveTilesIn(child); });
        }
        return any;
    }
    static bool hasActiveTiles(const TreeT& tree) { return hasActiveTilesIn(tree.topNode()); }

    /// The children of `node` (owned by it), in table order.
    template <typename NodeT>
    static std::vector<typename NodeT::ChildNodeType*> childrenOf(NodeT& node) {
        std::vector<typename NodeT::ChildNodeType*> children;
        children.reserve(tree::childCount(node));
        tree::forEachChild(node, [&](auto& child) { children.push_back(&child); });
        return children;
    }

    /// Splits each active tile of `node` into a child of the tile's value, all active.
    template <typename NodeT>
    static void splitActiveTiles(NodeT& node) {
        std::vector<Coord> origins;
        tree::forEachTile<ValueFilter::On>(
            node, [&](const auto& tile) { origins.push_back(tile.origin); });
        for (const Coord& origin : origins)
            tree::touchChild(node, origin);
    }
    template <typename NodeT>
    static void voxelizeIn(NodeT& node) {
        using ChildT = typename NodeT::ChildNodeType;
        splitActiveTiles(node);
        if constexpr (ChildT::LEVEL > 0)
            tree::forEachChild(node, [](ChildT& child) { voxelizeIn(child); });
    }
    /// Replaces every active tile by nodes down to dense leaves of the tile's value.
    static void voxelizeActiveTiles(TreeT& tree, bool threaded) {
        TopT& top = tree.topNode();
        using ChildT = typename TopT::ChildNodeType;
        // The top's own tiles first, serially; then each top-level branch in its own task.
        splitActiveTiles(top);
        if constexpr (ChildT::LEVEL > 0) {
            const auto children = childrenOf(top);
            util::parallelFor(
                children.size(), [&](size_t i) { voxelizeIn(*children[i]); }, threaded, 1);
        }
    }

    template <typename NodeT>
    static bool dropInactiveBranchesIn(NodeT& node, const ValueT& background) {
        using ChildT = typename NodeT::ChildNodeType;
        bool active = !node.getValueMask().isOff();
        const auto children = node.getChildMask();
        for (Index n : children.onBits()) {
            ChildT* child = node.getChild(n);
            bool childActive;
            if constexpr (ChildT::LEVEL == 0) {
                childActive = !child->isEmpty();
            } else {
                childActive = dropInactiveBranchesIn(*child, background);
            }
            if (!childActive)
                node.setTile(n, background, false);
            active = active || childActive;
        }
        return active;
    }
    /// Replaces every branch (a child node at any level) that holds no active value by an
    /// inactive background tile, or removes it from a root table; keeps inactive tiles.
    static void dropInactiveBranches(TreeT& tree, bool threaded) {
        TopT& top = tree.topNode();
        using ChildT = typename TopT::ChildNodeType;
        const ValueT background = tree.background();
        const auto children = childrenOf(top);
        std::vector<char> active(children.size());
        util::parallelFor(
            children.size(),
            [&](size_t i) {
                if constexpr (ChildT::LEVEL == 0) {
                    active[i] = !children[i]->isEmpty();
                } else {
                    active[i] = dropInactiveBranchesIn(*children[i], background);
                }
            },
            threaded, 1);
        for (size_t i = 0; i < children.size(); ++i) {
            if (!active[i])
                tree::clearRegion(top, children[i]->origin(), background);
        }
        tree.clearAllAccessors();
    }
};

/// Answers whether the leaf region at an origin lies under an active tile, with its own
/// accessor (one per task).
template <typename TreeT>
class CoverageProbe {
public:
    explicit CoverageProbe(const TreeT& tree) : mAcc(tree) {}
    bool operator()(const Coord& origin) const {
        return mAcc.probeConstLeaf(origin) == nullptr && mAcc.isValueOn(origin);
    }

private:
    tree::ValueAccessor<const TreeT> mAcc;
};

// ---- Drivers ----------------------------------------------------------------------------------

/// Dilation and erosion of one tree type under each tile policy; see tools/Morphology.h for
/// the semantics. The entry points are defined out of line so that `extern template` in the
/// public header keeps them out of user translation units.
template <typename TreeT>
class Morphology {
public:
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using Set = MaskRegionSet<LeafT::LOG2DIM>;
    using Mask = typename Set::Mask;
    using Tiles = TreeTileOps<TreeT>;
    static constexpr Int32 DIM = Int32(LeafT::DIM);

    static void dilate(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                       bool threaded);
    static void erode(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                      bool threaded);

private:
    struct Accept {
        bool operator()(const Coord&) const { return true; }
    };
    struct Uncovered {
        CoverageProbe<TreeT> covered;
        bool operator()(const Coord& o) const { return !covered(o); }
    };

    /// Adds the leaf regions of `tile` within `radius` regions of its boundary that have a
    /// region outside the tile, within `radius` regions, for which `open(origin, inRange)` is
    /// true (`inRange` false for origins beyond 32 bits).
    template <typename OpenT>
    static void tileShell(const TileRef& tile, int radius, OpenT& open, std::vector<Coord>& out);

    /// What erosion did to each active tile: the tile's regions in the set (consecutive from
    /// `firstProxy`); regions outside the set kept every voxel.
    class TileChanges {
    public:
        static constexpr size_t NOT_FOUND = ~size_t(0);
        TileChanges(const std::vector<TileRef>& tiles, const std::vector<uint32_t>& proxyTile,
                    const Set& set, size_t firstProxy);
        /// The tile at `origin` held by a node of `level`, or NOT_FOUND.
        size_t find(Index level, const Coord& origin) const;
        /// True when some voxel of tile `t` was switched off.
        bool changed(size_t t) const { return mOn[t] < Index64(mFirst[t + 1] - mFirst[t]); }
        /// True when every voxel of tile `t` was switched off.
        bool allOff(size_t t) const;
        /// A node replacing tile `t` of `value`: active where the voxels stayed on, pruned.
        template <typename ChildT>
        std::unique_ptr<ChildT> build(size_t t, const ValueT& value) const;

    private:
        const std::vector<TileRef>& mTiles;
        const Set& mSet;
        size_t mFirstProxy;
        std::vector<size_t> mFirst;  // tile t's set regions: [mFirst[t], mFirst[t+1]) + firstProxy
        std::vector<Index64> mOn, mOff;  // of those, how many came out all-on and all-off
    };
    template <typename NodeT>
    static void changeTilesIn(NodeT& node, const TileChanges& changes);
    /// Switches off, or replaces by pruned nodes, the active tiles that erosion changed.
    static void changeTiles(TreeT& tree, const TileChanges& changes);
};

template <typename TreeT>
template <typename OpenT>
void Morphology<TreeT>::tileShell(const TileRef& tile, int radius, OpenT& open,
                                  std::vector<Coord>& out) {
    const int m = tile.dim / DIM;  // regions per axis
    auto boundary = [&](int i) { return i < radius || i >= m - radius; };
    auto outside = [&](int i) { return i < 0 || i >= m; };
    for (int i = 0; i < m; ++i) {
        for (int j = 0; j < m; ++j) {
            const bool edge = boundary(i) || boundary(j);
            for (int k = 0; k < m; ++k) {
                if (!edge && !boundary(k)) {
                    k = m - radius - 1;  // skip the interior of this row
                    continue;
                }
                bool keep = false;
                for (int dx = -radius; dx <= radius && !keep; ++dx) {
                    for (int dy = -radius; dy <= radius && !keep; ++dy) {
                        for (int dz = -radius; dz <= radius && !keep; ++dz) {
                            if (!outside(i + dx) && !outside(j + dy) && !outside(k + dz))
                                continue;
                            Coord o;
                            const bool inRange =
                                offsetOrigin(tile.origin, i + dx, j + dy, k + dz, DIM, o);
                            keep = open(o, inRange);
                        }
                    }
                }
                if (keep)
                    out.push_back(tile.origin.offsetBy(i * DIM, j * DIM, k * DIM));
            }
        }
    }
}

template <typename TreeT>
void Morphology<TreeT>::dilate(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                               bool threaded) {
    if (iterations <= 0)
        return;
    if (mode == EXPAND_TILES)
        Tiles::voxelizeActiveTiles(tree, threaded);
    const bool tiles = mode != EXPAND_TILES && Tiles::hasActiveTiles(tree);
    const CoordBBox domain = TreeT::domain();

    // Every leaf is a region (empty ones too, so that no leaf is created twice).
    const NodeLists<TreeT> lists(tree, 0, threaded);
    const auto& leaves = lists.template nodes<0>();
    Set set;
    set.assign(
        leaves.size(), [&](size_t i) { return leaves[i]->origin(); },
        [&](size_t i) -> const auto& { return leaves[i]->getValueMask(); }, threaded);
    const size_t leafRegions = set.size();

    // Preserved tiles dilate like their voxels: their regions next to uncovered space join
    // as all-on masks.
    if (mode == PRESERVE_TILES && tiles) {
        const std::vector<TileRef> tileList = Tiles::activeTiles(tree);
        std::vector<std::vector<Coord>> shells(tileList.size());
        util::parallelFor(
            tileList.size(),
            [&](size_t t) {
                CoverageProbe<TreeT> covered(tree);
                auto open = [&](const Coord& o, bool inRange) {
                    return inRange && domain.isInside(o) && !covered(o);
                };
                tileShell(tileList[t], 1, open, shells[t]);
            },
            threaded, 1);
        for (const auto& shell : shells)
            for (const Coord& o : shell)
                set.add(o, Mask(true));
    }

    // Step by step: add the regions the step reaches (not under a preserved tile), then
    // gather every region's new mask.
    for (int it = 0; it < iterations; ++it) {
        if (mode == PRESERVE_TILES && tiles) {
            set.addReachedRegions(
                nn, domain, [&] { return Uncovered{CoverageProbe<TreeT>(tree)}; }, threaded);
        } else {
            set.addReachedRegions(
                nn, domain, [] { return Accept{}; }, threaded);
        }
        set.buildFaceTable(
            false, [] { return Accept{}; }, threaded);
        set.template step<false>(nn, threaded);
    }

    // Write the masks back into the existing leaves, and make the new leaves, in parallel; then
    // link the new ones, in an order that does not depend on the thread count.
    util::parallelFor(
        leafRegions, [&](size_t i) { leaves[i]->setValueMask(set.mask(i)); }, threaded, 256);
    std::vector<std::unique_ptr<LeafT>> added(set.size() - leafRegions);
    util::parallelForRange(
        added.size(),
        [&](size_t begin, size_t end) {
            CoverageProbe<TreeT> covered(tree);
            tree::ValueAccessor<const TreeT> acc(tree);
            for (size_t k = begin; k < end; ++k) {
                const size_t i = leafRegions + k;
                const Coord& o = set.origin(i);
                // Tile regions and, when tiles are ignored, regions the voxels reached under a
                // tile. Any other region lies in inactive space: its leaf takes the value there.
                if (tiles && covered(o))
                    continue;
                added[k] = std::make_unique<LeafT>(o, acc.getValue(o), false);
                added[k]->setValueMask(set.mask(i));
            }
        },
        threaded, 64);
    linkLeaves(tree, added, threaded);
    if (mode == PRESERVE_TILES)
        tree.prune();
}

template <typename TreeT>
void Morphology<TreeT>::erode(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                              bool threaded) {
    if (iterations <= 0)
        return;
    if (mode == EXPAND_TILES)
        Tiles::voxelizeActiveTiles(tree, threaded);
    const bool tiles = mode != EXPAND_TILES && Tiles::hasActiveTiles(tree);

    // Leaves with active voxels are the regions that can change (with the tiles' below).
    std::vector<LeafT*> regionLeaf = NodeLists<TreeT>(tree, 0, threaded).template nodes<0>();
    {
        util::LargeVector<char> empty(regionLeaf.size());
        util::parallelFor(
            regionLeaf.size(), [&](size_t i) { empty[i] = regionLeaf[i]->isEmpty(); }, threaded,
            256);
        size_t kept = 0;
        for (size_t i = 0; i < regionLeaf.size(); ++i) {
            if (!empty[i])
                regionLeaf[kept++] = regionLeaf[i];
        }
        regionLeaf.resize(kept);
    }
    Set set;
    set.assign(
        regionLeaf.size(), [&](size_t i) { return regionLeaf[i]->origin(); },
        [&](size_t i) -> const auto& { return regionLeaf[i]->getValueMask(); }, threaded);
    const size_t leafRegions = set.size();

    std::vector<TileRef> tileList;
    std::vector<uint32_t> proxyTile;  // for PRESERVE: the tile of each region past leafRegions
    if (tiles && mode == IGNORE_TILES) {
        // Tiles stay active: their regions next to a leaf join as pinned all-on masks, so
        // that the axis steps see them like voxels.
        std::vector<Coord> reached;
        std::mutex mutex;
        util::parallelForRange(
            leafRegions,
            [&](size_t begin, size_t end) {
                CoverageProbe<TreeT> covered(tree);
                std::vector<Coord> local;
                for (size_t i = begin; i < end; ++i) {
                    for (const RegionStep& d : REGION_STEPS) {
                        Coord o;
                        if (set.neighbour(i, d.x, d.y, d.z) == Set::NONE &&
                            offsetOrigin(set.origin(i), d.x, d.y, d.z, DIM, o) && covered(o))
                            local.push_back(o);
                    }
                }
                std::lock_guard<std::mutex> lock(mutex);
                reached.insert(reached.end(), local.begin(), local.end());
            },
            threaded, 256);
        std::sort(reached.begin(), reached.end());
        reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
        for (const Coord& o : reached)
            set.pin(set.add(o, Mask(true)));
    } else if (tiles && mode == PRESERVE_TILES) {
        // Tiles erode like their voxels. A tile's regions farther than `radius` regions from
        // any uncovered region keep every voxel for all the steps, and stand outside the set
        // as all-on neighbours; the others join the set.
        const int radius = (iterations - 1) / DIM + 1;
        tileList = Tiles::activeTiles(tree);
        std::vector<std::vector<Coord>> shells(tileList.size());
        util::parallelFor(
            tileList.size(),
            [&](size_t t) {
                CoverageProbe<TreeT> covered(tree);
                auto open = [&](const Coord& o, bool inRange) { return !inRange || !covered(o); };
                tileShell(tileList[t], radius, open, shells[t]);
            },
            threaded, 1);
        for (size_t t = 0; t < shells.size(); ++t) {
            for (const Coord& o : shells[t]) {
                set.add(o, Mask(true));
                proxyTile.push_back(uint32_t(t));
            }
        }
    }

    // Absent neighbours under an active tile read as all-on, others as all-off.
    set.buildFaceTable(
        tiles, [&] { return CoverageProbe<TreeT>(tree); }, threaded);
    for (int it = 0; it < iterations; ++it)
        set.template step<true>(nn, threaded);

    util::parallelFor(
        leafRegions, [&](size_t i) { regionLeaf[i]->setValueMask(set.mask(i)); }, threaded, 256);
    if (mode != PRESERVE_TILES)
        return;

    if (!tileList.empty()) {
        const TileChanges changes(tileList, proxyTile, set, leafRegions);
        changeTiles(tree, changes);
    }
    Tiles::dropInactiveBranches(tree, threaded);
}

template <typename TreeT>
Morphology<TreeT>::TileChanges::TileChanges(const std::vector<TileRef>& tiles,
                                            const std::vector<uint32_t>& proxyTile, const Set& set,
                                            size_t firstProxy)
    : mTiles(tiles),
      mSet(set),
      mFirstProxy(firstProxy),
      mFirst(tiles.size() + 1, 0),
      mOn(tiles.size(), 0),
      mOff(tiles.size(), 0) {
    // The proxies of one tile are consecutive in the set.
    for (size_t p = 0; p < proxyTile.size(); ++p) {
        const uint32_t t = proxyTile[p];
        ++mFirst[t + 1];
        const Mask& m = set.mask(firstProxy + p);
        mOn[t] += m.isOn();
        mOff[t] += m.isOff();
    }
    for (size_t t = 0; t < tiles.size(); ++t)
        mFirst[t + 1] += mFirst[t];
}

template <typename TreeT>
size_t Morphology<TreeT>::TileChanges::find(Index level, const Coord& origin) const {
    const TileRef key{origin, 0, level};
    const auto it = std::lower_bound(mTiles.begin(), mTiles.end(), key);
    if (it == mTiles.end() || it->level != level || it->origin != origin)
        return NOT_FOUND;
    return size_t(it - mTiles.begin());
}

template <typename TreeT>
bool Morphology<TreeT>::TileChanges::allOff(size_t t) const {
    const Index64 regions = Index64(mTiles[t].dim / DIM);
    return mOff[t] == regions * regions * regions;
}

template <typename TreeT>
template <typename ChildT>
std::unique_ptr<ChildT> Morphology<TreeT>::TileChanges::build(size_t t, const ValueT& value) const {
    auto child = std::make_unique<ChildT>(mTiles[t].origin, value, true);
    for (size_t p = mFirst[t]; p < mFirst[t + 1]; ++p) {
        const Mask& m = mSet.mask(mFirstProxy + p);
        if (m.isOn())
            continue;
        if constexpr (ChildT::LEVEL == 0) {
            child->setValueMask(m);
        } else {
            tree::detail::NoCache none;
            child->modifyValue(
                mSet.origin(mFirstProxy + p), [](const ValueT&, bool) { return false; },
                [&](LeafT& leaf, Index) { leaf.setValueMask(m); }, none);
        }
    }
    // Collapse what came out uniform, as pruning the eroded topology would.
    if constexpr (ChildT::LEVEL > 0)
        child->prune(ValueT{});
    return child;
}

template <typename TreeT>
template <typename NodeT>
void Morphology<TreeT>::changeTilesIn(NodeT& node, const TileChanges& changes) {
    using ChildT = typename NodeT::ChildNodeType;
    const auto children = Tiles::childrenOf(node);  // before tiles become children
    struct Change {
        Coord origin;
        ValueT value;
        size_t t;
    };
    std::vector<Change> todo;
    tree::forEachTile<ValueFilter::On>(node, [&](const auto& tile) {
        const size_t t = changes.find(NodeT::LEVEL, tile.origin);
        if (t != TileChanges::NOT_FOUND && changes.changed(t))
            todo.push_back({tile.origin, tile.value, t});
    });
    for (const Change& c : todo) {
        if (changes.allOff(c.t)) {
            tree::setTile(node, c.origin, Tiles::offValue(c.value), false);
        } else {
            tree::setChild(node, changes.template build<ChildT>(c.t, c.value));
        }
    }
    if constexpr (ChildT::LEVEL > 0) {
        for (ChildT* child : children)
            changeTilesIn(*child, changes);
    }
}

template <typename TreeT>
void Morphology<TreeT>::changeTiles(TreeT& tree, const TileChanges& changes) {
    changeTilesIn(tree.topNode(), changes);
}

}  // namespace vdb::tools::detail
