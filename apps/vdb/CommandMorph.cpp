// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb morph dilate|erode N`, `vdb floodfill` and `vdb prune`: the topology tools applied to
/// the grids of a file, written to a new file with the other grids unchanged.

#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>

#include "Commands.h"

namespace vdb::app {
namespace {

tools::NearestNeighbors parseNeighbors(const std::string& name) {
    if (name == "face" || name == "6")
        return tools::NN_FACE;
    if (name == "edge" || name == "18")
        return tools::NN_FACE_EDGE;
    return tools::NN_FACE_EDGE_VERTEX;
}

/// An upper estimate of the voxels a dilation by `n` leaves active: every active voxel grown
/// by the neighbourhood's ball of radius n (an octahedron, a cube with its corners cut, or a
/// cube), and at most the active bounding box grown by n on every side.
double dilatedVoxels(const GridBase& grid, int n, tools::NearestNeighbors nn) {
    const CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
    if (bbox.empty())
        return 0.0;
    double box = 1.0;
    for (const Int64 e : bbox.extents())
        box *= double(e) + 2.0 * n;
    const double d = 2.0 * n + 1.0, octahedron = d * (2.0 * n * n + 2.0 * n + 3.0) / 3.0;
    const double ball = nn == tools::NN_FACE        ? octahedron
                        : nn == tools::NN_FACE_EDGE ? (d * d * d + octahedron) / 2.0
                                                    : d * d * d;
    return std::min(box, double(grid.activeVoxelCount()) * ball);
}

tools::TilePolicy parseTilePolicy(const std::string& name) {
    if (name == "ignore")
        return tools::IGNORE_TILES;
    if (name == "expand")
        return tools::EXPAND_TILES;
    return tools::PRESERVE_TILES;
}

void addMorphCommand(CLI::App& app, Context& ctx) {
    struct Args {
        EditArgs edit;
        std::string operation;
        int iterations = 1;
        std::string neighbors = "face";
        std::string tiles = "preserve";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "morph", "Dilate or erode the active voxels of grids (bit-mask morphology)", true,
        [args, &ctx] {
            const Args& a = *args;
            const auto nn = parseNeighbors(a.neighbors);
            const auto policy = parseTilePolicy(a.tiles);
            const bool dilate = a.operation == "dilate";
            runEdit(ctx, a.edit, [&](Report& report, const GridBase::Ptr& grid) {
                withAnyGrid(grid, [&](auto& g) {
                    using ValueT = typename std::decay_t<decltype(g)>::ValueType;
                    if (dilate)
                        checkMemoryEstimate(
                            dilatedVoxels(*grid, a.iterations, nn) * (sizeof(ValueT) + 0.5),
                            "dilating grid \"" + grid->getName() + "\" by " +
                                std::to_string(a.iterations) + " voxels");
                    report.step(std::string(dilate ? "dilate " : "erode ") + grid->getName(), [&] {
                        if (dilate)
                            tools::dilateActiveValues(g.tree(), a.iterations, nn, policy);
                        else
                            tools::erodeActiveValues(g.tree(), a.iterations, nn, policy);
                    });
                });
                return true;
            });
        });
    cmd->add_option("operation", args->operation, "dilate or erode")
        ->required()
        ->check(CLI::IsMember({"dilate", "erode"}));
    cmd->add_option("iterations", args->iterations, "How many voxels to grow or shrink by")
        ->required()
        ->check(CLI::Range(1, 1000));
    addEditOptions(*cmd, args->edit);
    cmd->add_option("--nn", args->neighbors,
                    "Neighbourhood: face (6), edge (18) or vertex (26 neighbours)")
        ->check(CLI::IsMember({"face", "edge", "vertex", "6", "18", "26"}))
        ->capture_default_str();
    cmd->add_option("--tiles", args->tiles, "Active tiles: ignore, expand or preserve")
        ->check(CLI::IsMember({"ignore", "expand", "preserve"}))
        ->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb morph dilate 2 in.vdb -o out.vdb\n"
        "  vdb morph erode 1 in.vdb -o out.vdb --nn vertex --grid density");
}

void addFloodFillCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<EditArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "floodfill",
        "Give the inactive voxels and tiles of level sets the sign of the side they are on", true,
        [args, &ctx] {
            runEdit(
                ctx, *args,
                [&](Report& report, const GridBase::Ptr& grid) {
                    // Without --grid, only grids marked as level sets.
                    if (args->grid.empty() && grid->getGridClass() != GRID_LEVEL_SET)
                        return false;
                    withLevelSetGrid(grid, [&](auto& g) {
                        report.step("flood fill " + grid->getName(),
                                    [&] { tools::signedFloodFill(g.tree()); });
                    });
                    return true;
                },
                args->input + " has no level set grid; name a float grid with --grid");
        });
    addEditOptions(*cmd, *args);
    cmd->footer("Example:\n  vdb floodfill band.vdb -o filled.vdb");
}

void addPruneCommand(CLI::App& app, Context& ctx) {
    struct Args {
        EditArgs edit;
        double tolerance = 0;
        std::string mode = "auto";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        addCommand(app, ctx, "prune", "Replace constant or inactive nodes of grids by tiles", true,
                   [args, &ctx] {
                       const Args& a = *args;
                       runEdit(ctx, a.edit, [&](Report& report, const GridBase::Ptr& grid) {
                           std::string mode = a.mode;
                           if (mode == "auto")
                               mode = grid->getGridClass() == GRID_LEVEL_SET ? "levelset" : "value";
                           if (mode == "levelset") {
                               withLevelSetGrid(grid, [&](auto& g) {
                                   report.step("prune level set " + grid->getName(),
                                               [&] { tools::pruneLevelSet(g.tree()); });
                               });
                               return true;
                           }
                           withAnyGrid(grid, [&](auto& g) {
                               using ValueT = typename std::decay_t<decltype(g)>::ValueType;
                               report.step("prune " + grid->getName(), [&] {
                                   if (mode == "inactive") {
                                       tools::pruneInactive(g.tree());
                                   } else if constexpr (std::is_arithmetic_v<ValueT> &&
                                                        !std::is_same_v<ValueT, bool>) {
                                       tools::prune(g.tree(), static_cast<ValueT>(a.tolerance));
                                   } else {
                                       tools::prune(g.tree());
                                   }
                               });
                           });
                           return true;
                       });
                   });
    addEditOptions(*cmd, args->edit);
    cmd->add_option("--mode", args->mode,
                    "value: constant nodes (within --tolerance); inactive: nodes with no active "
                    "value; levelset: inactive nodes as inside/outside tiles; auto: levelset for "
                    "level sets, else value")
        ->check(CLI::IsMember({"auto", "value", "inactive", "levelset"}))
        ->capture_default_str();
    cmd->add_option("--tolerance", args->tolerance,
                    "Largest value difference pruned as constant (value mode)")
        ->check(finiteRange(0.0, 1e30))
        ->capture_default_str();
    cmd->footer("Example:\n  vdb prune density.vdb -o pruned.vdb --tolerance 0.001");
}

}  // namespace

void addMorphCommands(CLI::App& app, Context& ctx) {
    addMorphCommand(app, ctx);
    addFloodFillCommand(app, ctx);
    addPruneCommand(app, ctx);
}

}  // namespace vdb::app
