// SPDX-License-Identifier: Apache-2.0
// The standard trees and grids, instantiated once for every program that links vdb::vdb;
// their headers declare these `extern template`.

#include <vdb/Grid.h>
#include <vdb/tree/TreeConfigs.h>

namespace vdb {
namespace tree {

template class LeafNode<float, 3>;
template class InternalNode<LeafNode<float, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<float, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<float, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<float, 3>, 4>, 5>, HashTable>>;
template class LeafNode<double, 3>;
template class InternalNode<LeafNode<double, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<double, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<double, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<double, 3>, 4>, 5>, HashTable>>;
template class LeafNode<Int32, 3>;
template class InternalNode<LeafNode<Int32, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<Int32, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<Int32, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<Int32, 3>, 4>, 5>, HashTable>>;
template class LeafNode<Int64, 3>;
template class InternalNode<LeafNode<Int64, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<Int64, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<Int64, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<Int64, 3>, 4>, 5>, HashTable>>;
template class LeafNode<bool, 3>;
template class InternalNode<LeafNode<bool, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<bool, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<bool, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<bool, 3>, 4>, 5>, HashTable>>;
template class LeafNode<ValueMask, 3>;
template class InternalNode<LeafNode<ValueMask, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<ValueMask, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<ValueMask, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<ValueMask, 3>, 4>, 5>, HashTable>>;
template class LeafNode<Vec3s, 3>;
template class InternalNode<LeafNode<Vec3s, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<Vec3s, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<Vec3s, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<Vec3s, 3>, 4>, 5>, HashTable>>;
template class LeafNode<Vec3d, 3>;
template class InternalNode<LeafNode<Vec3d, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<Vec3d, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<Vec3d, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<Vec3d, 3>, 4>, 5>, HashTable>>;
template class LeafNode<Vec3i, 3>;
template class InternalNode<LeafNode<Vec3i, 3>, 4>;
template class InternalNode<InternalNode<LeafNode<Vec3i, 3>, 4>, 5>;
template class RootNode<InternalNode<InternalNode<LeafNode<Vec3i, 3>, 4>, 5>, HashTable>;
template class Tree<RootNode<InternalNode<InternalNode<LeafNode<Vec3i, 3>, 4>, 5>, HashTable>>;

}  // namespace tree

template class Grid<FloatTree>;
template class Grid<DoubleTree>;
template class Grid<Int32Tree>;
template class Grid<Int64Tree>;
template class Grid<BoolTree>;
template class Grid<MaskTree>;
template class Grid<Vec3STree>;
template class Grid<Vec3DTree>;
template class Grid<Vec3ITree>;

}  // namespace vdb
