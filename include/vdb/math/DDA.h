// SPDX-License-Identifier: Apache-2.0
/// @file
/// Digital differential analysers (3D Bresenham walks) along rays in index space: DDA walks
/// the cells of one uniform lattice, HierarchicalDDA walks a VDB tree as a multilevel DDA
/// (paper section 4.7).
///
/// Both use the node-centred convention of index space: voxel (i, j, k) is the unit cube
/// [i, i+1) x [j, j+1) x [k, k+1), so a point p lies in voxel floor(p), and a node whose origin
/// is o and whose edge is D voxels covers [o, o + D) on each axis.
///
/// HierarchicalDDA cuts a ray into spans, each inside one region of the tree that is stored as
/// a unit: a leaf, a tile of an internal node (a whole child region with one value), a root
/// tile, or a region of the root table with no entry (the background). Each empty or constant
/// region is crossed in one step at the level that stores it, so the cost of a ray is the
/// number of such regions it crosses, and only leaves are left for the caller to walk voxel by
/// voxel. Both level set intersection and volume rendering (tools/RayIntersector.h) are built
/// on it.
///
/// @code
/// vdb::math::HierarchicalDDA<vdb::FloatTree> hdda(grid.tree());
/// vdb::math::Ray<double> ray = worldRay.worldToIndex(grid.transform());
/// vdb::math::HierarchicalDDA<vdb::FloatTree>::Span span;
/// if (hdda.init(ray)) {
///     while (hdda.next(span)) {
///         if (span.leaf) { /* walk the voxels of the leaf for t in [span.t0, span.t1] */ }
///         else if (span.active) { /* a constant value, span.value, over the whole span */ }
///     }
/// }
/// @endcode
///
/// Cost: O(1) per span (a cached node-path lookup, as in an accessor, and a slab test against
/// the span's cube). Threads: a walker is not thread-safe; use one per thread. Any number of
/// walkers may read one tree concurrently.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Vec3.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>

namespace vdb::math {

/// Walks, in order, the cells that a ray crosses in the lattice of aligned cubes of 2^Log2Dim
/// voxels (Amanatides and Woo): cell c covers [c, c + 2^Log2Dim) on each axis, with each
/// component of c a multiple of 2^Log2Dim.
///
/// After init(), voxel() is the cell that holds the ray's start, time() the time the walk
/// entered it and next() the time it leaves it; step() moves to the following cell.
/// Threads: a plain value; concurrent const calls are safe.
template <typename RealT, Index Log2Dim = 0>
class DDA {
    static_assert(std::is_floating_point_v<RealT>, "a DDA walks a floating-point ray");
    static_assert(Log2Dim < 31, "a DDA cell must be smaller than the index space");

public:
    static constexpr Int32 DIM = Int32(1) << Log2Dim;

    DDA() = default;
    explicit DDA(const Ray<RealT>& ray) { init(ray, ray.t0(), ray.t1()); }
    DDA(const Ray<RealT>& ray, RealT startTime, RealT maxTime) { init(ray, startTime, maxTime); }

    /// Starts the walk at the point ray(startTime); the walk ends after maxTime.
    void init(const Ray<RealT>& ray, RealT startTime, RealT maxTime);

    /// Moves to the next cell along the ray and returns true, or returns false (and stays) when
    /// that cell starts after maxTime().
    bool step() {
        const int a = nextAxis();
        const RealT t = mNext[a];
        if (t > mMaxTime)
            return false;
        mTime = t;
        mVoxel[a] += mStep[a];
        mNext[a] += mDelta[a];
        return true;
    }

    /// The origin (smallest corner) of the current cell.
    const Coord& voxel() const { return mVoxel; }
    /// The time the ray entered the current cell (the start time for the first cell).
    RealT time() const { return mTime; }
    /// The time the ray leaves the current cell.
    RealT next() const { return mNext[nextAxis()]; }
    RealT maxTime() const { return mMaxTime; }

private:
    int nextAxis() const {
        // Index of the smallest of the three boundary times.
        const int ab = mNext[1] < mNext[0] ? 1 : 0;
        return mNext[2] < mNext[ab] ? 2 : ab;
    }

