// SPDX-License-Identifier: Apache-2.0
/// @file
/// Value transforms driven by a tree iterator, with OpenVDB 10's names (tools/ValueTransformer.h):
///
/// - foreach(iter, op): calls op(it) for every item the iterator visits; op changes values or
///   active states in place through the iterator (it.setValue(), it.setActiveState()).
/// - transformValues(inIter, outGrid, op): calls op(it, acc) for every item of the input
///   iterator, with `acc` an accessor of an output grid (of any type) that op writes into.
/// - setValueOnMin/Max/Sum/Mult(acc, ijk, v): set the voxel at ijk to min(old, v), max(old, v),
///   old + v or old * v and activate it (OpenVDB's accessor modifyValue helpers).
///
/// Threading. With `threaded`, the items are split into runs of whole leaves in one serial
/// pass of the iterator (each run starts at the first voxel of a leaf), and the runs are
/// processed in parallel. op must then be safe to call concurrently on different items and
/// must not change the tree's structure (no new or deleted nodes). In foreach the tiles
/// (values above the leaves) are visited serially after the voxels, so that op may change a
/// tile's state without racing on a shared node mask. In transformValues each run writes into
/// its own output tree; the runs' trees are then copied into outGrid in iteration order
/// (voxels and tiles that a run made active or gave a non-background value), so the result
/// equals the serial one whenever no two items write the same output voxel. With
/// `shareOp` false, each run calls its own copy of op.
///
/// @code
/// vdb::tools::foreach(grid->beginValueOn(), [](const auto& it) { it.setValue(*it * 2.0f); });
/// vdb::tools::transformValues(grid->cbeginValueOn(), *vecGrid,
///     [](const auto& it, auto& acc) { acc.setValue(it.getCoord(), vdb::Vec3s(*it)); });
/// @endcode

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

/// Calls op(it) for every item of `iter` (see the file comment for threading).
template <typename IterT, typename OpT>
void foreach (const IterT& iter, OpT && op, bool threaded = true, bool shareOp = true);

/// Calls op(it, acc) for every item of `inIter`, `acc` an accessor of `outGrid`'s tree (see the
/// file comment for threading).
template <typename InIterT, typename OutGridT, typename OpT>
void transformValues(const InIterT& inIter, OutGridT& outGrid, OpT&& op, bool threaded = true,
                     bool shareOp = true);

/// Sets the voxel at `ijk` to min(its value, `value`) and activates it.
template <typename AccessorT>
void setValueOnMin(AccessorT& acc, const Coord& ijk, const typename AccessorT::ValueType& value) {
    acc.setValueOn(ijk, std::min(acc.getValue(ijk), value));
}
/// Sets the voxel at `ijk` to max(its value, `value`) and activates it.
template <typename AccessorT>
void setValueOnMax(AccessorT& acc, const Coord& ijk, const typename AccessorT::ValueType& value) {
    acc.setValueOn(ijk, std::max(acc.getValue(ijk), value));
}
/// Adds `value` to the voxel at `ijk` and activates it.
template <typename AccessorT>
void setValueOnSum(AccessorT& acc, const Coord& ijk, const typename AccessorT::ValueType& value) {
    acc.setValueOn(ijk, typename AccessorT::ValueType(acc.getValue(ijk) + value));
}
/// Multiplies the voxel at `ijk` by `value` and activates it.
template <typename AccessorT>
void setValueOnMult(AccessorT& acc, const Coord& ijk, const typename AccessorT::ValueType& value) {
    acc.setValueOn(ijk, typename AccessorT::ValueType(acc.getValue(ijk) * value));
}

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// A run of consecutive items of an iterator: a copy of the iterator at its first item and the
/// number of items.
template <typename IterT>
struct IterRun {
    IterT first;
    size_t count;
};

/// True for iterators over values (voxels and tiles), false for leaf iterators.
template <typename IterT>
concept ValueIteratorType = requires(const IterT& it) {
    it.isTileValue();
    it.getCoord();
};

/// Splits the items of `iter` into runs of whole leaves of at least `grain` items (leaf
/// iterators: `grain` leaves), in one serial pass. With `tiles`, a copy of the iterator at each
/// tile is appended to it as well.
template <typename IterT>
std::vector<IterRun<IterT>> splitIntoRuns(const IterT& iter, size_t grain,
                                          std::vector<IterT>* tiles = nullptr) {
    std::vector<IterRun<IterT>> runs;
    size_t count = 0;
    if constexpr (ValueIteratorType<IterT>) {
        using TreeT = std::remove_cvref_t<decltype(iter.getTree())>;
        constexpr Index LEAF_LOG2 = TreeT::LeafNodeType::LOG2DIM;
        Coord leaf(0);
        bool inLeaf = false;
        for (IterT it = iter; it; ++it) {
            const bool voxel = !it.isTileValue();
            if (!voxel && tiles)
                tiles->push_back(it);
            const Coord origin = voxel ? it.getCoord().alignedDown(LEAF_LOG2) : Coord(0);
            const bool newLeaf = voxel && (!inLeaf || origin != leaf);
            if (runs.empty() || (newLeaf && count >= grain)) {
                if (!runs.empty())
                    runs.back().count = count;
                runs.push_back({it, 0});
                count = 0;
            }
            inLeaf = voxel;
            leaf = origin;
            ++count;
        }
    } else {
        for (IterT it = iter; it; ++it) {
            if (runs.empty() || count >= grain) {
                if (!runs.empty())
                    runs.back().count = count;
                runs.push_back({it, 0});
                count = 0;
            }
            ++count;
        }
    }
    if (!runs.empty())
        runs.back().count = count;
    return runs;
}

