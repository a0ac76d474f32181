// SPDX-License-Identifier: Apache-2.0
// Sphere rasterization for FloatGrid and DoubleGrid, instantiated once; the header declares
// these `extern template`.

#include <vdb/tools/ParticlesToLevelSet.h>

namespace vdb::tools {

template class ParticlesToLevelSet<FloatGrid>;
template class ParticlesToLevelSet<DoubleGrid>;

}  // namespace vdb::tools
