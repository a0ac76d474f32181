// SPDX-License-Identifier: Apache-2.0
/// @file
/// The implementation of tools/LevelSetUtil.h (not API): leaf-parallel conversions, and the
/// floods over leaf-sized bit masks behind the enclosed region and the segmentations.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Math.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/Statistics.h>
#include <vdb/tools/detail/LeafBuild.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace vdb::tools::detail {

// ---- Shared pieces ----------------------------------------------------------------------------

/// A new grid of type OutGridT around `tree` with `like`'s transform (and metadata when
/// `withMetadata`).
template <typename OutGridT, typename InGridT>
typename OutGridT::Ptr gridLike(const InGridT& like,
                                std::shared_ptr<typename OutGridT::TreeType> tree,
                                bool withMetadata) {
    auto grid = OutGridT::create(std::move(tree));
    if (withMetadata) {
        for (const auto& [name, value] : like.metadata())
            grid->insertMeta(name, value);
    }
    grid->setTransform(like.transform().copy());
    return grid;
}

/// The deepest (smallest) value of a signed distance field: the smallest tile value, or when
/// no tile is negative, the smallest voxel value.
template <typename TreeT>
typename TreeT::ValueType deepestValue(const TreeT& tree, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    ValueT deepest = std::numeric_limits<ValueT>::max();
    tree::visitTiles<ValueFilter::All>(
        tree.topNode(), [&](const auto& tile) { deepest = std::min(deepest, tile.value); });
    if (deepest > ValueT(0)) {
        const tree::LeafManager<const TreeT> leaves(tree);
        deepest =
            std::min(deepest, util::parallelReduce(
                                  leaves.leafCount(), std::numeric_limits<ValueT>::max(),
                                  [&](size_t begin, size_t end) {
                                      ValueT m = std::numeric_limits<ValueT>::max();
                                      for (size_t i = begin; i < end; ++i) {
                                          for (const ValueT& v : leaves.leaf(i).buffer(0))
                                              m = std::min(m, v);
                                      }
                                      return m;
                                  },
                                  [](ValueT a, ValueT b) { return std::min(a, b); }, threaded));
    }
    return deepest;
}

/// Makes one output leaf per leaf of `in` with `make(inLeaf)` (null to skip), in parallel, and
/// returns them in the order of the input's leaves.
template <typename OutLeafT, typename InTreeT, typename MakeT>
std::vector<std::unique_ptr<OutLeafT>> mapLeaves(const InTreeT& in, const MakeT& make,
                                                 bool threaded) {
    const tree::LeafManager<const InTreeT> leaves(in);
    std::vector<std::unique_ptr<OutLeafT>> out(leaves.leafCount());
    util::parallelFor(
        leaves.leafCount(), [&](size_t i) { out[i] = make(leaves.leaf(i)); }, threaded, 8);
    return out;
}

/// A bool leaf at `origin`, active and true where `bits` are on; null when none is.
template <typename BoolLeafT, typename MaskT>
std::unique_ptr<BoolLeafT> boolLeafFrom(const Coord& origin, const MaskT& bits) {
    if (bits.isOff())
        return nullptr;
    auto leaf = std::make_unique<BoolLeafT>(origin, false, false);
    for (Index n : bits.onBits())
        leaf->setValueOn(n, true);
    return leaf;
}

/// Floods `region` within one leaf: grows it through face neighbours inside `open` until it
/// stops changing. @pre region is inside open
template <Index Log2Dim, typename MaskT>
void floodInLeaf(MaskT& region, const MaskT& open) {
    using Ops = LeafMaskOps<Log2Dim>;
    static constexpr typename Ops::Word zero[Ops::WORDS] = {};
    MaskT next;
    for (;;) {
        const auto* e = region.words();
        auto* out = next.words();
        for (Index w = 0; w < Ops::WORDS; ++w) {
            out[w] = (Ops::template dilateWord<0>(e, zero, zero, w) |
                      Ops::template dilateWord<1>(e, zero, zero, w) |
                      Ops::template dilateWord<2>(e, zero, zero, w)) &
                     open.words()[w];
        }
        if (next == region)
            return;
        region = next;
    }
}

