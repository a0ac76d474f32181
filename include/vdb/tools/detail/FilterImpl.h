// SPDX-License-Identifier: Apache-2.0
/// @file
/// What tools/Filter.h and tools/LevelSetFilter.h share (not API): the alpha mask, the checks
/// of filter widths, and one filter pass over the active voxels of every leaf, which reads each
/// leaf's neighbourhood from buffer 0 (gathered into a dense block) and writes buffer 1.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// The largest width (half the kernel's edge, in voxels) that the mean and Gaussian filters
/// accept: a kernel of 2 x 128 + 1 voxels along each axis.
inline constexpr int FILTER_MAX_WIDTH = 128;
/// The largest width of the median filter, whose cost grows with the cube of the width: 33^3
/// values per voxel.
inline constexpr int MEDIAN_FILTER_MAX_WIDTH = 16;

namespace detail {

/// Throws ValueError unless 1 <= width <= maxWidth; `what` names the filter in the message.
inline void checkFilterWidth(int width, int maxWidth, const char* what) {
    if (width < 1 || width > maxWidth)
        throw ValueError(std::string(what) + ": the width must be 1 to " +
                         std::to_string(maxWidth) + " voxels, not " + std::to_string(width));
}

/// Throws ValueError unless every component of `value` is finite.
template <typename ValueT>
void checkFiniteOffset(const ValueT& value, const char* what) {
    bool finite = true;
    if constexpr (std::is_floating_point_v<ValueT>) {
        finite = std::isfinite(value);
    } else if constexpr (!std::is_arithmetic_v<ValueT>) {
        finite = std::isfinite(double(value[0])) && std::isfinite(double(value[1])) &&
                 std::isfinite(double(value[2]));
    }
    if (!finite)
        throw ValueError(std::string(what) + ": the offset must be finite");
}

/// Hermite's smooth step 3t^2 - 2t^3 of t clamped to [0, 1].
inline float smoothUnitStep(float t) {
    return t > 0.0f ? (t < 1.0f ? (3.0f - 2.0f * t) * t * t : 1.0f) : 0.0f;
}

/// The alpha of every voxel of a leaf-sized cell from a scalar mask grid: the mask's value
/// mapped from [min, max] to [0, 1] with a smooth step (1 - that when inverted). The mask is
/// read at the same index coordinates when its transform matches the grid's, else sampled
/// trilinearly at each voxel's world position. A filter mixes old and new values as
/// (1 - alpha) old + alpha new, and leaves voxels of alpha 0 alone.
/// Threads: one per thread (it holds an accessor).
template <typename MaskT>
class AlphaMask {
public:
    using MaskTreeT = typename MaskT::TreeType;
    static_assert(std::is_floating_point_v<typename MaskT::ValueType>,
                  "an alpha mask needs a grid with floating-point values");

    AlphaMask(const math::Transform& gridXform, const MaskT& mask, float min, float max,
              bool invert)
        : mGridXform(&gridXform),
          mMaskXform(&mask.transform()),
          mAcc(mask.tree()),
          mMin(min),
          mInvRange(1.0f / (max - min)),
          mInvert(invert),
          mAligned(gridXform.isApproxEqual(mask.transform())) {}

    /// Writes the alpha of the voxels of the cell at `origin` to `alpha` (leaf order).
    template <size_t NumValues>
    void cell(const Coord& origin, Index log2Dim, std::array<float, NumValues>& alpha) const {
        using MaskLeafT = typename MaskTreeT::LeafNodeType;
        const Index dim = Index(1) << log2Dim;
        if (mAligned && MaskLeafT::LOG2DIM == log2Dim) {
            if (const MaskLeafT* leaf = mAcc.probeConstLeaf(origin)) {
                const auto* values = leaf->buffer(0).data();
                for (size_t n = 0; n < NumValues; ++n)
                    alpha[n] = map(float(values[n]));
            } else {
                alpha.fill(map(float(mAcc.getValue(origin))));
            }
            return;
        }
        for (Index n = 0; n < Index(NumValues); ++n) {
            const Coord ijk = origin.offsetBy(
                Int32(n >> (2 * log2Dim)), Int32((n >> log2Dim) & (dim - 1)), Int32(n & (dim - 1)));
            float m;
            if (mAligned) {
                m = float(mAcc.getValue(ijk));
            } else {
                const Vec3d xyz = mMaskXform->worldToIndex(mGridXform->indexToWorld(ijk));
                m = float(BoxSampler::sample(mAcc, xyz));
            }
            alpha[n] = map(m);
        }
    }

private:
    float map(float m) const {
        const float a = smoothUnitStep((m - mMin) * mInvRange);
        return mInvert ? 1.0f - a : a;
    }

