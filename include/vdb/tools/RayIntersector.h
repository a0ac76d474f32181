// SPDX-License-Identifier: Apache-2.0
/// @file
/// Ray intersection with VDB grids, accelerated by the tree (paper section 4.7): the first
/// crossing of a level set's zero surface (LevelSetRayIntersector), and the spans of a ray
/// that cross active values of a volume (VolumeRayIntersector).
///
/// Both walk the ray with tree::HierarchicalDDA, which leaps over tiles and empty regions at
/// the level of the tree that stores them; only leaves are walked voxel by voxel.
///
/// Level sets: inside each leaf the ray is cut where it crosses the planes through voxel
/// centres, so that each piece lies in one trilinear cell, and the trilinear interpolant
/// (tools/BoxSampler) is evaluated at the cuts. The first piece whose ends differ in sign
/// holds the crossing; regula falsi (Illinois) on the interpolant refines it to 1e-6 voxels.
/// A cell whose lower corner holds a value at least two voxel sizes from the iso-value is
/// passed with one read: a level set changes by at most about a voxel size per voxel, so such
/// a cell has no crossing and the corner's sign (the assumption OpenVDB's linear search makes).
/// Tiles are constant, so a sign change between a tile and its neighbour is caught at their
/// common boundary. The normal is the normalized gradient of the trilinear interpolant.
/// Crossings that enter and leave one trilinear cell (grazing rays) are not reported.
///
/// Voxels need not be cubes: any linear transform (scale, scale and translation, affine) is
/// accepted, since the walk happens in index space. With voxels of unequal sides, "a voxel
/// size" above is the longest distance one index unit can span in the world (the largest
/// singular value of the transform's linear part), and world normals are index gradients
/// mapped by the inverse transpose of that linear part. Frustum transforms are refused.
///
/// @code
/// vdb::tools::LevelSetRayIntersector<vdb::FloatGrid> intersector(*sphere);
/// vdb::math::Ray<double> ray(vdb::Vec3d(0, 0, -5), vdb::Vec3d(0, 0, 1));
/// vdb::Vec3d xyz, normal;
/// double t;
/// if (intersector.intersectsWS(ray, xyz, normal, t)) { ... }  // world space
///
/// vdb::tools::VolumeRayIntersector<vdb::FloatGrid> volume(*fog);
/// if (volume.setWorldRay(ray)) {
///     double t0, t1;
///     while (volume.march(t0, t1)) { ... }  // index-space times of the active spans
/// }
/// @endcode
///
/// Cost: one hierarchical DDA step per tree region crossed, and in leaves one trilinear sample
/// per voxel-centre plane crossed. Threads: an intersector caches the tree path of its last
/// query, so it is not thread-safe; copies are cheap, so use one per thread.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/DDA.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tree/HierarchicalDDA.h>
#include <vdb/tree/ValueAccessor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

namespace vdb::tools {

/// Finds where rays first cross the iso-surface (by default the zero level) of a narrow-band
/// level set grid with a linear transform.
///
/// Index-space entry points take a ray in the grid's index space and report index-space
/// points and times; world-space entry points (intersectsWS) take and report world space.
/// A ray counts from its own t0 to its t1, clipped to the bounding box of the active voxels.
///
/// Invariant: the grid (and its tree) outlives the intersector and is not modified while in use.
/// Threads: not thread-safe (it caches the last tree path); copy it for each thread.
template <typename GridT>
class LevelSetRayIntersector {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    using RayType = math::Ray<double>;
    static_assert(std::is_floating_point_v<ValueType>,
                  "level set intersection needs a grid of floating-point values");

    /// @throw ValueError for a frustum transform, or when the grid is not a level set grid
    ///   (getGridClass() != GRID_LEVEL_SET).
    explicit LevelSetRayIntersector(const GridT& grid, ValueType isoValue = ValueType(0));

    const GridT& grid() const { return *mGrid; }
    ValueType getIsoValue() const { return mIsoValue; }
    /// The index-space box rays are clipped to: the active voxels, one voxel wider.
    const BBoxd& indexBBox() const { return mBBox; }

