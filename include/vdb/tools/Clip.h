// SPDX-License-Identifier: Apache-2.0
/// @file
/// Clipping a grid to a world-space box, a camera frustum or the active voxels of a mask grid,
/// with the names and rules of OpenVDB 10's tools/Clip.h. Each call returns a new grid (a copy
/// of the input's transform and metadata around a new tree); the input is not changed.
///
/// Box and mask. The region kept is a set of voxels of the grid's index space:
/// - clip(grid, worldBox): the voxels from floor(lo) to floor(hi), where [lo, hi] is the
///   index-space bounding box of the eight corners of `worldBox` (OpenVDB's convention: a
///   voxel whose center lies just below the box's lower faces is kept).
/// - clip(grid, mask): the active voxels and tiles of `mask`, any grid type. When the mask's
///   transform differs from the grid's, the mask is resampled first: a voxel of the grid is in
///   the region when the mask voxel holding its center (floor of the mapped index position) is
///   active, as OpenVDB's resampleToMatch with its nearest-voxel "BoolSampler" does.
/// The voxels that can survive are the grid's active voxels and tiles and, for a level set
/// (GRID_LEVEL_SET), also its inactive voxels and internal-node tiles with a negative value
/// (the inside). With keepInterior those inside the region keep their value and state, with
/// keepInterior false those outside it do; everything else becomes the background, inactive
/// (so inactive values of a fog volume are not kept). The grid class is kept.
///
/// Frustum. clip(grid, frustum) takes a transform of map type NonlinearFrustum: a voxel is
/// inside when its center, mapped to the frustum's index space, lies within the frustum's
/// index box (within 1e-15, as OpenVDB's BBoxd::isInside). Every value of the grid, active or
/// inactive, keeps its value and state where `inside == keepInterior` and becomes the
/// inactive background elsewhere. A level set's class becomes GRID_UNKNOWN, since a cut
/// level set has no inside.
///
/// Cost: box and mask clips do topology operations on masks, then copy the kept leaves in
/// parallel; resampling a mask costs one transform per grid voxel near the mask. The frustum
/// clip sorts tiles and leaves by the frustum-space bounds of their corners and evaluates the
/// map per voxel only for nodes that straddle the frustum's faces, leaves in parallel. Results
/// do not depend on the thread count.
///
/// @code
/// auto box = vdb::tools::clip(*grid, vdb::BBoxd({-1, -1, -1}, {1, 1, 1}));
/// auto outside = vdb::tools::clip(*grid, *maskGrid, /*keepInterior=*/false);
/// auto seen = vdb::tools::clip(*grid, *camera->frustumTransform());
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/detail/LeafPairs.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

/// `threaded` (ours, not OpenVDB's) runs the work serially when false; results are identical.

/// Returns a copy of `grid` clipped to the world-space box `worldBox` (keepInterior) or to its
/// exterior. An empty box keeps nothing (or everything, with keepInterior false).
/// @throw ValueError when a corner of the box is not finite.
template <VdbTree TreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const BBoxd& worldBox,
                               bool keepInterior = true, bool threaded = true);

/// Returns a copy of `grid` clipped to the frustum of `frustum` (keepInterior) or to its
/// exterior. @throw ValueError when `frustum` is not a NonlinearFrustum transform.
template <VdbTree TreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const math::Transform& frustum,
                               bool keepInterior = true, bool threaded = true);

/// Returns a copy of `grid` clipped to the active voxels and tiles of `mask` (keepInterior) or
/// to the rest of space. The mask may be of any value type and any transform.
template <VdbTree TreeT, VdbTree MaskTreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const Grid<MaskTreeT>& mask,
                               bool keepInterior = true, bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// The region of space a tree's top node has entries for (a bounded tree: its domain).
