// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb convert IN -o OUT`: rewrite a `.vdb` file with other storage settings (compression,
/// half floats), optionally keeping only some grids. Each grid's report line says the codec it
/// actually got (ZIP is not applied to level sets and fog volumes, as in OpenVDB), and grids
/// this library cannot write (point data grids) stop the command unless --drop-unsupported.

#include "Commands.h"

#include <filesystem>

namespace vdb::app {

namespace {

/// "blosc + active values, half floats" for a grid written with `flags`.
std::string storageText(const GridBase& grid, uint32_t flags) {
    std::string text = io::compressionToString(flags);
    if (grid.saveFloatAsHalf())
        text += ", half floats";
    return text;
}

}  // namespace

void addConvertCommand(CLI::App& app, Context& ctx) {
    struct Args {
        std::string input;
        std::vector<std::string> grids;
        bool full = false;
        bool dropUnsupported = false;
        OutputArgs out;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "convert", "Rewrite a .vdb file with other compression or precision", true,
        [args, &ctx] {
            const Args& a = *args;
            if (a.full && a.out.half)
                throw UsageError("--half and --full contradict each other");
            checkOutputPath(a.out.path);
            Report report(ctx);
            std::vector<io::UnsupportedGrid> unsupported;
            GridPtrVec grids = report.step("read " + a.input,
                                           [&] { return readGrids(a.input, ctx, &unsupported); });
            if (!a.grids.empty()) {
                GridPtrVec kept;
                for (const auto& name : a.grids)
                    for (const auto& grid : selectGrids(grids, name, a.input))
                        kept.push_back(grid);
                grids = std::move(kept);
                // Only the unsupported grids that were asked for by name matter.
                std::erase_if(unsupported, [&](const io::UnsupportedGrid& g) {
                    return std::find(a.grids.begin(), a.grids.end(), g.name) == a.grids.end();
                });
            }
            if (!unsupported.empty() && !a.dropUnsupported) {
                std::string names;
                for (const auto& g : unsupported)
                    appendQuoted(names, g.name, g.type);
                throw UsageError(a.input + " holds grids this library cannot write: " + names +
                                 "; they would be lost. Give --drop-unsupported to write the "
                                 "others without them");
            }
            if (a.full)
                for (const auto& grid : grids)
                    grid->setSaveFloatAsHalf(false);
            if (a.out.half)
                for (const auto& grid : grids)
                    grid->setSaveFloatAsHalf(true);

            // What each grid will get: the file's codec, less ZIP for level sets and fog.
            const uint32_t requested = parseCompression(a.out.compression);
            JsonWriter& json = report.json();
            json.key("input").value(a.input).key("grids").beginArray();
            for (const auto& grid : grids) {
                const uint32_t flags = io::gridCompression(grid->getGridClass(), requested);
                std::string line = "  " + grid->getName() + ": " + storageText(*grid, flags);
                if ((requested & io::COMPRESS_ZIP) && !(flags & io::COMPRESS_ZIP))
                    line += " (zip is not applied to " +
                            std::string(grid->getGridClass() == GRID_LEVEL_SET ? "level sets"
                                                                               : "fog volumes") +
                            ", as in OpenVDB)";
                report.note(line);
                json.beginObject()
                    .key("name")
                    .value(grid->getName())
                    .key("type")
                    .value(grid->type())
                    .key("compression")
                    .value(io::compressionToString(flags))
                    .key("half")
                    .value(grid->saveFloatAsHalf())
                    .endObject();
            }
            json.endArray().key("dropped").beginArray();
            for (const auto& g : unsupported) {
                report.note("  dropped \"" + g.name + "\": grids of type " + g.type +
                            " cannot be written by this library");
                json.beginObject().key("name").value(g.name).key("type").value(g.type).endObject();
            }
            json.endArray();
            writeOutput(report, a.out, grids);
            // file_size() fails for a device or a FIFO: no sizes then.
            std::error_code inError, outError;
            const auto in = std::filesystem::file_size(a.input, inError);
            const auto out = std::filesystem::file_size(a.out.path, outError);
            if (!inError && !outError)
                report.note("  " + bytesText(double(in)) + " -> " + bytesText(double(out)));
            report.finish();
        });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    cmd->add_option("-g,--grid", args->grids, "Keep only these grids (repeatable)");
    cmd->add_flag("--full", args->full, "Store float values at full precision (clear half)");
    cmd->add_flag("--drop-unsupported", args->dropUnsupported,
                  "Write the file without the grids this library cannot write (point data "
                  "grids), naming each; without it such grids stop the command");
    addOutputOptions(*cmd, args->out);
    cmd->footer(
        "ZIP is not applied to level sets and fog volumes (as in OpenVDB); each grid's line "
        "says the codec it got.\n\n"
        "Examples:\n  vdb convert in.vdb -o small.vdb --compression zip --half\n"
        "  vdb convert in.vdb -o density.vdb --grid density --compression none");
}

}  // namespace vdb::app