/// The voxels of a leaf (mask `bits`) that the face neighbours beyond its faces reach:
/// `prev[a]` and `next[a]` are the masks of the leaves at -DIM and +DIM along axis a (null where
/// there is none).
template <Index Log2Dim, typename MaskT>
MaskT reachedFromNeighbours(const std::array<const MaskT*, 3>& prev,
                            const std::array<const MaskT*, 3>& next) {
    using Ops = LeafMaskOps<Log2Dim>;
    static constexpr typename Ops::Word zero[Ops::WORDS] = {};
    MaskT in;
    auto* out = in.words();
    const auto words = [&](const MaskT* m) { return m ? m->words() : zero; };
    for (Index w = 0; w < Ops::WORDS; ++w) {
        typename Ops::Word below, above, word = 0;
        Ops::template neighbourWords<0>(zero, words(prev[0]), words(next[0]), w, below, above);
        word |= below | above;
        Ops::template neighbourWords<1>(zero, words(prev[1]), words(next[1]), w, below, above);
        word |= below | above;
        Ops::template neighbourWords<2>(zero, words(prev[2]), words(next[2]), w, below, above);
        word |= below | above;
        out[w] = word;
    }
    return in;
}

/// Leaf-sized cells with bit masks, and which cell lies next to which.
template <typename MaskT>
struct CellGraph {
    std::vector<Coord> origins;
    std::unordered_map<Coord, size_t> index;
    /// neighbours[c][2 a + s]: the cell at -DIM (s = 0) or +DIM (s = 1) along axis a, or NONE.
    std::vector<std::array<size_t, 6>> neighbours;
    static constexpr size_t NONE = ~size_t(0);

    void add(const Coord& origin) {
        index.emplace(origin, origins.size());
        origins.push_back(origin);
    }
    void link(Int32 dim) {
        neighbours.assign(origins.size(), {});
        for (size_t c = 0; c < origins.size(); ++c) {
            for (int a = 0; a < 3; ++a) {
                for (int s = 0; s < 2; ++s) {
                    Coord o = origins[c];
                    o[size_t(a)] += s ? dim : -dim;
                    const auto it = index.find(o);
                    neighbours[c][size_t(2 * a + s)] = it == index.end() ? NONE : it->second;
                }
            }
        }
    }
};

// ---- sdfToFogVolume ---------------------------------------------------------------------------

template <typename GridT>
void sdfToFogVolume(GridT& grid, typename GridT::ValueType cutoff) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    static_assert(std::is_floating_point_v<ValueT>, "sdfToFogVolume needs a floating-point grid");
    if (!(cutoff == cutoff))
        throw ValueError("sdfToFogVolume: the cutoff distance is not a number");
    TreeT& tree = grid.tree();
    // The ramp ends at the cutoff, or at the deepest value when the grid holds none deeper.
    cutoff = std::max(deepestValue(tree, true), ValueT(-std::abs(cutoff)));
    if (!(cutoff < ValueT(0))) {
        grid.setTree(std::make_shared<TreeT>(ValueT(0)));
    } else {
        // In place, as the values and states of the same nodes: leaves first, then tiles.
        const ValueT weight = ValueT(1) / cutoff;
        tree::LeafManager<TreeT> leaves(tree);
        leaves.foreach (
            [weight](LeafT& leaf, size_t) {
                ValueT* v = leaf.buffer(0).data();
                uint8_t on[LeafT::NUM_VALUES];  // loops without branches: they vectorise
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                    v[n] = v[n] > ValueT(0) ? ValueT(0) : std::min(v[n] * weight, ValueT(1));
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                    on[n] = uint8_t(v[n] > ValueT(0));
                leaf.getValueMask().setFromBytes(on);
            },
            true);
        forEachTile(
            tree,
            [](ValueT& value, bool& active) {
                active = value < ValueT(0);
                value = active ? ValueT(1) : ValueT(0);
            },
            true);
        tree.setBackground(ValueT(0));
        // Leaves wholly outside the surface are now inactive zeros: the background.
        pruneInactive(tree);
    }
    grid.setGridClass(GRID_FOG_VOLUME);
}

// ---- Masks ------------------------------------------------------------------------------------