template <typename TreeT>
CoordBBox storedExtent(const TreeT& tree) {
    using TopT = typename TreeT::TopNodeType;
    if constexpr (TreeT::BOUNDED) {
        return TreeT::domain();
    } else {
        CoordBBox bbox;
        const TopT& root = tree.root();
        for (auto c = root.cbegin(); root.valid(c); root.next(c))
            bbox.expand(CoordBBox::createCube(root.key(c), Int32(TopT::ChildNodeType::DIM)));
        return bbox;
    }
}

/// The edge, in voxels, of a tile at `level` of a tree of type TreeT (level 1: a leaf's).
template <typename TreeT>
Int32 tileDim(Index level) {
    using TopT = typename TreeT::TopNodeType;
    Int32 dim = 1;
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        ((level == L + 1 ? (dim = Int32(tree::NodeAtLevelT<TopT, L>::DIM), 0) : 0), ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL>{});
    return dim;
}

/// The voxels of `tree` that a box or mask clip can keep, as a mask tree of the same layout:
/// the active topology and, for a level set, the inactive voxels and internal-node tiles with
/// a negative value.
template <typename TreeT, typename MaskTreeT>
MaskTreeT clipCandidates(const TreeT& tree, bool levelSet, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    MaskTreeT candidates(false);
    candidates.topologyUnion(tree);
    if constexpr (std::is_signed_v<ValueT> || std::is_floating_point_v<ValueT>) {
        if (!levelSet)
            return candidates;
        // Inside tiles below the root.
        tree::visitTiles<ValueFilter::Off>(tree.topNode(), [&](const auto& tile) {
            if (tile.level < TreeT::TopNodeType::LEVEL || TreeT::BOUNDED) {
                if (tile.value < ValueT(0))
                    candidates.addTile(tile.level, tile.origin, true, true);
            }
        });
        // Inside voxels of the leaves.
        forEachLeafPair(
            tree, candidates,
            [](const auto& from, auto& to) {
                for (Index n = 0; n < std::remove_cvref_t<decltype(from)>::NUM_VALUES; ++n) {
                    if (from.getValue(n) < ValueT(0))
                        to.setValueOn(n);
                }
            },
            threaded);
    } else {
        (void)levelSet;
        (void)threaded;
    }
    return candidates;
}

/// A new tree holding the values and states of `tree` at the active voxels and tiles of
/// `keep`, and the inactive background everywhere else.
template <typename TreeT, typename MaskTreeT>
std::shared_ptr<TreeT> copyKept(const TreeT& tree, const MaskTreeT& keep, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using MaskLeafT = typename MaskTreeT::LeafNodeType;
    auto out = std::make_shared<TreeT>(tree.background());
    // Tiles: the tree is constant over each tile of `keep`.
    tree::visitTiles<ValueFilter::On>(keep.topNode(), [&](const auto& tile) {
        ValueT value;
        const bool active = tree.probeValue(tile.origin, value);
        out->addTile(tile.level, tile.origin, value, active);
    });
    // Leaves, built in parallel and linked serially.
    std::vector<const MaskLeafT*> masks;
    for (auto leaf = keep.cbeginLeaf(); leaf; ++leaf) {
        if (!leaf->isEmpty())
            masks.push_back(leaf.getLeaf());
    }
    std::vector<std::unique_ptr<LeafT>> leaves(masks.size());
    util::parallelFor(
        masks.size(),
        [&](size_t i) {
            const MaskLeafT& mask = *masks[i];
            auto leaf = std::make_unique<LeafT>(mask.origin(), tree.background(), false);
            if (const LeafT* from = tree.probeConstLeaf(mask.origin())) {
                for (Index n : mask.getValueMask().onBits()) {
                    leaf->setValueOnly(n, from->getValue(n));
                    leaf->setActiveState(n, from->isValueOn(n));
                }
            } else {
                ValueT value;
                const bool active = tree.probeValue(mask.origin(), value);
                for (Index n : mask.getValueMask().onBits()) {
                    leaf->setValueOnly(n, value);
                    leaf->setActiveState(n, active);
                }
            }
            leaves[i] = std::move(leaf);
        },
        threaded, 8);
    for (auto& leaf : leaves)
        out->addLeaf(std::move(leaf));
    return out;
}

