// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb advect`: move a level set through a velocity field (Enright's test field, a constant
/// velocity or a vector grid) with HJ-WENO5 / TVD-RK3 and narrow-band rebuilds; and
/// `vdb enright`: the Enright test, reporting the volume lost after the field's period.

#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/VelocityFields.h>

#include "Commands.h"

#include <cmath>
#include <cstdio>

namespace vdb::app {
namespace {

math::BiasedGradientScheme parseSpatial(const std::string& name) {
    return name == "first" ? math::FIRST_BIAS : math::HJWENO5_BIAS;
}

math::TemporalIntegrationScheme parseTemporal(const std::string& name) {
    if (name == "rk1")
        return math::TVD_RK1;
    if (name == "rk2")
        return math::TVD_RK2;
    return math::TVD_RK3;
}

/// The file of frame `frame` (1-based) of `count` written to `path`, by the tool's
/// frame-number rule (framePath: a run of # is the frame number): `path` itself for a single
/// frame without #.
std::string frameOutput(const std::string& path, int frame, int count, const std::string& option) {
    if (count <= 1 && !frameHashRun(path, option + " " + path))
        return path;
    return framePath(path, madeFrame(uint64_t(frame)), option);
}

struct SchemeArgs {
    std::string spatial = "weno5";
    std::string temporal = "rk3";
    double cfl = 0.5;
};

void addSchemeOptions(CLI::App& cmd, SchemeArgs& s) {
    cmd.add_option("--spatial", s.spatial, "Spatial scheme: weno5 (HJ-WENO5) or first (upwind)")
        ->check(CLI::IsMember({"weno5", "first"}))
        ->capture_default_str();
    cmd.add_option("--temporal", s.temporal, "Time integration: rk1, rk2 or rk3 (TVD Runge-Kutta)")
        ->check(CLI::IsMember({"rk1", "rk2", "rk3"}))
        ->capture_default_str();
    cmd.add_option("--cfl", s.cfl, "CFL number of the advection steps")
        ->check(finiteRange(0.01, 1.0))
        ->capture_default_str();
}

/// Advects `grid` from t0 to t1 through `field` in `frames` frames, writing each frame.
template <typename GridT, typename FieldT>
void advectFrames(Report& report, const typename GridT::Ptr& gridPtr, const FieldT& field,
                  const SchemeArgs& s, double t0, double t1, int frames, const OutputArgs& out) {
    GridT& grid = *gridPtr;
    tools::LevelSetAdvection<GridT, FieldT> advection(grid, field);
    advection.setSpatialScheme(parseSpatial(s.spatial));
    advection.setTemporalScheme(parseTemporal(s.temporal));
    advection.setCFL(static_cast<typename GridT::ValueType>(s.cfl));
    size_t steps = 0;
    report.json().key("frames").beginArray();
    for (int f = 1; f <= frames; ++f) {
        const double from = t0 + (t1 - t0) * (f - 1) / frames;
        const double to = t0 + (t1 - t0) * f / frames;
        constexpr uint64_t kTicks = 1000;
        report.step(
            "advect frame " + std::to_string(f) + "/" + std::to_string(frames),
            [&](Progress& progress) {
                double t = from;
                while (std::abs(to - t) > 1e-12 * std::max(1.0, std::abs(to))) {
                    const double dt = advection.step(t, to - t);
                    if (dt == 0)
                        break;  // only when no time is left to advance
                    t += dt;
                    ++steps;
                    progress.set(static_cast<uint64_t>(kTicks * (t - from) / (to - from)));
                }
            },
            kTicks);
        OutputArgs frameOut = out;
        frameOut.path = frameOutput(out.path, f, frames, "-o");
        requireNonEmpty(grid, "the level set at t = " + numberText(to));
        report.note("  t = " + numberText(to) + ", " + withCommas(steps) + " steps so far");
        report.json().beginObject().key("time").value(to).key("steps").value(
            static_cast<uint64_t>(steps));
        reportGrid(report, grid);
        writeOutput(report, frameOut, {gridPtr});  // and the output's keys
        report.json().endObject();
    }
    report.json().endArray();
}

void addAdvectCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input, grid;
        OutputArgs out;
        std::string field = "enright";
        std::vector<double> velocity{1.0, 0.0, 0.0};
        std::string velocityFile, velocityGrid;
        double start = 0.0;
        double time = 1.0;
        int frames = 1;
        SchemeArgs schemes;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "advect", "Advect a level set through a velocity field", true, [args, &ctx] {
            const Args& a = *args;
            checkOutputPath(frameOutput(a.out.path, 1, a.frames, "-o"));
            Report report(ctx);
            const GridPtrVec grids =
                report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
            GridBase::Ptr base;
            for (const auto& g : selectGrids(grids, a.grid, a.input))
                if (!base && (!a.grid.empty() || g->getGridClass() == GRID_LEVEL_SET))
                    base = g;
            if (!base)
                throw UsageError(a.input + " has no level set grid; name one with --grid");
            auto grid = gridPtrCast<FloatGrid>(base);
            if (!grid)
                throw UsageError("grid \"" + base->getName() + "\" has type " + base->type() +
                                 "; advect needs a float level set");
            report.json().key("input").value(a.input).key("field").value(a.field);
            // Steps: the distance the fastest velocity covers over the run, in CFL-sized steps.
            const double dx = grid->transform().voxelSize().minComponent();
            const auto checkSteps = [&](double speed) {
                checkStepEstimate(std::abs(a.time) * speed / (a.schemes.cfl * dx),
                                  "advecting for " + numberText(a.time) + " time units");
            };
            if (a.field == "enright") {
                checkSteps(1.1);  // the band's largest speed over the field's period, about 1.1
                const tools::EnrightField<float> field;
                advectFrames<FloatGrid>(report, grid, field, a.schemes, a.start, a.start + a.time,
                                        a.frames, a.out);
            } else if (a.field == "constant") {
                checkSteps(Vec3d(a.velocity[0], a.velocity[1], a.velocity[2]).length());
                const tools::ConstantVelocityField<float> field(
                    Vec3f(float(a.velocity[0]), float(a.velocity[1]), float(a.velocity[2])));
                advectFrames<FloatGrid>(report, grid, field, a.schemes, a.start, a.start + a.time,
                                        a.frames, a.out);
            } else {
                if (a.velocityFile.empty())
                    throw UsageError("--field grid needs --velocity-file");
                const GridPtrVec vgrids = report.step(
                    "read " + a.velocityFile, [&] { return readGrids(a.velocityFile, ctx); });
                Vec3SGrid::Ptr velocity;
                for (const auto& g : selectGrids(vgrids, a.velocityGrid, a.velocityFile))
                    if (!velocity)
                        velocity = gridPtrCast<Vec3SGrid>(g);
                if (!velocity)
                    throw UsageError(a.velocityFile + " has no vec3s grid for the velocity");
                double speed = double(velocity->background().length());
                for (auto it = velocity->cbeginValueOn(); it; ++it) {
                    const double v = double(it.getValue().length());
                    if (!std::isfinite(v))
                        throw UsageError("the velocity grid \"" + velocity->getName() + "\" of " +
                                         a.velocityFile + " holds a non-finite value at " +
                                         std::to_string(it.getCoord()[0]) + "," +
                                         std::to_string(it.getCoord()[1]) + "," +
                                         std::to_string(it.getCoord()[2]));
                    speed = std::max(speed, v);
                }
                checkSteps(speed);
                const tools::DiscreteField<Vec3SGrid> field(*velocity);
                advectFrames<FloatGrid>(report, grid, field, a.schemes, a.start, a.start + a.time,
                                        a.frames, a.out);
            }
            report.finish();
        });
    cmd->add_option("input", args->input, "The .vdb file with the level set")->required();
    cmd->add_option("-g,--grid", args->grid, "The level set grid (default: the first)");
    addOutputOptions(*cmd, args->out);
    cmd->add_option("--field", args->field, "Velocity: enright, constant or grid")
        ->check(CLI::IsMember({"enright", "constant", "grid"}))
        ->capture_default_str();
    cmd->add_option("--velocity", args->velocity, "Constant velocity x,y,z (world units)")
        ->expected(3)
        ->delimiter(',')
        ->check(finite())
        ->capture_default_str();
    cmd->add_option("--velocity-file", args->velocityFile,
                    "A .vdb file with a vec3s velocity grid");
    cmd->add_option("--velocity-grid", args->velocityGrid, "Its grid name (default: the first)");
    cmd->add_option("--start", args->start, "Start time")
        ->check(finiteRange(-1e9, 1e9))
        ->capture_default_str();
    cmd->add_option("-t,--time", args->time, "Time to advect for")
        ->check(finiteRange(-1e6, 1e6))
        ->capture_default_str();
    cmd->add_option("--frames", args->frames,
                    "Write this many frames (a run of # in OUT's file name is the frame number: "
                    "# writes 0001, ### writes 001)")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    addSchemeOptions(*cmd, args->schemes);
    addStepLimitOption(*cmd, ctx);
    cmd->footer(
        "Examples:\n  vdb advect sphere.vdb -o moved.vdb --field constant --velocity "
        "1,0,0 --time 0.5\n  vdb advect enright.vdb -o frame_#.vdb --field enright "
        "--time 3 --frames 30");
}

