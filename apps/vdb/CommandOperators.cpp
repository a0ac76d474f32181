// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb gradient|curl|divergence|laplacian IN -o OUT`: the differential operators of
/// tools/GridOperators.h applied to the grids of a file; the output file holds the results,
/// named after their inputs ("density_gradient").

#include <vdb/tools/GridOperators.h>

#include "Commands.h"

#include <string>
#include <type_traits>

namespace vdb::app {
namespace {

/// True when the operator `name` ("gradient", "curl", "divergence", "laplacian") applies to
/// grids of ValueT: the first two to floating-point scalars, the others to their vectors.
template <typename ValueT>
bool applies(const std::string& name) {
    if constexpr (std::is_floating_point_v<ValueT>) {
        return name == "gradient" || name == "laplacian";
    } else if constexpr (!std::is_arithmetic_v<ValueT>) {
        return std::is_floating_point_v<typename ValueT::value_type> &&
               (name == "curl" || name == "divergence");
    } else {
        return false;
    }
}

/// The operator `name` of `grid`. @pre applies<GridT::ValueType>(name)
template <typename GridT>
GridBase::Ptr applyOperator(const std::string& name, const GridT& grid) {
    using ValueT = typename GridT::ValueType;
    if constexpr (std::is_floating_point_v<ValueT>) {
        return name == "gradient" ? GridBase::Ptr(tools::gradient(grid))
                                  : GridBase::Ptr(tools::laplacian(grid));
    } else if constexpr (!std::is_arithmetic_v<ValueT>) {
        if constexpr (std::is_floating_point_v<typename ValueT::value_type>) {
            return name == "curl" ? GridBase::Ptr(tools::curl(grid))
                                  : GridBase::Ptr(tools::divergence(grid));
        }
    }
    return nullptr;
}

/// The memory of the result of `name` on `grid`: one output value per active voxel (active
/// tiles become voxels) in leaves about 1.2 times the size of their values.
double resultBytes(const std::string& name, const GridBase& grid) {
    const bool vectorOut = name == "gradient" || name == "curl";
    const double valueBytes = (grid.valueType() == "double" || grid.valueType() == "vec3d") ? 8 : 4;
    return double(grid.activeVoxelCount()) * valueBytes * (vectorOut ? 3 : 1) * 1.2;
}

void addOperatorCommand(CLI::App& app, Context& ctx, const std::string& name,
                        const std::string& description, const std::string& takes) {
    struct Args {
        std::string input;
        std::string grid;
        OutputArgs out;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(app, ctx, name, description, true, [args, &ctx, name, takes] {
        const Args& a = *args;
        checkOutputPath(a.out.path);
        Report report(ctx);
        const GridPtrVec grids =
            report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
        GridPtrVec results;
        report.json().key("input").value(a.input).key("grids").beginArray();
        for (const auto& grid : selectGrids(grids, a.grid, a.input)) {
            GridBase::Ptr result;
            withAnyGrid(grid, [&](auto& g) {
                if (!applies<typename std::decay_t<decltype(g)>::ValueType>(name))
                    return;
                checkMemoryEstimate(resultBytes(name, *grid),
                                    "the " + name + " of grid \"" + grid->getName() + "\"");
                result = report.step(name + " " + grid->getName(),
                                     [&] { return applyOperator(name, g); });
            });
            if (!result) {
                if (!a.grid.empty())
                    throw UsageError("grid \"" + grid->getName() + "\" has type " + grid->type() +
                                     "; the " + name + " needs " + takes);
                continue;
            }
            result->setName(grid->getName() + "_" + name);
            requireNonEmpty(*result, "the " + name + " of grid \"" + grid->getName() + "\"");
            report.json().beginObject();
            reportGrid(report, *result);
            report.json().endObject();
            results.push_back(result);
        }
        report.json().endArray();
        if (results.empty())
            throw UsageError(a.input + " has no grid the " + name + " applies to (it needs " +
                             takes + ")");
        writeOutput(report, a.out, results);
        report.finish();
    });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    cmd->add_option("-g,--grid", args->grid, "Only this grid (default: every grid it applies to)");
    addOutputOptions(*cmd, args->out);
    cmd->footer("Example:\n  vdb " + name + " in.vdb -o " + name + ".vdb");
}

}  // namespace

void addOperatorCommands(CLI::App& app, Context& ctx) {
    addOperatorCommand(app, ctx, "gradient", "Gradient of scalar grids (world units)",
                       "a float or double grid");
    addOperatorCommand(app, ctx, "laplacian", "Laplacian of scalar grids (world units)",
                       "a float or double grid");
    addOperatorCommand(app, ctx, "divergence", "Divergence of vector grids (world units)",
                       "a vec3s or vec3d grid");
    addOperatorCommand(app, ctx, "curl", "Curl of vector grids (world units)",
                       "a vec3s or vec3d grid");
}

}  // namespace vdb::app
