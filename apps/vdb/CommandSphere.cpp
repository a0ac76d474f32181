// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb sphere`: a narrow-band level set of a sphere, or the Enright test sphere.

#include <vdb/tools/LevelSetSphere.h>

#include "Commands.h"
#include "Geometry.h"

namespace vdb::app {

void addSphereCommand(CLI::App& app, Context& ctx) {
    struct Args {
        OutputArgs out;
        double radius = 1.0;
        std::vector<double> center{0.0, 0.0, 0.0};
        double voxelSize = 0.01;
        double halfWidth = 3.0;
        int enright = 0;
        std::string name = "sphere";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "sphere", "Make a narrow-band level set of a sphere", true, [args, &ctx] {
            Args& a = *args;
            const double r = a.enright > 0 ? 0.15 * a.enright : a.radius / a.voxelSize;
            if (a.enright == 0) {
                // The center is placed in double precision (tools::createLevelSetSphere), so
                // the whole index space is open to it.
                for (int i = 0; i < 3; ++i)
                    checkIndexRange(a.center[i] / a.voxelSize - r - a.halfWidth,
                                    a.center[i] / a.voxelSize + r + a.halfWidth,
                                    "a sphere of radius " + numberText(a.radius) +
                                        " at this center and voxel size " +
                                        numberText(a.voxelSize));
                if (!(r >= kMinSphereVoxels))
                    throw UsageError("a sphere of radius " + numberText(a.radius) + " is " +
                                     numberText(r) + " voxels at voxel size " +
                                     numberText(a.voxelSize) + ", below the " +
                                     numberText(kMinSphereVoxels) +
                                     " voxels a level set sphere needs (use a smaller voxel size)");
            }
            checkMemoryEstimate(levelSetBytes(4.0 * 3.14159265 * r * r, a.halfWidth),
                                "this sphere");
            runCreate(ctx, a.out, a.name, [&](Report& report) {
                return report.step("build sphere", [&] {
                    if (a.enright > 0)
                        return tools::createEnrightSphere<FloatGrid>(a.enright, a.halfWidth);
                    return tools::createLevelSetSphere<FloatGrid>(
                        a.radius, Vec3d(a.center[0], a.center[1], a.center[2]), a.voxelSize,
                        a.halfWidth);
                });
            });
        });
    addOutputOptions(*cmd, args->out);
    cmd->add_option("-r,--radius", args->radius, "Radius in world units")
        ->check(positive())
        ->capture_default_str();
    cmd->add_option("-c,--center", args->center, "Center: x y z in world units")
        ->expected(3)
        ->delimiter(',')
        ->check(finite())
        ->capture_default_str();
    cmd->add_option("-s,--voxel-size", args->voxelSize, "Voxel edge in world units")
        ->check(positive())
        ->capture_default_str();
    cmd->add_option("-w,--half-width", args->halfWidth, "Half the band width, in voxels")
        ->check(finiteRange(1.01, 1000.0))
        ->capture_default_str();
    cmd->add_option("--enright", args->enright,
                    "Instead: the Enright test sphere (radius 0.15 at 0.35,0.35,0.35 in the "
                    "unit box) at this resolution")
        ->check(CLI::Range(8, 16384));
    cmd->add_option("-n,--name", args->name, "Grid name")->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb sphere -o ball.vdb --radius 2 --center 1,0,0 --voxel-size 0.05\n"
        "  vdb sphere -o enright.vdb --enright 512 --half-width 5");
}

}  // namespace vdb::app