template <typename GridT>
auto sdfInteriorMask(const GridT& grid, typename GridT::ValueType iso) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using BoolGridT = typename GridT::template ValueConverter<bool>::Type;
    using BoolTreeT = typename BoolGridT::TreeType;
    using BoolLeafT = typename BoolTreeT::LeafNodeType;
    // Every value of a narrow band lies at or below the background: an isovalue above it
    // would make the mask infinite.
    iso = std::min(iso, ValueT(grid.background() - math::Tolerance<ValueT>::value()));
    auto leaves = mapLeaves<BoolLeafT>(
        grid.tree(),
        [&](const typename TreeT::LeafNodeType& leaf) {
            typename BoolLeafT::MaskType bits;
            const ValueT* v = leaf.buffer(0).data();
            for (Index n = 0; n < BoolLeafT::NUM_VALUES; ++n) {
                if (v[n] < iso)
                    bits.setOn(n);
            }
            return boolLeafFrom<BoolLeafT>(leaf.origin(), bits);
        },
        true);
    auto mask = std::make_shared<BoolTreeT>(false);
    linkLeaves(*mask, leaves, true);
    tree::visitTiles<ValueFilter::All>(grid.tree().topNode(), [&](const auto& tile) {
        if (tile.value < iso)
            mask->fill(tile.bbox(), true, true);
    });
    return gridLike<BoolGridT>(grid, mask, false);
}

template <typename GridT>
auto extractIsosurfaceMask(const GridT& grid, typename GridT::ValueType iso) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using BoolGridT = typename GridT::template ValueConverter<bool>::Type;
    using BoolTreeT = typename BoolGridT::TreeType;
    using BoolLeafT = typename BoolTreeT::LeafNodeType;
    const tree::LeafManager<const TreeT> leaves(grid.tree());
    std::vector<std::unique_ptr<BoolLeafT>> out(leaves.leafCount());
    util::parallelForRange(
        leaves.leafCount(),
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const TreeT> acc(grid.tree());
            NeighborhoodBlock<TreeT> block(Coord(1), BlockShape::Cross);
            for (size_t i = begin; i < end; ++i) {
                const LeafT& leaf = leaves.leaf(i);
                if (leaf.isEmpty())
                    continue;
                block.gather(leaf.origin(), &leaf, 0, acc);
                const int sx = block.sx(), sy = block.sy();
                typename BoolLeafT::MaskType bits;
                for (Index n : leaf.getValueMask().onBits()) {
                    const ValueT* c = block.atOffset(n);
                    const bool under = *c < iso;
                    if ((c[1] < iso) != under || (c[-1] < iso) != under || (c[sy] < iso) != under ||
                        (c[-sy] < iso) != under || (c[sx] < iso) != under ||
                        (c[-sx] < iso) != under)
                        bits.setOn(n);
                }
                out[i] = boolLeafFrom<BoolLeafT>(leaf.origin(), bits);
            }
        },
        true, 8);
    auto mask = std::make_shared<BoolTreeT>(false);
    linkLeaves(*mask, out, true);
    return gridLike<BoolGridT>(grid, mask, false);
}

// ---- Enclosed regions -------------------------------------------------------------------------

