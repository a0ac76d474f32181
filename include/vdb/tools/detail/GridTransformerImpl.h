// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/GridTransformer.h (not API): one resampling pass of a tree under an
/// affine map of index space, and GridTransformer's constructors.
///
/// A pass (TreeResampler::run) works in three steps:
/// 1. Every input leaf (clipped to the active bounding box in a level set) and, outside level
///    sets, every tile that is active or holds a value other than the background is mapped to
///    the box of output voxels it visits, as OpenVDB's resampler visits them (the mapped cell
///    span rounded outward, grown by the sampler's radius). The output leaves those boxes
///    overlap are counted against the voxel limit before anything is allocated, then listed
///    with the boxes that overlap each, and sorted.
/// 2. Each listed output leaf is filled in parallel: its footprint in the input is read once
///    into a dense block of values and active states, and each visited voxel is sampled there
///    at the input point it maps back to, computed from the leaf's origin alone (so values do
///    not depend on the thread count). A visited voxel is active when the sampler read an
///    active voxel; the others keep the background, inactive. Leaves without active voxels are
///    dropped when their values are all the background (or always, in a level set).
/// 3. The leaves are linked into a new tree in key order; a level set is flood-filled, and a
///    whole-voxel copy gets the input's tiles translated.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/detail/LeafBuild.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Assert.h>
#include <vdb/util/Parallel.h>

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

/// What a resampling pass does with the input's tiles and its level set band.
enum class ResampleMode {
    Sample,    ///< sample leaves and non-background tiles
    LevelSet,  ///< sample leaves only, then flood-fill the signs outside the band
    Copy,      ///< a whole-voxel translation: copy leaves by point sampling, translate tiles
};

/// The integer offset of `outFromIn` when it is a translation by whole voxels, to within 1e-6
/// of a voxel: transforms composed in floating point, or whose voxel size was stored as a float
/// and whose translation as a double, still qualify.
inline std::optional<Coord> wholeVoxelTranslation(const Mat4R& outFromIn) {
    constexpr double tol = 1e-6;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            if (!(std::abs(outFromIn(r, c) - (r == c ? 1.0 : 0.0)) <= tol))
                return std::nullopt;
        }
    }
    const Vec3R t = outFromIn.getTranslation();
    Coord offset;
    for (int i = 0; i < 3; ++i) {
        const double rounded = std::round(t[i]);
        if (!(std::abs(t[i] - rounded) <= tol) || !(std::abs(rounded) < 1e9))
            return std::nullopt;
        offset[i] = Int32(rounded);
    }
    return offset;
}

/// The output voxels (inclusive) a pass visits for the input voxels `box` (inclusive) under
/// `outFromIn`, as OpenVDB's resampler visits them: the corners of the box's cell span
/// [min, max + 1] mapped, the bounds rounded outward and grown by the sampler's radius.
/// @throw ValueError when the result leaves the index range (with a margin of a few leaves)
inline CoordBBox visitedBox(const CoordBBox& box, const Mat4R& outFromIn, int radius) {
    const Vec3d lo(box.min()), hi = Vec3d(box.max()) + Vec3d(1.0);
    Vec3d outLo(std::numeric_limits<double>::infinity()), outHi(-outLo[0]);
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3d p((corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1],
                      (corner & 4) ? hi[2] : lo[2]);
        const Vec3d q = outFromIn.transformPoint(p);
        for (int i = 0; i < 3; ++i) {
            outLo[i] = std::min(outLo[i], q[i]);
            outHi[i] = std::max(outHi[i], q[i]);
        }
    }
    constexpr double limit = 2147483648.0 - 4096.0;
    Coord min, max;
    for (int i = 0; i < 3; ++i) {
        const double l = std::floor(outLo[i]) - radius, h = std::ceil(outHi[i]) + radius;
        if (!(l >= -limit) || !(h <= limit)) {
            throw ValueError(
                "resampling: the output lies outside the index range of 32-bit coordinates");
        }
        min[i] = Int32(l);
        max[i] = Int32(h);
    }
    return CoordBBox(min, max);
}

