// SPDX-License-Identifier: Apache-2.0
// The Python classes BoolGrid and MaskGrid.

#include "GridBinding.h"

namespace vdb::python {

void bindBoolGrids(py::module_& m) {
    bindGrid<BoolGrid>(m, "BoolGrid", "A grid of bool values; NumPy dtype bool.");
    bindGrid<MaskGrid>(m, "MaskGrid",
                       "A grid of active states only (a voxel's value is its state); NumPy "
                       "dtype bool.");
}

}  // namespace vdb::python
