// SPDX-License-Identifier: Apache-2.0
/// @file
/// Fog volume rendering: renderFogVolume() integrates the emission-absorption model with
/// single scattering through a density grid lit by a sun (one directional light, with shadows)
/// and an ambient sky, and returns an image with the accumulated opacity as alpha.
/// evalFogVolumeStats() and suggestExtinction() give what good defaults are derived from: the
/// range of the values, the box of the positive ones (for framing), and the extinction at which
/// the picture's densest rays become nearly opaque.
///
/// Model. Density d(p) is the trilinear interpolant of the voxel values (voxel centres at
/// integer index coordinates) inside the cubes the tree stores as leaves, the tile value inside
/// active tiles, and zero in inactive tiles and where nothing is stored; negative values count
/// as zero. With extinction sigma per world unit at density 1 and transmittance T(s) =
/// exp(-integral of sigma d), a ray's colour is the integral of T(s) sigma d(s) albedo
/// (sun Tl(s) + ambient) ds, where Tl is the transmittance from s towards the sun, and its
/// alpha is 1 - T(end); the result is composited over the background.
///
/// Method (paper section 4.7). Rays are walked in index space with tree::HierarchicalDDA, so
/// empty regions, inactive tiles and leaves whose density is zero everywhere (found once per
/// render) are crossed in one step at the tree level that stores them. Runs of leaves are cut
/// into equal steps of at most `step` voxels, sampled at their midpoints, with each step's
/// transmittance integrated exactly: exp(-sigma d ds); active tiles are constant, so they take
/// steps of an eighth of their edge (only the light varies). A ray stops once T falls below
/// `cutoff`. The sun's transmittance Tl is marched the same way towards the light, at
/// `shadowStep`, and stops once it falls below `cutoff`. With the light cache it is marched
/// once per voxel, the first time a sample's trilinear cell needs it, into a light tree read
/// back with trilinear interpolation, so that its cost grows with the voxels seen rather than
/// with the samples of every pixel; LightCache::Auto (the default) uses it unless the picture
/// is so small that marching per sample costs less (pixels x the volume's width / step below
/// the voxels that could need it). Voxels
/// need not be cubes: steps are in index units, and each ray's extinction per index unit is sigma
/// times the world length of one index unit along it.
///
/// The image is cut into square tiles rendered in parallel (oneTBB); every pixel is computed
/// from its own camera ray alone and the light tree does not depend on the number of threads,
/// so neither does the image. Pixels are sampled once, at their centres.
///
/// @code
/// const auto stats = vdb::render::evalFogVolumeStats(*density);
/// auto camera = vdb::render::PerspectiveCamera::frame(stats.worldBBox(density->transform()),
///                                                     640, 480, vdb::Vec3d(-1, -0.6, -1.2));
/// vdb::render::VolumeRenderSettings settings;
/// settings.extinction = vdb::render::suggestExtinction(*density, camera);
/// vdb::render::Image image = vdb::render::renderFogVolume(*density, camera, settings);
/// @endcode
///
/// Cost: one march towards the sun per voxel seen (O(shadow ray length / shadowStep) each), and
/// per pixel O(regions crossed + ray length in the volume / step). Threads: the functions are
/// thread-safe; a VolumeRenderer is not (copy it per thread).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/render/Camera.h>
#include <vdb/render/Image.h>
#include <vdb/render/detail/Tiles.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/RayIntersector.h>
#include <vdb/tree/HierarchicalDDA.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

namespace vdb::render {

/// How VolumeRenderSettings find the sun's transmittance at samples.
enum class LightCache { Auto, On, Off };

/// Settings of renderFogVolume() and VolumeRenderer.
struct VolumeRenderSettings {
    double extinction = 1.0;                  ///< sigma: per world unit, at density 1
    Rgba albedo{1.0f, 1.0f, 1.0f, 1.0f};      ///< fraction of extinction that scatters light
    Vec3d lightDirection{0.5, 0.8, 0.6};      ///< world space, towards the sun
    Rgba lightColor{1.0f, 1.0f, 1.0f, 1.0f};  ///< the sun's radiance
    /// Light reaching every point from every direction, unshadowed (a sky).
    Rgba ambientColor{0.0f, 0.0f, 0.0f, 1.0f};
    double step = 0.5;        ///< longest primary step, in voxels (index units)
    double shadowStep = 1.0;  ///< longest step towards the sun, in voxels
    bool shadows = true;      ///< march the sun's transmittance (else the sun is unblocked)
    /// Whether the sun's transmittance is marched once per voxel into a light tree (On), per
    /// sample (Off), or by the estimated cost (Auto; On for VolumeRenderer used alone).
    LightCache lightCache = LightCache::Auto;
    double cutoff = 1e-3;  ///< transmittance below which marching stops, in (0, 1)
    Rgba background{0.0f, 0.0f, 0.0f, 0.0f};  ///< composited behind the volume
    size_t tileSize = 16;                     ///< edge of the square tiles rendered as tasks
    bool threaded = true;
};

/// What the defaults of a fog volume rendering are derived from.
struct FogVolumeStats {
    double minValue = 0.0, maxValue = 0.0;  ///< range of the active values (0, 0 when none)
    Index64 activeValues = 0;               ///< active voxels, tiles counted by their voxels
    /// The index box of the voxels with positive density (values above zero in leaves, active
    /// or not, and in active tiles): what rendering can show. Empty when there is none.
    CoordBBox positiveBBox;