template <typename GridT, typename BoolTreeT>
auto extractEnclosedRegion(const GridT& grid, typename GridT::ValueType iso,
                           const BoolTreeT* fillMask) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using MaskT = typename LeafT::MaskType;
    using BoolGridT = typename GridT::template ValueConverter<bool>::Type;
    using BoolLeafT = typename BoolTreeT::LeafNodeType;
    constexpr Int32 DIM = Int32(LeafT::DIM);
    const TreeT& in = grid.tree();
    const tree::LeafManager<const TreeT> leaves(in);
    const size_t n = leaves.leafCount();

    // Per leaf: the open voxels (>= iso) and the exterior seeds among them.
    CellGraph<MaskT> cells;
    for (size_t i = 0; i < n; ++i)
        cells.add(leaves.leaf(i).origin());
    cells.link(DIM);
    std::vector<MaskT> open(n), exterior(n);
    util::parallelForRange(
        n,
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const TreeT> acc(in);
            std::unique_ptr<tree::ValueAccessor<const BoolTreeT>> fillAcc;
            if (fillMask)
                fillAcc = std::make_unique<tree::ValueAccessor<const BoolTreeT>>(*fillMask);
            for (size_t i = begin; i < end; ++i) {
                const LeafT& leaf = leaves.leaf(i);
                const ValueT* v = leaf.buffer(0).data();
                for (Index k = 0; k < LeafT::NUM_VALUES; ++k) {
                    if (!(v[k] < iso))
                        open[i].setOn(k);
                }
                // Faces towards a tile or the background at or above the isovalue are open to
                // the outside.
                std::array<const MaskT*, 3> prev{}, next{};
                MaskT all(true);
                for (int a = 0; a < 3; ++a) {
                    for (int s = 0; s < 2; ++s) {
                        if (cells.neighbours[i][size_t(2 * a + s)] != cells.NONE)
                            continue;
                        Coord o = leaf.origin();
                        o[size_t(a)] += s ? DIM : -DIM;
                        if (!(acc.getValue(o) < iso))
                            (s ? next : prev)[size_t(a)] = &all;
                    }
                }
                MaskT seeds = reachedFromNeighbours<LeafT::LOG2DIM>(prev, next);
                // With a fill mask, open voxels outside it are exterior too.
                if (fillAcc) {
                    MaskT outside(true);
                    if (const BoolLeafT* f = fillAcc->probeConstLeaf(leaf.origin()))
                        outside -= f->getValueMask();
                    else if (fillAcc->isValueOn(leaf.origin()))
                        outside.setOff();
                    seeds |= outside;
                }
                seeds &= open[i];
                floodInLeaf<LeafT::LOG2DIM>(seeds, open[i]);
                exterior[i] = seeds;
            }
        },
        true, 16);

    // Spread the exterior across leaf faces until nothing changes (a work list of leaves).
    std::deque<size_t> queue;
    std::vector<char> queued(n, 0);
    for (size_t i = 0; i < n; ++i) {
        if (!exterior[i].isOff()) {
            for (size_t nb : cells.neighbours[i]) {
                if (nb != cells.NONE && !queued[nb]) {
                    queued[nb] = 1;
                    queue.push_back(nb);
                }
            }
        }
    }
    while (!queue.empty()) {
        const size_t i = queue.front();
        queue.pop_front();
        queued[i] = 0;
        std::array<const MaskT*, 3> prev{}, next{};
        for (int a = 0; a < 3; ++a) {
            const size_t p = cells.neighbours[i][size_t(2 * a)],
                         q = cells.neighbours[i][size_t(2 * a + 1)];
            prev[size_t(a)] = p == cells.NONE ? nullptr : &exterior[p];
            next[size_t(a)] = q == cells.NONE ? nullptr : &exterior[q];
        }
        MaskT grown = reachedFromNeighbours<LeafT::LOG2DIM>(prev, next);
        grown &= open[i];
        grown |= exterior[i];
        if (grown == exterior[i])
            continue;
        floodInLeaf<LeafT::LOG2DIM>(grown, open[i]);
        exterior[i] = grown;
        for (size_t nb : cells.neighbours[i]) {
            if (nb != cells.NONE && !queued[nb]) {
                queued[nb] = 1;
                queue.push_back(nb);
            }
        }
    }

    // The mask: every leaf voxel not exterior, and every tile below the isovalue.
    std::vector<std::unique_ptr<BoolLeafT>> out(n);
    util::parallelFor(
        n,
        [&](size_t i) {
            MaskT inside(true);
            inside -= exterior[i];
            out[i] = boolLeafFrom<BoolLeafT>(cells.origins[i], inside);
        },
        true, 16);
    auto mask = std::make_shared<BoolTreeT>(false);
    linkLeaves(*mask, out, true);
    tree::visitTiles<ValueFilter::All>(in.topNode(), [&](const auto& tile) {
        if (tile.value < iso)
            mask->fill(tile.bbox(), true, true);
    });
    return gridLike<BoolGridT>(grid, mask, false);
}

// ---- Connected components of active voxels ----------------------------------------------------