/// Calls fn(it) for the items of one run. The iterator never steps past the run's last item,
/// so it reads no node of another run.
template <typename IterT, typename FnT>
void visitRun(const IterRun<IterT>& run, const FnT& fn) {
    IterT it = run.first;
    for (size_t n = 0;;) {
        fn(std::as_const(it));
        if (++n == run.count)
            break;
        ++it;
    }
}

/// Runs `body(run, op)` for every run, in parallel, with the shared op or a copy per run.
template <typename IterT, typename OpT, typename BodyT>
void forEachRun(const std::vector<IterRun<IterT>>& runs, OpT& op, bool shareOp, const BodyT& body) {
    util::parallelFor(
        runs.size(),
        [&](size_t i) {
            if (shareOp) {
                body(runs[i], op);
            } else {
                std::remove_cvref_t<OpT> copy(op);
                body(runs[i], copy);
            }
        },
        true, 1);
}

/// Copies into `out` what the run's tree `part` holds: its leaves (whole, where `out` has
/// only an inactive background there; voxel by voxel elsewhere) and its tiles, wherever
/// a value is active or differs from the background.
template <typename TreeT>
void copyWrittenValues(TreeT& out, const TreeT& part) {
    using ValueT = typename TreeT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    const ValueT background = part.background();
    tree::ValueAccessor<TreeT> acc(out);
    for (auto it = part.cbeginValueAll(); it; ++it) {
        if (!it.isTileValue())
            continue;
        const ValueT value = it.getValue();
        if (it.isValueOn() || !(value == background)) {
            CoordBBox bbox;
            it.getBoundingBox(bbox);
            out.fill(bbox, value, it.isValueOn());
        }
    }
    for (auto leaf = part.cbeginLeaf(); leaf; ++leaf) {
        ValueT there;
        if (!acc.probeLeaf(leaf->origin()) && !acc.probeValue(leaf->origin(), there) &&
            there == out.background()) {
            out.addLeaf(std::make_unique<LeafT>(*leaf));
            continue;
        }
        for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
            const ValueT value = leaf->getValue(n);
            const Coord ijk = leaf->offsetToGlobalCoord(n);
            if (leaf->isValueOn(n)) {
                acc.setValueOn(ijk, value);
            } else if (!(value == background)) {
                acc.setValueOff(ijk, value);
            }
        }
    }
}

}  // namespace detail

template <typename IterT, typename OpT>
void foreach (const IterT& iter, OpT && op, bool threaded, bool shareOp) {
    if (!threaded) {
        for (IterT it = iter; it; ++it)
            op(std::as_const(it));
        return;
    }
    // Voxels (or leaves) in parallel; tiles afterwards, serially, through iterators copied
    // before any op ran (a run cannot be walked again once op has changed states in it).
    std::vector<IterT> tiles;
    const auto runs = detail::splitIntoRuns(iter, 4096, &tiles);
    detail::forEachRun(runs, op, shareOp, [](const auto& run, auto& runOp) {
        detail::visitRun(run, [&](const IterT& it) {
            if constexpr (detail::ValueIteratorType<IterT>) {
                if (it.isTileValue())
                    return;
            }
            runOp(it);
        });
    });
    for (const IterT& tile : tiles)
        op(tile);
}

template <typename InIterT, typename OutGridT, typename OpT>
void transformValues(const InIterT& inIter, OutGridT& outGrid, OpT&& op, bool threaded,
                     bool shareOp) {
    using OutTreeT = typename OutGridT::TreeType;
    auto& outTree = outGrid.tree();
    if (!threaded) {
        typename OutGridT::Accessor acc(outTree);
        for (InIterT it = inIter; it; ++it)
            op(std::as_const(it), acc);
        return;
    }
    const auto runs = detail::splitIntoRuns(inIter, 4096);
    std::vector<std::unique_ptr<OutTreeT>> parts(runs.size());
    detail::forEachRun(runs, op, shareOp, [&](const auto& run, auto& runOp) {
        auto part = std::make_unique<OutTreeT>(outTree.background());
        {
            typename OutGridT::Accessor acc(*part);
            detail::visitRun(run, [&](const InIterT& it) { runOp(it, acc); });
        }
        parts[size_t(&run - runs.data())] = std::move(part);
    });
    for (const auto& part : parts)
        detail::copyWrittenValues(outTree, *part);
}

}  // namespace vdb::tools
