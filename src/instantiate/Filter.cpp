// SPDX-License-Identifier: Apache-2.0
// The filters compiled once for the standard grids (extern templates in tools/Filter.h and
// tools/LevelSetFilter.h).

#include <vdb/tools/Filter.h>
#include <vdb/tools/LevelSetFilter.h>

namespace vdb::tools {

template class Filter<FloatGrid, FloatGrid>;
template class Filter<DoubleGrid, FloatGrid>;
template class Filter<Vec3SGrid, FloatGrid>;
template class LevelSetFilter<FloatGrid, FloatGrid>;
template class LevelSetFilter<DoubleGrid, FloatGrid>;

}  // namespace vdb::tools
