// SPDX-License-Identifier: Apache-2.0
// The sphere level sets for FloatGrid and DoubleGrid, instantiated once; the header declares
// these `extern template`.

#include <vdb/tools/LevelSetSphere.h>

namespace vdb::tools {

template FloatGrid::Ptr createLevelSetSphere<FloatGrid>(float, const Vec3f&, float, float, bool);
template DoubleGrid::Ptr createLevelSetSphere<DoubleGrid>(float, const Vec3f&, float, float, bool);
template FloatGrid::Ptr createLevelSetSphere<FloatGrid>(double, const Vec3d&, double, double, bool);
template DoubleGrid::Ptr createLevelSetSphere<DoubleGrid>(double, const Vec3d&, double, double,
                                                          bool);
template FloatGrid::Ptr createEnrightSphere<FloatGrid>(int, float, bool);
template DoubleGrid::Ptr createEnrightSphere<DoubleGrid>(int, float, bool);
template FloatGrid::Ptr createEnrightEightSpheres<FloatGrid>(int, float, bool);
template DoubleGrid::Ptr createEnrightEightSpheres<DoubleGrid>(int, float, bool);

}  // namespace vdb::tools