/// The face-connected components of the active voxels of a tree, on leaf-sized cells: the
/// tree's leaves and the cells of its active tiles.
template <typename TreeT>
struct ActiveComponents {
    using LeafT = typename TreeT::LeafNodeType;
    using MaskT = typename LeafT::MaskType;
    static constexpr Int32 DIM = Int32(LeafT::DIM);

    struct Cell {
        Coord origin;
        const LeafT* leaf;  // null: a cell of an active tile
        CoordBBox tile;     // the tile, for a tile cell
    };
    struct Segment {
        size_t cell;
        MaskT bits;
    };

    std::vector<Cell> cellList;
    std::vector<Segment> segments;
    /// components[c]: the segments of component c (ascending), largest component first.
    std::vector<std::vector<size_t>> components;

    explicit ActiveComponents(const TreeT& tree) {
        const tree::LeafManager<const TreeT> leaves(tree);
        CellGraph<MaskT> cells;
        for (size_t i = 0; i < leaves.leafCount(); ++i) {
            if (leaves.leaf(i).isEmpty())
                continue;
            cellList.push_back({leaves.leaf(i).origin(), &leaves.leaf(i), CoordBBox()});
            cells.add(leaves.leaf(i).origin());
        }
        tree::visitTiles<ValueFilter::On>(tree.topNode(), [&](const auto& tile) {
            const CoordBBox box = tile.bbox();
            for (Int32 x = box.min()[0]; x <= box.max()[0]; x += DIM)
                for (Int32 y = box.min()[1]; y <= box.max()[1]; y += DIM)
                    for (Int32 z = box.min()[2]; z <= box.max()[2]; z += DIM) {
                        cellList.push_back({Coord(x, y, z), nullptr, box});
                        cells.add(Coord(x, y, z));
                    }
        });
        cells.link(DIM);

        // Split each cell's active voxels into face-connected segments.
        std::vector<std::vector<MaskT>> perCell(cellList.size());
        util::parallelFor(
            cellList.size(),
            [&](size_t c) {
                MaskT rest = cellList[c].leaf ? cellList[c].leaf->getValueMask() : MaskT(true);
                while (!rest.isOff()) {
                    MaskT seg;
                    seg.setOn(rest.findFirstOn());
                    floodInLeaf<LeafT::LOG2DIM>(seg, rest);
                    rest -= seg;
                    perCell[c].push_back(seg);
                }
            },
            true, 16);
        std::vector<size_t> firstSegment(cellList.size() + 1, 0);
        for (size_t c = 0; c < cellList.size(); ++c) {
            firstSegment[c + 1] = firstSegment[c] + perCell[c].size();
            for (MaskT& bits : perCell[c])
                segments.push_back({c, bits});
        }

        // Join segments that touch across a cell face (union-find).
        std::vector<size_t> parent(segments.size());
        std::iota(parent.begin(), parent.end(), size_t(0));
        const auto find = [&](size_t s) {
            while (parent[s] != s)
                s = parent[s] = parent[parent[s]];
            return s;
        };
        for (size_t c = 0; c < cellList.size(); ++c) {
            for (int a = 0; a < 3; ++a) {
                const size_t d = cells.neighbours[c][size_t(2 * a + 1)];
                if (d == cells.NONE)
                    continue;
                for (size_t s = firstSegment[c]; s < firstSegment[c + 1]; ++s) {
                    // The voxels of cell d next to segment s's voxels on the high face.
                    std::array<const MaskT*, 3> prev{}, next{};
                    prev[size_t(a)] = &segments[s].bits;
                    const MaskT reach = reachedFromNeighbours<LeafT::LOG2DIM>(prev, next);
                    for (size_t t = firstSegment[d]; t < firstSegment[d + 1]; ++t) {
                        MaskT touch = reach;
                        touch &= segments[t].bits;
                        if (!touch.isOff())
                            parent[find(s)] = find(t);
                    }
                }
            }
        }

        // Group by root; largest first, ties by the first segment.
        std::unordered_map<size_t, size_t> group;
        for (size_t s = 0; s < segments.size(); ++s) {
            const size_t r = find(s);
            auto it = group.find(r);
            if (it == group.end()) {
                it = group.emplace(r, components.size()).first;
                components.emplace_back();
            }
            components[it->second].push_back(s);
        }
        std::vector<Index64> counts(components.size(), 0);
        for (size_t c = 0; c < components.size(); ++c)
            for (size_t s : components[c])
                counts[c] += segments[s].bits.countOn();
        std::vector<size_t> order(components.size());
        std::iota(order.begin(), order.end(), size_t(0));
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t x, size_t y) { return counts[x] > counts[y]; });
        std::vector<std::vector<size_t>> sorted;
        sorted.reserve(order.size());
        for (size_t c : order)
            sorted.push_back(std::move(components[c]));
        components = std::move(sorted);
    }

    /// The voxels of component `c` in cell `cell`'s segments, as (cell, bits), cell by cell.
    std::vector<std::pair<size_t, MaskT>> cellsOf(size_t c) const {
        std::vector<std::pair<size_t, MaskT>> out;
        for (size_t s : components[c]) {
            if (!out.empty() && out.back().first == segments[s].cell)
                out.back().second |= segments[s].bits;
            else
                out.emplace_back(segments[s].cell, segments[s].bits);
        }
        return out;
    }
};

