// SPDX-License-Identifier: Apache-2.0
// The Python classes Int32Grid and Int64Grid.

#include "GridBinding.h"

namespace vdb::python {

void bindIntGrids(py::module_& m) {
    bindGrid<Int32Grid>(m, "Int32Grid", "A grid of 32-bit integer values; NumPy dtype int32.");
    bindGrid<Int64Grid>(m, "Int64Grid", "A grid of 64-bit integer values; NumPy dtype int64.");
}

}  // namespace vdb::python
