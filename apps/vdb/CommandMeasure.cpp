// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb measure` (area, volume, curvatures and topology of level sets) and `vdb stats` (value
/// statistics and histograms of any grid): read-only commands that report figures.

#include <vdb/tools/LevelSetMeasure.h>
#include <vdb/tools/Statistics.h>

#include "Commands.h"

#include <cstdio>
#include <string>
#include <type_traits>

namespace vdb::app {
namespace {

/// The input file and grid selection of a read-only command.
struct ReadArgs {
    std::string input;
    std::string grid;
};

void addReadOptions(CLI::App& cmd, ReadArgs& args) {
    cmd.add_option("input", args.input, "The .vdb file to read")->required();
    cmd.add_option("-g,--grid", args.grid, "Only this grid (default: every grid it applies to)");
}

void addMeasureCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<ReadArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "measure",
        "Area, volume, curvature, Euler characteristic and genus of level sets", true,
        [args, &ctx] {
            const ReadArgs& a = *args;
            Report report(ctx);
            const GridPtrVec grids =
                report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
            report.json().key("input").value(a.input).key("grids").beginArray();
            size_t measured = 0;
            for (const auto& grid : selectGrids(grids, a.grid, a.input)) {
                if (a.grid.empty() && grid->getGridClass() != GRID_LEVEL_SET)
                    continue;
                if (grid->getGridClass() != GRID_LEVEL_SET)
                    throw UsageError("grid \"" + grid->getName() + "\" is not a level set (class " +
                                     std::string(gridClassToString(grid->getGridClass())) + ")");
                withLevelSetGrid(grid, [&](auto& g) {
                    using GridT = std::decay_t<decltype(g)>;
                    tools::LevelSetMeasure<GridT> m(g);
                    double area = 0, volume = 0, meanH = 0, totalK = 0;
                    int euler = 0;
                    report.step("measure " + grid->getName(), [&] {
                        area = m.area();
                        volume = m.volume();
                        meanH = m.avgMeanCurvature();
                        totalK = m.totGaussianCurvature();
                        euler = m.eulerCharacteristic();
                    });
                    const int genus = 1 - euler / 2;
                    report.note("  grid \"" + grid->getName() + "\": area " + numberText(area) +
                                ", volume " + numberText(volume) + ", mean curvature " +
                                numberText(meanH) + ", Euler characteristic " +
                                std::to_string(euler) + ", genus " + std::to_string(genus) +
                                " (world units)");
                    report.json()
                        .beginObject()
                        .key("name")
                        .value(grid->getName())
                        .key("area")
                        .value(area)
                        .key("volume")
                        .value(volume)
                        .key("averageMeanCurvature")
                        .value(meanH)
                        .key("totalGaussianCurvature")
                        .value(totalK)
                        .key("eulerCharacteristic")
                        .value(euler)
                        .key("genus")
                        .value(genus)
                        .endObject();
                });
                ++measured;
            }
            report.json().endArray();
            if (measured == 0)
                throw UsageError(a.input + " has no level set grid");
            report.finish();
        });
    addReadOptions(*cmd, *args);
    cmd->footer("Example:\n  vdb measure bunny.vdb --json");
}

/// True for the value types statistics take: numbers and floating-point vectors.
template <typename ValueT>
constexpr bool hasStatistics() {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return !std::is_same_v<ValueT, bool>;
    } else {
        return std::is_floating_point_v<typename ValueT::value_type>;
    }
}

/// Calls `f(typedGrid)` for the grids whose values have statistics; false for the others.
template <typename F>
bool withNumericGrid(const GridBase::Ptr& grid, F&& f) {
    bool done = false;
    withAnyGrid(grid, [&](auto& g) {
        using ValueT = typename std::decay_t<decltype(g)>::ValueType;
        if constexpr (hasStatistics<ValueT>()) {
            f(g);
            done = true;
        }
    });
    return done;
}

void addStatsCommand(CLI::App& app, Context& ctx) {
    struct Args {
        ReadArgs read;
        int bins = 10;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "stats",
        "Count, min, max, mean, standard deviation and histogram of the active values of grids "
        "(lengths for vector grids)",
        true, [args, &ctx] {
            const Args& a = *args;
            Report report(ctx);
            const GridPtrVec grids =
                report.step("read " + a.read.input, [&] { return readGrids(a.read.input, ctx); });
            report.json().key("input").value(a.read.input).key("grids").beginArray();
            for (const auto& grid : selectGrids(grids, a.read.grid, a.read.input)) {
                const bool numeric = withNumericGrid(grid, [&](auto& g) {
                    math::Stats s;
                    report.step("statistics of " + grid->getName(),
                                [&] { s = tools::statistics(g.cbeginValueOn()); });
                    std::vector<uint64_t> counts;
                    std::vector<double> edges;
                    if (s.size() > 0 && s.min() < s.max()) {
                        const math::Histogram h =
                            tools::histogram(g.cbeginValueOn(), s.min(), s.max(), size_t(a.bins));
                        for (int b = 0; b < a.bins; ++b) {
                            counts.push_back(h.count(b));
                            edges.push_back(h.min(b));
                        }
                        edges.push_back(s.max());
                    }
                    report.note("  grid \"" + grid->getName() + "\" (" + grid->valueType() +
                                "): " + withCommas(s.size()) + " active values" +
                                (s.size() == 0
                                     ? std::string()
                                     : ", min " + numberText(s.min()) + ", max " +
                                           numberText(s.max()) + ", mean " + numberText(s.mean()) +
                                           ", std " + numberText(s.stdDev())));
                    for (size_t b = 0; b < counts.size(); ++b) {
                        char line[128];
                        std::snprintf(line, sizeof line, "    [%12.6g, %12.6g%c %s", edges[b],
                                      edges[b + 1], b + 1 == counts.size() ? ']' : ')',
                                      withCommas(counts[b]).c_str());
                        report.note(line);
                    }
                    report.json()
                        .beginObject()
                        .key("name")
                        .value(grid->getName())
                        .key("valueType")
                        .value(grid->valueType())
                        .key("count")
                        .value(static_cast<uint64_t>(s.size()));
                    if (s.size() > 0) {
                        report.json()
                            .key("min")
                            .value(s.min())
                            .key("max")
                            .value(s.max())
                            .key("mean")
                            .value(s.mean())
                            .key("stdDev")
                            .value(s.stdDev());
                    }
                    report.json().key("histogram").beginArray();
                    for (size_t b = 0; b < counts.size(); ++b) {
                        report.json()
                            .beginObject()
                            .key("min")
                            .value(edges[b])
                            .key("max")
                            .value(edges[b + 1])
                            .key("count")
                            .value(counts[b])
                            .endObject();
                    }
                    report.json().endArray().endObject();
                });
                if (!numeric && !a.read.grid.empty())
                    throw UsageError("grid \"" + grid->getName() + "\" has type " + grid->type() +
                                     "; statistics need numeric values");
            }
            report.json().endArray();
            report.finish();
        });
    addReadOptions(*cmd, args->read);
    cmd->add_option("--bins", args->bins, "Histogram bins between the smallest and largest value")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    cmd->footer("Example:\n  vdb stats smoke.vdb --grid density --bins 20");
}

}  // namespace

void addMeasureCommands(CLI::App& app, Context& ctx) {
    addMeasureCommand(app, ctx);
    addStatsCommand(app, ctx);
}

}  // namespace vdb::app