    // ---- Index space
    bool intersectsIS(const RayType& iRay) const {
        double t;
        return march(iRay, t);
    }
    /// On a hit, `iTime` is the index-space time of the crossing on `iRay`.
    bool intersectsIS(const RayType& iRay, double& iTime) const { return march(iRay, iTime); }
    /// On a hit, `xyz` is the index-space crossing point.
    bool intersectsIS(const RayType& iRay, Vec3d& xyz) const {
        double t;
        return intersectsIS(iRay, xyz, t);
    }
    bool intersectsIS(const RayType& iRay, Vec3d& xyz, double& iTime) const {
        if (!march(iRay, iTime))
            return false;
        xyz = iRay(iTime);
        return true;
    }
    /// The unit normal (index space, pointing towards positive values) at the index point `xyz`.
    Vec3d indexNormal(const Vec3d& xyz) const;

    // ---- World space
    bool intersectsWS(const RayType& wRay) const {
        double t;
        return march(wRay.worldToIndex(mGrid->transform()), t);
    }
    /// On a hit, `wTime` is the world-space time of the crossing on `wRay`.
    bool intersectsWS(const RayType& wRay, double& wTime) const {
        Vec3d xyz;
        return intersectsWS(wRay, xyz, wTime);
    }
    /// On a hit, `xyz` is the world-space crossing point.
    bool intersectsWS(const RayType& wRay, Vec3d& xyz) const {
        double t;
        return intersectsWS(wRay, xyz, t);
    }
    bool intersectsWS(const RayType& wRay, Vec3d& xyz, double& wTime) const;
    /// On a hit, `normal` is the world-space unit normal there (pointing outwards, towards
    /// positive values).
    bool intersectsWS(const RayType& wRay, Vec3d& xyz, Vec3d& normal) const {
        double t;
        return intersectsWS(wRay, xyz, normal, t);
    }
    bool intersectsWS(const RayType& wRay, Vec3d& xyz, Vec3d& normal, double& wTime) const;

private:
    using Accessor = tree::ValueAccessor<const TreeType>;
    using HDDA = tree::HierarchicalDDA<TreeType>;
    using LeafT = typename TreeType::LeafNodeType;

    // The core: the index time of the first crossing of `iRay`, or false.
    bool march(const RayType& iRay, double& iTime) const;
    // The trilinear interpolant minus the iso-value at index point p.
    double field(const Vec3d& p) const;
    // The last sample of a march: its time, its value relative to the iso-value, and whether
    // that is the interpolant's value (else only its sign is known to be the interpolant's).
    struct Sample {
        double t = 0.0, f = 0.0;
        bool exact = false, valid = false;
    };
    // The interpolant minus the iso-value at p, inside the trilinear cell with lower corner c.
    double cellField(const LeafT& leaf, const Coord& c, const Vec3d& p) const;
    // Handles a sample whose sign differs from `prev`'s: true (and the crossing time in iTime)
    // when the interpolant really changes sign between them, else records the sample.
    bool resolve(const RayType& ray, Sample& prev, double t, double f, bool exact,
                 const LeafT* leaf, double& iTime) const;
    // Refines a crossing bracketed by (ta, fa) and (tb, fb), fa and fb of opposite signs. When
    // the bracket lies in one trilinear cell, its corners are read once and kept for the normal.
    double refine(const RayType& ray, double ta, double fa, double tb, double fb,
                  const LeafT* leaf) const;
    // The index-space gradient at the crossing point `ijk` of the last hit.
    Vec3d hitGradient(const Vec3d& ijk) const;

