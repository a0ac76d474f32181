// SPDX-License-Identifier: Apache-2.0
/// @file
/// Morphological dilation and erosion of the active voxels of a tree (paper section 4.1),
/// computed on the 64-bit words of the leaf value masks, with OpenVDB's names and semantics.
///
/// One step of dilation activates every voxel with an active neighbour; one step of erosion
/// deactivates every active voxel with an inactive neighbour. Neighbours are the 6 face, 18
/// face and edge, or 26 face, edge and corner voxels. Values never change, only active
/// states (see the tile policies for the values of nodes that appear or disappear).
///
/// Cost: per step, a few word operations per 64 voxels of every leaf that holds an active
/// voxel (8 words for an 8^3 leaf), and a handful of array lookups per leaf for its
/// neighbours. Threads: parallel over leaves when `threaded`; the result is the same, bit for
/// bit and node for node, for any number of threads.
///
/// @code
/// vdb::FloatTree tree(0.0f);
/// tree.setValue(vdb::Coord(0, 0, 0), 1.0f);
/// vdb::tools::dilateActiveValues(tree, 2, vdb::tools::NN_FACE_EDGE_VERTEX);  // a 5^3 cube
/// vdb::tools::erodeActiveValues(tree, 1, vdb::tools::NN_FACE_EDGE_VERTEX);   // a 3^3 cube
/// @endcode

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>

#include <concepts>

namespace vdb::tools {

/// Which neighbours of a voxel one step of dilation or erosion looks at.
enum NearestNeighbors {
    NN_FACE = 6,              ///< the 6 voxels that share a face
    NN_FACE_EDGE = 18,        ///< ... and the 12 that share an edge
    NN_FACE_EDGE_VERTEX = 26  ///< ... and the 8 that share a corner: the 3x3x3 cube
};

/// What dilation and erosion do with active tiles (constant regions above the leaves).
///
/// - IGNORE_TILES: tiles stay as they are. Dilation grows the leaf voxels only (through tile
///   regions as if the tiles were absent) and keeps the tiles; erosion erodes the leaf voxels
///   only, with tile voxels counting as active neighbours that never erode.
/// - EXPAND_TILES: every active tile is first expanded into dense leaves of its value; the
///   result keeps those leaves and has no active tiles.
/// - PRESERVE_TILES: tiles act as the active voxels they stand for. Dilation leaves them in
///   place and grows out of them; afterwards the whole tree is pruned (tolerance zero), so
///   that uniform nodes, old or new, become tiles. Erosion erodes tiles only where the
///   erosion reaches them, replacing such a tile by a pruned node of the tile's value; then
///   every node (leaf or internal) left without an active value is replaced by an inactive
///   background tile or, under a root, removed.
enum TilePolicy { IGNORE_TILES, EXPAND_TILES, PRESERVE_TILES };

/// A tree that morphology works on: any configuration of vdb::tree::Tree, with RootNode or
/// InternalNode on top and any leaf type (values, bool or ValueMask).
template <typename T>
concept MorphologyTree = requires(T& tree, const Coord& ijk) {
    typename T::ValueType;
    typename T::LeafNodeType;
    typename T::TopNodeType;
    { tree.getValue(ijk) } -> std::convertible_to<typename T::ValueType>;
    { tree.probeLeaf(ijk) } -> std::same_as<typename T::LeafNodeType*>;
    { tree.leafCount() } -> std::convertible_to<Index32>;
};

/// Activates, `iterations` times, every voxel with an active neighbour in `nn`.
///
/// Voxel values never change: a voxel that becomes active keeps the value it had, so a new
/// leaf takes the value of the inactive tile it replaces, or the background. In a bounded
/// tree nothing is activated outside Tree::domain(). Leaves are created where the dilation
/// reaches; with EXPAND_TILES and IGNORE_TILES no node is removed; see TilePolicy for tiles.
/// Matches OpenVDB 10's tools::dilateActiveValues with threading on.
template <MorphologyTree TreeT>
void dilateActiveValues(TreeT& tree, int iterations = 1, NearestNeighbors nn = NN_FACE,
                        TilePolicy mode = PRESERVE_TILES, bool threaded = true);

/// Dilates the tree of `leaves`, then rebuilds `leaves` (auxiliary buffers start again as
/// copies of buffer 0).
template <MorphologyTree TreeT>
void dilateActiveValues(tree::LeafManager<TreeT>& leaves, int iterations = 1,
                        NearestNeighbors nn = NN_FACE, TilePolicy mode = PRESERVE_TILES,
                        bool threaded = true);

/// Deactivates, `iterations` times, every active voxel with an inactive neighbour in `nn`.
///
/// Voxels outside the tree's leaves and tiles count as inactive. Voxel values never change,
/// except that with PRESERVE_TILES a node left without any active value is replaced by the
/// background (see TilePolicy). Matches OpenVDB 10's tools::erodeActiveValues, except in one
/// corner case of IGNORE_TILES with NN_FACE_EDGE(_VERTEX): OpenVDB, threaded, lets the
/// erosion pass through an ignored tile's edge or corner to leaf voxels beyond it; here, as
/// in OpenVDB's single-threaded run and its NN_FACE erosion, a tile only ever counts as
/// active.
template <MorphologyTree TreeT>
void erodeActiveValues(TreeT& tree, int iterations = 1, NearestNeighbors nn = NN_FACE,
                       TilePolicy mode = PRESERVE_TILES, bool threaded = true);

/// Erodes the tree of `leaves`, then rebuilds `leaves` (auxiliary buffers start again as
/// copies of buffer 0).
template <MorphologyTree TreeT>
void erodeActiveValues(tree::LeafManager<TreeT>& leaves, int iterations = 1,
                       NearestNeighbors nn = NN_FACE, TilePolicy mode = PRESERVE_TILES,
                       bool threaded = true);

}  // namespace vdb::tools

// ---- Implementation ---------------------------------------------------------------------------

#include <vdb/tools/detail/MorphologyImpl.h>

namespace vdb::tools {

template <MorphologyTree TreeT>
void dilateActiveValues(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                        bool threaded) {
    detail::Morphology<TreeT>::dilate(tree, iterations, nn, mode, threaded);
}

template <MorphologyTree TreeT>
void dilateActiveValues(tree::LeafManager<TreeT>& leaves, int iterations, NearestNeighbors nn,
                        TilePolicy mode, bool threaded) {
    detail::Morphology<TreeT>::dilate(leaves.tree(), iterations, nn, mode, threaded);
    leaves.rebuild(leaves.auxBufferCount());
}

template <MorphologyTree TreeT>
void erodeActiveValues(TreeT& tree, int iterations, NearestNeighbors nn, TilePolicy mode,
                       bool threaded) {
    detail::Morphology<TreeT>::erode(tree, iterations, nn, mode, threaded);
}

template <MorphologyTree TreeT>
void erodeActiveValues(tree::LeafManager<TreeT>& leaves, int iterations, NearestNeighbors nn,
                       TilePolicy mode, bool threaded) {
    detail::Morphology<TreeT>::erode(leaves.tree(), iterations, nn, mode, threaded);
    leaves.rebuild(leaves.auxBufferCount());
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/Morphology.cpp

namespace vdb::tools::detail {

extern template class Morphology<FloatTree>;
extern template class Morphology<DoubleTree>;
extern template class Morphology<Int32Tree>;
extern template class Morphology<Int64Tree>;
extern template class Morphology<BoolTree>;
extern template class Morphology<MaskTree>;

}  // namespace vdb::tools::detail
