// SPDX-License-Identifier: Apache-2.0
// The standard trees and grids (VDB_FOR_EACH_STANDARD_TREE in tree/TreeConfigs.h), instantiated
// once for every program that links vdb::vdb; their headers declare these `extern template`.

#include <vdb/Grid.h>
#include <vdb/tree/TreeConfigs.h>

namespace vdb {

#define VDB_STANDARD_TREE_INSTANTIATE(ValueT, Name) \
    VDB_STANDARD_TREE_CLASSES(, ValueT)             \
    template class Grid<Name##Tree>;
VDB_FOR_EACH_STANDARD_TREE(VDB_STANDARD_TREE_INSTANTIATE)
#undef VDB_STANDARD_TREE_INSTANTIATE

}  // namespace vdb
