// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery shared by LevelSetTracker and LevelSetAdvection (not API): a leaf's
/// neighbourhood gathered into a small dense block, and one explicit Euler stage of a
/// Hamilton-Jacobi equation run over the active voxels of every leaf, reading one temporal
/// buffer and writing another (paper 3.4 and 4.2).
///
/// Sequential stencil access, leaf by leaf: the leaf's own values and the slabs of its six face
/// neighbours (up to 3 voxels deep) are copied once per leaf into a block of (8 + 6)^3 values,
/// so that every stencil point of every voxel is a fixed offset into that block. The neighbours
/// are found with one accessor lookup each (a leaf, or the tile value that stands for it), six
/// per leaf instead of eighteen per voxel. NeighborhoodBlock does the same for blocks whose
/// depth is chosen at run time (the filters, the grid operators and the measures), filling the
/// edge and corner neighbours too when a stencil reads them.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <vector>

namespace vdb::tools::detail {

/// Copies into a dense block the part of the leaf-sized cell at `cellOrigin` that overlaps the
/// block. The block holds the index box [lo, lo + dims) with strides (sx, sy, 1); the cell's
/// values come from `src` (a leaf buffer, NUM_VALUES values in leaf order) or, when `src` is
/// null, are all `tile` (the tile or background that stands for the cell). Rows along z are
/// copied whole.
template <typename LeafT, typename ValueT>
void copyCellToBlock(const ValueT* src, const ValueT& tile, const Coord& cellOrigin,
                     const Coord& lo, const Coord& dims, ValueT* block, int sx, int sy) {
    constexpr int DIM = int(LeafT::DIM), LOG2 = int(LeafT::LOG2DIM);
    int a0[3], a1[3];
    for (int a = 0; a < 3; ++a) {
        a0[a] = std::max(lo[a], cellOrigin[a]);
        a1[a] = std::min(lo[a] + dims[a], cellOrigin[a] + DIM);
        if (a0[a] >= a1[a])
            return;
    }
    const int n = a1[2] - a0[2];
    for (int x = a0[0]; x < a1[0]; ++x) {
        for (int y = a0[1]; y < a1[1]; ++y) {
            ValueT* dst = block + (x - lo[0]) * sx + (y - lo[1]) * sy + (a0[2] - lo[2]);
            if (src) {
                const int offset = ((x - cellOrigin[0]) << (2 * LOG2)) |
                                   ((y - cellOrigin[1]) << LOG2) | (a0[2] - cellOrigin[2]);
                std::memcpy(dst, src + offset, sizeof(ValueT) * size_t(n));
            } else {
                std::fill_n(dst, n, tile);
            }
        }
    }
}

/// Copies the cell at `cellOrigin` from buffer `buf` of the leaf there, or from the tile value
/// that stands for it, into the block (see copyCellToBlock()).
/// @pre every leaf of the tree has at least buf + 1 buffers
template <typename TreeT>
void gatherCell(const tree::ValueAccessor<const TreeT>& acc, Index buf, const Coord& cellOrigin,
                const Coord& lo, const Coord& dims, typename TreeT::ValueType* block, int sx,
                int sy) {
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    if (const LeafT* leaf = acc.probeConstLeaf(cellOrigin)) {
        copyCellToBlock<LeafT>(leaf->buffer(buf).data(), ValueT{}, cellOrigin, lo, dims, block, sx,
                               sy);
    } else {
        copyCellToBlock<LeafT, ValueT>(nullptr, acc.getValue(cellOrigin), cellOrigin, lo, dims,
                                       block, sx, sy);
    }
}

/// A leaf's values and the face slabs of its neighbours, `R` voxels deep, in one dense block.
/// Only the cross-shaped part that axis-aligned stencils read is filled: the leaf and the six
/// slabs; edge and corner regions are left unspecified.
template <typename TreeT, int R>
class LeafNeighborhood {
public:
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    static constexpr int DIM = int(LeafT::DIM);
    static constexpr int LOG2 = int(LeafT::LOG2DIM);
    static constexpr int S = DIM + 2 * R;  ///< edge of the block
    static constexpr int SX = S * S;       ///< stride of x in the block
    static constexpr int SY = S;           ///< stride of y in the block
    static_assert(R >= 1 && R <= DIM, "a leaf neighbourhood reaches into face neighbours only");