template <typename GridT>
void extractActiveVoxelSegmentMasks(
    const GridT& grid,
    std::vector<typename GridT::template ValueConverter<bool>::Type::Ptr>& masks) {
    using BoolGridT = typename GridT::template ValueConverter<bool>::Type;
    using BoolTreeT = typename BoolGridT::TreeType;
    using BoolLeafT = typename BoolTreeT::LeafNodeType;
    const ActiveComponents<typename GridT::TreeType> comps(grid.tree());
    std::vector<typename BoolGridT::Ptr> out(comps.components.size());
    util::parallelFor(
        out.size(),
        [&](size_t c) {
            std::vector<std::unique_ptr<BoolLeafT>> leaves;
            for (const auto& [cell, bits] : comps.cellsOf(c))
                leaves.push_back(boolLeafFrom<BoolLeafT>(comps.cellList[cell].origin, bits));
            auto mask = std::make_shared<BoolTreeT>(false);
            linkLeaves(*mask, leaves, false);
            out[c] = gridLike<BoolGridT>(grid, mask, false);
        },
        true, 1);
    masks.insert(masks.end(), out.begin(), out.end());
}

template <typename GridT>
void segmentActiveVoxels(const GridT& grid, std::vector<typename GridT::Ptr>& segments) {
    using TreeT = typename GridT::TreeType;
    using LeafT = typename TreeT::LeafNodeType;
    const TreeT& in = grid.tree();
    const ActiveComponents<TreeT> comps(in);
    if (comps.components.size() <= 1) {
        auto tree = comps.components.empty() ? std::make_shared<TreeT>(in.background())
                                             : std::make_shared<TreeT>(in);
        segments.push_back(gridLike<GridT>(grid, tree, true));
        return;
    }
    std::vector<typename GridT::Ptr> out(comps.components.size());
    util::parallelFor(
        out.size(),
        [&](size_t c) {
            std::vector<std::unique_ptr<LeafT>> leaves;
            std::vector<CoordBBox> tiles;
            for (const auto& [cell, bits] : comps.cellsOf(c)) {
                const auto& info = comps.cellList[cell];
                if (!info.leaf) {
                    if (tiles.empty() || !(tiles.back() == info.tile))
                        tiles.push_back(info.tile);
                    continue;
                }
                auto leaf = std::make_unique<LeafT>(info.origin, in.background(), false);
                const auto* src = info.leaf->buffer(0).data();
                for (Index n : bits.onBits())
                    leaf->setValueOn(n, src[n]);
                leaves.push_back(std::move(leaf));
            }
            auto tree = std::make_shared<TreeT>(in.background());
            linkLeaves(*tree, leaves, false);
            for (const CoordBBox& box : tiles)
                tree->fill(box, in.getValue(box.min()), true);
            out[c] = gridLike<GridT>(grid, tree, true);
        },
        true, 1);
    segments.insert(segments.end(), out.begin(), out.end());
}

// ---- Segments of a signed distance field ------------------------------------------------------

