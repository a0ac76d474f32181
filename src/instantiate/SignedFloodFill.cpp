// SPDX-License-Identifier: Apache-2.0
// The signed flood fill for the standard level-set trees, instantiated once; the header
// declares these `extern template`.

#include <vdb/tools/SignedFloodFill.h>

namespace vdb::tools {

template void signedFloodFill(FloatTree&, bool);
template void signedFloodFill(DoubleTree&, bool);
template void signedFloodFillWithValues(FloatTree&, const float&, const float&, bool);
template void signedFloodFillWithValues(DoubleTree&, const double&, const double&, bool);

}  // namespace vdb::tools
