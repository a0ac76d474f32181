// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb rebuild IN.vdb -o OUT.vdb`: a clean narrow-band level set of a grid's isosurface (a fog
/// volume's surface, a distorted band, or a level set at another voxel size or band width).

#include <vdb/tools/LevelSetRebuild.h>

#include "Commands.h"
#include "SurfaceGrid.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace vdb::app {

void addRebuildCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input;
        OutputArgs out;
        std::string grid;
        std::optional<double> isovalue;
        float halfWidth = 3.0f;
        double voxelSize = 0.0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "rebuild",
        "Rebuild a clean narrow-band level set of a grid's isosurface (fog volume, distorted "
        "band, new voxel size)",
        true, [args, &ctx] {
            const Args& a = *args;
            if (a.isovalue && !std::isfinite(*a.isovalue))
                throw UsageError("--isovalue must be a finite number");
            runCreate(
                ctx, a.out, {},
                [&](Report& report) {
                    const GridPtrVec grids =
                        report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
                    const GridBase::Ptr grid = pickSurfaceGrid(grids, a.grid, a.input);
                    // A non-uniform linear transform is rebuilt in its index space, as
                    // tools::levelSetRebuild documents; a frustum needs a new voxel size.
                    if (!grid->transform().isLinear() && a.voxelSize <= 0)
                        throw UsageError("grid \"" + grid->getName() +
                                         "\" has a frustum transform; a level set needs a "
                                         "linear one (give --voxel-size)");
                    const double iso = isovalueFor(*grid, a.isovalue);
                    math::Transform::Ptr xform = grid->transform().copy();
                    if (a.voxelSize > 0)
                        xform = math::Transform::createLinearTransform(a.voxelSize);
                    const Vec3d size = xform->voxelSize();
                    checkSurfacePrecision(*grid, std::min({size[0], size[1], size[2]}));
                    std::ostringstream label;
                    label << "rebuild grid \"" << grid->getName() << "\" at isovalue " << iso;
                    GridBase::Ptr result;
                    withLevelSetGrid(grid, [&](auto& g) {
                        result = report.step(label.str(), [&] {
                            return GridBase::Ptr(
                                tools::levelSetRebuild(g, float(iso), a.halfWidth, xform.get()));
                        });
                    });
                    result->setName(grid->getName());
                    report.json()
                        .key("grid")
                        .value(grid->getName())
                        .key("isovalue")
                        .value(iso)
                        .key("voxelSize")
                        .value(result->voxelSize()[0]);
                    return result;
                },
                "the isovalue does not cross the grid's values");
        });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    addOutputOptions(*cmd, args->out);
    cmd->add_option("-g,--grid", args->grid,
                    "The grid to rebuild (default: the first float or double level set, else "
                    "the first float or double grid)");
    cmd->add_option("-i,--isovalue", args->isovalue,
                    "The value of the surface (default: 0, or 0.5 for fog volumes)");
    cmd->add_option("-w,--half-width", args->halfWidth, "Half the band width, in voxels")
        ->check(CLI::Range(1.0f, 1000.0f))
        ->capture_default_str();
    cmd->add_option("-s,--voxel-size", args->voxelSize,
                    "Voxel edge of the result in world units (default: the input's)")
        ->check(positive());
    cmd->footer(
        "Examples:\n  vdb rebuild smoke.vdb -o smoke-sdf.vdb --grid density --isovalue 0.2\n"
        "  vdb rebuild bunny.vdb -o coarse.vdb --voxel-size 0.02 --half-width 4");
}

}  // namespace vdb::app
