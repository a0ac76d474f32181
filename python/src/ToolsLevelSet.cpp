// SPDX-License-Identifier: Apache-2.0
// vdb.tools: the level set utilities of LevelSetUtil.h (fog volumes, interior masks,
// segmentation) and the fast sweeping tools of FastSweeping.h (redistancing, dilation, masks
// and the extension of a field grid off a surface), with OpenVDB's names, for the grid types
// the C++ library instantiates them for.

#include <vdb/Exceptions.h>
#include <vdb/GridTypes.h>
#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/LevelSetUtil.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <limits>
#include <string>
#include <vector>

namespace vdb::python {

namespace {

/// Throws ValueError for a negative iteration count.
void checkIterations(int nIter, const char* op) {
    if (nIter < 0)
        throw py::value_error(std::string(op) + ": nIter must not be negative");
}

template <typename GridPtrT>
py::list toList(std::vector<GridPtrT>& grids) {
    py::list out;
    for (auto& g : grids)
        out.append(GridBase::Ptr(g));
    return out;
}

// ---- LevelSetUtil

template <typename GridT>
void bindFogVolume(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "sdfToFogVolume",
        [](GridT& g, py::object cutoff) {
            checkUnpinned(&g.tree(), "sdfToFogVolume");
            const ValueT c = cutoff.is_none() ? std::numeric_limits<ValueT>::max()
                                              : toValue<ValueT>(cutoff, "sdfToFogVolume");
            py::gil_scoped_release release;
            tools::sdfToFogVolume(g, c);
        },
        py::arg("grid"), py::arg("cutoffDistance") = py::none(),
        "sdfToFogVolume(grid, cutoffDistance=None): turn a level set (FloatGrid or DoubleGrid) "
        "into a fog volume in place: values d <= 0 become d / -cutoff (0 at the surface to 1 at "
        "depth cutoff, clamped to the deepest value; None: no limit), the interior tiles active "
        "tiles of 1, everything outside inactive 0. The grid class becomes FOG_VOLUME.");
}

void bindLevelSetUtil(py::module_& t) {
    RealGridTypes::forEach([&]<typename GridT>() { bindFogVolume<GridT>(t); });
    t.def(
        "sdfInteriorMask",
        [](const FloatGrid& g, float iso) {
            py::gil_scoped_release release;
            return tools::sdfInteriorMask(g, iso);
        },
        py::arg("grid"), py::arg("isovalue") = 0.0f,
        "sdfInteriorMask(grid, isovalue=0) -> BoolGrid: active and True where the FloatGrid's "
        "value is below isovalue (voxels and tiles, active or not).");
    t.def(
        "extractEnclosedRegion",
        [](const FloatGrid& g, float iso, const BoolGrid* fillMask) {
            py::gil_scoped_release release;
            return tools::extractEnclosedRegion(g, iso, fillMask ? &fillMask->tree() : nullptr);
        },
        py::arg("grid"), py::arg("isovalue") = 0.0f, py::arg("fillMask") = nullptr,
        "extractEnclosedRegion(grid, isovalue=0, fillMask=None) -> BoolGrid: the interior of a "
        "FloatGrid and the cavities it encloses (everything except the exterior region of "
        "values >= isovalue); with fillMask (a BoolGrid in the grid's index space), cavities "
        "not wholly inside the mask count as exterior.");
    t.def(
        "extractIsosurfaceMask",
        [](const FloatGrid& g, float iso) {
            py::gil_scoped_release release;
            return tools::extractIsosurfaceMask(g, iso);
        },
        py::arg("grid"), py::arg("isovalue"),
        "extractIsosurfaceMask(grid, isovalue) -> BoolGrid: the active voxels of a FloatGrid "
        "with a face neighbour on the other side of isovalue.");
    t.def(
        "extractActiveVoxelSegmentMasks",
        [](const FloatGrid& g) {
            std::vector<BoolGrid::Ptr> masks;
            {
                py::gil_scoped_release release;
                tools::extractActiveVoxelSegmentMasks(g, masks);
            }
            return toList(masks);
        },
        py::arg("grid"),
        "extractActiveVoxelSegmentMasks(grid) -> list of BoolGrid: one mask per face-connected "
        "component of the active voxels and tiles of a FloatGrid, largest first.");
    t.def(
        "segmentActiveVoxels",
        [](const FloatGrid& g) {
            std::vector<FloatGrid::Ptr> parts;
            {
                py::gil_scoped_release release;
                tools::segmentActiveVoxels(g, parts);
            }
            return toList(parts);
        },
        py::arg("grid"),
        "segmentActiveVoxels(grid) -> list of FloatGrid: one grid per face-connected component "
        "of the active voxels and tiles, holding its values, largest first (one empty grid "
        "when there are no active values).");
    t.def(
        "segmentSDF",
        [](const FloatGrid& g) {
            std::vector<FloatGrid::Ptr> parts;
            {
                py::gil_scoped_release release;
                tools::segmentSDF(g, parts);
            }
            return toList(parts);
        },
        py::arg("grid"),
        "segmentSDF(grid) -> list of FloatGrid: one flood-filled narrow-band level set per "
        "connected surface of a level set, largest first (one empty grid when there is no "
        "surface).");
}

// ---- Fast sweeping

template <typename GridT>
void bindSweeping(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    t.def(
        "fogToSdf",
        [](const GridT& g, ValueT iso, int nIter) {
            checkIterations(nIter, "fogToSdf");
            py::gil_scoped_release release;
            return tools::fogToSdf(g, iso, nIter);
        },
        py::arg("grid"), py::arg("isoValue"), py::arg("nIter") = 1,
        "fogToSdf(grid, isoValue, nIter=1) -> grid: the signed distance field of the isosurface "
        "at isoValue of a fog volume (FloatGrid or DoubleGrid; above isoValue is inside) on its "
        "active voxels, by nIter iterations of fast sweeping; marked LEVEL_SET.");
    t.def(
        "sdfToSdf",
        [](const GridT& g, ValueT iso, int nIter) {
            checkIterations(nIter, "sdfToSdf");
            py::gil_scoped_release release;
            return tools::sdfToSdf(g, iso, nIter);
        },
        py::arg("grid"), py::arg("isoValue") = ValueT(0), py::arg("nIter") = 1,
        "sdfToSdf(grid, isoValue=0, nIter=1) -> grid: restores |grad| = 1 over the active "
        "voxels of an approximate signed distance field (FloatGrid or DoubleGrid).");
    t.def(
        "dilateSdf",
        [](const GridT& g, int dilation, tools::NearestNeighbors nn, int nIter,
           tools::FastSweepingDomain mode) {
            checkIterations(nIter, "dilateSdf");
            if (dilation < 0)
                throw py::value_error("dilateSdf: the dilation must not be negative");
            py::gil_scoped_release release;
            return tools::dilateSdf(g, dilation, nn, nIter, mode);
        },
        py::arg("grid"), py::arg("dilation"), py::arg("nn") = tools::NN_FACE, py::arg("nIter") = 1,
        py::arg("mode") = tools::FastSweepingDomain::SWEEP_ALL,
        "dilateSdf(grid, dilation, nn=NN_FACE, nIter=1, mode=SWEEP_ALL) -> grid: the signed "
        "distance field with its band widened by `dilation` voxels (the old band keeps its "
        "values); SWEEP_GREATER_THAN_ISOVALUE or SWEEP_LESS_THAN_ISOVALUE grow only the outside "
        "or the inside.");
}

/// Binds fogToExt, sdfToExt, fogToSdfAndExt and sdfToSdfAndExt for surfaces of type GridT and
/// fields of type FieldGridT.
template <typename GridT, typename FieldGridT>
void bindExtension(py::module_& t) {
    using ValueT = typename GridT::ValueType;
    using ExtGridPtr = typename FieldGridT::ConstPtr;
    // The extension grid of the other side, sharing extGrid's tree; null for None.
    const auto other = [](const FieldGridT* extGrid, int nIter, const char* op) {
        checkIterations(nIter, op);
        return extGrid ? ExtGridPtr(extGrid->copy()) : ExtGridPtr();
    };
    const auto named = [](auto grid, const FieldGridT& field) {
        grid->setName(field.getName());
        grid->setGridClass(field.getGridClass());
        return GridBase::Ptr(grid);
    };
    const char* gridDoc = std::is_same_v<GridT, FloatGrid>
                              ? " (a FloatGrid surface with a FloatGrid or Vec3SGrid field)"
                              : " (a DoubleGrid surface with a DoubleGrid or Vec3DGrid field)";
    t.def(
        "fogToExt",
        [other, named](const GridT& g, const FieldGridT& field, ValueT iso, int nIter,
                       tools::FastSweepingDomain mode, const FieldGridT* extGrid) {
            const ExtGridPtr ext = other(extGrid, nIter, "fogToExt");
            py::gil_scoped_release release;
            return named(tools::fogToExt(g, tools::WorldSampler(field), field.background(), iso,
                                         nIter, mode, ext),
                         field);
        },
        py::arg("grid"), py::arg("field"), py::arg("isoValue"), py::arg("nIter") = 1,
        py::arg("mode") = tools::FastSweepingDomain::SWEEP_ALL, py::arg("extGrid") = nullptr,
        (std::string("fogToExt(grid, field, isoValue, nIter=1, mode=SWEEP_ALL, extGrid=None) -> "
                     "grid: the values of the grid `field`, sampled trilinearly where the "
                     "isosurface at isoValue of the fog volume `grid` crosses its active voxels, "
                     "extended along the surface normals through those voxels; the field's "
                     "background is the result's. With a mode other than SWEEP_ALL, extGrid "
                     "(same transform) gives the values on the other side") +
         gridDoc + ".")
            .c_str());
    t.def(
        "sdfToExt",
        [other, named](const GridT& g, const FieldGridT& field, ValueT iso, int nIter,
                       tools::FastSweepingDomain mode, const FieldGridT* extGrid) {
            const ExtGridPtr ext = other(extGrid, nIter, "sdfToExt");
            py::gil_scoped_release release;
            return named(tools::sdfToExt(g, tools::WorldSampler(field), field.background(), iso,
                                         nIter, mode, ext),
                         field);
        },
        py::arg("grid"), py::arg("field"), py::arg("isoValue") = ValueT(0), py::arg("nIter") = 1,
        py::arg("mode") = tools::FastSweepingDomain::SWEEP_ALL, py::arg("extGrid") = nullptr,
        (std::string("sdfToExt(grid, field, isoValue=0, nIter=1, mode=SWEEP_ALL, extGrid=None) "
                     "-> grid: as fogToExt for a signed distance field") +
         gridDoc + ".")
            .c_str());
    t.def(
        "fogToSdfAndExt",
        [other, named](const GridT& g, const FieldGridT& field, ValueT iso, int nIter,
                       tools::FastSweepingDomain mode, const FieldGridT* extGrid) {
            const ExtGridPtr ext = other(extGrid, nIter, "fogToSdfAndExt");
            py::gil_scoped_release release;
            auto [sdf, extension] = tools::fogToSdfAndExt(
                g, tools::WorldSampler(field), field.background(), iso, nIter, mode, ext);
            return std::make_pair(GridBase::Ptr(sdf), named(extension, field));
        },
        py::arg("grid"), py::arg("field"), py::arg("isoValue"), py::arg("nIter") = 1,
        py::arg("mode") = tools::FastSweepingDomain::SWEEP_ALL, py::arg("extGrid") = nullptr,
        (std::string("fogToSdfAndExt(grid, field, isoValue, nIter=1, mode=SWEEP_ALL, "
                     "extGrid=None) -> (sdf, ext): fogToSdf and fogToExt in one pass") +
         gridDoc + ".")
            .c_str());
    t.def(
        "sdfToSdfAndExt",
        [other, named](const GridT& g, const FieldGridT& field, ValueT iso, int nIter,
                       tools::FastSweepingDomain mode, const FieldGridT* extGrid) {
            const ExtGridPtr ext = other(extGrid, nIter, "sdfToSdfAndExt");
            py::gil_scoped_release release;
            auto [sdf, extension] = tools::sdfToSdfAndExt(
                g, tools::WorldSampler(field), field.background(), iso, nIter, mode, ext);
            return std::make_pair(GridBase::Ptr(sdf), named(extension, field));
        },
        py::arg("grid"), py::arg("field"), py::arg("isoValue") = ValueT(0), py::arg("nIter") = 1,
        py::arg("mode") = tools::FastSweepingDomain::SWEEP_ALL, py::arg("extGrid") = nullptr,
        (std::string("sdfToSdfAndExt(grid, field, isoValue=0, nIter=1, mode=SWEEP_ALL, "
                     "extGrid=None) -> (sdf, ext): sdfToSdf and sdfToExt in one pass") +
         gridDoc + ".")
            .c_str());
}

template <typename MaskGridT>
void bindMaskSdf(py::module_& t) {
    t.def(
        "maskSdf",
        [](const FloatGrid& g, const MaskGridT& mask, bool ignoreActiveTiles, int nIter) {
            checkIterations(nIter, "maskSdf");
            py::gil_scoped_release release;
            return tools::maskSdf(g, mask, ignoreActiveTiles, nIter);
        },
        py::arg("grid"), py::arg("mask"), py::arg("ignoreActiveTiles") = false,
        py::arg("nIter") = 1,
        "maskSdf(grid, mask, ignoreActiveTiles=False, nIter=1) -> FloatGrid: the signed "
        "distance field extended into the active voxels of `mask` (a MaskGrid, BoolGrid or "
        "FloatGrid with the same transform; a level set mask stands for its interior). Raises "
        "ValueError when the transforms differ.");
}

}  // namespace

void bindToolsLevelSet(py::module_& t) {
    py::enum_<tools::FastSweepingDomain>(t, "FastSweepingDomain",
                                         "Which voxels fast sweeping updates.")
        .value("SWEEP_ALL", tools::FastSweepingDomain::SWEEP_ALL)
        .value("SWEEP_GREATER_THAN_ISOVALUE",
               tools::FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE)
        .value("SWEEP_LESS_THAN_ISOVALUE", tools::FastSweepingDomain::SWEEP_LESS_THAN_ISOVALUE)
        .export_values();
    bindLevelSetUtil(t);
    RealGridTypes::forEach([&]<typename GridT>() { bindSweeping<GridT>(t); });
    bindMaskSdf<MaskGrid>(t);
    bindMaskSdf<BoolGrid>(t);
    bindMaskSdf<FloatGrid>(t);
    bindExtension<FloatGrid, FloatGrid>(t);
    bindExtension<FloatGrid, Vec3SGrid>(t);
    bindExtension<DoubleGrid, DoubleGrid>(t);
    bindExtension<DoubleGrid, Vec3DGrid>(t);
}

}  // namespace vdb::python