    /// Position in the block of the leaf-local voxel (i, j, k); i, j, k in [-R, DIM + R).
    static constexpr int index(int i, int j, int k) {
        return ((i + R) * S + (j + R)) * S + (k + R);
    }

    /// Fills the block from buffer `buf` of `leaf` and of its face neighbours.
    /// @pre every leaf of the tree has at least buf + 1 buffers
    void gather(const LeafT& leaf, Index buf, const tree::ValueAccessor<const TreeT>& acc) {
        const Coord lo = leaf.origin().offsetBy(-R), dims(S);
        copyCellToBlock<LeafT>(leaf.buffer(buf).data(), ValueT{}, leaf.origin(), lo, dims,
                               mData.data(), SX, SY);
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = -1; side <= 1; side += 2) {
                Coord o = leaf.origin();
                o[size_t(axis)] += side * DIM;
                gatherCell(acc, buf, o, lo, dims, mData.data(), SX, SY);
            }
        }
    }

    const ValueT* data() const { return mData.data(); }

private:
    alignas(64) std::array<ValueT, size_t(S* S* S)> mData;
};

/// Which neighbouring cells a NeighborhoodBlock fills: the face neighbours only (axis-aligned
/// stencils), or every neighbour (stencils with mixed terms, dense boxes).
enum class BlockShape { Cross, Full };

/// The values around one leaf-sized cell, `radius[a]` voxels deep on both sides along axis a,
/// in a dense block whose size is chosen at run time (filters of any width). With
/// BlockShape::Cross only the cell and the slabs of its face neighbours are filled (each slab
/// may reach several cells away); the edge and corner regions are left unspecified.
/// Threads: one block per thread; gather() reuses the storage.
template <typename TreeT>
class NeighborhoodBlock {
public:
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    static constexpr int DIM = int(LeafT::DIM);
    static constexpr int LOG2 = int(LeafT::LOG2DIM);

    NeighborhoodBlock(const Coord& radius, BlockShape shape) : mRadius(radius), mShape(shape) {
        for (int a = 0; a < 3; ++a)
            mDims[a] = DIM + 2 * radius[a];
        mSy = mDims[2];
        mSx = mDims[1] * mDims[2];
        mData.resize(size_t(mDims[0]) * size_t(mSx));
    }

    /// Fills the block around the cell at `origin` from buffer `buf` of the leaves of `acc`'s
    /// tree (tile values where there is no leaf). `leaf` is the leaf at `origin` when the caller
    /// has it, else null (then it is looked up).
    /// @pre every leaf of the tree has at least buf + 1 buffers
    void gather(const Coord& origin, const LeafT* leaf, Index buf,
                const tree::ValueAccessor<const TreeT>& acc) {
        const Coord lo = origin - mRadius;
        int reach[3];
        for (int a = 0; a < 3; ++a)
            reach[a] = (mRadius[a] + DIM - 1) / DIM;
        for (int i = -reach[0]; i <= reach[0]; ++i) {
            for (int j = -reach[1]; j <= reach[1]; ++j) {
                for (int k = -reach[2]; k <= reach[2]; ++k) {
                    const int offAxes = (i != 0) + (j != 0) + (k != 0);
                    if (mShape == BlockShape::Cross && offAxes > 1)
                        continue;
                    const Coord cell = origin.offsetBy(i * DIM, j * DIM, k * DIM);
                    if (offAxes == 0 && leaf) {
                        copyCellToBlock<LeafT>(leaf->buffer(buf).data(), ValueT{}, cell, lo, mDims,
                                               mData.data(), mSx, mSy);
                    } else {
                        gatherCell(acc, buf, cell, lo, mDims, mData.data(), mSx, mSy);
                    }
                }
            }
        }
    }

