// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb filter` (smoothing and offsetting of level sets and of value grids) and `vdb fog`
/// (level sets to fog volumes): read, edit the selected grids, write every grid.

#include <vdb/tools/Filter.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetUtil.h>

#include "Commands.h"

#include <cmath>
#include <string>
#include <type_traits>

namespace vdb::app {
namespace {

bool isLevelSet(const GridBase& grid) {
    return grid.getGridClass() == GRID_LEVEL_SET &&
           (dynamic_cast<const FloatGrid*>(&grid) || dynamic_cast<const DoubleGrid*>(&grid));
}

/// `v` as a value of type ValueT (every component, for vectors).
template <typename ValueT>
ValueT uniformValue(double v) {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return ValueT(v);
    } else {
        return ValueT(typename ValueT::value_type(v));
    }
}

struct FilterArgs {
    EditArgs edit;
    std::string op;
    int width = 1;
    int iterations = 1;
    double amount = std::nan("");  // NaN: not given (--amount must be finite)
    bool hasAmount() const { return !std::isnan(amount); }
};

/// Checks the option combinations that CLI11 cannot, before any file is read.
void checkFilterArgs(const FilterArgs& a) {
    if (a.op == "median" && a.width > tools::MEDIAN_FILTER_MAX_WIDTH)
        throw UsageError("--width of a median filter must be 1 to " +
                         std::to_string(tools::MEDIAN_FILTER_MAX_WIDTH) + " voxels, not " +
                         std::to_string(a.width));
    if (a.op == "offset" && !a.hasAmount())
        throw UsageError("--op offset needs --amount (world units; positive moves outwards)");
    if (a.op != "offset" && a.hasAmount())
        throw UsageError("--amount applies to --op offset only");
}

/// Runs the level set filter `a.op` on `grid`, a.iterations times.
template <typename GridT>
void filterLevelSet(GridT& grid, const FilterArgs& a) {
    using ValueT = typename GridT::ValueType;
    if (a.op == "offset") {
        // Each half voxel of offset is one step and one rebuild of the band.
        const double steps =
            std::ceil(std::abs(a.amount) / (0.5 * grid.voxelSize()[0])) * a.iterations;
        checkStepEstimate(steps, "offsetting grid \"" + grid.getName() + "\" by " +
                                     numberText(a.amount * a.iterations));
    }
    tools::LevelSetFilter<GridT> filter(grid);
    for (int i = 0; i < a.iterations; ++i) {
        if (a.op == "mean")
            filter.mean(a.width);
        else if (a.op == "gaussian")
            filter.gaussian(a.width);
        else if (a.op == "median")
            filter.median(a.width);
        else if (a.op == "curvature")
            filter.meanCurvature();
        else if (a.op == "laplacian")
            filter.laplacian();
        else
            filter.offset(ValueT(-a.amount));  // the library's positive offset erodes
    }
}

/// Runs the value filter `a.op` on `grid`.
template <typename GridT>
void filterValues(GridT& grid, const FilterArgs& a) {
    using ValueT = typename GridT::ValueType;
    tools::Filter<GridT> filter(grid);
    if (a.op == "mean") {
        filter.mean(a.width, a.iterations);
    } else if (a.op == "gaussian") {
        filter.gaussian(a.width, a.iterations);
    } else if (a.op == "median") {
        if constexpr (std::is_arithmetic_v<ValueT>) {
            filter.median(a.width, a.iterations);
        } else {
            throw UsageError("grid \"" + grid.getName() + "\" has type " + grid.type() +
                             "; the median filter needs a scalar grid");
        }
    } else {
        for (int i = 0; i < a.iterations; ++i)
            filter.offset(uniformValue<ValueT>(a.amount));
    }
}

void addFilterCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<FilterArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "filter",
        "Smooth or offset grids: level sets keep a valid narrow band, other grids are filtered "
        "over their active values",
        true, [args, &ctx] {
            const FilterArgs& a = *args;
            checkFilterArgs(a);
            const bool levelSetOnly = a.op == "curvature" || a.op == "laplacian";
            runEdit(
                ctx, a.edit,
                [&](Report& report, const GridBase::Ptr& grid) {
                    if (isLevelSet(*grid)) {
                        withLevelSetGrid(grid, [&](auto& g) {
                            report.step(a.op + " " + grid->getName(),
                                        [&] { filterLevelSet(g, a); });
                        });
                        return true;
                    }
                    if (levelSetOnly) {
                        if (!a.edit.grid.empty())
                            throw UsageError("grid \"" + grid->getName() + "\" (" + grid->type() +
                                             ", class " +
                                             std::string(gridClassToString(grid->getGridClass())) +
                                             ") is not a level set; --op " + a.op + " needs one");
                        return false;
                    }
                    // Without --grid, only the grids the value filters take.
                    if (a.edit.grid.empty() && !gridIsOneOf<FloatingPointGridTypes>(*grid))
                        return false;
                    if (a.op == "median" && a.edit.grid.empty() &&
                        (gridPtrCast<Vec3SGrid>(grid) || gridPtrCast<Vec3DGrid>(grid)))
                        return false;
                    withRealGrid(grid, "filters take", [&](auto& g) {
                        report.step(a.op + " " + grid->getName(), [&] { filterValues(g, a); });
                    });
                    return true;
                },
                a.edit.input + " has no grid that --op " + a.op + " applies to" +
                    (levelSetOnly ? " (it needs a level set)" : ""));
        });
    cmd->add_option("--op", args->op,
                    "mean, gaussian, median, offset; for level sets also curvature (mean "
                    "curvature flow) and laplacian")
        ->required()
        ->check(CLI::IsMember({"mean", "gaussian", "median", "curvature", "laplacian", "offset"}));
    cmd->add_option("--width", args->width,
                    "Half the kernel's edge in voxels (mean, gaussian: 1 to " +
                        std::to_string(tools::FILTER_MAX_WIDTH) + "; median: 1 to " +
                        std::to_string(tools::MEDIAN_FILTER_MAX_WIDTH) + ")")
        ->check(CLI::Range(1, tools::FILTER_MAX_WIDTH))
        ->capture_default_str();
    cmd->add_option("--iterations", args->iterations, "How many times to apply the filter")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    cmd->add_option("--amount", args->amount,
                    "Offset: world units for level sets (positive moves the surface outwards), "
                    "value units otherwise")
        ->check(finite());
    addEditOptions(*cmd, args->edit);
    addStepLimitOption(*cmd, ctx);
    cmd->footer(
        "Examples:\n  vdb filter bunny.vdb -o smooth.vdb --op gaussian --width 2\n"
        "  vdb filter bunny.vdb -o fat.vdb --op offset --amount 0.05\n"
        "  vdb filter smoke.vdb -o soft.vdb --op mean --iterations 3 --grid density");
}