    bool empty() const { return positiveBBox.empty(); }
    /// The world box around the cubes of positiveBBox's voxels. @pre !empty()
    BBoxd worldBBox(const math::Transform& xform) const {
        return xform.indexToWorld(
            BBoxd(Vec3d(positiveBBox.min()) - 0.5, Vec3d(positiveBBox.max()) + 0.5));
    }
};

/// The value range and the box of positive densities of `grid`, in one parallel pass over its
/// leaves and one over its tiles.
template <typename GridT>
FogVolumeStats evalFogVolumeStats(const GridT& grid, bool threaded = true);

/// The extinction (per world unit at density 1) at which `quantile` of the rays of `camera`
/// that meet positive densities reach an optical depth of at most `opticalDepth`: a grid of at
/// most probes x probes rays spread over the image measures the density integrals, and the
/// one at that quantile is mapped to `opticalDepth`. So the picture's densest rays become
/// nearly opaque (T = exp(-opticalDepth)) and the rest show the inside, whatever the scale
/// of the values and the thickness of the volume. Returns 0 when no probe meets a density.
/// @throw ValueError for an opticalDepth that is not positive and finite, a quantile outside
///   (0, 1], zero probes, or a frustum transform.
template <typename GridT>
double suggestExtinction(const GridT& grid, const Camera& camera, double opticalDepth = 4.0,
                         double quantile = 0.9, size_t probes = 128, bool threaded = true);

/// Renders the fog volume `grid` (values are densities) as seen by `camera`, with the model in
/// the file comment. Colours are linear and not premultiplied; alpha is the opacity.
/// @throw ValueError as VolumeRenderer, or for a zero tile size.
template <typename GridT>
Image renderFogVolume(const GridT& grid, const Camera& camera,
                      const VolumeRenderSettings& settings = {});

namespace detail {

/// Reads the values at the corners of trilinear cells of one tree (c + (a, b, k), a, b, k in
/// {0, 1}, for the cell with lower corner c), remembering the leaves, or the tile values, of
/// the 2 x 2 x 2 leaf-sized blocks around the last cell read, so that the consecutive cells of
/// a ray read their values without descending the tree.
///
/// Invariant: the tree is not modified while a reader is in use.
/// Threads: not thread-safe; use one reader per thread.
template <typename TreeT>
class CellReader {
public:
    using ValueType = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;

    explicit CellReader(const TreeT& tree) : mAcc(tree) {}

    /// Fills v[a][b][k] with the value at c + (a, b, k), read from leaves by `load(leaf, n)`.
    template <typename LoadT>
    void get(const Coord& c, ValueType (&v)[2][2][2], const LoadT& load) {
        setCell(c);
        tools::detail::readCellCorners<LeafT>(
            c, v,
            [this](int m, ValueType& tile) {
                const LeafT* leaf = block(m);
                tile = mTile[size_t(m)];
                return leaf;
            },
            load);
    }
    void get(const Coord& c, ValueType (&v)[2][2][2]) {
        get(c, v, [](const LeafT& leaf, Index n) { return leaf.getValue(n); });
    }