    const GridT* mGrid;
    ValueType mIsoValue;
    double mFar;  // two voxel sizes: values this far from the iso-value are far from the surface
    BBoxd mBBox;
    // Rows: the world images of index gradients along each axis (the inverse transpose of the
    // transform's linear part), so that a world normal is their dot products with a gradient.
    std::array<Vec3d, 3> mNormalFromGradient;
    mutable Accessor mAcc;
    mutable HDDA mHdda;
    // The trilinear cell of the last refined crossing and its corner values.
    mutable Coord mHitCell;
    mutable ValueType mHitCorners[2][2][2];
    mutable bool mHitCellValid = false;
};

/// Cuts rays into the spans that cross active values of a volume (a fog volume, a density
/// grid), for volume rendering.
///
/// The walk is voxel-centred: the span of voxel v is the part of the ray nearest to v, the
/// cube [v - 0.5, v + 0.5), so that sampling a span with BoxSampler reads the voxels it belongs
/// to. A span is either a run of leaves (values vary: sample them) or one active tile (the
/// value is constant over the whole span: no sampling needed); inactive tiles and empty regions
/// are leapt over. The span times are index-space times on the index ray.
///
/// Invariant: the grid outlives the intersector and is not modified while in use.
/// Threads: not thread-safe; copy it for each thread.
template <typename GridT>
class VolumeRayIntersector {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    using RayType = math::Ray<double>;

    /// One span of active values along the ray.
    struct Segment {
        double t0 = 0, t1 = 0;  ///< index-space times
        bool constant = false;  ///< true for an active tile: the value is `value` throughout
        ValueType value{};      ///< the tile's value when `constant`
        Index level = 0;        ///< 0 for leaves, else the level of the node holding the tile
        Index log2Dim = 0;      ///< log2 of the edge of the tile (of the leaves when 0 level)
    };

    explicit VolumeRayIntersector(const GridT& grid);

    const GridT& grid() const { return *mGrid; }
    /// The index-space box rays are clipped to: the active voxels, half a voxel wider.
    const BBoxd& indexBBox() const { return mBBox; }

    /// Starts marching `iRay` (index space); false when it misses the active voxels.
    bool setIndexRay(const RayType& iRay);
    /// Starts marching `wRay`, converted to index space; false when it misses.
    bool setWorldRay(const RayType& wRay) {
        return setIndexRay(wRay.worldToIndex(mGrid->transform()));
    }
    /// The index-space ray of the current march.
    const RayType& getIndexRay() const { return mRay; }

    /// Reports the next span of active values: consecutive leaves as one span, each active tile
    /// as its own. Returns false when the ray has no more.
    bool march(Segment& segment);
    /// Reports the next maximal run of active values, leaves and active tiles merged, as
    /// index-space times [t0, t1].
    bool march(double& t0, double& t1);

private:
    using HDDA = tree::HierarchicalDDA<TreeType>;
    using Span = typename HDDA::Span;

    // Fetches the next non-empty region into mPending; false at the end of the ray.
    bool fetch();

