// SPDX-License-Identifier: Apache-2.0
/// @file
/// HierarchicalDDA: a VDB tree walked along a ray as a multilevel DDA (paper section 4.7), one
/// uniform DDA (math/DDA.h) per level of the tree.
///
/// Index space is node-centred: voxel (i, j, k) is the unit cube [i, i+1) x [j, j+1) x [k, k+1),
/// so a point p lies in voxel floor(p), and a node whose origin is o and whose edge is D voxels
/// covers [o, o + D) on each axis.
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
/// vdb::tree::HierarchicalDDA<vdb::FloatTree> hdda(grid.tree());
/// vdb::math::Ray<double> ray = worldRay.worldToIndex(grid.transform());
/// vdb::tree::HierarchicalDDA<vdb::FloatTree>::Span span;
/// if (hdda.init(ray)) {
///     while (hdda.next(span)) {
///         if (span.leaf) { /* walk the voxels of the leaf for t in [span.t0, span.t1] */ }
///         else if (span.active) { /* a constant value, span.value, over the whole span */ }
///     }
/// }
/// @endcode
///
/// Cost: O(1) per span: one step of a uniform DDA at the level that stores the region (three
/// comparisons and an add) and one child-mask test, plus the start of a DDA for each node
/// entered. Threads: a walker is not thread-safe; use one per thread. Any number of walkers may
/// read one tree concurrently.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/DDA.h>
#include <vdb/math/Math.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/NodeTraits.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>

namespace vdb::tree {

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
/// The walk keeps one uniform DDA per level of the tree, over the child cells of the node it
/// is crossing at that level (the root's entries at the top): a child node is entered by
/// starting the DDA of the level below at the current time, a cell without a child is
/// reported as one span, and leaving a node hands the walk back to its parent's DDA, which
/// steps across the same face (the parent never picks its own exit axis there, so the levels
/// cannot disagree about which face was crossed). A step is a comparison of three exit times
/// and one add, so an empty cell costs about what a voxel step costs, at whatever level it is
/// stored. A level's exit times are computed from its cell's faces when its DDA starts, then
/// advanced by one cell's crossing time per step.
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
    static constexpr bool IS_ROOT = IS_ROOT_NODE<TopNodeType>;
    static_assert(TOP >= 1, "a hierarchical DDA needs at least one level above the leaves");

    /// With `mergeTiles`, consecutive tiles of one internal node that hold the same value and
    /// state are reported as one span (with the origin and size of the first of them), for
    /// callers that only look at the values; else each tile is a span of its own.
    explicit HierarchicalDDA(const TreeType& tree, bool mergeTiles = false);

    /// The index-space region the walk is limited to (empty when the tree stores nothing).
    const CoordBBox& bounds() const { return mBounds; }

    /// Starts a walk of the index-space `ray` over the times [t0, t1], clipped to bounds().
    /// Returns false when nothing of that range lies in bounds().
    bool init(const math::Ray<double>& ray, double t0, double t1);
    bool init(const math::Ray<double>& ray) { return init(ray, ray.t0(), ray.t1()); }

    /// Fills `span` with the next region along the ray and returns true, or returns false when
    /// the walk is over.
    bool next(Span& span) {
        if (mDone)
            return false;
        while (!dispatch<TOP>(span)) {
        }
        return true;
    }

    /// Continues the current walk from time `t` in voxel `ijk` (where the ray is at time t),
    /// for callers that walked ahead on their own, voxel by voxel; the end time is kept.
    void restart(double t, const Coord& ijk);

    /// The end of the clipped time range of the current walk.
    double endTime() const { return mEnd; }

private:
    template <Index L>
    using NodeAt = NodeAtLevelT<TopNodeType, L>;
    template <typename Seq>
    struct NodeTuple;
    template <size_t... L>
    struct NodeTuple<std::index_sequence<L...>> {
        using Type = std::tuple<const NodeAt<Index(L)>*...>;
    };
    // Slot P: the node of level P being crossed (slot 0, a leaf, is unused).
    using Nodes = typename NodeTuple<std::make_index_sequence<TOP + 1>>::Type;