    /// The block position of the cell-local voxel (i, j, k); each in [-radius, DIM + radius).
    const ValueT* at(int i, int j, int k) const {
        return mData.data() + (i + mRadius[0]) * mSx + (j + mRadius[1]) * mSy + (k + mRadius[2]);
    }
    /// The block position of the voxel at `offset` in the cell (leaf order).
    const ValueT* atOffset(Index offset) const {
        return at(int(offset >> (2 * LOG2)), int((offset >> LOG2) & (DIM - 1)),
                  int(offset & (DIM - 1)));
    }
    /// Strides of x and y in the block (z's is 1).
    int sx() const { return mSx; }
    int sy() const { return mSy; }
    const Coord& radius() const { return mRadius; }

private:
    Coord mRadius, mDims;
    BlockShape mShape;
    int mSx = 0, mSy = 0;
    std::vector<ValueT> mData;
};

/// A view of a voxel's neighbourhood in a dense block: at(i, j, k) is the value at offset
/// (i, j, k), for the difference formulas of math/FiniteDifference.h.
template <typename ValueT>
struct BlockPoint {
    const ValueT* c;
    int sx, sy;
    ValueT operator()(int i, int j, int k) const { return c[i * sx + j * sy + k]; }
};

/// The 7 samples through `c` with stride `stride` (c[0] is the centre), reading only the
/// `R` samples on either side that a stencil of radius R needs (a neighbourhood block of
/// radius R holds no more); the unread outer entries repeat the outermost read sample.
template <int R, typename ValueT>
inline std::array<ValueT, 7> lineThrough(const ValueT* c, int stride) {
    static_assert(R >= 1 && R <= 3, "stencil radius 1 to 3");
    constexpr int r1 = 1, r2 = R < 2 ? R : 2, r3 = R;
    return {c[-r3 * stride], c[-r2 * stride], c[-r1 * stride], c[0],
            c[r1 * stride],  c[r2 * stride],  c[r3 * stride]};
}

/// One Euler stage over the active voxels of every leaf, a row of DIM voxels along z at a time
/// so that the row's arithmetic runs in vector lanes: `rowOp(leafIndex, ordinal, rowBits, c,
/// res)` writes into res[0, DIM) the new values of the row whose first voxel is at `c` in the
/// neighbourhood block of buffer `src` (strides SX, SY, 1); bit k of `rowBits` says whether
/// voxel k of the row is active (only those results are used) and `ordinal` counts the active
/// voxels of the leaf before the row, in offset order. For each active voxel at offset n,
///   out[n] = res[k]                                   when alpha == 0
///   out[n] = alpha * buffer0[n] + (1 - alpha) * res[k] otherwise,
/// where `out` is buffer `dst`. Every voxel's result depends only on buffer `src` (and buffer 0
/// at the same voxel), so results do not depend on the thread count.
/// @pre src != dst; every leaf has the buffers named; dst may be 0
template <int R, typename TreeT, typename RowOpT>
void eulerStage(tree::LeafManager<TreeT>& leaves, Index src, Index dst,
                typename TreeT::ValueType alpha, const RowOpT& rowOp, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    using Block = LeafNeighborhood<TreeT, R>;
    constexpr int DIM = Block::DIM;
    static_assert(DIM <= 64 && 64 % DIM == 0, "a row of a leaf lies in one mask word");
    constexpr uint64_t ROW = DIM == 64 ? ~uint64_t(0) : (uint64_t(1) << DIM) - 1;
    const TreeT& tree = leaves.tree();
    const ValueT beta = ValueT(1) - alpha;
    util::parallelForRange(
        leaves.leafCount(),
        [&](size_t begin, size_t end) {
            tree::ValueAccessor<const TreeT> acc(tree);
            Block block;
            alignas(64) ValueT res[DIM];
            for (size_t li = begin; li < end; ++li) {
                auto& leaf = leaves.leaf(li);
                if (leaf.isEmpty())
                    continue;
                block.gather(leaf, src, acc);
                const ValueT* phi0 = leaf.buffer(0).data();
                ValueT* out = leaf.buffer(dst).data();
                const auto* words = leaf.getValueMask().words();
                Index ordinal = 0;
                for (int i = 0; i < DIM; ++i) {
                    for (int j = 0; j < DIM; ++j) {
                        const int first = (i * DIM + j) * DIM;
                        const uint64_t rowBits = (words[first >> 6] >> (first & 63)) & ROW;
                        if (rowBits == 0)
                            continue;
                        rowOp(li, ordinal, rowBits, block.data() + Block::index(i, j, 0), res);
                        for (uint64_t bits = rowBits; bits; bits &= bits - 1) {
                            const int k = std::countr_zero(bits);
                            const int n = first + k;
                            out[n] = alpha == ValueT(0) ? res[k] : alpha * phi0[n] + beta * res[k];
                        }
                        ordinal += Index(std::popcount(rowBits));
                    }
                }
            }
        },
        threaded, 4);
}