    const GridT* mGrid;
    BBoxd mBBox;
    HDDA mHdda;
    RayType mRay;
    Span mPending;
    bool mHasPending = false;
    bool mValid = false;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Throws unless `grid`'s transform is linear (any map but a frustum).
template <typename GridT>
void requireLinearTransform(const GridT& grid, const char* who) {
    if (!grid.transform().isLinear())
        throw ValueError(std::string(who) + ": frustum transforms are not supported");
}

/// The longest world-space distance that one index unit can span: the largest singular value
/// of the linear part of `xform` (the voxel size for cubic voxels). @pre xform.isLinear()
inline double maxIndexToWorldStretch(const math::Transform& xform) {
    if (xform.hasUniformScale())
        return xform.indexToWorldDirection(Vec3d(1, 0, 0)).length();
    // Power iteration on A^T A, A the linear part, from each axis (one of them has a component
    // along the dominant singular vector); the iterates' stretch grows towards the maximum.
    double best = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        Vec3d v(0.0);
        v[axis] = 1.0;
        for (int iter = 0; iter < 64; ++iter) {
            const Vec3d w = xform.indexToWorldDirection(v);
            best = std::max(best, w.length() / v.length());
            // A^T A v: A^T maps a world vector back along the rows of the linear part.
            Vec3d next;
            for (int i = 0; i < 3; ++i) {
                Vec3d e(0.0);
                e[i] = 1.0;
                next[i] = xform.indexToWorldDirection(e).dot(w);
            }
            if (!next.normalize(0.0))
                break;
            v = next;
        }
    }
    return best * (1.0 + 1e-9);
}

/// The index-space box of `tree`'s active voxels widened by `pad` voxels on every side, in
/// the voxel-centred convention (voxel v covers [v - 0.5, v + 0.5]). Empty for an empty tree.
template <typename TreeT>
BBoxd paddedActiveBBox(const TreeT& tree, double pad) {
    CoordBBox box;
    if (!tree.evalActiveVoxelBoundingBox(box))
        return BBoxd();
    return BBoxd(Vec3d(box.min()) - (0.5 + pad), Vec3d(box.max()) + (0.5 + pad));
}

/// Reads the values at the corners c + (a, b, k), a, b, k in {0, 1}, of the trilinear cell
/// with lower corner `c` into v[a][b][k], given `block(m, tile)`: the leaf of the leaf-sized
/// block m around c (bit 0 of m: the next block in +x, bit 1: in +y, bit 2: in +z, from the
/// block of c), or null with that block's constant value stored in `tile`. Only the blocks the
/// cell reaches into are asked for; when it lies in one leaf, its buffer is read directly.
/// `load(leaf, n)` reads the value at offset n of a leaf (by default leaf.getValue(n)).
template <typename LeafT, typename ValueT, typename BlockT>
void readCellCorners(const Coord& c, ValueT (&v)[2][2][2], const BlockT& block) {
    readCellCorners<LeafT>(c, v, block,
                           [](const LeafT& leaf, Index n) { return leaf.getValue(n); });
}
template <typename LeafT, typename ValueT, typename BlockT, typename LoadT>
void readCellCorners(const Coord& c, ValueT (&v)[2][2][2], const BlockT& block, const LoadT& load) {
    constexpr Int32 LAST = Int32(LeafT::DIM) - 1;
    const Coord local(c[0] & LAST, c[1] & LAST, c[2] & LAST);
    // Along each axis where the cell sticks out of its block, the upper corners lie in the
    // next block.
    const int out = (local[0] == LAST) | (local[1] == LAST) << 1 | (local[2] == LAST) << 2;
    if (out == 0) {
        ValueT tile{};
        if (const LeafT* leaf = block(0, tile)) {
            constexpr Index X = Index(1) << (2 * LeafT::LOG2DIM), Y = Index(1) << LeafT::LOG2DIM;
            const Index n = LeafT::coordToOffset(c);
            for (Index a = 0; a < 2; ++a)
                for (Index b = 0; b < 2; ++b) {
                    v[a][b][0] = load(*leaf, n + a * X + b * Y);
                    v[a][b][1] = load(*leaf, n + a * X + b * Y + 1);
                }
        } else {
            for (ValueT* x = &v[0][0][0]; x != &v[0][0][0] + 8; ++x)
                *x = tile;
        }
        return;
    }
    const LeafT* leaves[8] = {};
    ValueT tiles[8] = {};
    for (int m = 0; m < 8; ++m)
        if ((m & ~out) == 0)
            leaves[m] = block(m, tiles[m]);
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int k = 0; k < 2; ++k) {
                const int m = (a & out) | ((b << 1) & out) | ((k << 2) & out);
                v[a][b][k] = leaves[m] ? load(*leaves[m], LeafT::coordToOffset(c.offsetBy(a, b, k)))
                                       : tiles[m];
            }
}

/// readCellCorners() with the blocks found through `acc`, or `leaf` where it is one of them
/// (`leaf` may be null or any leaf of the tree).
template <typename AccT, typename LeafT, typename ValueT>
void getCellCorners(const AccT& acc, const LeafT* leaf, const Coord& c, ValueT (&v)[2][2][2]) {
    constexpr Int32 DIM = Int32(LeafT::DIM);
    const Coord base = c.alignedDown(LeafT::LOG2DIM);
    readCellCorners<LeafT>(c, v, [&](int m, ValueT& tile) -> const LeafT* {
        const Coord origin = base.offsetBy(m & 1 ? DIM : 0, m & 2 ? DIM : 0, m & 4 ? DIM : 0);
        if (leaf && leaf->origin() == origin)
            return leaf;
        const LeafT* found = acc.probeConstLeaf(origin);
        if (!found)
            tile = acc.getValue(origin);
        return found;
    });
}

}  // namespace detail

