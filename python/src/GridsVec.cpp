// SPDX-License-Identifier: Apache-2.0
// The Python classes Vec3SGrid, Vec3DGrid and Vec3IGrid.

#include "GridBinding.h"

namespace vdb::python {

void bindVecGrids(py::module_& m) {
    bindGrid<Vec3SGrid>(m, "Vec3SGrid",
                        "A grid of 3-vectors of float; NumPy dtype float32, a last axis of 3.");
    bindGrid<Vec3DGrid>(m, "Vec3DGrid",
                        "A grid of 3-vectors of double; NumPy dtype float64, a last axis of 3.");
    bindGrid<Vec3IGrid>(m, "Vec3IGrid",
                        "A grid of 3-vectors of int32; NumPy dtype int32, a last axis of 3.");
}

}  // namespace vdb::python
