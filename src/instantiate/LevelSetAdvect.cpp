// SPDX-License-Identifier: Apache-2.0
// The level set tools compiled once: the tracker, the advection with each velocity field of
// VelocityFields.h, and the Enright test driver (extern templates in their headers).

#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/LevelSetTracker.h>

namespace vdb::tools {

template class LevelSetTracker<FloatGrid>;
template class LevelSetTracker<DoubleGrid>;

template class LevelSetAdvection<FloatGrid, EnrightField<float>>;
template class LevelSetAdvection<FloatGrid, ConstantVelocityField<float>>;
template class LevelSetAdvection<FloatGrid, DiscreteField<Vec3SGrid>>;
template class LevelSetAdvection<DoubleGrid, ConstantVelocityField<double>>;

template EnrightResult runEnrightTest<FloatGrid>(
    const EnrightTestOptions&, const std::function<void(const EnrightSample&, const FloatGrid&)>&);

}  // namespace vdb::tools