    const math::Transform* mGridXform;
    const math::Transform* mMaskXform;
    tree::ValueAccessor<const MaskTreeT> mAcc;
    float mMin, mInvRange;
    bool mInvert;
    bool mAligned;
};

/// The mask settings a filter keeps: the range of mask values mapped to alpha 0..1 and whether
/// the mapping is inverted.
template <typename AlphaT>
struct MaskRange {
    AlphaT min = AlphaT(0), max = AlphaT(1);
    bool invert = false;

    void set(AlphaT lo, AlphaT hi) {
        if (!(lo < hi))
            throw ValueError("setMaskRange: expected min < max");
        min = lo;
        max = hi;
    }
};

/// `value` scaled by the float `s` in the value's own precision (integers through float, as
/// OpenVDB's filters compute them).
template <typename ValueT>
ValueT scaledBy(const ValueT& value, float s) {
    if constexpr (std::is_floating_point_v<ValueT>) {
        return value * ValueT(s);
    } else if constexpr (std::is_arithmetic_v<ValueT>) {
        return ValueT(float(value) * s);
    } else {
        using T = typename ValueT::value_type;
        return value * T(s);
    }
}

/// (1 - a) old + a new, for the alpha `a` of a masked filter (a == 1: new).
template <typename ValueT>
ValueT blend(const ValueT& oldValue, const ValueT& newValue, float a) {
    return scaledBy(oldValue, 1.0f - a) + scaledBy(newValue, a);
}

/// The alpha mask of `mask` for a grid with transform `xform`, or null without a mask.
template <typename MaskT>
std::unique_ptr<AlphaMask<MaskT>> makeAlphaMask(const math::Transform& xform, const MaskT* mask,
                                                const MaskRange<float>& range) {
    if (!mask)
        return nullptr;
    return std::make_unique<AlphaMask<MaskT>>(xform, *mask, range.min, range.max, range.invert);
}

/// One filter pass: for every active voxel n of every leaf,
///   buffer1[n] = op(block, n)                    without a mask,
///   buffer1[n] = blend(buffer0[n], op(block, n), alpha[n])   with one (op skipped where alpha
///                                                 is 0, where buffer 1 takes buffer 0's value),
/// where `block` holds the leaf's neighbourhood from buffer 0, `radius` deep along each axis
/// (of `shape`). Every result depends only on buffer 0, so the pass does not depend on the
/// thread count. @pre every leaf has an auxiliary buffer
template <typename TreeT, typename MaskT, typename OpT>
void filterPass(tree::LeafManager<TreeT>& leaves, const Coord& radius, BlockShape shape,
                const math::Transform& xform, const MaskT* mask, const MaskRange<float>& range,
                const OpT& op, bool threaded) {
    using LeafT = typename TreeT::LeafNodeType;
    using ValueT = typename TreeT::ValueType;
    const TreeT& tree = leaves.tree();
    util::parallelForRange(
        leaves.leafCount(),
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const TreeT> acc(tree);
            NeighborhoodBlock<TreeT> block(radius, shape);
            const auto alphaMask = makeAlphaMask(xform, mask, range);
            std::array<float, LeafT::NUM_VALUES> alpha;
            for (size_t i = begin; i < end; ++i) {
                LeafT& leaf = leaves.leaf(i);
                if (leaf.isEmpty())
                    continue;
                if (alphaMask)
                    alphaMask->cell(leaf.origin(), LeafT::LOG2DIM, alpha);
                block.gather(leaf.origin(), &leaf, 0, acc);
                const ValueT* in = leaf.buffer(0).data();
                ValueT* out = leaf.buffer(1).data();
                const auto* words = leaf.getValueMask().words();
                for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w) {
                    for (uint64_t bits = words[w]; bits; bits &= bits - 1) {
                        const Index n = (w << 6) + Index(std::countr_zero(bits));
                        if (!alphaMask) {
                            out[n] = op(block, n);
                        } else if (alpha[n] > 0.0f) {
                            out[n] = blend(in[n], op(block, n), alpha[n]);
                        } else {
                            out[n] = in[n];
                        }
                    }
                }
            }
        },
        threaded, 4);
}