template <typename GridT>
LevelSetRayIntersector<GridT>::LevelSetRayIntersector(const GridT& grid, ValueType isoValue)
    : mGrid(&grid),
      mIsoValue(isoValue),
      mFar(0.0),
      mBBox(detail::paddedActiveBBox(grid.tree(), 1.0)),
      mAcc(grid.tree()),
      mHdda(grid.tree(), /*mergeTiles=*/true) {
    detail::requireLinearTransform(grid, "LevelSetRayIntersector");
    if (grid.getGridClass() != GRID_LEVEL_SET)
        throw ValueError("LevelSetRayIntersector: the grid is not a level set");
    const math::Transform& xform = grid.transform();
    mFar = 2.0 * detail::maxIndexToWorldStretch(xform);
    for (int j = 0; j < 3; ++j) {
        Vec3d e(0.0);
        e[j] = 1.0;
        mNormalFromGradient[size_t(j)] = xform.worldToIndexDirection(e);
    }
}

template <typename GridT>
double LevelSetRayIntersector<GridT>::field(const Vec3d& p) const {
    return double(BoxSampler::sample(mAcc, p)) - double(mIsoValue);
}

template <typename GridT>
double LevelSetRayIntersector<GridT>::refine(const RayType& ray, double ta, double fa, double tb,
                                             double fb, const LeafT* leaf) const {
    // When both ends lie in one trilinear cell (the usual case: consecutive samples bound a
    // cell), read its corners once and evaluate the interpolant directly.
    const Vec3d pa = ray(ta), pb = ray(tb), mid = (pa + pb) * 0.5;
    const Coord c(Int32(math::detail::floorInRange(mid[0])),
                  Int32(math::detail::floorInRange(mid[1])),
                  Int32(math::detail::floorInRange(mid[2])));
    const Vec3d lo = Vec3d(c) - 1e-6, hi = Vec3d(c) + (1.0 + 1e-6);
    mHitCellValid = BBoxd(lo, hi).isInside(pa) && BBoxd(lo, hi).isInside(pb);
    if (mHitCellValid) {
        mHitCell = c;
        detail::getCellCorners(mAcc, leaf, c, mHitCorners);
    }
    auto f = [&](double t) {
        if (!mHitCellValid)
            return field(ray(t));
        Vec3d uvw = ray(t) - Vec3d(c);
        for (int i = 0; i < 3; ++i)
            uvw[i] = math::clamp01(uvw[i]);
        return double(BoxSampler::trilinear(mHitCorners, uvw)) - double(mIsoValue);
    };
    // Illinois regula falsi: the secant, with the retained end's value halved whenever the
    // same end is kept twice, so that convergence stays superlinear.
    int side = 0;
    for (int iter = 0; iter < 40 && tb - ta > 1e-6; ++iter) {
        const double t = (ta * fb - tb * fa) / (fb - fa);
        const double ft = f(t);
        if (ft == 0.0)
            return t;
        if ((ft < 0.0) == (fa < 0.0)) {
            ta = t;
            fa = ft;
            if (side == -1)
                fb *= 0.5;
            side = -1;
        } else {
            tb = t;
            fb = ft;
            if (side == 1)
                fa *= 0.5;
            side = 1;
        }
    }
    return (ta * fb - tb * fa) / (fb - fa);
}

template <typename GridT>
double LevelSetRayIntersector<GridT>::cellField(const LeafT& leaf, const Coord& c,
                                                const Vec3d& p) const {
    Vec3d uvw = p - Vec3d(c);
    for (int i = 0; i < 3; ++i)
        uvw[i] = math::clamp01(uvw[i]);
    ValueType v[2][2][2];
    detail::getCellCorners(mAcc, &leaf, c, v);
    return double(BoxSampler::trilinear(v, uvw)) - double(mIsoValue);
}