    /// Makes the blocks around the cell with lower corner `c` the current ones, for leafAt().
    void setCell(const Coord& c) {
        const Coord base = c.alignedDown(LeafT::LOG2DIM);
        if (base != mBase) {
            mBase = base;
            mKnown = 0;
        }
    }
    /// The leaf holding `ijk`, a corner of the cell given to setCell() or get(), or null.
    const LeafT* leafAt(const Coord& ijk) {
        const Coord d = ijk.alignedDown(LeafT::LOG2DIM) - mBase;
        return block((d[0] != 0) | (d[1] != 0) << 1 | (d[2] != 0) << 2);
    }

private:
    // The leaf of block m (bit 0: +x, bit 1: +y, bit 2: +z of mBase), or null with its tile
    // value in mTile[m].
    const LeafT* block(int m) {
        if (!(mKnown & (1u << m))) {
            constexpr Int32 DIM = Int32(LeafT::DIM);
            const Coord origin = mBase.offsetBy(m & 1 ? DIM : 0, m & 2 ? DIM : 0, m & 4 ? DIM : 0);
            mLeaf[size_t(m)] = mAcc.probeConstLeaf(origin);
            if (!mLeaf[size_t(m)])
                mTile[size_t(m)] = mAcc.getValue(origin);
            mKnown |= 1u << m;
        }
        return mLeaf[size_t(m)];
    }

    tree::ValueAccessor<const TreeT> mAcc;
    Coord mBase = Coord::max();
    unsigned mKnown = 0;  // bit m: block m looked up
    std::array<const LeafT*, 8> mLeaf{};
    std::array<ValueType, 8> mTile{};
};

}  // namespace detail

/// The per-ray part of renderFogVolume(): colour and transmittance along world-space rays.
/// Construction finds the leaves that hold density (in parallel when settings.threaded) and
/// makes the light tree; copies share it, and fill it as their samples need its values.
///
/// Invariant: the grid outlives the renderer and its copies and is not modified meanwhile.
/// Threads: not thread-safe (walkers and accessors cache tree paths); copy it per thread.
template <typename GridT>
class VolumeRenderer {
public:
    using RayType = math::Ray<double>;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    static_assert(std::is_floating_point_v<ValueType>, "densities are floating-point values");

    /// `pixels`, when not 0, is the number of rays to be shaded, for LightCache::Auto.
    /// @throw ValueError for a frustum transform, a zero or non-finite light direction, a step
    ///   or shadow step that is not positive and finite, an extinction that is negative or not
    ///   finite, or a cutoff outside (0, 1).
    VolumeRenderer(const GridT& grid, const VolumeRenderSettings& settings, size_t pixels = 0);

    /// The colour seen along `wRay` from its t0 to its t1, composited over the background.
    Rgba shade(const RayType& wRay);
    /// The optical depth (the integral of sigma d) along `wRay` from its t0 to its t1, by the
    /// same steps as shade() but without the cutoff.
    double opticalDepth(const RayType& wRay);
    /// exp(-opticalDepth(wRay)).
    double transmittance(const RayType& wRay) { return std::exp(-opticalDepth(wRay)); }
    /// The sun's transmittance from the index-space point `ijk` (1 without shadows), marched.
    double lightTransmittance(const Vec3d& ijk);

    const VolumeRenderSettings& settings() const { return mSettings; }

private:
    using LeafT = typename TreeType::LeafNodeType;
    using LightTree = FloatTree;
    using LightLeaf = typename LightTree::LeafNodeType;
    // Light tree values: a transmittance in [0, 1], UNMARCHED for a voxel not marched yet, and
    // -1 (the background) where no sample looks.
    static constexpr float UNMARCHED = -2.0f;
    static_assert(LeafT::DIM == LightLeaf::DIM,
                  "fog rendering needs leaves of 8^3 voxels: the light tree mirrors them");

    /// What the copies of a renderer share: the light tree, whose active voxels are the corners
    /// of the trilinear cells with positive density that samples in the grid's leaves can
    /// use, and whose values there are, with the light cache, the sun's transmittance at the
    /// voxel centres, marched by the first sample that needs it (UNMARCHED until then; -1
    /// elsewhere, and everywhere without the cache). The grid's leaves whose cubes can hold
    /// positive density are exactly those with a light leaf at their origin.
    struct Shared {
        LightTree light{-1.0f};
        BBoxd bounds;  // index box where density can be positive (voxel-centred)
        bool cached = false;
    };