template <typename GridT>
void segmentSDF(const GridT& grid, std::vector<typename GridT::Ptr>& segments) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using BoolGridT = typename GridT::template ValueConverter<bool>::Type;
    using BoolTreeT = typename BoolGridT::TreeType;
    const TreeT& in = grid.tree();
    const auto surface = extractIsosurfaceMask(grid, ValueT(0));
    std::vector<typename BoolGridT::Ptr> masks;
    extractActiveVoxelSegmentMasks(*surface, masks);
    if (masks.empty()) {
        segments.push_back(gridLike<GridT>(grid, std::make_shared<TreeT>(in.background()), true));
        return;
    }
    const ValueT inside = -std::abs(deepestValue(in, true));
    const ValueT outside = std::abs(in.background());
    std::vector<typename GridT::Ptr> out(masks.size());
    util::parallelFor(
        masks.size(),
        [&](size_t c) {
            // Grow the surface voxels through the band, away from the surface.
            BoolTreeT& region = masks[c]->tree();
            tree::ValueAccessor<BoolTreeT> regionAcc(region);
            const tree::ValueAccessor<const TreeT> acc(in);
            std::vector<Coord> stack;
            for (auto it = region.cbeginValueOn(); it; ++it)
                stack.push_back(it.getCoord());
            while (!stack.empty()) {
                const Coord ijk = stack.back();
                stack.pop_back();
                const ValueT here = std::abs(acc.getValue(ijk));
                for (int a = 0; a < 3; ++a) {
                    for (int s = -1; s <= 1; s += 2) {
                        Coord nb = ijk;
                        nb[size_t(a)] += s;
                        ValueT v;
                        if (!acc.probeValue(nb, v) || regionAcc.isValueOn(nb) ||
                            !(std::abs(v) > here))
                            continue;
                        regionAcc.setValueOn(nb, true);
                        stack.push_back(nb);
                    }
                }
            }
            // Copy the values of the region and flood fill.
            std::vector<std::unique_ptr<LeafT>> leaves;
            for (auto leafIt = region.cbeginLeaf(); leafIt; ++leafIt) {
                const LeafT* src = acc.probeConstLeaf(leafIt->origin());
                if (!src)
                    continue;
                auto leaf = std::make_unique<LeafT>(leafIt->origin(), in.background(), false);
                const ValueT* v = src->buffer(0).data();
                for (Index n : leafIt->getValueMask().onBits())
                    leaf->setValueOn(n, v[n]);
                leaves.push_back(std::move(leaf));
            }
            auto tree = std::make_shared<TreeT>(in.background());
            linkLeaves(*tree, leaves, false);
            signedFloodFillWithValues(*tree, outside, inside, false);
            out[c] = gridLike<GridT>(grid, tree, true);
        },
        true, 1);
    segments.insert(segments.end(), out.begin(), out.end());
}

}  // namespace vdb::tools::detail

namespace vdb::tools {

template <typename GridT>
void sdfToFogVolume(GridT& grid, typename GridT::ValueType cutoffDistance) {
    detail::sdfToFogVolume(grid, cutoffDistance);
}

template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr sdfInteriorMask(
    const GridT& grid, typename GridT::ValueType isovalue) {
    return detail::sdfInteriorMask(grid, isovalue);
}

template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr extractEnclosedRegion(
    const GridT& grid, typename GridT::ValueType isovalue,
    const typename GridT::TreeType::template ValueConverter<bool>::Type* fillMask) {
    return detail::extractEnclosedRegion(grid, isovalue, fillMask);
}

template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr extractIsosurfaceMask(
    const GridT& grid, typename GridT::ValueType isovalue) {
    return detail::extractIsosurfaceMask(grid, isovalue);
}

template <typename GridT>
void extractActiveVoxelSegmentMasks(
    const GridT& grid,
    std::vector<typename GridT::template ValueConverter<bool>::Type::Ptr>& masks) {
    detail::extractActiveVoxelSegmentMasks(grid, masks);
}

template <typename GridT>
void segmentActiveVoxels(const GridT& grid, std::vector<typename GridT::Ptr>& segments) {
    detail::segmentActiveVoxels(grid, segments);
}

template <typename GridT>
void segmentSDF(const GridT& grid, std::vector<typename GridT::Ptr>& segments) {
    detail::segmentSDF(grid, segments);
}

}  // namespace vdb::tools