    // Runs the visit of the level being walked; true when it filled `span`, false when it
    // entered a child node (the walk goes on one level down).
    template <Index P>
    bool dispatch(Span& span) {
        if constexpr (P > 1) {
            if (mLevel != P)
                return dispatch<P - 1>(span);
        }
        return visit<P>(span);
    }
    template <Index P>
    bool visit(Span& span);
    // Starts the DDA of level P (over the child cells of `node`) at the current time.
    template <Index P>
    void enter(const NodeAt<P>& node);
    // With tile merging: moves the DDA of level P into the next cell across its face on
    // `axis` when that cell is in the same node and holds a tile equal to `span`'s; else false.
    template <Index P>
    bool extendTile(int axis, const Span& span);
    // Moves the DDA of level P to the next cell across its face on `axis`, climbing to the
    // parent when the ray leaves the node.
    template <Index P>
    void advance(int axis);
    // The edge of the cells the DDA of level P walks (the children of the node at level P).
    template <Index P>
    static constexpr Int64 CELL = Int64(1) << NodeAt<P>::ChildNodeType::TOTAL;
    // The lower corner, on `axis`, of the cell after the current one of level P.
    template <Index P>
    Int64 nextCorner(int axis) const {
        return Int64(mCell[P][axis]) + mStep[axis] * CELL<P>;
    }
    // Whether the corner `c` from nextCorner() is still inside the node of level P < TOP.
    template <Index P>
    bool insideNode(int axis, Int64 c) const {
        const Int64 o = mOrigin[P][axis];
        return (c >= o) & (c < o + Int64(NodeAt<P>::DIM));
    }
    // Moves the DDA of level P to the cell with corner `c` on `axis`.
    template <Index P>
    void moveTo(int axis, Int64 c) {
        mCell[P][axis] = Int32(c);
        mExit[P][axis] += double(CELL<P>) * mInvAbs[axis];
    }
    // (Re)starts the DDA of level P in the cell holding voxel `ijk`.
    template <Index P>
    void startAt(const Coord& ijk);
    template <Index P>
    void restartAt(const Coord& ijk);
    // The time the ray leaves a cell whose lower corner on `axis` is c and whose edge is dim.
    double exitTime(int axis, Int64 c, Int64 dim) const {
        return (double(c) + mFar[axis] * double(dim) - mEye[axis]) * mInvDirFinite[axis] +
               mBias[axis];
    }

    const TreeType* mTree;
    bool mMergeTiles;
    CoordBBox mBounds;
    Nodes mNodes{};
    // Per level P: the origin of the node being crossed, the origin of the child cell the ray
    // is in, and the times the ray leaves that cell through its far face on each axis.
    std::array<Coord, TOP + 1> mOrigin{}, mCell{};
    std::array<std::array<double, 3>, TOP + 1> mExit{};
    Index mLevel = TOP;
    // The current walk: the ray, the time where the next span starts, the end.
    Vec3d mEye, mDir;
    // Per axis: 1 when the ray moves up (it leaves a cube through its upper face), else 0; the
    // reciprocal direction, 0 where the ray does not move; +infinity there, else 0.
    Vec3d mFar, mInvDirFinite, mBias;
    std::array<Int64, 3> mStep{};     // +1 or -1: the direction the ray moves along each axis
    std::array<double, 3> mInvAbs{};  // |1 / direction| (0 where the ray does not move)
    double mTime = 0, mEnd = 0;
    bool mDone = true;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename TreeT>
HierarchicalDDA<TreeT>::HierarchicalDDA(const TreeType& tree, bool mergeTiles)
    : mTree(&tree), mMergeTiles(mergeTiles) {
    if constexpr (IS_ROOT) {
        using ChildT = typename TopNodeType::ChildNodeType;
        const TopNodeType& root = tree.topNode();
        for (auto c = root.cbegin(); root.valid(c); root.next(c))
            mBounds.expand(CoordBBox::createCube(root.key(c), Int32(ChildT::DIM)));
    } else {
        mBounds = TreeType::domain();
        std::get<TOP>(mNodes) = &tree.topNode();
        mOrigin[TOP] = tree.topNode().origin();
    }
}

template <typename TreeT>
bool HierarchicalDDA<TreeT>::init(const math::Ray<double>& ray, double t0, double t1) {
    mDone = true;
    if (mBounds.empty())
        return false;
    // Clip [t0, t1] to the closed box [min, max + 1] of the bounds' voxels.
    math::Ray<double> clipped(ray);
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
        mStep[i] = mDir[i] > 0.0 ? 1 : -1;
        mInvAbs[i] = moving ? std::abs(ray.invDir()[i]) : 0.0;
    }
    mTime = t0;
    mEnd = t1;
    const Vec3d p = ray(mTime);
    Coord ijk;
    for (int i = 0; i < 3; ++i) {
        // Rounding may put the entry point just outside the box.
        ijk[i] = math::detail::floorClamped(p[i], mBounds.min()[i], mBounds.max()[i]);
    }
    mDone = false;
    startAt<TOP>(ijk);
    return true;
}

template <typename TreeT>
void HierarchicalDDA<TreeT>::restart(double t, const Coord& ijk) {
    mTime = t;
    mDone = !(t <= mEnd) || !mBounds.isInside(ijk);
    if (!mDone)
        restartAt<1>(ijk);
}