    /// A walker of index rays through the regions that may hold density (one per thread and
    /// use: the primary rays and the rays towards the sun each have one).
    class Marcher {
    public:
        Marcher(const TreeType& tree, const Shared& shared)
            : mTree(&tree),
              mShared(&shared),
              mCells(tree),
              mLiveAcc(shared.light),
              mHdda(tree, /*mergeTiles=*/false) {}
        /// Calls f(p, cell, d, ds) for each sample with positive density d along `ray` (index
        /// space) from t0 to t1 in order: p the point, ds the step length in index units, cell
        /// the lower corner of p's trilinear cell, or null inside a tile. Stops when f returns
        /// false.
        template <typename F>
        void march(const RayType& ray, double step, const F& f);
        /// The density at p, in the trilinear cell with lower corner c.
        double density(const Vec3d& p, const Coord& c) {
            ValueType v[2][2][2];
            mCells.get(c, v);
            return double(tools::BoxSampler::trilinear(v, p - Vec3d(c)));
        }

    private:
        // Whether samples in `leaf`'s cube can see positive density: it has a light leaf.
        bool live(const LeafT* leaf) const {
            return mLiveAcc.probeConstLeaf(leaf->origin()) != nullptr;
        }
        const TreeType* mTree;
        const Shared* mShared;
        detail::CellReader<TreeType> mCells;
        tree::ValueAccessor<const LightTree> mLiveAcc;
        tree::HierarchicalDDA<TreeType> mHdda;
    };

    // Builds the shared light tree, with values when the settings ask for the light cache
    // (for Auto, by the cost estimate for `pixels` rays).
    static std::shared_ptr<const Shared> makeShared(const GridT& grid,
                                                    const VolumeRenderSettings& settings,
                                                    size_t pixels);
    // The optical depth towards the sun from index point p, stopping past maxDepth.
    double shadowDepth(const Vec3d& p, double maxDepth);
    // The sun's transmittance at p (cell: its trilinear cell, or null in a tile).
    double sunlight(const Vec3d& p, const Coord* cell);
    // World units per index unit along the unit index direction `dir`.
    double worldLength(const Vec3d& dir) const {
        return mGrid->transform().indexToWorldDirection(dir).length();
    }

    const GridT* mGrid;
    VolumeRenderSettings mSettings;
    Vec3d mIndexLight;   // unit, index space, towards the sun
    double mLightSigma;  // extinction per index unit along mIndexLight
    std::shared_ptr<const Shared> mShared;
    Marcher mPrimary, mShadow;
    detail::CellReader<LightTree> mLight;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Calls f(box, value) for every active tile of the node `node` and of the internal nodes
/// below it (not for leaf voxels).
template <typename NodeT, typename F>
void forEachActiveTile(const NodeT& node, const F& f) {
    using ChildT = typename NodeT::ChildNodeType;
    tree::forEachTile<ValueFilter::On>(node, [&](const auto& tile) {
        f(CoordBBox::createCube(tile.origin, Int32(ChildT::DIM)), tile.value);
    });
    if constexpr (ChildT::LEVEL > 0)
        tree::forEachChild(node, [&](const ChildT& child) { forEachActiveTile(child, f); });
}

/// Per-leaf facts of a fog volume, from one pass over its leaves.
template <typename TreeT>
struct FogLeafScan {
    using LeafT = typename TreeT::LeafNodeType;
    std::vector<const LeafT*> leaves;
    FogVolumeStats stats;
};

template <typename TreeT>
FogLeafScan<TreeT> scanFogLeaves(const TreeT& tree, bool threaded) {
    using LeafT = typename TreeT::LeafNodeType;
    FogLeafScan<TreeT> scan;
    for (const LeafT& leaf : tree.leaves())
        scan.leaves.push_back(&leaf);
    struct Part {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -std::numeric_limits<double>::infinity();
        Index64 active = 0;
        CoordBBox positive;
    };
    const auto join = [](Part a, const Part& b) {
        a.lo = std::min(a.lo, b.lo);
        a.hi = std::max(a.hi, b.hi);
        a.active += b.active;
        a.positive.expand(b.positive);
        return a;
    };
    Part all = util::parallelReduce(
        scan.leaves.size(), Part{},
        [&](size_t begin, size_t end) {
            Part part;
            for (size_t i = begin; i < end; ++i) {
                const LeafT& leaf = *scan.leaves[i];
                const auto& mask = leaf.getValueMask();
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                    const double v = double(leaf.getValue(n));
                    if (v > 0.0)
                        part.positive.expand(leaf.offsetToGlobalCoord(n));
                    if (mask.isOn(n) && !std::isnan(v)) {
                        part.lo = std::min(part.lo, v);
                        part.hi = std::max(part.hi, v);
                    }
                }
                part.active += mask.countOn();
            }
            return part;
        },
        join, threaded, /*grain=*/16);
    forEachActiveTile(tree.topNode(), [&](const CoordBBox& box, const auto& value) {
        Part tile;
        const double v = double(value);
        if (!std::isnan(v))
            tile.lo = tile.hi = v;
        tile.active = box.volume();
        if (v > 0.0)
            tile.positive = box;
        all = join(all, tile);
    });
    if (all.lo <= all.hi) {
        scan.stats.minValue = all.lo;
        scan.stats.maxValue = all.hi;
    }
    scan.stats.activeValues = all.active;
    scan.stats.positiveBBox = all.positive;
    return scan;
}

}  // namespace detail

