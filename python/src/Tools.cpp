// SPDX-License-Identifier: Apache-2.0
// vdb.tools: CSG, morphology, level set advection and rebuild, spheres and mesh conversion,
// with OpenVDB's names, for the grid types each C++ tool is instantiated for.

#include <vdb/GridTypes.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/LevelSetRebuild.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/VelocityFields.h>

#include "Common.h"
#include "TreeBlocks.h"

namespace vdb::python {

namespace {

template <typename GridT>
void bindCsg(py::module_& t) {
    using Kind = void (*)(GridT&, GridT&, bool, bool);
    struct Op {
        const char* name;
        Kind fn;
        const char* doc;
    };
    for (const Op& op : {
             Op{"csgUnion", &tools::csgUnion<typename GridT::TreeType>,
                "csgUnion(a, b, prune=True): a becomes the union of level sets a and b; b is "
                "emptied."},
             Op{"csgIntersection", &tools::csgIntersection<typename GridT::TreeType>,
                "csgIntersection(a, b, prune=True): a becomes the intersection; b is emptied."},
             Op{"csgDifference", &tools::csgDifference<typename GridT::TreeType>,
                "csgDifference(a, b, prune=True): a becomes a minus b; b is emptied."},
         }) {
        const Kind fn = op.fn;
        const char* name = op.name;
        t.def(
            op.name,
            [fn, name](GridT& a, GridT& b, bool prune) {
                checkUnpinned(&a.tree(), name);
                checkUnpinned(&b.tree(), name);
                if (a.treePtr() == b.treePtr())
                    throw py::value_error(std::string(name) + ": the grids share one tree");
                py::gil_scoped_release release;
                fn(a, b, prune, true);
            },
            py::arg("a"), py::arg("b"), py::arg("prune") = true, op.doc);
    }
    using CopyKind = typename GridT::Ptr (*)(const GridT&, const GridT&, bool);
    struct CopyOp {
        const char* name;
        CopyKind fn;
    };
    for (const CopyOp& op :
         {CopyOp{"csgUnionCopy", &tools::csgUnionCopy<typename GridT::TreeType>},
          CopyOp{"csgIntersectionCopy", &tools::csgIntersectionCopy<typename GridT::TreeType>},
          CopyOp{"csgDifferenceCopy", &tools::csgDifferenceCopy<typename GridT::TreeType>}}) {
        const CopyKind fn = op.fn;
        t.def(
            op.name,
            [fn](const GridT& a, const GridT& b) {
                py::gil_scoped_release release;
                return fn(a, b, true);
            },
            py::arg("a"), py::arg("b"),
            "...Copy(a, b) -> grid: the result as a new grid; a and b are unchanged.");
    }
}

template <typename GridT>
void bindMorphology(py::module_& t) {
    t.def(
        "dilateActiveValues",
        [](GridT& g, int iterations, tools::NearestNeighbors nn, tools::TilePolicy mode) {
            checkUnpinned(&g.tree(), "dilateActiveValues");
            if (iterations < 0)
                throw py::value_error("dilateActiveValues: iterations must not be negative");
            py::gil_scoped_release release;
            tools::dilateActiveValues(g.tree(), iterations, nn, mode);
        },
        py::arg("grid"), py::arg("iterations") = 1, py::arg("nn") = tools::NN_FACE,
        py::arg("mode") = tools::PRESERVE_TILES,
        "dilateActiveValues(grid, iterations=1, nn=NN_FACE, mode=PRESERVE_TILES): activate "
        "the neighbours of active voxels, `iterations` times.");
    t.def(
        "erodeActiveValues",
        [](GridT& g, int iterations, tools::NearestNeighbors nn, tools::TilePolicy mode) {
            checkUnpinned(&g.tree(), "erodeActiveValues");
            if (iterations < 0)
                throw py::value_error("erodeActiveValues: iterations must not be negative");
            py::gil_scoped_release release;
            tools::erodeActiveValues(g.tree(), iterations, nn, mode);
        },
        py::arg("grid"), py::arg("iterations") = 1, py::arg("nn") = tools::NN_FACE,
        py::arg("mode") = tools::PRESERVE_TILES,
        "erodeActiveValues(grid, iterations=1, nn=NN_FACE, mode=PRESERVE_TILES): deactivate "
        "active voxels with an inactive neighbour, `iterations` times.");
}

template <typename GridT>
void bindLevelSetTools(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "levelSetRebuild",
        [](const GridT& g, float isovalue, float halfWidth) {
            py::gil_scoped_release release;
            return tools::levelSetRebuild(g, isovalue, halfWidth);
        },
        py::arg("grid"), py::arg("isovalue") = 0.0f, py::arg("halfWidth") = 3.0f,
        "levelSetRebuild(grid, isovalue=0, halfWidth=3) -> grid: a clean narrow-band level set "
        "of the isosurface.");
    t.def(
        "pruneLevelSet",
        [](GridT& g) {
            checkUnpinned(&g.tree(), "pruneLevelSet");
            py::gil_scoped_release release;
            tools::pruneLevelSet(g.tree());
        },
        py::arg("grid"),
        "pruneLevelSet(grid): replace inactive nodes with tiles of -background inside and "
        "+background outside.");
    t.def(
        "advect",
        [](GridT& g, const math::Vec3<ValueT>& velocity, double t0, double t1) {
            checkUnpinned(&g.tree(), "advect");
            py::gil_scoped_release release;
            tools::ConstantVelocityField<ValueT> field(velocity);
            tools::LevelSetAdvection<GridT, tools::ConstantVelocityField<ValueT>> adv(g, field);
            return adv.advect(t0, t1);
        },
        py::arg("grid"), py::arg("velocity"), py::arg("t0"), py::arg("t1"),
        "advect(grid, velocity, t0, t1) -> steps: move a level set with a constant world-space "
        "velocity from time t0 to t1 (HJWENO5 in space, TVD-RK2 in time, band rebuilt after "
        "each CFL-limited step).");
    if constexpr (std::is_same_v<GridT, FloatGrid>) {
        t.def(
            "advect",
            [](FloatGrid& g, const Vec3SGrid& velocity, double t0, double t1) {
                checkUnpinned(&g.tree(), "advect");
                py::gil_scoped_release release;
                tools::DiscreteField<Vec3SGrid> field(velocity);
                tools::LevelSetAdvection<FloatGrid, tools::DiscreteField<Vec3SGrid>> adv(g, field);
                return adv.advect(t0, t1);
            },
            py::arg("grid"), py::arg("velocity"), py::arg("t0"), py::arg("t1"),
            "advect(grid, velocityGrid, t0, t1) -> steps: move a level set with the velocities "
            "of a Vec3SGrid (staggered when its class is STAGGERED), sampled trilinearly.");
        t.def(
            "advectEnright",
            [](FloatGrid& g, double t0, double t1) {
                checkUnpinned(&g.tree(), "advectEnright");
                py::gil_scoped_release release;
                tools::EnrightField<float> field;
                tools::LevelSetAdvection<FloatGrid, tools::EnrightField<float>> adv(g, field);
                return adv.advect(t0, t1);
            },
            py::arg("grid"), py::arg("t0"), py::arg("t1"),
            "advectEnright(grid, t0, t1) -> steps: move a level set in the Enright test's "
            "periodic deformation field (period 3), the benchmark of the paper's section 5.");
        t.def(
            "createEnrightSphere",
            [](int resolution, float halfWidth) {
                py::gil_scoped_release release;
                return tools::createEnrightSphere<FloatGrid>(resolution, halfWidth);
            },
            py::arg("resolution"), py::arg("halfWidth") = 5.0f,
            "createEnrightSphere(resolution, halfWidth=5) -> FloatGrid: radius 0.15 at "
            "(0.35, 0.35, 0.35) with voxel size 1 / resolution.");
    }
}

}  // namespace

