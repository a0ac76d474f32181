// SPDX-License-Identifier: Apache-2.0
/// @file
/// The subcommands of the `vdb` tool, one Command*.cpp each.

#pragma once

#include "Cli.h"

namespace vdb::app {

void addInfoCommand(CLI::App& app, Context& ctx);
void addConvertCommand(CLI::App& app, Context& ctx);
void addCsgCommand(CLI::App& app, Context& ctx);
void addClipCommand(CLI::App& app, Context& ctx);
void addMorphCommands(CLI::App& app, Context& ctx);  // morph, floodfill, prune
void addSphereCommand(CLI::App& app, Context& ctx);
void addAdvectCommands(CLI::App& app, Context& ctx);  // advect, enright
void addRenderCommand(CLI::App& app, Context& ctx);
void addMeshCommand(CLI::App& app, Context& ctx);
void addSpheresCommand(CLI::App& app, Context& ctx);
void addDemoCommand(CLI::App& app, Context& ctx);
void addToMeshCommand(CLI::App& app, Context& ctx);
void addRebuildCommand(CLI::App& app, Context& ctx);
void addResampleCommand(CLI::App& app, Context& ctx);
void addFilterCommands(CLI::App& app, Context& ctx);     // filter, fog
void addMeasureCommands(CLI::App& app, Context& ctx);    // measure, stats
void addOperatorCommands(CLI::App& app, Context& ctx);   // gradient, laplacian, divergence, curl
void addFastSweepCommands(CLI::App& app, Context& ctx);  // redistance, extend

}  // namespace vdb::app