template <typename GridT>
FogVolumeStats evalFogVolumeStats(const GridT& grid, bool threaded) {
    return detail::scanFogLeaves(grid.tree(), threaded).stats;
}

template <typename GridT>
std::shared_ptr<const typename VolumeRenderer<GridT>::Shared> VolumeRenderer<GridT>::makeShared(
    const GridT& grid, const VolumeRenderSettings& settings, size_t pixels) {
    const TreeType& tree = grid.tree();
    auto shared = std::make_shared<Shared>();
    const detail::FogLeafScan<TreeType> scan = detail::scanFogLeaves(tree, settings.threaded);
    if (scan.stats.empty())
        return shared;
    // Samples with positive density lie within a voxel of a positive voxel.
    const CoordBBox& pos = scan.stats.positiveBBox;
    shared->bounds = BBoxd(Vec3d(pos.min()) - 1.5, Vec3d(pos.max()) + 1.5);

    // The light tree's active voxels: the corners of every trilinear cell with a positive
    // corner that samples in a leaf's cube can use, that is, for each leaf with origin o, the
    // voxels of [o - 1, o + 8]^3 within one voxel (any direction) of a positive voxel of that
    // block. Each leaf's block is read and dilated in parallel; the light leaves are then made
    // and their masks merged in order.
    constexpr Int32 DIM = Int32(LeafT::DIM), W = DIM + 2;  // the block: W^3 voxels
    using MaskT = typename LightLeaf::MaskType;
    struct Marks {
        std::array<MaskT, 27> masks;  // per neighbour block n (offsets n % 3, n / 3 % 3, n / 9)
        unsigned used = 0;            // bit n: masks[n] has a bit on
    };
    std::vector<Marks> marks(scan.leaves.size());
    util::parallelFor(
        scan.leaves.size(),
        [&](size_t i) {
            detail::CellReader<TreeType> cells(tree);
            const Coord o = scan.leaves[i]->origin();
            // Positive flags of the block [o - 1, o + DIM]^3, read by trilinear cells.
            std::vector<uint8_t> pos(size_t(W * W * W), 0), grown(pos.size(), 0);
            const auto at = [&](Int32 x, Int32 y, Int32 z) { return size_t((x * W + y) * W + z); };
            bool any = false;
            for (Int32 x = 0; x < W; x += 2)
                for (Int32 y = 0; y < W; y += 2)
                    for (Int32 z = 0; z < W; z += 2) {
                        ValueType v[2][2][2];
                        cells.get(o.offsetBy(x - 1, y - 1, z - 1), v);
                        for (Int32 a = 0; a < 2; ++a)
                            for (Int32 b = 0; b < 2; ++b)
                                for (Int32 c = 0; c < 2; ++c) {
                                    const bool p = double(v[a][b][c]) > 0.0;
                                    pos[at(x + a, y + b, z + c)] = p;
                                    any = any || p;
                                }
                    }
            if (!any)
                return;
            // Dilate by one voxel, one axis at a time.
            for (int axis = 0; axis < 3; ++axis) {
                for (Int32 x = 0; x < W; ++x)
                    for (Int32 y = 0; y < W; ++y)
                        for (Int32 z = 0; z < W; ++z) {
                            Int32 q[3] = {x, y, z};
                            uint8_t on = pos[at(x, y, z)];
                            for (Int32 d : {-1, 1}) {
                                q[axis] += d;
                                if (q[axis] >= 0 && q[axis] < W)
                                    on |= pos[at(q[0], q[1], q[2])];
                                q[axis] -= d;
                            }
                            grown[at(x, y, z)] = on;
                        }
                pos.swap(grown);
            }
            Marks& m = marks[i];
            for (Int32 x = 0; x < W; ++x)
                for (Int32 y = 0; y < W; ++y)
                    for (Int32 z = 0; z < W; ++z) {
                        if (!pos[at(x, y, z)])
                            continue;
                        // The neighbour block holding voxel o + (x, y, z) - 1, and its offset.
                        const Int32 l[3] = {x - 1, y - 1, z - 1};
                        int n = 0, stride = 1;
                        Coord local;
                        for (int k = 0; k < 3; ++k) {
                            const int side = l[k] < 0 ? 0 : l[k] < DIM ? 1 : 2;
                            n += side * stride;
                            stride *= 3;
                            local[k] = l[k] - (side - 1) * DIM;
                        }
                        m.masks[size_t(n)].setOn(LightLeaf::coordToOffset(local));
                        m.used |= 1u << n;
                    }
        },
        settings.threaded, /*grain=*/4);
    LightTree& light = shared->light;
    {
        tree::ValueAccessor<LightTree> lightAcc(light);
        for (size_t i = 0; i < marks.size(); ++i) {
            const Coord o = scan.leaves[i]->origin();
            for (int n = 0; n < 27; ++n) {
                if (!(marks[i].used & (1u << n)))
                    continue;
                LightLeaf* leaf = lightAcc.touchLeaf(
                    o.offsetBy((n % 3 - 1) * DIM, (n / 3 % 3 - 1) * DIM, (n / 9 - 1) * DIM));
                leaf->getValueMask() |= marks[i].masks[size_t(n)];
            }
        }
    }
    // The light cache: its cost is one march per active voxel of the light tree; marching per
    // sample costs about one march per sample, pixels x the volume's width / step at most.
    bool cache = settings.shadows && settings.lightCache != LightCache::Off;
    if (cache && settings.lightCache == LightCache::Auto && pixels > 0) {
        const double voxels = double(light.activeVoxelCount());
        const double samples = double(pixels) * std::cbrt(voxels) / settings.step;
        cache = voxels <= samples;
    }
    if (!cache)
        return shared;

    // Marked unmarched: sunlight() marches each voxel the first time a sample needs it.
    std::vector<LightLeaf*> lightLeaves;
    for (LightLeaf& leaf : light.leaves())
        lightLeaves.push_back(&leaf);
    util::parallelFor(
        lightLeaves.size(),
        [&](size_t i) {
            LightLeaf& leaf = *lightLeaves[i];
            for (Index n : leaf.getValueMask().onBits())
                leaf.setValueOnly(n, UNMARCHED);
        },
        settings.threaded);
    shared->cached = true;
    return shared;
}