/// The mean along `axis` of the 2 width + 1 values centred on voxel n, summed from the lowest
/// coordinate up and scaled by `frac` (1 / (2 width + 1)).
template <typename BlockT, typename ScaleT>
auto boxAverage(const BlockT& block, Index n, int axis, int width, ScaleT frac) {
    using ValueT = typename BlockT::ValueT;
    const int stride = axis == 0 ? block.sx() : axis == 1 ? block.sy() : 1;
    const ValueT* c = block.atOffset(n);
    ValueT sum = c[-width * stride];
    for (int d = -width + 1; d <= width; ++d)
        sum = sum + c[d * stride];
    if constexpr (std::is_same_v<ScaleT, float>) {
        return scaledBy(sum, frac);
    } else {
        return ValueT(sum * frac);
    }
}

/// The median of the (2 width + 1)^3 values centred on voxel n (the lower middle element;
/// the count is odd), using `scratch` as working storage.
template <typename BlockT>
typename BlockT::ValueT boxMedian(const BlockT& block, Index n, int width,
                                  std::vector<typename BlockT::ValueT>& scratch) {
    const auto* c = block.atOffset(n);
    scratch.clear();
    for (int i = -width; i <= width; ++i)
        for (int j = -width; j <= width; ++j)
            for (int k = -width; k <= width; ++k)
                scratch.push_back(c[i * block.sx() + j * block.sy() + k]);
    const size_t mid = (scratch.size() - 1) / 2;
    std::nth_element(scratch.begin(), scratch.begin() + std::ptrdiff_t(mid), scratch.end());
    return scratch[mid];
}

/// Adds `offset` (times the voxel's alpha, with a mask) to every active voxel of the leaves,
/// in place.
template <typename TreeT, typename MaskT>
void offsetPass(tree::LeafManager<TreeT>& leaves, const typename TreeT::ValueType& offset,
                const math::Transform& xform, const MaskT* mask, const MaskRange<float>& range,
                bool threaded) {
    using LeafT = typename TreeT::LeafNodeType;
    util::parallelForRange(
        leaves.leafCount(),
        [&](size_t begin, size_t end) {
            const auto alphaMask = makeAlphaMask(xform, mask, range);
            std::array<float, LeafT::NUM_VALUES> alpha;
            for (size_t i = begin; i < end; ++i) {
                LeafT& leaf = leaves.leaf(i);
                if (leaf.isEmpty())
                    continue;
                if (alphaMask)
                    alphaMask->cell(leaf.origin(), LeafT::LOG2DIM, alpha);
                auto* values = leaf.buffer(0).data();
                const auto* words = leaf.getValueMask().words();
                for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w) {
                    auto* row = values + (w << 6);
                    if (!alphaMask && words[w] == ~uint64_t(0)) {
                        for (Index n = 0; n < 64; ++n)  // a full word: a loop that vectorises
                            row[n] = row[n] + offset;
                        continue;
                    }
                    for (uint64_t bits = words[w]; bits; bits &= bits - 1) {
                        const Index n = (w << 6) + Index(std::countr_zero(bits));
                        if (!alphaMask)
                            values[n] = values[n] + offset;
                        else if (alpha[n] > 0.0f)
                            values[n] = values[n] + scaledBy(offset, alpha[n]);
                    }
                }
            }
        },
        threaded, 16);
}

}  // namespace detail
}  // namespace vdb::tools
