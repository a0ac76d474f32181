// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb csg union|intersection|difference A B -o OUT`: CSG of two level sets on whole branches.

#include <vdb/tools/Composite.h>

#include "Commands.h"

namespace vdb::app {
namespace {

/// The grid `name` of `path` (the first float or double level set when `name` is empty).
GridBase::Ptr pickLevelSet(const GridPtrVec& grids, const std::string& name,
                           const std::string& path) {
    for (const auto& grid : selectGrids(grids, name, path)) {
        if (gridIsOneOf<RealGridTypes>(*grid) &&
            (!name.empty() || grid->getGridClass() == GRID_LEVEL_SET))
            return grid;
        if (!name.empty())
            withLevelSetGrid(grid, [](auto&) {});  // throws the type error
    }
    throw UsageError(path + " has no float or double level set grid; name one with --grid");
}

}  // namespace

void addCsgCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string operation;
        std::string a, b;
        std::string gridA, gridB;
        OutputArgs out;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "csg", "Union, intersection or difference of two level sets", true, [args, &ctx] {
            const Args& a = *args;
            runCreate(
                ctx, a.out, {},
                [&](Report& report) {
                    const GridPtrVec gridsA =
                        report.step("read " + a.a, [&] { return readGrids(a.a, ctx); });
                    const GridPtrVec gridsB =
                        report.step("read " + a.b, [&] { return readGrids(a.b, ctx); });
                    GridBase::Ptr lhs = pickLevelSet(gridsA, a.gridA, a.a);
                    GridBase::Ptr rhs = pickLevelSet(gridsB, a.gridB, a.b);
                    if (lhs->type() != rhs->type())
                        throw UsageError("grid \"" + lhs->getName() + "\" of " + a.a + " is " +
                                         lhs->type() + " but grid \"" + rhs->getName() + "\" of " +
                                         a.b + " is " + rhs->type() +
                                         "; both must have the same type");
                    requireMatchingTransforms(*lhs, a.a, *rhs, a.b, "CSG");
                    withLevelSetGrid(lhs, [&](auto& g) {
                        auto& other = *gridPtrCast<std::decay_t<decltype(g)>>(rhs);
                        report.step("csg " + a.operation, [&] {
                            if (a.operation == "union")
                                tools::csgUnion(g, other);
                            else if (a.operation == "intersection")
                                tools::csgIntersection(g, other);
                            else
                                tools::csgDifference(g, other);
                        });
                    });
                    report.json().key("operation").value(a.operation);
                    return lhs;
                },
                "the " + a.operation + " of the two shapes is empty");
        });
    cmd->add_option("operation", args->operation, "union, intersection or difference (A - B)")
        ->required()
        ->check(CLI::IsMember({"union", "intersection", "difference"}));
    cmd->add_option("a", args->a, "First .vdb file")->required();
    cmd->add_option("b", args->b, "Second .vdb file")->required();
    cmd->add_option("--grid-a", args->gridA, "Grid of A (default: its first level set)");
    cmd->add_option("--grid-b", args->gridB, "Grid of B (default: its first level set)");
    addOutputOptions(*cmd, args->out);
    cmd->footer(
        "Examples:\n  vdb csg union a.vdb b.vdb -o both.vdb\n"
        "  vdb csg difference block.vdb hole.vdb -o cut.vdb --grid-b tool");
}

}  // namespace vdb::app