void addFogCommand(CLI::App& app, Context& ctx) {
    struct Args {
        EditArgs edit;
        double cutoff = 0;  // 0: the band's inside half
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        addCommand(app, ctx, "fog",
                   "Turn level sets into fog volumes: density from 0 at the surface to 1 inside",
                   true, [args, &ctx] {
                       const Args& a = *args;
                       runEdit(
                           ctx, a.edit,
                           [&](Report& report, const GridBase::Ptr& grid) {
                               // Without --grid, only grids marked as level sets.
                               if (a.edit.grid.empty() && grid->getGridClass() != GRID_LEVEL_SET)
                                   return false;
                               withLevelSetGrid(grid, [&](auto& g) {
                                   using ValueT = typename std::decay_t<decltype(g)>::ValueType;
                                   report.step("fog " + grid->getName(), [&] {
                                       if (a.cutoff > 0)
                                           tools::sdfToFogVolume(g, ValueT(a.cutoff));
                                       else
                                           tools::sdfToFogVolume(g);
                                   });
                               });
                               return true;
                           },
                           a.edit.input + " has no level set grid; name a float grid with --grid");
                   });
    addEditOptions(*cmd, args->edit);
    cmd->add_option("--cutoff", args->cutoff,
                    "Depth (world units) at which the density reaches 1 (default: the band's "
                    "inside half)")
        ->check(positive());
    cmd->footer("Example:\n  vdb fog bunny.vdb -o bunny_fog.vdb");
}

}  // namespace

void addFilterCommands(CLI::App& app, Context& ctx) {
    addFilterCommand(app, ctx);
    addFogCommand(app, ctx);
}

}  // namespace vdb::app
