// SPDX-License-Identifier: Apache-2.0
// Mesh scan conversion for FloatGrid and DoubleGrid, instantiated once; the header declares
// these `extern template`.

#include <vdb/tools/MeshToVolume.h>

namespace vdb::tools {

template FloatGrid::Ptr meshToVolume<FloatGrid>(const math::Transform&, const std::vector<Vec3s>&,
                                                const std::vector<Vec3I>&,
                                                const std::vector<Vec4I>&,
                                                const MeshToVolumeOptions&, MeshToVolumeReport*);
template DoubleGrid::Ptr meshToVolume<DoubleGrid>(const math::Transform&, const std::vector<Vec3s>&,
                                                  const std::vector<Vec3I>&,
                                                  const std::vector<Vec4I>&,
                                                  const MeshToVolumeOptions&, MeshToVolumeReport*);

}  // namespace vdb::tools
