// SPDX-License-Identifier: Apache-2.0
// The Python classes FloatGrid and DoubleGrid.

#include "GridBinding.h"

namespace vdb::python {

void bindFloatGrids(py::module_& m) {
    bindGrid<FloatGrid>(m, "FloatGrid", "A grid of float (32-bit) values; NumPy dtype float32.");
    bindGrid<DoubleGrid>(m, "DoubleGrid", "A grid of double (64-bit) values; NumPy dtype float64.");
}

}  // namespace vdb::python
