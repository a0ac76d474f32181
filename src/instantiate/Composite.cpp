// SPDX-License-Identifier: Apache-2.0
// The CSG operations of tools/Composite.h for the standard level set trees, instantiated once;
// the header declares these `extern template`.

#include <vdb/tools/Composite.h>

namespace vdb::tools {

template struct detail::CsgRunner<FloatTree>;
template struct detail::CsgRunner<DoubleTree>;

}  // namespace vdb::tools