/// The origins of the leaves (of edge 2^log2) that `box` overlaps, as a box of leaf indices.
inline CoordBBox leafIndexRange(const CoordBBox& box, Index log2) {
    return CoordBBox(Coord(box.min()[0] >> log2, box.min()[1] >> log2, box.min()[2] >> log2),
                     Coord(box.max()[0] >> log2, box.max()[1] >> log2, box.max()[2] >> log2));
}

/// Calls `op(box, value, active)` for every tile of `tree` that is active or whose value is
/// not the background (inactive background tiles add nothing to a resampling).
template <typename TreeT, typename OpT>
void forEachValuedTile(const TreeT& tree, const OpT& op) {
    using TopT = typename TreeT::TopNodeType;
    const auto& background = tree.background();
    const auto visit = [&](const CoordBBox& box, const auto& value, bool active) {
        if (active || !(value == background))
            op(box, value, active);
    };
    const auto visitNode = [&](const auto& node) {
        using NodeT = std::remove_cvref_t<decltype(node)>;
        constexpr Int32 dim = Int32(NodeT::ChildNodeType::DIM);
        tree::forEachTile(node, [&](const auto& tile) {
            visit(CoordBBox::createCube(tile.origin, dim), tile.value, tile.active);
        });
    };
    const NodeLists<const TreeT> lists(tree, 1);
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        (lists.template foreach<L + 1>(visitNode, false), ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL - 1>{});
    visitNode(tree.topNode());
}

/// A dense copy of the values and active states of a box of a tree, read by the samplers as
/// an accessor (getValue, probeValue). Reads outside the box are a precondition violation.
template <typename TreeT>
class DenseBlockReader {
public:
    using ValueType = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;

    /// Copies the voxels of `box` (inclusive) from the tree `acc` reads.
    void gather(const tree::ValueAccessor<const TreeT>& acc, const CoordBBox& box) {
        mMin = box.min();
        const Coord dim = box.dim();
        mStrideY = size_t(dim[2]);
        mStrideX = size_t(dim[1]) * mStrideY;
        const size_t n = size_t(dim[0]) * mStrideX;
        mValues.resize(n);
        mActive.resize(n);
        constexpr Int32 DIM = Int32(LeafT::DIM);
        const Coord first = box.min().alignedDown(LeafT::LOG2DIM);
        for (Int32 x = first[0]; x <= box.max()[0]; x += DIM) {
            for (Int32 y = first[1]; y <= box.max()[1]; y += DIM) {
                for (Int32 z = first[2]; z <= box.max()[2]; z += DIM) {
                    const Coord origin(x, y, z);
                    const CoordBBox part(Coord::maxComponent(origin, box.min()),
                                         Coord::minComponent(origin.offsetBy(DIM - 1), box.max()));
                    if (const LeafT* leaf = acc.probeConstLeaf(origin)) {
                        copyLeaf(*leaf, part);
                    } else {
                        ValueType value;
                        const bool on = acc.probeValue(origin, value);
                        fillPart(part, value, on);
                    }
                }
            }
        }
    }