template <typename GridT>
template <typename F>
void VolumeRenderer<GridT>::Marcher::march(const RayType& ray, double step, const F& f) {
    RayType clipped(ray);
    if (mShared->bounds.empty() || !clipped.clip(mShared->bounds))
        return;
    // Shift by half a voxel: the walker's node-centred cube of v, [v, v + 1), becomes the
    // voxel-centred [v - 0.5, v + 0.5). Times are unchanged by a translation.
    const RayType shifted(ray.eye() + 0.5, ray.dir(), clipped.t0(), clipped.t1());
    if (!mHdda.init(shifted))
        return;
    typename tree::HierarchicalDDA<TreeType>::Span span;
    bool more = mHdda.next(span);
    while (more) {
        if (span.leaf) {
            if (!live(span.leaf)) {
                more = mHdda.next(span);
                continue;
            }
            // A run of consecutive live leaves, cut into equal steps.
            const double a = span.t0;
            double b = span.t1;
            while ((more = mHdda.next(span)) && span.leaf && live(span.leaf))
                b = span.t1;
            const size_t n = size_t(std::max(1.0, std::ceil((b - a) / step)));
            const double ds = (b - a) / double(n);
            for (size_t k = 0; k < n; ++k) {
                const Vec3d p = ray(a + (double(k) + 0.5) * ds);
                const Coord c(Int32(math::detail::floorInRange(p[0])),
                              Int32(math::detail::floorInRange(p[1])),
                              Int32(math::detail::floorInRange(p[2])));
                const double d = density(p, c);
                if (d > 0.0 && !f(p, &c, d, ds))
                    return;
            }
            continue;
        }
        const double d = double(span.value);
        if (span.active && d > 0.0 && span.t1 > span.t0) {
            // A constant tile: only the light varies along it.
            const double tileStep =
                std::max(step, double(Index64(1) << span.log2Dim) / double(LeafT::DIM));
            const size_t n = size_t(std::max(1.0, std::ceil((span.t1 - span.t0) / tileStep)));
            const double ds = (span.t1 - span.t0) / double(n);
            for (size_t k = 0; k < n; ++k)
                if (!f(ray(span.t0 + (double(k) + 0.5) * ds), nullptr, d, ds))
                    return;
        }
        more = mHdda.next(span);
    }
}

