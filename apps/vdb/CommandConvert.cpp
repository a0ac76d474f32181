// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb convert IN -o OUT`: rewrite a `.vdb` file with other storage settings (compression,
/// half floats), optionally keeping only some grids.

#include "Commands.h"

#include <filesystem>

namespace vdb::app {

void addConvertCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input;
        std::vector<std::string> grids;
        bool full = false;
        OutputArgs out;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        addCommand(app, ctx, "convert", "Rewrite a .vdb file with other compression or precision",
                   true, [args, &ctx] {
                       const Args& a = *args;
                       if (a.full && a.out.half)
                           throw UsageError("--half and --full contradict each other");
                       checkOutputPath(a.out.path);
                       Report report(ctx);
                       GridPtrVec grids =
                           report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
                       if (!a.grids.empty()) {
                           GridPtrVec kept;
                           for (const auto& name : a.grids)
                               for (const auto& grid : selectGrids(grids, name, a.input))
                                   kept.push_back(grid);
                           grids = std::move(kept);
                       }
                       if (a.full)
                           for (const auto& grid : grids)
                               grid->setSaveFloatAsHalf(false);
                       report.json().key("input").value(a.input).key("grids").value(
                           static_cast<uint64_t>(grids.size()));
                       writeOutput(report, a.out, grids);
                       std::error_code ec;
                       const auto in = std::filesystem::file_size(a.input, ec);
                       const auto out = std::filesystem::file_size(a.out.path, ec);
                       report.note("  " + bytesText(in) + " -> " + bytesText(out));
                       report.finish();
                   });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    cmd->add_option("-g,--grid", args->grids, "Keep only these grids (repeatable)");
    cmd->add_flag("--full", args->full, "Store float values at full precision (clear half)");
    addOutputOptions(*cmd, args->out);
    cmd->footer(
        "Examples:\n  vdb convert in.vdb -o small.vdb --compression zip --half\n"
        "  vdb convert in.vdb -o density.vdb --grid density --compression none");
}

}  // namespace vdb::app
