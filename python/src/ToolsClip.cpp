// SPDX-License-Identifier: Apache-2.0
// vdb.tools: clipping (Clip.h), interior masks (Mask.h), activation by value (Activate.h) and
// compositing (compMax, compMin, compSum, compMul, compDiv, compReplace of Composite.h), with
// OpenVDB's names, for every grid type of the module.

#include <vdb/GridTypes.h>
#include <vdb/math/BBox.h>
#include <vdb/tools/Activate.h>
#include <vdb/tools/Clip.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/Mask.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <string>
#include <utility>

namespace vdb::python {

std::shared_ptr<const MaskGrid> activeMask(py::handle obj, const char* op) {
    if (py::isinstance<MaskGrid>(obj))
        return requireGrid(obj.cast<MaskGrid::Ptr>(), op);
    MaskGrid::Ptr mask;
    const bool isGrid =
        py::isinstance<GridBase>(obj) &&
        tryDispatchGrid<GridTypes>(obj.cast<const GridBase&>(), [&](const auto& grid) {
            py::gil_scoped_release release;
            mask = MaskGrid::create();
            mask->setTransform(grid.transform().copy());
            mask->tree().topologyUnion(grid.tree());
        });
    if (!isGrid)
        throw py::type_error(std::string(op) + ": expected a grid as the mask, got " +
                             typeNameOf(obj));
    return mask;
}

namespace {

// ---- Clip, interior masks, activation

template <typename GridT>
void bindClip(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "clip",
        [](const GridT& g, const std::pair<Vec3d, Vec3d>& box, bool keepInterior) {
            py::gil_scoped_release release;
            return tools::clip(g, BBoxd(box.first, box.second), keepInterior);
        },
        py::arg("grid"), py::arg("bbox"), py::arg("keepInterior") = true,
        "clip(grid, bbox, keepInterior=True) -> grid: a copy of the grid clipped to the "
        "world-space box bbox = ((x0, y0, z0), (x1, y1, z1)) (keepInterior) or to its exterior; "
        "the voxels from floor(lo) to floor(hi) of the box's index-space bounds are kept. A "
        "level set also keeps its inside. Raises ValueError for a non-finite corner.");
    t.def(
        "clip",
        [](const GridT& g, const math::Transform& frustum, bool keepInterior) {
            py::gil_scoped_release release;
            return tools::clip(g, frustum, keepInterior);
        },
        py::arg("grid"), py::arg("frustum"), py::arg("keepInterior") = true,
        "clip(grid, frustum, keepInterior=True) -> grid: a copy of the grid clipped to the "
        "frustum of a frustum Transform (createFrustumTransform), or to its exterior. Raises "
        "ValueError when the transform is not a frustum.");
    t.def(
        "clip",
        [](const GridT& g, const GridBase::Ptr& mask, bool keepInterior) {
            const MaskGrid::ConstPtr m = activeMask(py::cast(requireGrid(mask, "clip")), "clip");
            py::gil_scoped_release release;
            return tools::clip(g, *m, keepInterior);
        },
        py::arg("grid"), py::arg("mask"), py::arg("keepInterior") = true,
        "clip(grid, mask, keepInterior=True) -> grid: a copy of the grid clipped to the active "
        "voxels and tiles of `mask` (any grid; resampled to the grid's index space when its "
        "transform differs), or to the rest of space.");
    t.def(
        "interiorMask",
        [](const GridT& g, double isovalue) {
            py::gil_scoped_release release;
            return tools::interiorMask(g, isovalue);
        },
        py::arg("grid"), py::arg("isovalue") = 0.0,
        "interiorMask(grid, isovalue=0) -> BoolGrid: for a float level set, the region below "
        "isovalue; for a BoolGrid, a deep copy; for any other grid, its active topology.");
    t.def(
        "activate",
        [](GridT& g, const ValueT& value, std::optional<ValueT> tolerance) {
            checkUnpinned(&g.tree(), "activate");
            py::gil_scoped_release release;
            tools::activate(g, value, tolerance.value_or(ValueT{}));
        },
        py::arg("grid"), py::arg("value"), py::arg("tolerance") = py::none(),
        "activate(grid, value, tolerance=0): activate every inactive voxel and tile whose value "
        "equals `value` (within `tolerance`, per component for vectors).");
    t.def(
        "deactivate",
        [](GridT& g, const ValueT& value, std::optional<ValueT> tolerance) {
            checkUnpinned(&g.tree(), "deactivate");
            py::gil_scoped_release release;
            tools::deactivate(g, value, tolerance.value_or(ValueT{}));
        },
        py::arg("grid"), py::arg("value"), py::arg("tolerance") = py::none(),
        "deactivate(grid, value, tolerance=0): deactivate every active voxel and tile whose "
        "value equals `value` (within `tolerance`).");
}

// ---- Compositing

template <typename GridT>
void bindComposite(py::module_& t) {
    using Fn = void (*)(GridT&, GridT&, bool);
    struct Op {
        const char* name;
        Fn fn;
        const char* doc;
    };
    for (const Op& op : {
             Op{"compMax", &tools::compMax<typename GridT::TreeType>,
                "compMax(a, b): a becomes max(a, b) value by value (vectors: the longer), active "
                "where either was; b is emptied. Raises ValueError when the transforms differ "
                "or a and b share a tree."},
             Op{"compMin", &tools::compMin<typename GridT::TreeType>,
                "compMin(a, b): a becomes min(a, b) value by value (vectors: the shorter); b is "
                "emptied."},
             Op{"compSum", &tools::compSum<typename GridT::TreeType>,
                "compSum(a, b): a becomes a + b value by value; b is emptied."},
             Op{"compMul", &tools::compMul<typename GridT::TreeType>,
                "compMul(a, b): a becomes a * b value by value; b is emptied."},
             Op{"compDiv", &tools::compDiv<typename GridT::TreeType>,
                "compDiv(a, b): a becomes a / b value by value (integers: 0 / 0 gives 0, x / 0 "
                "the largest value with x's sign); b is emptied."},
         }) {
        const Fn fn = op.fn;
        const char* name = op.name;
        t.def(
            op.name,
            [fn, name](GridT& a, GridT& b) {
                checkUnpinned(&a.tree(), name);
                checkUnpinned(&b.tree(), name);
                py::gil_scoped_release release;
                fn(a, b, true);
            },
            py::arg("a"), py::arg("b"), op.doc);
    }
    t.def(
        "compReplace",
        [](GridT& a, const GridT& b) {
            checkUnpinned(&a.tree(), "compReplace");
            py::gil_scoped_release release;
            tools::compReplace(a, b);
        },
        py::arg("a"), py::arg("b"),
        "compReplace(a, b): copy the active values of b into a (a's active topology becomes the "
        "union of both); b is not changed. Raises ValueError when the transforms differ.");
}

}  // namespace

void bindToolsClip(py::module_& t) {
    GridTypes::forEach([&]<typename GridT>() { bindClip<GridT>(t); });
    GridTypes::Remove<MaskGrid>::forEach([&]<typename GridT>() { bindComposite<GridT>(t); });
}

}  // namespace vdb::python
