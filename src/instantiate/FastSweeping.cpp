// SPDX-License-Identifier: Apache-2.0
// Fast sweeping for FloatGrid and DoubleGrid (with scalar and vector extension fields),
// instantiated once; the header declares these `extern template`.

#include <vdb/tools/FastSweeping.h>

namespace vdb::tools {

template class FastSweeping<FloatGrid>;
template class FastSweeping<FloatGrid, Vec3s>;
template class FastSweeping<DoubleGrid>;
template class FastSweeping<DoubleGrid, Vec3d>;
template FloatGrid::Ptr fogToSdf(const FloatGrid&, float, int);
template DoubleGrid::Ptr fogToSdf(const DoubleGrid&, double, int);
template FloatGrid::Ptr sdfToSdf(const FloatGrid&, float, int);
template DoubleGrid::Ptr sdfToSdf(const DoubleGrid&, double, int);
template FloatGrid::Ptr dilateSdf(const FloatGrid&, int, NearestNeighbors, int, FastSweepingDomain);
template DoubleGrid::Ptr dilateSdf(const DoubleGrid&, int, NearestNeighbors, int,
                                   FastSweepingDomain);
template FloatGrid::Ptr maskSdf(const FloatGrid&, const MaskGrid&, bool, int);
template FloatGrid::Ptr maskSdf(const FloatGrid&, const BoolGrid&, bool, int);
template FloatGrid::Ptr maskSdf(const FloatGrid&, const FloatGrid&, bool, int);

}  // namespace vdb::tools
