// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb spheres -o OUT.vdb`: spheres to a narrow-band level set, either the torus-knot-helix of
/// the paper's Fig. 8 or spheres listed in a text file.

#include "Commands.h"
#include "Geometry.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace vdb::app {
namespace {

/// Reads spheres from a text file: one "x y z radius" per line, separated by spaces, tabs or
/// commas; blank lines and lines starting with '#' are skipped, and so is a first line that is
/// not numeric (a CSV header).
tools::SphereList readSpheres(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw UsageError("cannot open " + path);
    tools::SphereList spheres;
    std::string line;
    size_t lineNumber = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        std::replace(line.begin(), line.end(), ',', ' ');
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#')
            continue;
        std::istringstream fields(line);
        double v[4];
        int count = 0;
        while (count < 4 && fields >> v[count])
            ++count;
        std::string rest;
        const bool extra = static_cast<bool>(fields >> rest);
        if (count == 0 && lineNumber == 1 && spheres.positions.empty())
            continue;  // a header line
        const std::string where = path + ":" + std::to_string(lineNumber) + ": ";
        if (count < 4 || extra)
            throw UsageError(where + "expected four numbers \"x y z radius\"");
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) ||
            !std::isfinite(v[3]) || std::abs(v[0]) > 1e30 || std::abs(v[1]) > 1e30 ||
            std::abs(v[2]) > 1e30)
            throw UsageError(where + "a coordinate or radius is not a finite number");
        if (!(v[3] > 0))
            throw UsageError(where + "the radius must be positive");
        spheres.positions.emplace_back(float(v[0]), float(v[1]), float(v[2]));
        spheres.radii.push_back(float(v[3]));
        if (spheres.radii.size() % (1u << 20) == 0)
            checkMemoryEstimate(double(spheres.radii.size()) * (sizeof(Vec3s) + sizeof(float)) * 2,
                                "the spheres of " + path + " (" + withCommas(spheres.radii.size()) +
                                    " read so far)");
    }
    if (in.bad())
        throw UsageError("cannot read " + path);
    if (spheres.positions.empty())
        throw UsageError(path + " lists no spheres");
    return spheres;
}

}  // namespace

FloatGrid::Ptr spheresToGrid(Report& report, const tools::SphereList& spheres, double voxelSize,
                             float halfWidth) {
    // Band voxels: at most every sphere's band, and at most the spheres' bounding box.
    BBoxd box;
    double bandVoxels = 0.0;
    for (size_t n = 0; n < spheres.positions.size(); ++n) {
        const double r = spheres.radii[n] / voxelSize;
        box.expand(Vec3d(spheres.positions[n]) - spheres.radii[n]);
        box.expand(Vec3d(spheres.positions[n]) + spheres.radii[n]);
        bandVoxels += 4.0 * 3.14159 * (r * r + halfWidth * halfWidth) * 2.0 * halfWidth;
    }
    for (int a = 0; a < 3; ++a)
        checkIndexRange(box.min()[a] / voxelSize - halfWidth, box.max()[a] / voxelSize + halfWidth,
                        "these spheres at voxel size " + numberText(voxelSize));
    const Vec3d cells = box.extents() / voxelSize + 2.0 * halfWidth;
    bandVoxels = std::min(bandVoxels, cells[0] * cells[1] * cells[2]);
    checkMemoryEstimate(12.0 * bandVoxels, "these spheres at this voxel size");
    // The rasterizer holds the centers as floats.
    checkFloatPrecision(box, voxelSize, "the box of these spheres");

    auto grid = FloatGrid::create(float(halfWidth * voxelSize));
    grid->setTransform(math::Transform::createLinearTransform(voxelSize));
    grid->setGridClass(GRID_LEVEL_SET);
    tools::ParticlesToLevelSet<FloatGrid> raster(*grid);
    report.step("rasterize " + withCommas(spheres.positions.size()) + " spheres", [&] {
        raster.rasterizeSpheres(spheres.positions, spheres.radii);
        raster.finalize();
    });
    if (raster.getMinCount() > 0)
        report.note("  " + withCommas(raster.getMinCount()) + " spheres skipped: radius below " +
                    std::to_string(raster.getRmin()) + " voxels");
    return grid;
}

void addSpheresCommand(CLI::App& app, Context& ctx) {
    struct Args {
        OutputArgs out;
        std::string input;
        size_t count = 1'000'000;
        float radius = 0.005f;
        double voxelSize = 1.0 / 1024.0;
        float halfWidth = 3.0f;
        uint64_t seed = 20130601;
        std::string name = "spheres";
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = addCommand(
        app, ctx, "spheres",
        "Spheres to a narrow-band level set: the torus-knot-helix of the paper's Fig. 8, or "
        "spheres from a text file",
        true, [args, &ctx] {
            Args& a = *args;
            if (a.input.empty())
                checkMemoryEstimate(double(a.count) * (sizeof(Vec3s) + sizeof(float)) * 2.0,
                                    withCommas(a.count) + " spheres");
            runCreate(
                ctx, a.out, a.name,
                [&](Report& report) {
                    const tools::SphereList spheres =
                        a.input.empty()
                            ? report.step("place " + withCommas(a.count) + " spheres on the helix",
                                          [&] {
                                              return tools::torusKnotHelixSpheres(a.count, a.radius,
                                                                                  a.seed);
                                          })
                            : report.step("read " + a.input, [&] { return readSpheres(a.input); });
                    report.json().key("spheres").value(
                        static_cast<uint64_t>(spheres.positions.size()));
                    return spheresToGrid(report, spheres, a.voxelSize, a.halfWidth);
                },
                "spheres below " + numberText(kMinSphereVoxels) + " voxels of radius are skipped");
        });
    addOutputOptions(*cmd, args->out);
    cmd->add_option("-i,--input", args->input,
                    "Instead of the helix: a text file of spheres, one \"x y z radius\" per line "
                    "(spaces or commas; '#' comments)");
    cmd->add_option("--count", args->count, "Helix: number of spheres")
        ->check(CLI::Range(size_t(1), size_t(100'000'000)))
        ->capture_default_str();
    cmd->add_option("-r,--radius", args->radius,
                    "Helix: largest sphere radius (radii are 0.75 to 1 times it); the curve "
                    "fills the unit box")
        ->check(positive())
        ->capture_default_str();
    cmd->add_option("-s,--voxel-size", args->voxelSize, "Voxel edge in world units")
        ->check(positive())
        ->capture_default_str();
    cmd->add_option("-w,--half-width", args->halfWidth, "Half the band width, in voxels")
        ->check(finiteRange(1.0, 1000.0))
        ->capture_default_str();
    cmd->add_option("--seed", args->seed, "Helix: random seed")->capture_default_str();
    cmd->add_option("-n,--name", args->name, "Grid name")->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb spheres -o helix.vdb --count 1000000 --voxel-size 0.001\n"
        "  vdb spheres -o points.vdb --input points.csv --voxel-size 0.05");
}

}  // namespace vdb::app