/// The box or mask clip once the region is a mask tree in the grid's index space.
template <typename TreeT, typename MaskTreeT>
typename Grid<TreeT>::Ptr clipToRegion(const Grid<TreeT>& grid, const MaskTreeT& region,
                                       bool keepInterior, bool threaded) {
    MaskTreeT keep = clipCandidates<TreeT, MaskTreeT>(
        grid.tree(), grid.getGridClass() == GRID_LEVEL_SET, threaded);
    if (keepInterior) {
        keep.topologyIntersection(region);
    } else {
        keep.topologyDifference(region);
    }
    auto out = grid.copy();
    out->setTree(copyKept(grid.tree(), keep, threaded));
    return out;
}

/// The active voxels of `mask` resampled into the index space `to`: a voxel is on when the
/// mask voxel holding its center is active. Only the leaves of `to` where `within` has
/// something active are computed.
template <typename OutMaskTreeT, typename MaskTreeT>
OutMaskTreeT resampleMask(const Grid<MaskTreeT>& mask, const math::Transform& to,
                          const OutMaskTreeT& within, bool threaded) {
    using OutLeafT = typename OutMaskTreeT::LeafNodeType;
    constexpr Int32 LEAF_DIM = Int32(OutLeafT::DIM);
    const math::Transform& from = mask.transform();
    const auto toIndex = [&](const Vec3d& maskIjk) {
        return to.worldToIndex(from.indexToWorld(maskIjk));
    };
    // The leaves of `to` near each active region of the mask.
    std::set<Coord> origins;
    const auto addRegion = [&](const CoordBBox& bbox) {
        BBoxd box;
        for (int i = 0; i < 8; ++i) {
            box.expand(toIndex(Vec3d(i & 1 ? bbox.max()[0] + 1.0 : bbox.min()[0],
                                     i & 2 ? bbox.max()[1] + 1.0 : bbox.min()[1],
                                     i & 4 ? bbox.max()[2] + 1.0 : bbox.min()[2])));
        }
        const Coord lo = math::floorToCoord(box.min() - Vec3d(1.0)).alignedDown(OutLeafT::LOG2DIM);
        const Coord hi = math::floorToCoord(box.max() + Vec3d(1.0));
        for (Int32 x = lo[0]; x <= hi[0]; x += LEAF_DIM) {
            for (Int32 y = lo[1]; y <= hi[1]; y += LEAF_DIM) {
                for (Int32 z = lo[2]; z <= hi[2]; z += LEAF_DIM) {
                    const Coord origin(x, y, z);
                    if (within.probeConstLeaf(origin) || within.isValueOn(origin))
                        origins.insert(origin);
                    if (z > hi[2] - LEAF_DIM)
                        break;
                }
                if (y > hi[1] - LEAF_DIM)
                    break;
            }
            if (x > hi[0] - LEAF_DIM)
                break;
        }
    };
    for (auto leaf = mask.tree().cbeginLeaf(); leaf; ++leaf) {
        if (!leaf->getValueMask().isOff())
            addRegion(leaf->getNodeBoundingBox());
    }
    tree::visitTiles<ValueFilter::On>(mask.tree().topNode(),
                                      [&](const auto& tile) { addRegion(tile.bbox()); });
    // Each leaf of `to`: one mapped lookup per voxel.
    std::vector<Coord> list(origins.begin(), origins.end());
    std::vector<std::unique_ptr<OutLeafT>> leaves(list.size());
    util::parallelFor(
        list.size(),
        [&](size_t i) {
            tree::ValueAccessor<const MaskTreeT> acc(mask.tree());
            auto leaf = std::make_unique<OutLeafT>(list[i]);
            for (Index n = 0; n < OutLeafT::NUM_VALUES; ++n) {
                const Vec3d ijk(leaf->offsetToGlobalCoord(n));
                if (acc.isValueOn(math::floorToCoord(from.worldToIndex(to.indexToWorld(ijk)))))
                    leaf->setValueOn(n);
            }
            leaves[i] = std::move(leaf);
        },
        threaded, 4);
    OutMaskTreeT result(false);
    for (auto& leaf : leaves) {
        if (!leaf->isEmpty())
            result.addLeaf(std::move(leaf));
    }
    return result;
}

