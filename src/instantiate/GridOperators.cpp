// SPDX-License-Identifier: Apache-2.0
// The grid operators compiled once for the standard grids (extern templates in
// tools/GridOperators.h).

#include <vdb/tools/GridOperators.h>

namespace vdb::tools {

template Vec3SGrid::Ptr gradient(const FloatGrid&, bool);
template Vec3DGrid::Ptr gradient(const DoubleGrid&, bool);
template Vec3SGrid::Ptr gradient(const FloatGrid&, const MaskGrid&, bool);
template FloatGrid::Ptr divergence(const Vec3SGrid&, bool);
template DoubleGrid::Ptr divergence(const Vec3DGrid&, bool);
template FloatGrid::Ptr divergence(const Vec3SGrid&, const MaskGrid&, bool);
template Vec3SGrid::Ptr curl(const Vec3SGrid&, bool);
template Vec3DGrid::Ptr curl(const Vec3DGrid&, bool);
template Vec3SGrid::Ptr curl(const Vec3SGrid&, const MaskGrid&, bool);
template FloatGrid::Ptr laplacian(const FloatGrid&, bool);
template DoubleGrid::Ptr laplacian(const DoubleGrid&, bool);
template FloatGrid::Ptr laplacian(const FloatGrid&, const MaskGrid&, bool);
template FloatGrid::Ptr meanCurvature(const FloatGrid&, bool);
template DoubleGrid::Ptr meanCurvature(const DoubleGrid&, bool);
template FloatGrid::Ptr meanCurvature(const FloatGrid&, const MaskGrid&, bool);
template FloatGrid::Ptr magnitude(const Vec3SGrid&, bool);
template DoubleGrid::Ptr magnitude(const Vec3DGrid&, bool);
template FloatGrid::Ptr magnitude(const Vec3SGrid&, const MaskGrid&, bool);
template Vec3SGrid::Ptr normalize(const Vec3SGrid&, bool);
template Vec3DGrid::Ptr normalize(const Vec3DGrid&, bool);
template Vec3SGrid::Ptr normalize(const Vec3SGrid&, const MaskGrid&, bool);

}  // namespace vdb::tools