    Coord mVoxel;
    std::array<Int32, 3> mStep{};
    std::array<RealT, 3> mNext{}, mDelta{};
    RealT mTime = 0, mMaxTime = 0;
};

namespace detail {

/// floor(x) for x already limited to the Int32 range, without a call into libm (the x86-64
/// baseline has no rounding instruction): truncate, then step down for negative fractions.
inline Int64 floorInRange(double x) {
    const Int64 i = Int64(x);
    return i - Int64(double(i) > x);
}

/// floor(x) limited to [lo, hi]; NaN gives lo.
inline Int32 floorClamped(double x, Int32 lo, Int32 hi) {
    if (!(x >= double(lo)))
        return lo;
    if (x >= double(hi))
        return hi;
    return Int32(floorInRange(x));
}

/// The node type at `Level` below (or at) `NodeT`; level 0 is the leaf.
template <typename NodeT, Index Level>
struct DDANodeAt {
    using Type = typename DDANodeAt<typename NodeT::ChildNodeType, Level>::Type;
};
template <typename NodeT, Index Level>
requires(NodeT::LEVEL == Level) struct DDANodeAt<NodeT, Level> {
    using Type = NodeT;
};

/// True for a top node that is a RootNode (an unbounded tree).
template <typename NodeT>
inline constexpr bool DDA_IS_ROOT = requires {
    NodeT::IS_ROOT;
};

}  // namespace detail

/// One stretch of a ray inside a single region that a tree stores as a unit.
template <typename ValueT, typename LeafT>
struct DDASpan {
    double t0 = 0, t1 = 0;        ///< the times on the ray; t0 <= t1
    Coord origin;                 ///< the smallest corner of the region
    Index log2Dim = 0;            ///< the region's edge is 2^log2Dim voxels
    Index level = 0;              ///< 0 for a leaf, else the level of the node holding the tile
    const LeafT* leaf = nullptr;  ///< the leaf, or null for a tile or the background
    ValueT value{};               ///< the tile's value (the background where nothing is stored)
    bool active = false;          ///< the tile's state (false for the background and leaves)
};

/// The multilevel DDA of the paper's section 4.7 over the tree `TreeT` (a root tree or a tree
/// with a fixed internal node on top, any node sizes).
///
/// next() reports, in ray order, consecutive spans that together cover the walked time range
/// without gaps: one span for each leaf, tile or empty root region the ray passes through.
/// Regions are found top-down through a cache of the last node visited at each level (the
/// accessor's idea), and each span ends where the ray leaves the region's cube, found by a slab
/// test against that cube alone. Moving to the next region steps across the face through which
/// the ray left, so the walk always advances, even for rays along faces and edges.
///
/// The walk is limited to the tree's extent: the cubes of the root's entries for a root tree
/// (regions beyond them are background), the fixed domain for a bounded tree.
///
/// Invariant: the tree is not modified while a walker is in use.
/// Threads: not thread-safe; use one walker per thread.
template <typename TreeT>
class HierarchicalDDA {
public:
    using TreeType = std::remove_const_t<TreeT>;
    using TopNodeType = typename TreeType::TopNodeType;
    using LeafNodeType = typename TreeType::LeafNodeType;
    using ValueType = typename TreeType::ValueType;
    using Span = DDASpan<ValueType, LeafNodeType>;
    static constexpr Index TOP = TopNodeType::LEVEL;
    static constexpr bool IS_ROOT = detail::DDA_IS_ROOT<TopNodeType>;

    explicit HierarchicalDDA(const TreeType& tree);

    /// The index-space region the walk is limited to (empty when the tree stores nothing).
    const CoordBBox& bounds() const { return mBounds; }

    /// Starts a walk of the index-space `ray` over the times [t0, t1], clipped to bounds().
    /// Returns false when nothing of that range lies in bounds().
    bool init(const Ray<double>& ray, double t0, double t1);
    bool init(const Ray<double>& ray) { return init(ray, ray.t0(), ray.t1()); }

    /// Fills `span` with the next region along the ray and returns true, or returns false when
    /// the walk is over.
    bool next(Span& span);

    /// Continues the current walk from time `t` in voxel `ijk` (where the ray is at time t),
    /// for callers that walked ahead on their own, voxel by voxel; the end time is kept.
    void restart(double t, const Coord& ijk) {
        mTime = t;
        mIjk = ijk;
        mDone = !(t <= mEnd) || !mBounds.isInside(ijk);
    }

    /// The end of the clipped time range of the current walk.
    double endTime() const { return mEnd; }

private:
    template <Index L>
    using NodeAt = typename detail::DDANodeAt<TopNodeType, L>::Type;
    template <typename Seq>
    struct CacheTuple;
    template <size_t... L>
    struct CacheTuple<std::index_sequence<L...>> {
        using Type = std::tuple<const NodeAt<Index(L)>*...>;
    };
    using Nodes = typename CacheTuple<std::make_index_sequence<TOP>>::Type;