void bindTools(py::module_&, py::module_& t) {
    py::enum_<tools::NearestNeighbors>(t, "NearestNeighbors")
        .value("NN_FACE", tools::NN_FACE)
        .value("NN_FACE_EDGE", tools::NN_FACE_EDGE)
        .value("NN_FACE_EDGE_VERTEX", tools::NN_FACE_EDGE_VERTEX)
        .export_values();
    py::enum_<tools::TilePolicy>(t, "TilePolicy")
        .value("IGNORE_TILES", tools::IGNORE_TILES)
        .value("EXPAND_TILES", tools::EXPAND_TILES)
        .value("PRESERVE_TILES", tools::PRESERVE_TILES)
        .export_values();

    RealGridTypes::forEach([&]<typename GridT>() { bindCsg<GridT>(t); });
    NumericGridTypes::Append<BoolGrid, MaskGrid>::forEach(
        [&]<typename GridT>() { bindMorphology<GridT>(t); });
    RealGridTypes::forEach([&]<typename GridT>() { bindLevelSetTools<GridT>(t); });

    t.def(
        "createLevelSetSphere",
        [](double radius, const Vec3d& center, double voxelSize, double halfWidth,
           py::object gridType) -> GridBase::Ptr {
            const bool isDouble = gridType.is(py::type::of<DoubleGrid>());
            if (!isDouble && !gridType.is_none() && !gridType.is(py::type::of<FloatGrid>()))
                throw py::type_error(
                    "createLevelSetSphere: gridType must be FloatGrid or "
                    "DoubleGrid");
            py::gil_scoped_release release;
            if (isDouble)
                return tools::createLevelSetSphere<DoubleGrid>(radius, center, voxelSize,
                                                               halfWidth);
            return tools::createLevelSetSphere<FloatGrid>(radius, center, voxelSize, halfWidth);
        },
        py::arg("radius"), py::arg("center") = Vec3d(0.0), py::arg("voxelSize") = 1.0,
        py::arg("halfWidth") = 3.0, py::arg("gridType") = py::none(),
        "createLevelSetSphere(radius, center=(0, 0, 0), voxelSize=1, halfWidth=3, "
        "gridType=FloatGrid) -> grid: the narrow-band level set of a sphere.");
}

}  // namespace vdb::python