    ValueType getValue(const Coord& ijk) const { return mValues[index(ijk)]; }
    bool probeValue(const Coord& ijk, ValueType& value) const {
        const size_t n = index(ijk);
        value = mValues[n];
        return mActive[n] != 0;
    }

private:
    size_t index(const Coord& ijk) const {
        const size_t n = size_t(ijk[0] - mMin[0]) * mStrideX + size_t(ijk[1] - mMin[1]) * mStrideY +
                         size_t(ijk[2] - mMin[2]);
        VDB_ASSERT(n < mValues.size());
        return n;
    }
    void copyLeaf(const LeafT& leaf, const CoordBBox& part) {
        constexpr Int32 DIM = Int32(LeafT::DIM);
        const Coord o = leaf.origin();
        for (Int32 x = part.min()[0]; x <= part.max()[0]; ++x) {
            for (Int32 y = part.min()[1]; y <= part.max()[1]; ++y) {
                size_t n = index(Coord(x, y, part.min()[2]));
                Index m = Index(((x - o[0]) * DIM + (y - o[1])) * DIM + (part.min()[2] - o[2]));
                for (Int32 z = part.min()[2]; z <= part.max()[2]; ++z, ++n, ++m) {
                    mValues[n] = leaf.getValue(m);
                    mActive[n] = leaf.isValueOn(m) ? 1 : 0;
                }
            }
        }
    }
    void fillPart(const CoordBBox& part, const ValueType& value, bool on) {
        for (Int32 x = part.min()[0]; x <= part.max()[0]; ++x) {
            for (Int32 y = part.min()[1]; y <= part.max()[1]; ++y) {
                const size_t n = index(Coord(x, y, part.min()[2]));
                const size_t len = size_t(part.max()[2] - part.min()[2] + 1);
                std::fill_n(mValues.begin() + std::ptrdiff_t(n), len, value);
                std::fill_n(mActive.begin() + std::ptrdiff_t(n), len, uint8_t(on ? 1 : 0));
            }
        }
    }

    Coord mMin;
    size_t mStrideX = 0, mStrideY = 0;
    std::vector<ValueType> mValues;
    std::vector<uint8_t> mActive;  // 1 where the voxel is active
};

/// The output boxes a pass visits: one per input leaf (clipped to the active bounding box for
/// level sets) and, for ResampleMode::Sample, one per tile that is active or not the
/// background. Throws ValueError, before anything else is allocated, when the output leaves
/// they overlap hold more than `maxVoxels` voxels in all.
template <typename TreeT>
std::vector<CoordBBox> visitedBoxes(const TreeT& tree, const Mat4R& outFromIn, int radius,
                                    ResampleMode mode, Index64 maxVoxels) {
    using LeafT = typename TreeT::LeafNodeType;
    constexpr Int32 DIM = Int32(LeafT::DIM);
    CoordBBox clip;
    if (mode == ResampleMode::LevelSet)
        tree.evalActiveVoxelBoundingBox(clip);
    std::vector<CoordBBox> boxes;
    boxes.reserve(tree.leafCount());
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        // OpenVDB's resampler spans a leaf as [origin, origin + DIM] (one voxel past its end).
        CoordBBox box = CoordBBox::createCube(it->origin(), DIM + 1);
        if (mode == ResampleMode::LevelSet) {
            box = CoordBBox(Coord::maxComponent(box.min(), clip.min()),
                            Coord::minComponent(box.max(), clip.max()));
        }
        if (!box.empty())
            boxes.push_back(box);
    }
    if (mode == ResampleMode::Sample) {
        forEachValuedTile(tree,
                          [&](const CoordBBox& box, const auto&, bool) { boxes.push_back(box); });
    }
    // Bound the output by the leaves each box overlaps, in double (no overflow).
    double voxels = 0.0;
    for (CoordBBox& box : boxes) {
        box = visitedBox(box, outFromIn, radius);
        const Coord d = leafIndexRange(box, LeafT::LOG2DIM).dim();
        voxels += double(d[0]) * double(d[1]) * double(d[2]) * double(LeafT::NUM_VALUES);
    }
    if (voxels > double(maxVoxels)) {
        // Beyond 64 bits the count is only an order of magnitude.
        std::ostringstream count;
        if (voxels < 9.2e18)
            count << Index64(voxels);
        else
            count << std::setprecision(2) << voxels;
        throw ValueError("resampling would produce up to " + count.str() +
                         " voxels, more than the limit of " + std::to_string(maxVoxels));
    }
    return boxes;
}