template <typename GridT>
bool LevelSetRayIntersector<GridT>::resolve(const RayType& ray, Sample& prev, double t, double f,
                                            bool exact, const LeafT* leaf, double& iTime) const {
    const double fa = prev.exact ? prev.f : field(ray(prev.t));
    const double fb = exact ? f : field(ray(t));
    if ((fb < 0.0) != (fa < 0.0)) {
        iTime = fb == 0.0 ? t : refine(ray, prev.t, fa, t, fb, leaf);
        return true;
    }
    prev = Sample{t, fb, true, true};
    return false;
}

template <typename GridT>
bool LevelSetRayIntersector<GridT>::march(const RayType& iRay, double& iTime) const {
    mHitCellValid = false;
    RayType ray(iRay);
    if (!ray.clip(mBBox))
        return false;
    // The walk is node-centred: voxel v owns [v, v + 1), which is also the trilinear cell with
    // lower corner v, so the voxel DDA inside a leaf visits the ray's trilinear cells in order.
    if (!mHdda.init(ray, ray.t0(), ray.t1()))
        return false;

    Sample prev;
    // Records a sample; true when it closes a sign change of the interpolant.
    auto sample = [&](double t, double f, bool exact, const LeafT* leaf) {
        if (prev.valid && ((f < 0.0) != (prev.f < 0.0))) [[unlikely]]
            return resolve(ray, prev, t, f, exact, leaf, iTime);
        prev = Sample{t, f, exact, true};
        return false;
    };

    typename HDDA::Span span;
    const LeafT* lastLeaf = nullptr;
    const double end = mHdda.endTime();
    while (mHdda.next(span)) {
        lastLeaf = span.leaf;
        if (!span.leaf) {
            // A tile or the background: one value over the whole region.
            if (sample(span.t0, double(span.value) - double(mIsoValue), false, nullptr))
                return true;
            prev.t = span.t1;
            continue;
        }
        // Walk the trilinear cells from here, through this leaf and any leaves that follow
        // it, until the ray enters a region without a leaf; the hierarchical walk resumes
        // there. A cell whose lower corner is at least mFar from the iso-value cannot hold a
        // crossing (a level set changes by at most one voxel size per voxel, and the cell's
        // diagonal is sqrt(3) voxels): its sign is the corner's.
        const LeafT* leaf = span.leaf;
        Coord origin = span.origin;
        math::DDA<double, 0> dda(ray, span.t0, end);
        // Rounding may put the entry point just behind the leaf's face: step into the leaf
        // (handing such a voxel back to the hierarchical walk would bring the ray here again).
        for (int k = 0; k < 3 && dda.voxel().alignedDown(LeafT::LOG2DIM) != origin; ++k)
            if (!dda.step())
                break;
        for (;;) {
            const Coord& c = dda.voxel();
            const double t = dda.time();
            if (c.alignedDown(LeafT::LOG2DIM) != origin) {
                const LeafT* next = mAcc.probeConstLeaf(c);
                if (!next) {
                    mHdda.restart(t, c);
                    break;
                }
                leaf = lastLeaf = next;
                origin = next->origin();
            }
            const double v = double(leaf->getValue(LeafT::coordToOffset(c))) - double(mIsoValue);
            const bool far = std::abs(v) >= mFar;
            if (sample(t, far ? v : cellField(*leaf, c, ray(t)), !far, leaf))
                return true;
            if (!dda.step()) {
                mHdda.restart(end + 1.0, c);  // the ray's end: the walk is over
                break;
            }
        }
    }
    if (lastLeaf) {
        if (sample(end, field(ray(end)), true, lastLeaf))
            return true;
    }
    return false;
}

template <typename GridT>
Vec3d LevelSetRayIntersector<GridT>::hitGradient(const Vec3d& ijk) const {
    if (!mHitCellValid)
        return BoxSampler::gradient(mAcc, ijk);
    Vec3d uvw = ijk - Vec3d(mHitCell);
    for (int i = 0; i < 3; ++i)
        uvw[i] = math::clamp01(uvw[i]);
    return BoxSampler::trilinearGradient(mHitCorners, uvw);
}

template <typename GridT>
Vec3d LevelSetRayIntersector<GridT>::indexNormal(const Vec3d& xyz) const {
    return BoxSampler::gradient(mAcc, xyz).unitSafe();
}

