// SPDX-License-Identifier: Apache-2.0
// Level set rebuilding for FloatGrid and DoubleGrid, instantiated once; the header declares
// these `extern template`.

#include <vdb/tools/LevelSetRebuild.h>

namespace vdb::tools {

template FloatGrid::Ptr levelSetRebuild(const FloatGrid&, float, float, float,
                                        const math::Transform*);
template DoubleGrid::Ptr levelSetRebuild(const DoubleGrid&, float, float, float,
                                         const math::Transform*);

}  // namespace vdb::tools