/// Checks the voxel bound of visitedBoxes() alone.
template <typename TreeT>
void checkResampleSize(const TreeT& tree, const Mat4R& outFromIn, Index64 maxVoxels) {
    (void)visitedBoxes(tree, outFromIn, 1, ResampleMode::LevelSet, maxVoxels);
}

/// One resampling pass of a tree (see the file comment); a class so that the standard trees
/// and samplers are instantiated once.
template <typename SamplerT, typename TreeT>
class TreeResampler {
public:
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;

    /// Returns `in` resampled under `outFromIn` (input index to output index).
    static std::shared_ptr<TreeT> run(const TreeT& in, const Mat4R& outFromIn, ResampleMode mode,
                                      bool threaded, Index64 maxVoxels);

private:
    static constexpr Int32 DIM = Int32(LeafT::DIM);
    // Footprints above this many voxels are read through an accessor instead of a block.
    static constexpr Index64 MAX_BLOCK_VOXELS = Index64(1) << 15;
};

template <typename SamplerT, typename TreeT>
std::shared_ptr<TreeT> TreeResampler<SamplerT, TreeT>::run(const TreeT& in, const Mat4R& outFromIn,
                                                           ResampleMode mode, bool threaded,
                                                           Index64 maxVoxels) {
    const Mat4R inFromOut = outFromIn.inverse();
    const std::vector<CoordBBox> boxes =
        visitedBoxes(in, outFromIn, SamplerT::radius(), mode, maxVoxels);

    // List the output leaves the boxes overlap, each with the boxes that overlap it, sorted.
    struct Visit {
        Coord origin;
        Index box;
        bool operator<(const Visit& o) const {
            return origin != o.origin ? origin < o.origin : box < o.box;
        }
    };
    tbb::enumerable_thread_specific<std::vector<Visit>> found;
    util::parallelFor(
        boxes.size(),
        [&](size_t s) {
            const CoordBBox range = leafIndexRange(boxes[s], LeafT::LOG2DIM);
            auto& list = found.local();
            for (Int32 x = range.min()[0]; x <= range.max()[0]; ++x)
                for (Int32 y = range.min()[1]; y <= range.max()[1]; ++y)
                    for (Int32 z = range.min()[2]; z <= range.max()[2]; ++z)
                        list.push_back({Coord(x * DIM, y * DIM, z * DIM), Index(s)});
        },
        threaded, 16);
    std::vector<Visit> visits;
    for (auto& list : found) {
        visits.insert(visits.end(), list.begin(), list.end());
        std::vector<Visit>().swap(list);
    }
    std::sort(visits.begin(), visits.end());
    std::vector<size_t> starts;  // the first visit of each output leaf, then visits.size()
    for (size_t v = 0; v < visits.size(); ++v) {
        if (v == 0 || visits[v].origin != visits[v - 1].origin)
            starts.push_back(v);
    }
    starts.push_back(visits.size());
    const size_t leafCount = starts.size() - 1;

    // Fill each output leaf from its footprint in the input.
    const ValueT background = in.background();
    const Vec3d dx = inFromOut.transformDirection(Vec3d(1, 0, 0));
    const Vec3d dy = inFromOut.transformDirection(Vec3d(0, 1, 0));
    const Vec3d dz = inFromOut.transformDirection(Vec3d(0, 0, 1));
    std::vector<std::unique_ptr<LeafT>> leaves(leafCount);
    util::parallelForRange(
        leafCount,
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const TreeT> acc(in);
            DenseBlockReader<TreeT> block;
            for (size_t i = begin; i < end; ++i) {
                const Coord origin = visits[starts[i]].origin;
                // The voxels of the leaf that some box visits.
                typename LeafT::MaskType visited;
                const CoordBBox leafBox = CoordBBox::createCube(origin, DIM);
                for (size_t v = starts[i]; v < starts[i + 1]; ++v) {
                    const CoordBBox& box = boxes[visits[v].box];
                    const CoordBBox part(Coord::maxComponent(box.min(), leafBox.min()),
                                         Coord::minComponent(box.max(), leafBox.max()));
                    for (Int32 a = part.min()[0]; a <= part.max()[0]; ++a)
                        for (Int32 b = part.min()[1]; b <= part.max()[1]; ++b)
                            for (Int32 c = part.min()[2]; c <= part.max()[2]; ++c)
                                visited.setOn(LeafT::coordToOffset(Coord(a, b, c)));
                }
                const Vec3d base = inFromOut.transformPoint(Vec3d(origin));
                // The footprint: the leaf's corners mapped back, grown by the stencil.
                Vec3d lo(base), hi(base);
                for (int corner = 1; corner < 8; ++corner) {
                    const Vec3d p = base + dx * double((corner & 1) ? DIM - 1 : 0) +
                                    dy * double((corner & 2) ? DIM - 1 : 0) +
                                    dz * double((corner & 4) ? DIM - 1 : 0);
                    for (int a = 0; a < 3; ++a) {
                        lo[a] = std::min(lo[a], p[a]);
                        hi[a] = std::max(hi[a], p[a]);
                    }
                }
                const CoordBBox footprint(floorToCoord(lo) - Coord(3), floorToCoord(hi) + Coord(3));
                auto leaf = std::make_unique<LeafT>(origin, background);
                ValueT* values = leaf->buffer(0).data();
                typename LeafT::MaskType& states = leaf->getValueMask();
                bool anyValue = false;
                const auto fill = [&](const auto& reader) {
                    Index n = 0;
                    for (Int32 a = 0; a < DIM; ++a) {
                        for (Int32 b = 0; b < DIM; ++b) {
                            const Vec3d row = base + dx * double(a) + dy * double(b);
                            for (Int32 c = 0; c < DIM; ++c, ++n) {
                                if (!visited.isOn(n))
                                    continue;
                                if (SamplerT::sample(reader, row + dz * double(c), values[n]))
                                    states.setOn(n);
                                else
                                    anyValue = anyValue || !(values[n] == background);
                            }
                        }
                    }
                };
                if (footprint.volume() <= MAX_BLOCK_VOXELS) {
                    block.gather(acc, footprint);
                    fill(block);
                } else {
                    fill(acc);
                }
                if (!states.isOff() || (anyValue && mode != ResampleMode::LevelSet))
                    leaves[i] = std::move(leaf);
            }
        },
        threaded, 4);

    auto out = std::make_shared<TreeT>(background);
    linkLeaves(*out, leaves, threaded);
    if (mode == ResampleMode::Copy) {
        const Coord offset = floorToCoord(outFromIn.getTranslation() + Vec3d(0.5));
        forEachValuedTile(in, [&](const CoordBBox& box, const ValueT& value, bool active) {
            out->fill(CoordBBox(box.min() + offset, box.max() + offset), value, active);
        });
    } else if (mode == ResampleMode::LevelSet) {
        if constexpr (SignedVdbTree<TreeT>)
            signedFloodFill(*out, threaded);
    }
    return out;
}

