// SPDX-License-Identifier: Apache-2.0
// The prune family for the standard level-set trees, instantiated once; the header declares
// these `extern template`.

#include <vdb/tools/Prune.h>

namespace vdb::tools {

template void prune(FloatTree&, float, bool);
template void prune(DoubleTree&, double, bool);
template void pruneInactive(FloatTree&, bool);
template void pruneInactive(DoubleTree&, bool);
template void pruneLevelSet(FloatTree&, bool);
template void pruneLevelSet(DoubleTree&, bool);

}  // namespace vdb::tools
