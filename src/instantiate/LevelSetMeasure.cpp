// SPDX-License-Identifier: Apache-2.0
// The level set measures compiled once (extern templates in tools/LevelSetMeasure.h).

#include <vdb/tools/LevelSetMeasure.h>

namespace vdb::tools {

template class LevelSetMeasure<FloatGrid>;
template class LevelSetMeasure<DoubleGrid>;
template double smearedHeavisideVolume(const FloatGrid&, double, bool);
template double smearedHeavisideVolume(const DoubleGrid&, double, bool);

}  // namespace vdb::tools
