// SPDX-License-Identifier: Apache-2.0
// Dilation and erosion of the standard trees, instantiated once for every program that links
// vdb::vdb; tools/Morphology.h declares these `extern template`.

#include <vdb/tools/Morphology.h>

namespace vdb::tools::detail {

template class Morphology<FloatTree>;
template class Morphology<DoubleTree>;
template class Morphology<Int32Tree>;
template class Morphology<Int64Tree>;
template class Morphology<BoolTree>;
template class Morphology<MaskTree>;

}  // namespace vdb::tools::detail