void addEnrightCommand(CLI::App& app, Context& ctx) {
    struct Args {
        int resolution = 128;
        int frames = 12;
        double time = tools::EnrightField<float>::PERIOD;
        float halfWidth = 5.0f;
        std::string framesOut;
        SchemeArgs schemes;
        std::string compression = "blosc";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "enright",
        "The Enright test: a sphere advected through the period of Enright's field", true,
        [args, &ctx] {
            const Args& a = *args;
            if (!a.framesOut.empty())
                checkOutputPath(frameOutput(a.framesOut, 1, a.frames, "--write-frames"));
            // The sphere's band in three time levels plus the rebuild's copies; its steps as
            // in advect.
            const double r = 0.15 * a.resolution;
            checkMemoryEstimate(4.0 * levelSetBytes(4.0 * 3.14159265 * r * r, a.halfWidth),
                                "the Enright test at this resolution");
            checkStepEstimate(a.time * 1.1 * a.resolution / a.schemes.cfl,
                              "the Enright test over " + numberText(a.time) + " time units");
            tools::EnrightTestOptions options;
            options.resolution = a.resolution;
            options.frames = a.frames;
            options.endTime = a.time;
            options.halfWidth = a.halfWidth;
            options.spatialScheme = parseSpatial(a.schemes.spatial);
            options.temporalScheme = parseTemporal(a.schemes.temporal);
            options.cfl = a.schemes.cfl;
            Report report(ctx);
            report.note("  frame      time      steps        volume    active voxels");
            report.json().key("resolution").value(a.resolution).key("samples").beginArray();
            int frame = 0;
            const tools::EnrightResult result = report.step(
                "Enright test at " + std::to_string(a.resolution) + "^3",
                [&](Progress& progress) {
                    return tools::runEnrightTest<FloatGrid>(
                        options, [&](const tools::EnrightSample& s, const FloatGrid& grid) {
                            char line[160];
                            std::snprintf(line, sizeof line, "  %5d  %8.4f  %9zu  %12.8f  %15s",
                                          frame, s.time, s.steps, s.volume,
                                          withCommas(s.activeVoxels).c_str());
                            report.note(line);
                            report.json()
                                .beginObject()
                                .key("time")
                                .value(s.time)
                                .key("steps")
                                .value(static_cast<uint64_t>(s.steps))
                                .key("volume")
                                .value(s.volume)
                                .key("activeVoxels")
                                .value(static_cast<uint64_t>(s.activeVoxels))
                                .endObject();
                            if (frame > 0 && !a.framesOut.empty()) {
                                auto copy = grid.deepCopy();
                                copy->setName("enright");
                                writeGrids(
                                    frameOutput(a.framesOut, frame, a.frames, "--write-frames"),
                                    {copy}, parseCompression(a.compression));
                            }
                            progress.set(static_cast<uint64_t>(frame));
                            ++frame;
                        });
                },
                static_cast<uint64_t>(a.frames));
            report.json().endArray().key("volumeLoss").value(result.volumeLoss());
            char summary[128];
            std::snprintf(summary, sizeof summary,
                          "  volume %.8f -> %.8f: %.3f%% lost (analytic %.8f)",
                          result.initial.volume, result.final.volume, 100.0 * result.volumeLoss(),
                          4.0 / 3.0 * 3.14159265358979 * 0.15 * 0.15 * 0.15);
            report.note(summary);
            report.finish();
        });
    cmd->add_option("-r,--resolution", args->resolution, "Voxels per unit length")
        ->check(CLI::Range(8, 4096))
        ->capture_default_str();
    cmd->add_option("--frames", args->frames, "Samples (and written frames) over the run")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    cmd->add_option("-t,--time", args->time, "End time (the field's period by default)")
        ->check(positive())
        ->capture_default_str();
    cmd->add_option("-w,--half-width", args->halfWidth, "Half the band width, in voxels")
        ->check(finiteRange(2.0, 100.0))
        ->capture_default_str();
    cmd->add_option("--write-frames", args->framesOut,
                    "Write each frame to this .vdb path (a run of # in its file name is the frame "
                    "number: # writes 0001, ### writes 001)");
    cmd->add_option("--compression", args->compression, "Compression of written frames")
        ->check(CLI::IsMember({"none", "zip", "blosc", "raw"}))
        ->capture_default_str();
    addSchemeOptions(*cmd, args->schemes);
    addStepLimitOption(*cmd, ctx);
    cmd->footer(
        "Examples:\n  vdb enright --resolution 128\n"
        "  vdb enright -r 256 --frames 30 --write-frames enright_#.vdb --json");
}

}  // namespace

void addAdvectCommands(CLI::App& app, Context& ctx) {
    addAdvectCommand(app, ctx);
    addEnrightCommand(app, ctx);
}

}  // namespace vdb::app
