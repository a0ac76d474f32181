// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb clip IN -o OUT (--bbox X0,Y0,Z0,X1,Y1,Z1 | --mask M.vdb) [--outside]`: clips the grids
/// of a file to a world-space box or to the active voxels of a mask grid (tools/Clip.h).

#include <vdb/tools/Clip.h>

#include "Commands.h"

#include <cmath>

namespace vdb::app {

void addClipCommand(CLI::App& app, Context& ctx) {
    struct Args {
        EditArgs edit;
        std::vector<double> bbox;
        std::string mask;
        std::string maskGrid;
        bool outside = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "clip", "Clip grids to a world-space box or to the active voxels of a mask", true,
        [args, &ctx] {
            const Args& a = *args;
            if (a.bbox.empty() == a.mask.empty())
                throw UsageError("clip needs exactly one of --bbox and --mask");
            BBoxd box;
            if (!a.bbox.empty()) {
                box = BBoxd(Vec3d(a.bbox[0], a.bbox[1], a.bbox[2]),
                            Vec3d(a.bbox[3], a.bbox[4], a.bbox[5]));
                for (int i = 0; i < 3; ++i) {
                    if (!(box.min()[i] <= box.max()[i]))
                        throw UsageError(
                            "--bbox: the minimum corner must not exceed the maximum "
                            "corner (got " +
                            numberText(box.min()[i]) + " > " + numberText(box.max()[i]) + ")");
                }
            }
            // The mask's active topology, whatever its value type.
            MaskGrid::Ptr mask;
            if (!a.mask.empty()) {
                checkOutputPath(a.edit.out.path);
                const GridPtrVec masks = readGrids(a.mask, ctx);
                const GridBase::Ptr chosen = selectGrids(masks, a.maskGrid, a.mask).front();
                mask = MaskGrid::create(false);
                mask->setTransform(chosen->transform().copy());
                withAnyGrid(chosen, [&](auto& m) { mask->tree().topologyUnion(m.tree()); });
            }
            const bool keepInterior = !a.outside;
            runEdit(
                ctx, a.edit,
                [&](Report& report, const GridBase::Ptr& grid) {
                    withAnyGrid(grid, [&](auto& g) {
                        report.step("clip " + grid->getName(), [&] {
                            if (mask) {
                                g.setTree(tools::clip(g, *mask, keepInterior)->treePtr());
                            } else {
                                g.setTree(tools::clip(g, box, keepInterior)->treePtr());
                            }
                        });
                    });
                    return true;
                },
                "no grid to clip in " + a.edit.input);
        });
    addEditOptions(*cmd, args->edit);
    cmd->add_option("--bbox", args->bbox,
                    "World-space box xmin,ymin,zmin,xmax,ymax,zmax (voxels from the floor of the "
                    "lower corner to the floor of the upper corner, in index space)")
        ->expected(6)
        ->delimiter(',')
        ->check(finite());
    cmd->add_option("--mask", args->mask, "A .vdb file whose grid's active voxels are kept");
    cmd->add_option("--mask-grid", args->maskGrid,
                    "The grid of the mask file (default: its first)");
    cmd->add_flag("--outside", args->outside, "Keep what lies outside the box or mask instead");
    cmd->footer(
        "Examples:\n  vdb clip smoke.vdb -o part.vdb --bbox -1,0,-1,1,2,1\n"
        "  vdb clip smoke.vdb -o cut.vdb --mask region.vdb --outside");
}

}  // namespace vdb::app
