// SPDX-License-Identifier: Apache-2.0
// Resampling passes for FloatTree, DoubleTree and Vec3STree with the point, box and quadratic
// samplers, instantiated once; tools/GridTransformer.h declares these `extern template`.

#include <vdb/tools/GridTransformer.h>

namespace vdb::tools::detail {

template class TreeResampler<PointSampler, FloatTree>;
template class TreeResampler<BoxSampler, FloatTree>;
template class TreeResampler<QuadraticSampler, FloatTree>;
template class TreeResampler<PointSampler, DoubleTree>;
template class TreeResampler<BoxSampler, DoubleTree>;
template class TreeResampler<QuadraticSampler, DoubleTree>;
template class TreeResampler<PointSampler, Vec3STree>;
template class TreeResampler<BoxSampler, Vec3STree>;
template class TreeResampler<QuadraticSampler, Vec3STree>;

}  // namespace vdb::tools::detail