template <typename GridT>
VolumeRenderer<GridT>::VolumeRenderer(const GridT& grid, const VolumeRenderSettings& settings,
                                      size_t pixels)
    : mGrid(&grid),
      mSettings(settings),
      mIndexLight(0.0),
      mLightSigma(0.0),
      mShared(std::make_shared<Shared>()),
      mPrimary(grid.tree(), *mShared),
      mShadow(grid.tree(), *mShared),
      mLight(mShared->light) {
    if (!grid.transform().isLinear())
        throw ValueError("VolumeRenderer: frustum transforms are not supported");
    const auto finitePositive = [](double x) { return std::isfinite(x) && x > 0.0; };
    if (!finitePositive(settings.step) || !finitePositive(settings.shadowStep))
        throw ValueError("VolumeRenderer: the steps must be positive and finite");
    if (!(std::isfinite(settings.extinction) && settings.extinction >= 0.0))
        throw ValueError("VolumeRenderer: the extinction must be finite and not negative");
    if (!(settings.cutoff > 0.0 && settings.cutoff < 1.0))
        throw ValueError("VolumeRenderer: the cutoff must lie in (0, 1)");
    const Vec3d light = detail::unitLight(settings.lightDirection);
    mIndexLight = grid.transform().worldToIndexDirection(light).unitSafe(0.0);
    mLightSigma = settings.extinction * worldLength(mIndexLight);
    mShared = makeShared(grid, settings, pixels);
    mPrimary = Marcher(grid.tree(), *mShared);
    mShadow = Marcher(grid.tree(), *mShared);
    mLight = detail::CellReader<LightTree>(mShared->light);
}

template <typename GridT>
double VolumeRenderer<GridT>::shadowDepth(const Vec3d& p, double maxDepth) {
    double depth = 0.0;
    mShadow.march(RayType(p, mIndexLight, 0.0, std::numeric_limits<double>::max()),
                  mSettings.shadowStep, [&](const Vec3d&, const Coord*, double d, double ds) {
                      depth += mLightSigma * d * ds;
                      return depth <= maxDepth;
                  });
    return depth;
}

template <typename GridT>
double VolumeRenderer<GridT>::lightTransmittance(const Vec3d& ijk) {
    if (!mSettings.shadows)
        return 1.0;
    return std::exp(-shadowDepth(ijk, std::numeric_limits<double>::infinity()));
}

template <typename GridT>
double VolumeRenderer<GridT>::sunlight(const Vec3d& p, const Coord* cell) {
    if (!mSettings.shadows)
        return 1.0;
    const double maxDepth = -std::log(mSettings.cutoff);
    if (cell && mShared->cached) {
        // The corners' transmittances, each marched by the first sample that needs it. Threads
        // share the light tree: its values are read and written atomically (the tree is not
        // const: Shared holds it as a cache), and two threads that march one voxel at once
        // store the same value.
        const auto slot = [](const LightLeaf& leaf, Index n) {
            return std::atomic_ref<float>(const_cast<float&>(leaf.getValue(n)));
        };
        float v[2][2][2];
        mLight.get(*cell, v, [&](const LightLeaf& leaf, Index n) {
            return slot(leaf, n).load(std::memory_order_relaxed);
        });
        bool marched = true;
        for (int a = 0; a < 2 && marched; ++a)
            for (int b = 0; b < 2 && marched; ++b)
                for (int k = 0; k < 2 && marched; ++k) {
                    float& x = v[a][b][k];
                    if (x == UNMARCHED) {
                        const Coord q = cell->offsetBy(a, b, k);
                        x = float(std::exp(-shadowDepth(Vec3d(q), maxDepth)));
                        slot(*mLight.leafAt(q), LightLeaf::coordToOffset(q))
                            .store(x, std::memory_order_relaxed);
                    }
                    marched = x >= 0.0f;  // else not a voxel of the light tree
                }
        if (marched)
            return double(tools::BoxSampler::trilinear(v, p - Vec3d(*cell)));
    }
    return std::exp(-shadowDepth(p, maxDepth));
}

