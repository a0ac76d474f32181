// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb render IN.vdb -o OUT.png`: a picture of a level set (ray-traced surface) or of a fog
/// volume (emission-absorption with shadows), framed automatically or by camera options.

#include <vdb/render/Camera.h>
#include <vdb/render/Renderer.h>

#include "Commands.h"
#include "PngWriter.h"

#include <filesystem>
#include <memory>

namespace vdb::app {
namespace {

Vec3d toVec(const std::vector<double>& v) {
    return Vec3d(v[0], v[1], v[2]);
}

struct RenderArgs {
    std::string input;
    std::string output;
    std::string grid;
    std::string normals;
    std::string mode = "auto";
    std::string camera = "perspective";
    size_t width = 960;
    size_t height = 720;
    double fov = 40.0;
    std::vector<double> view{-1.0, -0.6, -1.2};
    std::vector<double> up{0.0, 1.0, 0.0};
    std::vector<double> position, lookAt;
    std::vector<double> light{0.5, 0.8, 0.6};
    double extinction = 0;
    double step = 0.5;
};

std::unique_ptr<render::Camera> makeCamera(const RenderArgs& a, const BBoxd& worldBox) {
    const Vec3d up = toVec(a.up);
    if (!a.position.empty()) {
        if (a.lookAt.empty())
            throw UsageError("--position needs --look-at");
        if (a.camera == "ortho")
            return std::make_unique<render::OrthographicCamera>(a.width, a.height,
                                                                toVec(a.position), toVec(a.lookAt),
                                                                up, worldBox.extents().length());
        return std::make_unique<render::PerspectiveCamera>(a.width, a.height, toVec(a.position),
                                                           toVec(a.lookAt), up, a.fov);
    }
    if (a.camera == "ortho")
        return std::make_unique<render::OrthographicCamera>(
            render::OrthographicCamera::frame(worldBox, a.width, a.height, toVec(a.view), up));
    return std::make_unique<render::PerspectiveCamera>(
        render::PerspectiveCamera::frame(worldBox, a.width, a.height, toVec(a.view), a.fov, up));
}

}  // namespace

void addRenderCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "render", "Render a level set or a fog volume to a PNG picture", true,
        [args, &ctx] {
            const RenderArgs& a = *args;
            checkOutputPath(a.output);
            if (!a.normals.empty())
                checkOutputPath(a.normals);
            checkMemoryEstimate(double(a.width) * double(a.height) * 2 * sizeof(render::Rgba),
                                "this image");
            Report report(ctx);
            const GridPtrVec grids =
                report.step("read " + a.input, [&] { return readGrids(a.input, ctx); });
            // The named grid, or the first float/double grid (level sets first).
            GridBase::Ptr grid;
            for (const auto& g : selectGrids(grids, a.grid, a.input)) {
                const bool floating =
                    gridPtrCast<FloatGrid>(g) != nullptr || gridPtrCast<DoubleGrid>(g) != nullptr;
                if (floating && (!grid || (grid->getGridClass() != GRID_LEVEL_SET &&
                                           g->getGridClass() == GRID_LEVEL_SET)))
                    grid = g;
            }
            if (!grid)
                throw UsageError(a.input + " has no float or double grid to render");
            const CoordBBox bbox = grid->evalActiveVoxelBoundingBox();
            if (bbox.empty())
                throw UsageError("grid \"" + grid->getName() + "\" of " + a.input +
                                 " is empty: nothing to render");
            const BBoxd worldBox = grid->transform().indexToWorld(bbox);
            const auto camera = makeCamera(a, worldBox);
            const bool levelSet = a.mode == "levelset" ||
                                  (a.mode == "auto" && grid->getGridClass() == GRID_LEVEL_SET);

            render::Image image, normals;
            withLevelSetGrid(grid, [&](auto& g) {
                report.step(
                    std::string(levelSet ? "ray-trace " : "volume-render ") + grid->getName() +
                        " (" + std::to_string(a.width) + "x" + std::to_string(a.height) + ")",
                    [&] {
                        if (levelSet) {
                            render::LevelSetRenderSettings settings;
                            settings.lightDirection = toVec(a.light);
                            image = render::renderLevelSet(g, *camera, settings,
                                                           a.normals.empty() ? nullptr : &normals);
                        } else {
                            render::VolumeRenderSettings settings;
                            settings.lightDirection = toVec(a.light);
                            settings.step = a.step;
                            // Default: an optical depth of about 4 across the volume.
                            settings.extinction =
                                a.extinction > 0
                                    ? a.extinction
                                    : 4.0 / std::max(1e-12, worldBox.extents().length());
                            image = render::renderFogVolume(g, *camera, settings);
                        }
                    });
            });
            report.step("write " + a.output, [&] { writePng(a.output, image); });
            if (!a.normals.empty())
                report.step("write " + a.normals, [&] { writePng(a.normals, normals); });
            report.json()
                .key("input")
                .value(a.input)
                .key("grid")
                .value(grid->getName())
                .key("mode")
                .value(levelSet ? "levelset" : "fog")
                .key("width")
                .value(static_cast<uint64_t>(a.width))
                .key("height")
                .value(static_cast<uint64_t>(a.height))
                .key("output")
                .value(a.output);
            report.finish();
        });
    cmd->add_option("input", args->input, "The .vdb file to read")->required();
    cmd->add_option("-o,--output", args->output, "The PNG picture to write")->required();
    cmd->add_option("-g,--grid", args->grid, "The grid to render (default: the first level set)");
    cmd->add_option("--mode", args->mode, "auto (by grid class), levelset or fog")
        ->check(CLI::IsMember({"auto", "levelset", "fog"}))
        ->capture_default_str();
    cmd->add_option("--camera", args->camera, "perspective or ortho")
        ->check(CLI::IsMember({"perspective", "ortho"}))
        ->capture_default_str();
    cmd->add_option("--width", args->width, "Image width in pixels")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    cmd->add_option("--height", args->height, "Image height in pixels")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    cmd->add_option("--fov", args->fov, "Vertical field of view in degrees (perspective)")
        ->check(CLI::Range(1.0, 179.0))
        ->capture_default_str();
    cmd->add_option("--view", args->view,
                    "Viewing direction x,y,z for automatic framing of the grid's bounding box")
        ->expected(3)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--position", args->position, "Camera position x,y,z (world units)")
        ->expected(3)
        ->delimiter(',');
    cmd->add_option("--look-at", args->lookAt, "Point x,y,z the camera looks at")
        ->expected(3)
        ->delimiter(',');
    cmd->add_option("--up", args->up, "Up direction x,y,z")
        ->expected(3)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--light", args->light, "Direction x,y,z towards the light")
        ->expected(3)
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--normals", args->normals, "Also write the surface normals as a PNG");
    cmd->add_option("--extinction", args->extinction,
                    "Fog: extinction per world unit at density 1 (default: optical depth ~4 "
                    "across the bounding box)")
        ->check(CLI::Range(0.0, 1e30));
    cmd->add_option("--step", args->step, "Fog: step inside leaves, in voxels")
        ->check(CLI::Range(0.01, 100.0))
        ->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb render sphere.vdb -o sphere.png\n"
        "  vdb render smoke.vdb -o smoke.png --grid density --width 640 --height 480\n"
        "  vdb render bunny.vdb -o bunny.png --position 0,1,5 --look-at 0,0,0 --fov 30");
}

}  // namespace vdb::app