    template <Index L>
    bool cached(const Coord& ijk) const {
        constexpr uint32_t high = ~((uint32_t(1) << NodeAt<L>::TOTAL) - 1);
        const Coord& key = mKeys[L];
        return (((uint32_t(ijk[0]) & high) ^ uint32_t(key[0])) |
                ((uint32_t(ijk[1]) & high) ^ uint32_t(key[1])) |
                ((uint32_t(ijk[2]) & high) ^ uint32_t(key[2]))) == 0;
    }
    template <Index L>
    void lookupFrom(const Coord& ijk, Span& span);
    template <typename NodeT>
    void descend(const NodeT& node, const Coord& ijk, Span& span);

    const TreeType* mTree;
    CoordBBox mBounds;
    std::array<Coord, TOP> mKeys;
    Nodes mNodes{};
    // The current walk: the ray, the voxel where the next span starts, its time, the end.
    Vec3d mEye, mDir;
    // Per axis: 1 when the ray moves up (it leaves a cube through its upper face), else 0; the
    // reciprocal direction, 0 where the ray does not move; +infinity there, else 0.
    Vec3d mFar, mInvDirFinite, mBias;
    Coord mIjk;
    double mTime = 0, mEnd = 0;
    bool mDone = true;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename RealT, Index Log2Dim>
void DDA<RealT, Log2Dim>::init(const Ray<RealT>& ray, RealT startTime, RealT maxTime) {
    mTime = startTime;
    mMaxTime = maxTime;
    const Vec3<RealT> pos = ray(startTime);
    constexpr Int32 lo = std::numeric_limits<Int32>::min(), hi = std::numeric_limits<Int32>::max();
    mVoxel = Coord(detail::floorClamped(double(pos[0]), lo, hi),
                   detail::floorClamped(double(pos[1]), lo, hi),
                   detail::floorClamped(double(pos[2]), lo, hi))
                 .alignedDown(Log2Dim);
    for (int i = 0; i < 3; ++i) {
        const RealT d = ray.dir()[i], inv = ray.invDir()[i];
        if (d > RealT(0)) {
            mStep[i] = DIM;
            mDelta[i] = RealT(DIM) * inv;
            mNext[i] = startTime + (RealT(mVoxel[i]) + RealT(DIM) - pos[i]) * inv;
        } else if (d < RealT(0)) {
            mStep[i] = -DIM;
            mDelta[i] = -RealT(DIM) * inv;
            mNext[i] = startTime + (RealT(mVoxel[i]) - pos[i]) * inv;
        } else {
            mStep[i] = 0;
            mDelta[i] = std::numeric_limits<RealT>::max();
            mNext[i] = std::numeric_limits<RealT>::max();
        }
    }
}

template <typename TreeT>
HierarchicalDDA<TreeT>::HierarchicalDDA(const TreeType& tree) : mTree(&tree) {
    mKeys.fill(Coord::max());  // low bits set: never the key of a node
    if constexpr (IS_ROOT) {
        using ChildT = typename TopNodeType::ChildNodeType;
        const TopNodeType& root = tree.topNode();
        for (auto c = root.cbegin(); root.valid(c); root.next(c))
            mBounds.expand(CoordBBox::createCube(root.key(c), Int32(ChildT::DIM)));
    } else {
        mBounds = TreeType::domain();
    }
}

template <typename TreeT>
bool HierarchicalDDA<TreeT>::init(const Ray<double>& ray, double t0, double t1) {
    mDone = true;
    if (mBounds.empty())
        return false;
    // Clip [t0, t1] to the closed box [min, max + 1] of the bounds' voxels.
    Ray<double> clipped(ray);
    clipped.setTimes(t0, t1);
    const BBoxd box(Vec3d(mBounds.min()), Vec3d(mBounds.max()) + 1.0);
    if (!clipped.intersects(box, t0, t1) || !(t0 <= t1))
        return false;
    mEye = ray.eye();
    mDir = ray.dir();
    for (int i = 0; i < 3; ++i) {
        const bool moving = mDir[i] != 0.0;
        mFar[i] = mDir[i] > 0.0 ? 1.0 : 0.0;
        mInvDirFinite[i] = moving ? ray.invDir()[i] : 0.0;
        mBias[i] = moving ? 0.0 : std::numeric_limits<double>::infinity();
    }
    mTime = t0;
    mEnd = t1;
    const Vec3d p = ray(mTime);
    for (int i = 0; i < 3; ++i) {
        // Rounding may put the entry point just outside the box.
        mIjk[i] = detail::floorClamped(p[i], mBounds.min()[i], mBounds.max()[i]);
    }
    mDone = false;
    return true;
}

template <typename TreeT>
bool HierarchicalDDA<TreeT>::next(Span& span) {
    if (mDone)
        return false;
    lookupFrom<0>(mIjk, span);
    const Int64 dim = Int64(1) << span.log2Dim;
    span.origin = mIjk.alignedDown(span.log2Dim);

    // Exit time of the region's cube: the earliest of the three far faces (axes the ray does
    // not move along give +infinity through mBias), chosen without branches.
    double t[3];
    for (int i = 0; i < 3; ++i) {
        const double face = double(span.origin[i]) + mFar[i] * double(dim);
        t[i] = (face - mEye[i]) * mInvDirFinite[i] + mBias[i];
    }
    int axis = t[1] < t[0] ? 1 : 0;
    axis = t[2] < t[axis] ? 2 : axis;
    const double exitTime = t[axis];
    span.t0 = mTime;
    if (!(exitTime < mEnd)) {
        span.t1 = mEnd;
        mDone = true;
        return true;
    }
    span.t1 = exitTime > mTime ? exitTime : mTime;

    // Step across the exit face; the other two components come from the exit point, kept
    // inside the region's cube so that rounding cannot move them backwards.
    const Vec3d p = mEye + mDir * span.t1;
    Int64 c[3];
    for (int i = 0; i < 3; ++i) {
        const Int64 lo = span.origin[i];
        c[i] = detail::floorClamped(p[i], Int32(lo), Int32(lo + dim - 1));
    }
    c[axis] = mDir[axis] > 0.0 ? Int64(span.origin[axis]) + dim : Int64(span.origin[axis]) - 1;
    if ((c[axis] < mBounds.min()[axis]) | (c[axis] > mBounds.max()[axis])) {
        mDone = true;  // the walk leaves the tree's extent
        return true;
    }
    mIjk = Coord(Int32(c[0]), Int32(c[1]), Int32(c[2]));
    mTime = span.t1;
    return true;
}

template <typename TreeT>
template <Index L>
void HierarchicalDDA<TreeT>::lookupFrom(const Coord& ijk, Span& span) {
    if constexpr (L == TOP) {
        const TopNodeType& top = mTree->topNode();
        if constexpr (IS_ROOT) {
            using ChildT = typename TopNodeType::ChildNodeType;
            const auto* entry = top.findEntry(TopNodeType::coordToKey(ijk));
            if (entry && entry->child) {
                std::get<TOP - 1>(mNodes) = entry->child;
                mKeys[TOP - 1] = ijk.alignedDown(ChildT::TOTAL);
                descend(*entry->child, ijk, span);
                return;
            }
            span.leaf = nullptr;
            span.level = TOP;
            span.log2Dim = ChildT::TOTAL;
            span.value = entry ? entry->tile : top.background();
            span.active = entry ? entry->active : false;
        } else {
            descend(top, ijk, span);
        }
    } else {
        if (cached<L>(ijk)) {
            descend(*std::get<L>(mNodes), ijk, span);
        } else {
            lookupFrom<L + 1>(ijk, span);
        }
    }
}

template <typename TreeT>
template <typename NodeT>
void HierarchicalDDA<TreeT>::descend(const NodeT& node, const Coord& ijk, Span& span) {
    if constexpr (NodeT::LEVEL == 0) {
        span.leaf = &node;
        span.level = 0;
        span.log2Dim = NodeT::TOTAL;
        span.active = false;
    } else {
        using ChildT = typename NodeT::ChildNodeType;
        const Index n = NodeT::coordToOffset(ijk);
        if (const ChildT* child = node.getChild(n)) {
            std::get<ChildT::LEVEL>(mNodes) = child;
            mKeys[ChildT::LEVEL] = ijk.alignedDown(ChildT::TOTAL);
            descend(*child, ijk, span);
            return;
        }
        span.leaf = nullptr;
        span.level = NodeT::LEVEL;
        span.log2Dim = ChildT::TOTAL;
        span.value = node.getTileValue(n);
        span.active = node.isTileOn(n);
    }
}

}  // namespace vdb::math