template <typename GridT>
Rgba VolumeRenderer<GridT>::shade(const RayType& wRay) {
    const VolumeRenderSettings& s = mSettings;
    double T = 1.0, r = 0.0, g = 0.0, b = 0.0;
    const RayType ray = wRay.worldToIndex(mGrid->transform());
    const double sigma = s.extinction * worldLength(ray.dir());  // per index unit
    if (sigma > 0.0) {
        const Rgba &a = s.albedo, &sun = s.lightColor, &sky = s.ambientColor;
        mPrimary.march(ray, s.step, [&](const Vec3d& p, const Coord* cell, double d, double ds) {
            const double stepT = std::exp(-sigma * d * ds);
            const double w = T * (1.0 - stepT);
            const double l = sunlight(p, cell);
            r += w * a.r * (sun.r * l + sky.r);
            g += w * a.g * (sun.g * l + sky.g);
            b += w * a.b * (sun.b * l + sky.b);
            T *= stepT;
            return T >= s.cutoff;
        });
    }
    // Over the background, then from premultiplied to straight colour.
    const Rgba& bg = s.background;
    const double alpha = (1.0 - T) + T * bg.a;
    if (!(alpha > 0.0))
        return Rgba{0.0f, 0.0f, 0.0f, 0.0f};
    const double over = T * bg.a;
    return Rgba{float((r + over * bg.r) / alpha), float((g + over * bg.g) / alpha),
                float((b + over * bg.b) / alpha), float(alpha)};
}

template <typename GridT>
double VolumeRenderer<GridT>::opticalDepth(const RayType& wRay) {
    const RayType ray = wRay.worldToIndex(mGrid->transform());
    const double sigma = mSettings.extinction * worldLength(ray.dir());
    double depth = 0.0;
    mPrimary.march(ray, mSettings.step, [&](const Vec3d&, const Coord*, double d, double ds) {
        depth += sigma * d * ds;
        return true;
    });
    return depth;
}

template <typename GridT>
Image renderFogVolume(const GridT& grid, const Camera& camera,
                      const VolumeRenderSettings& settings) {
    const VolumeRenderer<GridT> prototype(grid, settings, camera.width() * camera.height());
    Image image(camera.width(), camera.height());
    detail::forEachPixelInTiles(
        camera.width(), camera.height(), settings.tileSize, settings.threaded,
        [&] { return prototype; },
        [&](size_t x, size_t y, VolumeRenderer<GridT>& renderer) {
            image(x, y) = renderer.shade(camera.ray(double(x) + 0.5, double(y) + 0.5));
        });
    return image;
}

template <typename GridT>
double suggestExtinction(const GridT& grid, const Camera& camera, double opticalDepth,
                         double quantile, size_t probes, bool threaded) {
    if (!(std::isfinite(opticalDepth) && opticalDepth > 0.0))
        throw ValueError("suggestExtinction: the optical depth must be positive and finite");
    if (!(quantile > 0.0 && quantile <= 1.0))
        throw ValueError("suggestExtinction: the quantile must lie in (0, 1]");
    if (probes == 0)
        throw ValueError("suggestExtinction: at least one probe ray is needed");
    VolumeRenderSettings settings;
    settings.extinction = 1.0;  // the optical depth is then the density integral
    settings.shadows = false;
    settings.threaded = threaded;
    const VolumeRenderer<GridT> prototype(grid, settings);
    const size_t nx = std::min(probes, camera.width()), ny = std::min(probes, camera.height());
    std::vector<double> depth(nx * ny, 0.0);
    util::parallelFor(
        ny,
        [&](size_t j) {
            VolumeRenderer<GridT> renderer(prototype);
            const double y = (double(j) + 0.5) * double(camera.height()) / double(ny);
            for (size_t i = 0; i < nx; ++i) {
                const double x = (double(i) + 0.5) * double(camera.width()) / double(nx);
                depth[j * nx + i] = renderer.opticalDepth(camera.ray(x, y));
            }
        },
        threaded, /*grain=*/1);
    std::vector<double> hits;
    for (double d : depth)
        if (d > 0.0 && std::isfinite(d))
            hits.push_back(d);
    if (hits.empty())
        return 0.0;
    // The smallest depth that at least `quantile` of the hits do not exceed.
    const double rank = std::ceil(quantile * double(hits.size()));
    const size_t k = std::min(hits.size(), size_t(std::max(1.0, rank))) - 1;
    std::nth_element(hits.begin(), hits.begin() + std::ptrdiff_t(k), hits.end());
    return opticalDepth / hits[k];
}

}  // namespace vdb::render