// ---- GridTransformer's constructors

/// The index of `c` in `order`, or 3 when `order` is not a permutation of `letters`.
inline int orderPosition(const std::string& order, const char* letters, char c) {
    if (order.size() != 3)
        return 3;
    for (const char* l = letters; *l; ++l) {
        if (std::count(order.begin(), order.end(), *l) != 1)
            return 3;
    }
    return int(order.find(c));
}

}  // namespace vdb::tools::detail

namespace vdb::tools {

inline GridTransformer::GridTransformer(const Mat4R& xform) : mTransform(xform) {
    if (!xform.isAffine())
        throw ValueError("GridTransformer: the matrix is not affine (last column not 0, 0, 0, 1)");
    (void)xform.inverse();  // throws ValueError when singular or not finite
    // A scale followed by a rotation (rows of the linear part mutually orthogonal) downscaled
    // by more than half along an input axis is mipmapped: halve the input along that axis
    // first, then apply the rest (rows scaled back up).
    Vec3R rows[3];
    for (int r = 0; r < 3; ++r)
        rows[r] = Vec3R(xform(r, 0), xform(r, 1), xform(r, 2));
    const double tol = 1e-8 * (rows[0].lengthSqr() + rows[1].lengthSqr() + rows[2].lengthSqr());
    for (int r = 0; r < 3; ++r) {
        if (std::abs(rows[r].dot(rows[(r + 1) % 3])) > tol)
            return;
    }
    Vec3R restore(1.0);
    for (int r = 0; r < 3; ++r) {
        const double s = rows[r].length();
        if (s < 0.5) {
            mMipLevels[r] = int(std::floor(-std::log2(s)));
            restore[r] = double(Int64(1) << mMipLevels[r]);
        }
    }
    mPostScale = Mat4R::scale(restore) * xform;
}

inline GridTransformer::GridTransformer(const Vec3R& pivot, const Vec3R& scale, const Vec3R& rotate,
                                        const Vec3R& translate, const std::string& xformOrder,
                                        const std::string& rotOrder) {
    initMipmap(pivot, scale, xformOrder, rotate, rotOrder, translate);
    (void)mTransform.inverse();  // throws ValueError when singular or not finite
}

inline void GridTransformer::initMipmap(const Vec3R& pivot, const Vec3R& scale,
                                        const std::string& xformOrder, const Vec3R& rotate,
                                        const std::string& rotOrder, const Vec3R& translate) {
    using detail::orderPosition;
    if (orderPosition(xformOrder, "tsr", 't') > 2)
        throw ValueError("GridTransformer: invalid transform order \"" + xformOrder + "\"");
    if (orderPosition(rotOrder, "xyz", 'x') > 2)
        throw ValueError("GridTransformer: invalid rotation order \"" + rotOrder + "\"");
    mPivot = pivot;
    // Scales below one half are split into halvings (mipmapping) and a remainder.
    Vec3R remainder = scale;
    for (int i = 0; i < 3; ++i) {
        const double s = std::abs(scale[i]);
        if (s < 0.5 && s > 0.0) {
            mMipLevels[i] = int(std::floor(-std::log2(s)));
            remainder[i] = scale[i] * double(Int64(1) << mMipLevels[i]);
        }
    }
    // Row vectors: the first operation of the order is the leftmost factor, so the matrices
    // are built from the last operation back, each new one multiplied on the left. The
    // operations after the scale go to the post-scale matrix, those before it to the
    // pre-scale matrix.
    mTransform = mPreScale = mPostScale = Mat4R::identity();
    Mat4R* rest = &mPostScale;
    const auto both = [&](const Mat4R& m, const Mat4R& r) {
        mTransform.preMult(m);
        rest->preMult(r);
    };
    for (int i = 2; i >= 0; --i) {
        switch (xformOrder[size_t(i)]) {
            case 'r': {
                both(Mat4R::translation(pivot), Mat4R::translation(pivot));
                for (int j = 2; j >= 0; --j) {
                    const char axis = rotOrder[size_t(j)];
                    const int a = axis - 'x';
                    const Mat4R rot = Mat4R::rotation(math::Axis(a), rotate[a]);
                    both(rot, rot);
                }
                both(Mat4R::translation(-pivot), Mat4R::translation(-pivot));
                break;
            }
            case 's':
                both(Mat4R::translation(pivot), Mat4R::translation(pivot));
                both(Mat4R::scale(scale), Mat4R::scale(remainder));
                both(Mat4R::translation(-pivot), Mat4R::translation(-pivot));
                rest = &mPreScale;
                break;
            default:  // 't'
                both(Mat4R::translation(translate), Mat4R::translation(translate));
                break;
        }
    }
}

}  // namespace vdb::tools
