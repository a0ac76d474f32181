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
/// per leaf instead of eighteen per voxel.

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
        const ValueT* src = leaf.buffer(buf).data();
        for (int i = 0; i < DIM; ++i) {
            for (int j = 0; j < DIM; ++j) {
                std::memcpy(&mData[size_t(index(i, j, 0))], src + ((i << (2 * LOG2)) | (j << LOG2)),
                            sizeof(ValueT) * DIM);
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = -1; side <= 1; side += 2) {
                Coord o = leaf.origin();
                o[size_t(axis)] += side * DIM;
                // Slab coordinates along `axis`: [-R, 0) below the leaf, [DIM, DIM + R) above;
                // the neighbour's local coordinate is the same modulo DIM.
                const int lo = side < 0 ? -R : DIM;
                if (const LeafT* nb = acc.probeConstLeaf(o)) {
                    const ValueT* nsrc = nb->buffer(buf).data();
                    for (int a = lo; a < lo + R; ++a) {
                        const int la = a & (DIM - 1);
                        for (int u = 0; u < DIM; ++u) {
                            for (int v = 0; v < DIM; ++v) {
                                int c[3];
                                c[axis] = la;
                                c[(axis + 1) % 3] = u;
                                c[(axis + 2) % 3] = v;
                                int p[3] = {c[0], c[1], c[2]};
                                p[axis] = a;
                                mData[size_t(index(p[0], p[1], p[2]))] =
                                    nsrc[(c[0] << (2 * LOG2)) | (c[1] << LOG2) | c[2]];
                            }
                        }
                    }
                } else {
                    const ValueT tile = acc.getValue(o);
                    for (int a = lo; a < lo + R; ++a) {
                        for (int u = 0; u < DIM; ++u) {
                            for (int v = 0; v < DIM; ++v) {
                                int p[3];
                                p[axis] = a;
                                p[(axis + 1) % 3] = u;
                                p[(axis + 2) % 3] = v;
                                mData[size_t(index(p[0], p[1], p[2]))] = tile;
                            }
                        }
                    }
                }
            }
        }
    }

    const ValueT* data() const { return mData.data(); }

private:
    alignas(64) std::array<ValueT, size_t(S* S* S)> mData;
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

/// One Euler stage over the active voxels of every leaf: for each active voxel at offset n,
///   out[n] = op(leafIndex, ordinal, centre)                          when alpha == 0
///   out[n] = alpha * buffer0[n] + (1 - alpha) * op(...)              otherwise,
/// where `out` is buffer `dst`, `centre` points at the voxel in the neighbourhood block of
/// buffer `src` (strides SX, SY, 1) and `ordinal` counts the active voxels of the leaf in
/// offset order. Every voxel's result depends only on buffer `src` (and buffer 0 at the same
/// voxel), so results do not depend on the thread count.
/// @pre src != dst; every leaf has the buffers named; dst may be 0
template <int R, typename TreeT, typename OpT>
void eulerStage(tree::LeafManager<TreeT>& leaves, Index src, Index dst,
                typename TreeT::ValueType alpha, const OpT& op, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    using Block = LeafNeighborhood<TreeT, R>;
    const TreeT& tree = leaves.tree();
    const ValueT beta = ValueT(1) - alpha;
    util::parallelForRange(
        leaves.leafCount(),
        [&](size_t begin, size_t end) {
            tree::ValueAccessor<const TreeT> acc(tree);
            Block block;
            for (size_t li = begin; li < end; ++li) {
                auto& leaf = leaves.leaf(li);
                if (leaf.isEmpty())
                    continue;
                block.gather(leaf, src, acc);
                const ValueT* phi0 = leaf.buffer(0).data();
                ValueT* out = leaf.buffer(dst).data();
                const auto* words = leaf.getValueMask().words();
                Index ordinal = 0;
                for (Index w = 0; w < leaf.getValueMask().WORD_COUNT; ++w) {
                    for (uint64_t bits = words[w]; bits; bits &= bits - 1) {
                        const int n = int(w << 6) + std::countr_zero(bits);
                        const int i = n >> (2 * Block::LOG2);
                        const int j = (n >> Block::LOG2) & (Block::DIM - 1);
                        const int k = n & (Block::DIM - 1);
                        const ValueT e = op(li, ordinal++, block.data() + Block::index(i, j, k));
                        out[n] = alpha == ValueT(0) ? e : alpha * phi0[n] + beta * e;
                    }
                }
            }
        },
        threaded, 4);
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