/// The one-sided derivatives (D- in `dm`, D+ in `dp`, index space) of `Scheme` along the three
/// axes at the DIM voxels of a row of a neighbourhood block (strides sx, sy, 1) starting at
/// `c`: dm[a][k] and dp[a][k] for axis a at voxel k. One loop per axis over the row's voxels,
/// which the compiler runs in vector lanes.
template <math::BiasedGradientScheme Scheme, int DIM, typename ValueT>
inline void rowDifferences(const ValueT* c, int sx, int sy, ValueT (&dm)[3][DIM],
                           ValueT (&dp)[3][DIM]) {
    constexpr int R = math::stencilRadius(Scheme);
    const int strides[3] = {sx, sy, 1};
    for (int a = 0; a < 3; ++a) {
        const int stride = strides[a];
        for (int k = 0; k < DIM; ++k) {
            const auto line = lineThrough<R>(c + k, stride);
            math::biasedDifferences<Scheme>(line.data(), dm[a][k], dp[a][k]);
        }
    }
}

/// Runs the stages of one TVD Runge-Kutta step of a Hamilton-Jacobi equation phi_t = -F(phi) in
/// the leaves' buffers, `stage(src, dst, alpha)` doing one Euler stage as eulerStage() does. The
/// new values end in buffer 0:
///   RK1: 0 -> 1, swap 0 and 1;
///   RK2: 0 -> 1, then 1 -> 0 combined with 1/2 of buffer 0;
///   RK3: 0 -> 1, 1 -> 2 combined with 3/4 of buffer 0, 2 -> 0 combined with 1/3 of buffer 0.
/// @pre the leaves have math::auxBufferCount(scheme) auxiliary buffers
template <typename TreeT, typename StageT>
void rungeKuttaStep(tree::LeafManager<TreeT>& leaves, math::TemporalIntegrationScheme scheme,
                    const StageT& stage, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    switch (scheme) {
        case math::TVD_RK1:
            stage(0, 1, ValueT(0));
            leaves.swapLeafBuffers(0, 1, threaded);
            break;
        case math::TVD_RK2:
            stage(0, 1, ValueT(0));
            stage(1, 0, ValueT(0.5));
            break;
        default:
            stage(0, 1, ValueT(0));
            stage(1, 2, ValueT(0.75));
            stage(2, 0, ValueT(1) / ValueT(3));
            break;
    }
}

/// Prefix sums of the active voxel counts of the leaves: entry i is the number of active voxels
/// in the leaves before leaf i; the last entry is the total.
template <typename TreeT>
std::vector<size_t> activeVoxelOffsets(const tree::LeafManager<TreeT>& leaves) {
    std::vector<size_t> offsets(leaves.leafCount() + 1, 0);
    for (size_t i = 0; i < leaves.leafCount(); ++i)
        offsets[i + 1] = offsets[i] + size_t(leaves.leaf(i).onVoxelCount());
    return offsets;
}

}  // namespace vdb::tools::detail
