// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb tomesh IN.vdb -o OUT.obj|.ply|.stl`: the isosurface of a grid as a polygon mesh file.

#include <vdb/meshio/MeshWriter.h>
#include <vdb/tools/VolumeToMesh.h>

#include "Commands.h"
#include "Geometry.h"
#include "SurfaceGrid.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace vdb::app {

GridBase::Ptr pickSurfaceGrid(const GridPtrVec& grids, const std::string& name,
                              const std::string& path) {
    const auto isFloating = [](const GridBase::Ptr& grid) {
        return gridIsOneOf<RealGridTypes>(*grid);
    };
    const GridPtrVec candidates = selectGrids(grids, name, path);
    if (!name.empty()) {
        const GridBase::Ptr& grid = candidates.front();
        if (!isFloating(grid))
            throw UsageError("grid \"" + name + "\" of " + path + " holds " + grid->valueType() +
                             " values; a surface needs a float or double grid");
        return grid;
    }
    for (const auto& grid : candidates)
        if (isFloating(grid) && grid->getGridClass() == GRID_LEVEL_SET)
            return grid;
    for (const auto& grid : candidates)
        if (isFloating(grid))
            return grid;
    throw UsageError(path + " has no float or double grid");
}

double isovalueFor(const GridBase& grid, const std::optional<double>& isovalue) {
    if (isovalue)
        return *isovalue;
    return grid.getGridClass() == GRID_FOG_VOLUME ? 0.5 : 0.0;
}

void checkSurfacePrecision(const GridBase& grid, double voxelSize) {
    const CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty())
        return;
    checkFloatPrecision(grid.transform().indexToWorld(box),
                        std::min(voxelSize, grid.voxelSize()[0]),
                        "the surface of grid \"" + grid.getName() + "\"");
}

void addToMeshCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input;
        std::string output;
        std::string grid;
        std::optional<double> isovalue;
        double adaptivity = 0.0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "tomesh", "Write the isosurface of a grid as a polygon mesh (OBJ, PLY, STL)",
        true, [args, &ctx] {
            const Args& a = *args;
            if (a.isovalue && !std::isfinite(*a.isovalue))
                throw UsageError("--isovalue must be a finite number");
            checkOutputPath(a.output);
            try {
                meshio::meshFormatOf(a.output);
            } catch (const IoError&) {
                throw UsageError("output " + a.output +
                                 ": unknown mesh format (use .obj, .ply or .stl)");
            }
            Report report(ctx);
            const GridPtrVec grids =
                report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
            const GridBase::Ptr grid = pickSurfaceGrid(grids, a.grid, a.input);
            const double iso = isovalueFor(*grid, a.isovalue);
            checkSurfacePrecision(*grid, grid->voxelSize()[0]);
            std::ostringstream label;
            label << "mesh grid \"" << grid->getName() << "\" at isovalue " << iso;
            if (a.adaptivity > 0)
                label << ", adaptivity " << a.adaptivity;
            meshio::Mesh mesh;
            const auto start = std::chrono::steady_clock::now();
            report.step(label.str(), [&] {
                tools::volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads, iso,
                                    a.adaptivity);
            });
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            report.json()
                .key("grid")
                .value(grid->getName())
                .key("isovalue")
                .value(iso)
                .key("adaptivity")
                .value(a.adaptivity);
            reportMesh(report, mesh);
            if (mesh.points.empty())
                throw UsageError("grid \"" + grid->getName() + "\" has no surface at isovalue " +
                                 numberText(iso) + ": an empty mesh is not written");
            report.step("write " + a.output, [&] { meshio::writeMesh(a.output, mesh); });
            std::error_code ec;
            const auto bytes = std::filesystem::file_size(a.output, ec);
            report.json()
                .key("seconds")
                .value(seconds)
                .key("output")
                .value(a.output)
                .key("outputBytes")
                .value(static_cast<uint64_t>(ec ? 0 : bytes));
            report.finish();
        });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    cmd->add_option("-o,--output", args->output,
                    "The mesh file to write: .obj, .ply (binary) or .stl (binary); replaced "
                    "atomically")
        ->required();
    cmd->add_option("-g,--grid", args->grid,
                    "The grid to mesh (default: the first float or double level set, else the "
                    "first float or double grid)");
    cmd->add_option("-i,--isovalue", args->isovalue,
                    "The value of the surface (default: 0, or 0.5 for fog volumes)");
    cmd->add_option("-a,--adaptivity", args->adaptivity,
                    "0: a quad per surface voxel; up to 1: merge flat regions into larger "
                    "polygons")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->footer(
        "Polygons wind counter-clockwise seen from outside, as the formats expect.\n"
        "Examples:\n  vdb tomesh bunny.vdb -o bunny.ply\n"
        "  vdb tomesh smoke.vdb -o smoke.obj --grid density --isovalue 0.2 --adaptivity 0.5");
}

}  // namespace vdb::app