template <typename TreeT>
template <Index P>
void HierarchicalDDA<TreeT>::restartAt(const Coord& ijk) {
    // Climb from the level being walked to the lowest node that holds ijk.
    if constexpr (P < TOP) {
        if (mLevel > P)
            return restartAt<P + 1>(ijk);
        constexpr uint32_t DIM = NodeAt<P>::DIM;
        const Coord& o = mOrigin[P];
        if (uint32_t(ijk[0] - o[0]) >= DIM || uint32_t(ijk[1] - o[1]) >= DIM ||
            uint32_t(ijk[2] - o[2]) >= DIM) {
            mLevel = P + 1;
            return restartAt<P + 1>(ijk);
        }
    }
    startAt<P>(ijk);
}

template <typename TreeT>
template <Index P>
void HierarchicalDDA<TreeT>::startAt(const Coord& ijk) {
    constexpr Index LOG2 = NodeAt<P>::ChildNodeType::TOTAL;
    mLevel = P;
    mCell[P] = ijk.alignedDown(LOG2);
    for (int i = 0; i < 3; ++i)
        mExit[P][i] = exitTime(i, mCell[P][i], Int64(1) << LOG2);
}

template <typename TreeT>
template <Index P>
void HierarchicalDDA<TreeT>::enter(const NodeAt<P>& node) {
    constexpr Int32 DIM = Int32(NodeAt<P>::DIM);
    std::get<P>(mNodes) = &node;
    const Coord& o = mOrigin[P] = node.origin();
    // Where the ray is now, kept inside the node's cube so that rounding cannot move it out.
    const Vec3d p = mEye + mDir * mTime;
    Coord ijk;
    for (int i = 0; i < 3; ++i)
        ijk[i] = math::detail::floorClamped(p[i], o[i], o[i] + (DIM - 1));
    startAt<P>(ijk);
}

template <typename TreeT>
template <Index P>
bool HierarchicalDDA<TreeT>::visit(Span& span) {
    using NodeT = NodeAt<P>;
    using ChildT = typename NodeT::ChildNodeType;
    const Coord& cell = mCell[P];
    const ChildT* child = nullptr;
    if constexpr (P == TOP && IS_ROOT) {
        const TopNodeType& root = mTree->topNode();
        const auto* entry = root.findEntry(cell);
        if (entry && entry->child) {
            child = entry->child;
        } else {
            span.value = entry ? entry->tile : root.background();
            span.active = entry ? entry->active : false;
        }
    } else {
        const NodeT& node = *std::get<P>(mNodes);
        const Index n = NodeT::coordToOffset(cell);
        child = node.getChild(n);
        if (!child) {
            span.value = node.getTileValue(n);
            span.active = node.isTileOn(n);
        }
    }
    if (child) {
        if constexpr (ChildT::LEVEL > 0) {
            enter<ChildT::LEVEL>(*child);
            return false;
        } else {
            span.leaf = child;
            span.level = 0;
            span.active = false;
        }
    } else {
        span.leaf = nullptr;
        span.level = P;
    }
    span.origin = cell;
    span.log2Dim = ChildT::TOTAL;
    span.t0 = mTime;
    for (;;) {
        // The cell's exit: the earliest of its three far faces (axes the ray does not move
        // along are at +infinity).
        const std::array<double, 3>& t = mExit[P];
        const int axis = math::detail::argMin3(t);
        if (!(t[axis] < mEnd)) {
            span.t1 = mEnd;
            mDone = true;
            return true;
        }
        span.t1 = t[axis] > mTime ? t[axis] : mTime;
        mTime = span.t1;
        if constexpr (!(P == TOP && IS_ROOT)) {
            if (mMergeTiles && !child && extendTile<P>(axis, span))
                continue;
        }
        advance<P>(axis);
        return true;
    }
}

template <typename TreeT>
template <Index P>
bool HierarchicalDDA<TreeT>::extendTile(int axis, const Span& span) {
    using NodeT = NodeAt<P>;
    const Int64 c = nextCorner<P>(axis);
    if (!insideNode<P>(axis, c))
        return false;
    Coord cell = mCell[P];
    cell[axis] = Int32(c);
    const NodeT& node = *std::get<P>(mNodes);
    const Index n = NodeT::coordToOffset(cell);
    if (node.isChild(n) || !(node.getTileValue(n) == span.value) || node.isTileOn(n) != span.active)
        return false;
    moveTo<P>(axis, c);
    return true;
}

template <typename TreeT>
template <Index P>
void HierarchicalDDA<TreeT>::advance(int axis) {
    const Int64 c = nextCorner<P>(axis);
    if constexpr (P == TOP) {
        if ((c < mBounds.min()[axis]) | (c > mBounds.max()[axis])) {
            mDone = true;  // the walk leaves the tree's extent
            return;
        }
    } else {
        if (!insideNode<P>(axis, c)) {
            // The ray leaves this node: the parent steps across the same face.
            mLevel = P + 1;
            advance<P + 1>(axis);
            return;
        }
    }
    moveTo<P>(axis, c);
}

}  // namespace vdb::tree
