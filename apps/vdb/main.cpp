// SPDX-License-Identifier: Apache-2.0
/// @file
/// The `vdb` command-line tool: the paper's pipeline (level sets from geometry, morphology,
/// CSG, files, pictures) as subcommands. Every failure ends in one line on stderr and a
/// non-zero exit status: 2 for a bad request, 1 for a failed operation, 130 for Ctrl-C.

#include <vdb/Exceptions.h>

#include "Commands.h"

#include <cstdio>
#include <new>

namespace {

const char* const kFooter = R"(Examples:
  vdb demo                      (spheres and a mesh to level sets, CSG, .vdb, PNG)
  vdb mesh bunny.ply -o bunny.vdb --resolution 512
  vdb tomesh bunny.vdb -o bunny.ply --adaptivity 0.3
  vdb spheres -o helix.vdb --count 1000000
  vdb render bunny.vdb -o bunny.png
  vdb sphere -o sphere.vdb --radius 1 --voxel-size 0.01
  vdb info sphere.vdb
  vdb morph dilate 2 sphere.vdb -o fat.vdb
  vdb csg difference a.vdb b.vdb -o cut.vdb
  vdb convert in.vdb -o small.vdb --compression zip --half
  vdb filter bunny.vdb -o smooth.vdb --op gaussian --width 2
  vdb measure bunny.vdb
  vdb stats smoke.vdb --grid density
  vdb gradient bunny.vdb -o normals.vdb
  vdb fog bunny.vdb -o bunny_fog.vdb

Run 'vdb COMMAND --help' for the options of one command.)";

// The deepest subcommand named on the command line ("vdb" when none).
std::string commandName(const CLI::App& app) {
    std::string name = app.get_name();
    for (const CLI::App* sub : app.get_subcommands())
        return name + " " + commandName(*sub);
    return name;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vdb::app;
    installInterruptHandler();

    CLI::App app("vdb: sparse volumes after Museth's VDB, in OpenVDB's .vdb format.", "vdb");
    app.require_subcommand(1, 1);
    app.set_version_flag("--version", "vdb 0.1.0");
    app.footer(kFooter);
    Context ctx;
    addDemoCommand(app, ctx);
    addInfoCommand(app, ctx);
    addMeshCommand(app, ctx);
    addToMeshCommand(app, ctx);
    addSpheresCommand(app, ctx);
    addSphereCommand(app, ctx);
    addMorphCommands(app, ctx);
    addCsgCommand(app, ctx);
    addClipCommand(app, ctx);
    addAdvectCommands(app, ctx);
    addRebuildCommand(app, ctx);
    addFastSweepCommands(app, ctx);
    addResampleCommand(app, ctx);
    addConvertCommand(app, ctx);
    addRenderCommand(app, ctx);
    addFilterCommands(app, ctx);
    addMeasureCommands(app, ctx);
    addOperatorCommands(app, ctx);

    std::string names;
    bool known = false;
    for (const auto& command : ctx.commands) {
        names += (names.empty() ? "" : ", ") + command.app->get_name();
        known = known || (argc > 1 && command.app->get_name() == argv[1]);
    }
    if (argc > 1 && argv[1][0] != '-' && !known) {
        std::fprintf(stderr, "vdb: error: unknown command '%s' (commands: %s)\n", argv[1],
                     names.c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0)  // --help, --version
            return app.exit(e);
        const std::string name = commandName(app);
        std::fprintf(stderr, "%s: error: %s (see '%s --help')\n", name.c_str(), e.what(),
                     name.c_str());
        return 2;
    }

    const std::string name = commandName(app);
    try {
        ctx.apply();
        for (const auto& command : ctx.commands)
            if (command.app->parsed())
                command.run();
        return 0;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
        return 2;
    } catch (const vdb::Exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: error: out of memory\n", name.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
        return 1;
    }
}