/// The frustum-space bounds of the voxel centers of `bbox` (the bounds of its 8 corners; the
/// frustum map keeps lines straight, so they bound every voxel between).
inline BBoxd frustumBounds(const math::Transform& grid, const math::Transform& frustum,
                           const CoordBBox& bbox) {
    BBoxd out;
    for (int i = 0; i < 8; ++i) {
        const Vec3d ijk(i & 1 ? bbox.max()[0] : bbox.min()[0],
                        i & 2 ? bbox.max()[1] : bbox.min()[1],
                        i & 4 ? bbox.max()[2] : bbox.min()[2]);
        out.expand(frustum.worldToIndex(grid.indexToWorld(ijk)));
    }
    return out;
}

/// The frustum clip's per-voxel test and the box classifications built on it.
class FrustumTest {
public:
    FrustumTest(const math::Transform& grid, const math::Transform& frustum)
        : mGrid(grid), mFrustum(frustum), mBox(frustum.mapParams().frustumBBox) {}

    bool contains(const Coord& ijk) const {
        const Vec3d p = mFrustum.worldToIndex(mGrid.indexToWorld(Vec3d(ijk)));
        constexpr double t = 1e-15;
        return p[0] > mBox.min()[0] - t && p[0] < mBox.max()[0] + t && p[1] > mBox.min()[1] - t &&
               p[1] < mBox.max()[1] + t && p[2] > mBox.min()[2] - t && p[2] < mBox.max()[2] + t;
    }
    /// 1: every voxel of `bbox` is inside, -1: none is, 0: either may be.
    int classify(const CoordBBox& bbox) const {
        const BBoxd b = frustumBounds(mGrid, mFrustum, bbox);
        bool inside = true, outside = false;
        for (int i = 0; i < 3; ++i) {
            inside = inside && b.min()[i] > mBox.min()[i] && b.max()[i] < mBox.max()[i];
            outside =
                outside || b.max()[i] < mBox.min()[i] - 1e-9 || b.min()[i] > mBox.max()[i] + 1e-9;
        }
        return inside ? 1 : outside ? -1 : 0;
    }

private:
    const math::Transform& mGrid;
    const math::Transform& mFrustum;
    BBoxd mBox;
};

}  // namespace detail

template <VdbTree TreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const BBoxd& worldBox, bool keepInterior,
                               bool threaded) {
    using MaskTreeT = typename TreeT::template ValueConverter<ValueMask>::Type;
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(worldBox.min()[i]) || !std::isfinite(worldBox.max()[i]))
            throw ValueError("clip: the box's corners must be finite");
    }
    MaskTreeT region(false);
    if (!worldBox.empty()) {
        // Index-space bounds, clamped to the part of space the grid stores anything in.
        BBoxd box = grid.transform().worldToIndex(worldBox);
        const CoordBBox extent = detail::storedExtent(grid.tree());
        if (!extent.empty()) {
            const Vec3d lo(extent.min()), hi(extent.max());
            box = BBoxd(Vec3d::maxComponent(box.min(), lo), Vec3d::minComponent(box.max(), hi));
            if (!box.empty())
                region.fill(CoordBBox(math::floorToCoord(box.min()), math::floorToCoord(box.max())),
                            true, true);
        }
    }
    return detail::clipToRegion(grid, region, keepInterior, threaded);
}

