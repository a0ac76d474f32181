// SPDX-License-Identifier: Apache-2.0
/// @file
/// The fast sweeping subcommands:
/// - `vdb redistance IN.vdb -o OUT.vdb`: a signed distance field on the active voxels of a
///   level set with a distorted band, or of a fog volume (tools::sdfToSdf, tools::fogToSdf).
/// - `vdb extend IN.vdb --field F.vdb -o OUT.vdb`: a field (velocity, colour, temperature)
///   sampled on IN's isosurface and extended along the surface normals through IN's active
///   voxels (tools::sdfToExt, tools::fogToExt).
///
/// Whether the input is a fog volume or a level set comes from its grid class: a grid of
/// class "fog volume" is dense inside (values above the isovalue are inside, default isovalue
/// 0.5); any other class (level set, unknown, staggered) is a signed distance field (values
/// below the isovalue are inside, default isovalue 0). --fog treats any grid as a fog volume.

#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/Interpolation.h>

#include "Commands.h"
#include "SurfaceGrid.h"

#include <cmath>
#include <optional>
#include <sstream>

namespace vdb::app {
namespace {

/// The options both commands share.
struct SweepArgs {
    std::string input;
    OutputArgs out;
    std::string grid;
    std::optional<double> isovalue;
    int iterations = 1;
    bool fog = false;
};

void addSweepOptions(CLI::App& cmd, SweepArgs& args) {
    cmd.add_option("input", args.input, "The .vdb file to read")->required();
    addOutputOptions(cmd, args.out);
    cmd.add_option("-g,--grid", args.grid,
                   "The surface grid (default: the first float or double level set, else the "
                   "first float or double grid)");
    cmd.add_option("-i,--isovalue", args.isovalue,
                   "The value of the surface (default: 0, or 0.5 for fog volumes)")
        ->check(finite());
    cmd.add_option("-n,--iterations", args.iterations,
                   "Iterations of eight sweeps (more for concave shapes)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    cmd.add_flag("--fog", args.fog,
                 "Treat the grid as a fog volume (inside above the isovalue) whatever its class");
}

/// The surface grid of the input, whether it is a fog volume, and the isovalue.
struct SweepInput {
    GridBase::Ptr grid;
    bool fog = false;
    double iso = 0.0;
};

/// Reads and checks the surface grid: float or double values, cubic voxels, and no more memory
/// than allowed once active tiles become voxels (the result and the input's copy).
SweepInput readSweepInput(Report& report, const SweepArgs& a, const Context& ctx) {
    const GridPtrVec grids =
        report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
    SweepInput in;
    in.grid = pickSurfaceGrid(grids, a.grid, a.input);
    if (!in.grid->transform().isLinear() || !in.grid->transform().hasUniformScale())
        throw UsageError("grid \"" + in.grid->getName() +
                         "\" has a transform that is not linear with a uniform scale; distances "
                         "need cubic voxels");
    const double bytesPerVoxel = gridPtrCast<FloatGrid>(in.grid) ? 4.0 : 8.0;
    checkMemoryEstimate(3.0 * double(in.grid->activeVoxelCount()) * bytesPerVoxel * 1.3,
                        "fast sweeping of grid \"" + in.grid->getName() + "\"");
    in.fog = a.fog || in.grid->getGridClass() == GRID_FOG_VOLUME;
    in.iso = a.isovalue ? *a.isovalue : (in.fog ? 0.5 : 0.0);
    return in;
}

/// Adds the surface grid's name, whether it is a fog volume and the isovalue to the JSON
/// document.
void reportSweepInput(Report& report, const SweepInput& in) {
    report.json()
        .key("grid")
        .value(in.grid->getName())
        .key("fogVolume")
        .value(in.fog)
        .key("isovalue")
        .value(in.iso);
}

std::string noSurfaceMessage(const GridBase& grid, double iso) {
    std::ostringstream msg;
    msg << "the isovalue " << iso << " does not cross the active values of grid \""
        << grid.getName() << "\": no voxel lies next to the surface";
    return msg.str();
}

}  // namespace

void addFastSweepCommands(CLI::App& app, Context& ctx) {
    // ---- redistance
    auto args = std::make_shared<SweepArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "redistance",
        "Recompute signed distances over the active voxels of a level set or fog volume (fast "
        "sweeping)",
        true, [args, &ctx] {
            const SweepArgs& a = *args;
            runCreate(ctx, a.out, {}, [&](Report& report) {
                const SweepInput in = readSweepInput(report, a, ctx);
                std::ostringstream label;
                label << "redistance " << (in.fog ? "fog volume" : "level set") << " \""
                      << in.grid->getName() << "\" at isovalue " << in.iso;
                GridBase::Ptr result;
                withLevelSetGrid(in.grid, [&](auto& g) {
                    using GridT = std::decay_t<decltype(g)>;
                    result = report.step(label.str(), [&] {
                        tools::FastSweeping<GridT> fs;
                        fs.initSdf(g, typename GridT::ValueType(in.iso), !in.fog);
                        if (fs.boundaryVoxelCount() == 0)
                            throw UsageError(noSurfaceMessage(g, in.iso));
                        fs.sweep(a.iterations);
                        fs.sdfGrid()->setGridClass(GRID_LEVEL_SET);
                        return GridBase::Ptr(fs.sdfGrid());
                    });
                });
                reportSweepInput(report, in);
                return result;
            });
        });
    addSweepOptions(*cmd, *args);
    cmd->footer(
        "A grid of class fog volume is inside where it is above the isovalue; any other grid is "
        "a signed distance field, inside below it (--fog overrides).\n"
        "Examples:\n  vdb redistance smoothed.vdb -o clean.vdb\n"
        "  vdb redistance smoke.vdb -o smoke-sdf.vdb --grid density --isovalue 0.2");