template <typename GridT>
bool LevelSetRayIntersector<GridT>::intersectsWS(const RayType& wRay, Vec3d& xyz,
                                                 double& wTime) const {
    const math::Transform& xform = mGrid->transform();
    const RayType iRay = wRay.worldToIndex(xform);
    double t;
    if (!march(iRay, t))
        return false;
    xyz = xform.indexToWorld(iRay(t));
    // The world time of that point on wRay (the index ray's direction was normalized).
    wTime = (xyz - wRay.eye()).dot(wRay.dir()) / wRay.dir().lengthSqr();
    return true;
}

template <typename GridT>
bool LevelSetRayIntersector<GridT>::intersectsWS(const RayType& wRay, Vec3d& xyz, Vec3d& normal,
                                                 double& wTime) const {
    const math::Transform& xform = mGrid->transform();
    const RayType iRay = wRay.worldToIndex(xform);
    double t;
    if (!march(iRay, t))
        return false;
    const Vec3d ijk = iRay(t);
    xyz = xform.indexToWorld(ijk);
    wTime = (xyz - wRay.eye()).dot(wRay.dir()) / wRay.dir().lengthSqr();
    // World gradient: the index gradient through the inverse transpose of the linear part.
    const Vec3d g = hitGradient(ijk);
    normal = Vec3d(mNormalFromGradient[0].dot(g), mNormalFromGradient[1].dot(g),
                   mNormalFromGradient[2].dot(g))
                 .unitSafe();
    return true;
}

template <typename GridT>
VolumeRayIntersector<GridT>::VolumeRayIntersector(const GridT& grid)
    : mGrid(&grid), mBBox(detail::paddedActiveBBox(grid.tree(), 0.0)), mHdda(grid.tree()) {
    detail::requireLinearTransform(grid, "VolumeRayIntersector");
}

template <typename GridT>
bool VolumeRayIntersector<GridT>::setIndexRay(const RayType& iRay) {
    mRay = iRay;
    mHasPending = false;
    mValid = false;
    RayType clipped(iRay);
    if (!clipped.clip(mBBox))
        return false;
    // Shift by half a voxel: the walker's node-centred cube of v, [v, v + 1), becomes the
    // voxel-centred [v - 0.5, v + 0.5). Times are unchanged by a translation.
    const RayType shifted(iRay.eye() + 0.5, iRay.dir(), clipped.t0(), clipped.t1());
    mValid = mHdda.init(shifted);
    return mValid;
}

template <typename GridT>
bool VolumeRayIntersector<GridT>::fetch() {
    while (mHdda.next(mPending)) {
        if (mPending.t1 > mPending.t0 && (mPending.leaf || mPending.active))
            return true;
    }
    return false;
}

template <typename GridT>
bool VolumeRayIntersector<GridT>::march(Segment& segment) {
    if (!mValid)
        return false;
    if (!mHasPending && !fetch()) {
        mValid = false;
        return false;
    }
    mHasPending = false;
    segment.t0 = mPending.t0;
    segment.t1 = mPending.t1;
    segment.level = mPending.level;
    segment.log2Dim = mPending.log2Dim;
    segment.constant = mPending.leaf == nullptr;
    segment.value = segment.constant ? mPending.value : ValueType{};
    if (segment.constant)
        return true;
    // Merge the leaves that follow without a gap.
    while (fetch()) {
        if (mPending.leaf && mPending.t0 <= segment.t1) {
            segment.t1 = mPending.t1;
            continue;
        }
        mHasPending = true;
        break;
    }
    return true;
}

template <typename GridT>
bool VolumeRayIntersector<GridT>::march(double& t0, double& t1) {
    Segment s;
    if (!march(s))
        return false;
    t0 = s.t0;
    t1 = s.t1;
    // Merge whatever follows without a gap.
    while (mValid) {
        if (!mHasPending && !fetch()) {
            mValid = false;
            break;
        }
        if (mPending.t0 > t1) {
            mHasPending = true;
            break;
        }
        t1 = mPending.t1;
        mHasPending = false;
    }
    return true;
}

}  // namespace vdb::tools
