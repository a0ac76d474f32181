// SPDX-License-Identifier: Apache-2.0
// The level set utilities compiled once for the standard grids (extern templates in
// tools/LevelSetUtil.h).

#include <vdb/tools/LevelSetUtil.h>

namespace vdb::tools {

template void sdfToFogVolume(FloatGrid&, float);
template void sdfToFogVolume(DoubleGrid&, double);
template BoolGrid::Ptr sdfInteriorMask(const FloatGrid&, float);
template BoolGrid::Ptr extractEnclosedRegion(const FloatGrid&, float, const BoolTree*);
template BoolGrid::Ptr extractIsosurfaceMask(const FloatGrid&, float);
template void extractActiveVoxelSegmentMasks(const FloatGrid&, std::vector<BoolGrid::Ptr>&);
template void segmentActiveVoxels(const FloatGrid&, std::vector<FloatGrid::Ptr>&);
template void segmentSDF(const FloatGrid&, std::vector<FloatGrid::Ptr>&);

}  // namespace vdb::tools