    // ---- extend
    struct ExtendArgs {
        SweepArgs sweep;
        std::string field;
        std::string fieldGrid;
    };
    auto ext = std::make_shared<ExtendArgs>();
    CLI::App* extend = addCommand(
        app, ctx, "extend",
        "Extend a field (velocity, colour) off a surface along its normals through the surface "
        "grid's active voxels (fast sweeping)",
        true, [ext, &ctx] {
            const SweepArgs& a = ext->sweep;
            runCreate(ctx, a.out, {}, [&](Report& report) {
                const SweepInput in = readSweepInput(report, a, ctx);
                const GridPtrVec fields =
                    report.step("read " + ext->field, [&] { return readGrids(ext->field, ctx); });
                const GridBase::Ptr field = selectGrids(fields, ext->fieldGrid, ext->field).front();
                if (field->activeVoxelCount() == 0)
                    throw UsageError("field grid \"" + field->getName() + "\" of " + ext->field +
                                     " has no active values");
                std::ostringstream label;
                label << "extend field \"" << field->getName() << "\" off the surface of \""
                      << in.grid->getName() << "\" at isovalue " << in.iso;
                GridBase::Ptr result;
                withLevelSetGrid(in.grid, [&](auto& g) {
                    using GridT = std::decay_t<decltype(g)>;
                    withRealGrid(field, "extend takes fields of", [&](auto& f) {
                        using FieldGridT = std::decay_t<decltype(f)>;
                        using ExtValueT = typename FieldGridT::ValueType;
                        result = report.step(label.str(), [&] {
                            tools::FastSweeping<GridT, ExtValueT> fs;
                            fs.initExt(g, tools::WorldSampler(f), f.background(),
                                       typename GridT::ValueType(in.iso), !in.fog);
                            if (fs.boundaryVoxelCount() == 0)
                                throw UsageError(noSurfaceMessage(g, in.iso));
                            fs.sweep(a.iterations);
                            return GridBase::Ptr(fs.extGrid());
                        });
                    });
                });
                result->setName(field->getName());
                result->setGridClass(field->getGridClass());
                reportSweepInput(report, in);
                return result;
            });
        });
    addSweepOptions(*extend, ext->sweep);
    extend->add_option("-f,--field", ext->field, "The .vdb file of the field to extend")
        ->required();
    extend->add_option("--field-grid", ext->fieldGrid,
                       "The field's grid (default: the first grid of the field file)");
    extend->footer(
        "The field is sampled (trilinearly, at world positions) where the surface crosses the "
        "active voxels; the result has the surface grid's transform and active voxels.\n"
        "Example:\n  vdb extend liquid.vdb --field vel.vdb --field-grid vel -o vel-ext.vdb");
}

}  // namespace vdb::app
