// SPDX-License-Identifier: Apache-2.0
/// @file
/// Named tree configurations: the standard Tree4 and every configuration of the paper's
/// Table II, written [Hash,5,4,3] (a hash-table root over internal nodes of 32^3 and 16^3
/// children and 8^3 leaves) or [6,5,4,3] (a fixed 64^3 internal node on top instead of a root).

#pragma once

#include <vdb/tree/InternalNode.h>
#include <vdb/tree/LeafNode.h>
#include <vdb/tree/RootNode.h>
#include <vdb/tree/Tree.h>

namespace vdb::tree {

/// The standard four-level tree: root, internal nodes of 2^N1 and 2^N2 children per axis,
/// leaves of 2^N3 voxels per axis. `Tree4<float, 5, 4, 3>::Type` is FloatTree.
template <typename ValueT, Index N1 = 5, Index N2 = 4, Index N3 = 3>
struct Tree4 {
    using Type =
        Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueT, N3>, N2>, N1>, HashTable>>;
};

// ---- Unbounded: a root table over three levels
template <typename ValueT>
using HashTree543 =
    Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueT, 3>, 4>, 5>, HashTable>>;
template <typename ValueT>
using MapTree543 = Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueT, 3>, 4>, 5>, MapTable>>;
template <typename ValueT>
using HashTree432 =
    Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueT, 2>, 3>, 4>, HashTable>>;
template <typename ValueT>
using MapTree432 = Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueT, 2>, 3>, 4>, MapTable>>;

// ---- Bounded: a fixed internal node on top (domain centered on the origin)
template <typename ValueT>
using FixedTree76543 =
    Tree<InternalNode<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 3>, 4>, 5>, 6>, 7>>;
template <typename ValueT>
using FixedTree6543 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 3>, 4>, 5>, 6>>;
template <typename ValueT>
using FixedTree643 = Tree<InternalNode<InternalNode<LeafNode<ValueT, 3>, 4>, 6>>;
template <typename ValueT>
using FixedTree103 = Tree<InternalNode<LeafNode<ValueT, 3>, 10>>;
template <typename ValueT>
using FixedTree6545 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 5>, 4>, 5>, 6>>;
template <typename ValueT>
using FixedTree6544 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 4>, 4>, 5>, 6>>;
template <typename ValueT>
using FixedTree6542 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 2>, 4>, 5>, 6>>;
template <typename ValueT>
using FixedTree6666 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 6>, 6>, 6>, 6>>;
template <typename ValueT>
using FixedTree5555 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 5>, 5>, 5>, 5>>;
template <typename ValueT>
using FixedTree4444 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 4>, 4>, 4>, 4>>;
template <typename ValueT>
using FixedTree3333 = Tree<InternalNode<InternalNode<InternalNode<LeafNode<ValueT, 3>, 3>, 3>, 3>>;

}  // namespace vdb::tree

// ---- The standard trees

/// The value types of the standard trees, Tree4<ValueT, 5, 4, 3> (OpenVDB's registered grid
/// types), in one list from which their instantiation (src/instantiate/Trees.cpp), the extern
/// declarations below and those of their grids (Grid.h) are written. X(ValueT, Name) is called
/// once per type; Name is the prefix of the aliases (FloatTree, FloatGrid).
#define VDB_FOR_EACH_STANDARD_TREE(X) \
    X(float, Float)                   \
    X(double, Double)                 \
    X(Int32, Int32)                   \
    X(Int64, Int64)                   \
    X(bool, Bool)                     \
    X(ValueMask, Mask)                \
    X(Vec3s, Vec3S)                   \
    X(Vec3d, Vec3D)                   \
    X(Vec3i, Vec3I)

/// The node classes of the standard tree of `ValueT`, each as `PREFIX template class ...;`
/// (PREFIX is `extern` for a declaration, empty for the instantiation).
#define VDB_STANDARD_TREE_CLASSES(PREFIX, ValueT)                                                 \
    PREFIX template class ::vdb::tree::LeafNode<ValueT, 3>;                                       \
    PREFIX template class ::vdb::tree::InternalNode<::vdb::tree::LeafNode<ValueT, 3>, 4>;         \
    PREFIX template class ::vdb::tree::InternalNode<                                              \
        ::vdb::tree::InternalNode<::vdb::tree::LeafNode<ValueT, 3>, 4>, 5>;                       \
    PREFIX template class ::vdb::tree::RootNode<                                                  \
        ::vdb::tree::InternalNode<::vdb::tree::InternalNode<::vdb::tree::LeafNode<ValueT, 3>, 4>, \
                                  5>,                                                             \
        ::vdb::tree::HashTable>;                                                                  \
    PREFIX template class ::vdb::tree::Tree<::vdb::tree::RootNode<                                \
        ::vdb::tree::InternalNode<::vdb::tree::InternalNode<::vdb::tree::LeafNode<ValueT, 3>, 4>, \
                                  5>,                                                             \
        ::vdb::tree::HashTable>>;

namespace vdb {

using FloatTree = tree::Tree4<float>::Type;
using DoubleTree = tree::Tree4<double>::Type;
using Int32Tree = tree::Tree4<Int32>::Type;
using Int64Tree = tree::Tree4<Int64>::Type;
using BoolTree = tree::Tree4<bool>::Type;
using MaskTree = tree::Tree4<ValueMask>::Type;
using Vec3STree = tree::Tree4<Vec3s>::Type;
using Vec3DTree = tree::Tree4<Vec3d>::Type;
using Vec3ITree = tree::Tree4<Vec3i>::Type;

}  // namespace vdb

// Instantiated once in src/instantiate/Trees.cpp.
#define VDB_STANDARD_TREE_EXTERN(ValueT, Name) VDB_STANDARD_TREE_CLASSES(extern, ValueT)
namespace vdb {
VDB_FOR_EACH_STANDARD_TREE(VDB_STANDARD_TREE_EXTERN)
}  // namespace vdb

#undef VDB_STANDARD_TREE_EXTERN