template <VdbTree TreeT, VdbTree MaskTreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const Grid<MaskTreeT>& mask,
                               bool keepInterior, bool threaded) {
    using RegionTreeT = typename TreeT::template ValueConverter<ValueMask>::Type;
    if (grid.transform() == mask.transform()) {
        RegionTreeT region(false);
        region.topologyUnion(mask.tree());
        return detail::clipToRegion(grid, region, keepInterior, threaded);
    }
    const RegionTreeT candidates = detail::clipCandidates<TreeT, RegionTreeT>(
        grid.tree(), grid.getGridClass() == GRID_LEVEL_SET, threaded);
    const RegionTreeT region = detail::resampleMask(mask, grid.transform(), candidates, threaded);
    return detail::clipToRegion(grid, region, keepInterior, threaded);
}

template <VdbTree TreeT>
typename Grid<TreeT>::Ptr clip(const Grid<TreeT>& grid, const math::Transform& frustum,
                               bool keepInterior, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    if (frustum.mapType() != math::MapType::NonlinearFrustum)
        throw ValueError("clip: the frustum must be a NonlinearFrustum transform");
    const TreeT& tree = grid.tree();
    const ValueT background = tree.background();
    const detail::FrustumTest test(grid.transform(), frustum);
    const int keep = keepInterior ? 1 : -1;
    auto out = std::make_shared<TreeT>(background);

    // Leaves to build voxel by voxel: (origin, source leaf or null for a tile value).
    struct Partial {
        Coord origin;
        const LeafT* leaf;
        ValueT value;
        bool active;
    };
    std::vector<Partial> partial;

    // Tiles: kept whole, dropped whole, or split down to the leaves that straddle a face.
    const auto tileDim = [](Index level) { return detail::tileDim<TreeT>(level); };
    const auto splitTile = [&](const auto& self, Index level, const Coord& origin,
                               const ValueT& value, bool active) -> void {
        const CoordBBox bbox = CoordBBox::createCube(origin, tileDim(level));
        const int c = test.classify(bbox);
        if (c == keep) {
            out->addTile(level, origin, value, active);
        } else if (c == 0) {
            if (level == 1) {
                partial.push_back({origin, nullptr, value, active});
            } else {
                const Int32 sub = tileDim(level - 1);
                for (Int32 x = 0; x < tileDim(level); x += sub)
                    for (Int32 y = 0; y < tileDim(level); y += sub)
                        for (Int32 z = 0; z < tileDim(level); z += sub)
                            self(self, level - 1, origin.offsetBy(x, y, z), value, active);
            }
        }
    };
    tree::visitTiles<ValueFilter::All>(tree.topNode(), [&](const auto& tile) {
        if (tile.active || !math::isApproxEqual(tile.value, background))
            splitTile(splitTile, tile.level, tile.origin, tile.value, tile.active);
    });
    // Leaves: copied whole when inside, voxel by voxel when straddling.
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const int c = test.classify(leaf->getNodeBoundingBox());
        if (c == keep) {
            out->addLeaf(std::make_unique<LeafT>(*leaf));
        } else if (c == 0) {
            partial.push_back({leaf->origin(), leaf.getLeaf(), ValueT{}, false});
        }
    }
    std::vector<std::unique_ptr<LeafT>> leaves(partial.size());
    util::parallelFor(
        partial.size(),
        [&](size_t i) {
            const Partial& p = partial[i];
            auto leaf = std::make_unique<LeafT>(p.origin, background, false);
            for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                if (test.contains(leaf->offsetToGlobalCoord(n)) != keepInterior)
                    continue;
                leaf->setValueOnly(n, p.leaf ? p.leaf->getValue(n) : p.value);
                leaf->setActiveState(n, p.leaf ? p.leaf->isValueOn(n) : p.active);
            }
            leaves[i] = std::move(leaf);
        },
        threaded, 4);
    for (auto& leaf : leaves)
        out->addLeaf(std::move(leaf));

    auto result = grid.copy();
    result->setTree(out);
    if (result->getGridClass() == GRID_LEVEL_SET)
        result->setGridClass(GRID_UNKNOWN);
    return result;
}

}  // namespace vdb::tools
