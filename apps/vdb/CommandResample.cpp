// SPDX-License-Identifier: Apache-2.0
/// @file
/// `vdb resample IN.vdb -o OUT.vdb (--voxel-size S | --match REF.vdb | --scale F)`: grids
/// resampled to another voxel size or to another file's index space (tools/GridTransformer.h).
/// Level sets are rebuilt into a clean narrow band; other grids are reconstructed by the point,
/// box (default) or quadratic sampler.

#include <vdb/tools/GridTransformer.h>

#include "Commands.h"
#include "SurfaceGrid.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace vdb::app {

namespace {

struct ResampleArgs {
    EditArgs edit;
    double voxelSize = 0.0;
    std::string match;
    double scale = 0.0;
    std::string sampler = "box";
};

/// The transform `grid` is resampled to.
math::Transform::Ptr targetTransform(const ResampleArgs& a, const GridBase& grid,
                                     const math::Transform* reference) {
    if (!grid.transform().isLinear())
        throw UsageError("grid \"" + grid.getName() +
                         "\" has a frustum transform; resample needs a linear one");
    if (reference)
        return reference->copy();
    // Scale index space about index 0, so the grid keeps its place and orientation.
    const double factor = a.voxelSize > 0 ? a.voxelSize / grid.voxelSize()[0] : a.scale;
    math::Transform::Ptr xform = grid.transform().copy();
    xform->preScale(factor);
    return xform;
}

template <typename SamplerT, typename GridT>
void resampleGrid(GridT& grid, const math::Transform::Ptr& target, Index64 maxVoxels) {
    auto out = GridT::create();
    out->setTransform(target);
    try {
        tools::resampleToMatch<SamplerT>(grid, *out, maxVoxels);
    } catch (const ValueError& e) {
        // The hint only where the voxel limit (set by --max-memory) refused the work.
        const std::string what = e.what();
        const bool overLimit = what.find("more than the limit") != std::string::npos;
        throw UsageError("grid \"" + grid.getName() + "\": " + what +
                         (overLimit ? " (--max-memory raises the limit)" : ""));
    }
    grid.setTree(out->treePtr());
    grid.setTransform(target);
}

}  // namespace

void addResampleCommand(CLI::App& app, Context& ctx) {
    auto args = std::make_shared<ResampleArgs>();
    CLI::App* cmd = addCommand(
        app, ctx, "resample",
        "Resample grids to another voxel size or to another file's transform (level sets are "
        "rebuilt into a clean narrow band)",
        true, [args, &ctx] {
            const ResampleArgs& a = *args;
            const int given = int(a.voxelSize > 0) + int(!a.match.empty()) + int(a.scale > 0);
            if (given != 1)
                throw UsageError("give exactly one of --voxel-size, --match and --scale");
            math::Transform::Ptr reference;
            if (!a.match.empty()) {
                const GridPtrVec refs = readGrids(a.match, ctx);
                if (refs.empty())
                    throw UsageError(a.match + " holds no grid whose transform could be matched");
                reference = refs.front()->transform().copy();
                if (!reference->isLinear())
                    throw UsageError("the first grid of " + a.match +
                                     " has a frustum transform; resample needs a linear one");
            }
            runEdit(ctx, a.edit, [&](Report& report, const GridBase::Ptr& grid) {
                const auto target = targetTransform(a, *grid, reference.get());
                if (!gridIsOneOf<FloatingPointGridTypes>(*grid)) {
                    throw UsageError("grid \"" + grid->getName() + "\" has type " + grid->type() +
                                     "; resample handles float, double, vec3s and vec3d grids "
                                     "(choose grids with --grid)");
                }
                // Level sets are rebuilt through a mesh of float points in world space, for any
                // linear target: the finest of its voxel sizes sets the precision needed.
                if (grid->getGridClass() == GRID_LEVEL_SET && gridIsOneOf<RealGridTypes>(*grid)) {
                    const Vec3d size = target->voxelSize();
                    checkSurfacePrecision(*grid, std::min({size[0], size[1], size[2]}));
                }
                // The voxels the output may hold, at about the bytes of one value each.
                const double bytesPerVoxel = gridPtrCast<FloatGrid>(grid)    ? 4.0
                                             : gridPtrCast<Vec3SGrid>(grid)  ? 12.0
                                             : gridPtrCast<DoubleGrid>(grid) ? 8.0
                                                                             : 24.0;
                const Index64 maxVoxels = Index64(std::min(
                    double(tools::DEFAULT_MAX_RESAMPLE_VOXELS), memoryLimit() / bytesPerVoxel));
                report.step(
                    "resample " + grid->getName() + " to voxel size " +
                        numberText(target->voxelSize()[0]),
                    [&] {
                        withAnyGrid(grid, [&](auto& g) {
                            using GridT = std::decay_t<decltype(g)>;
                            using V = typename GridT::ValueType;
                            if constexpr (std::is_floating_point_v<V> || std::is_same_v<V, Vec3s> ||
                                          std::is_same_v<V, Vec3d>) {
                                if (a.sampler == "point")
                                    resampleGrid<tools::PointSampler>(g, target, maxVoxels);
                                else if (a.sampler == "quadratic")
                                    resampleGrid<tools::QuadraticSampler>(g, target, maxVoxels);
                                else
                                    resampleGrid<tools::BoxSampler>(g, target, maxVoxels);
                            }
                        });
                    });
                return true;
            });
        });
    addEditOptions(*cmd, args->edit);
    cmd->add_option("-s,--voxel-size", args->voxelSize,
                    "Voxel edge of the result along x, in world units (other axes scale alike)")
        ->check(positive());
    cmd->add_option("-m,--match", args->match,
                    "Resample into the transform of the first grid of this .vdb file");
    cmd->add_option("--scale", args->scale,
                    "Multiply the voxel size by this factor (2: half the resolution)")
        ->check(positive());
    cmd->add_option("--sampler", args->sampler,
                    "Reconstruction of grids other than level sets: point, box or quadratic")
        ->check(CLI::IsMember({"point", "box", "quadratic"}))
        ->capture_default_str();
    cmd->footer(
        "Examples:\n  vdb resample smoke.vdb -o coarse.vdb --scale 2\n"
        "  vdb resample bunny.vdb -o fine.vdb --voxel-size 0.005 --sampler quadratic\n"
        "  vdb resample vel.vdb -o vel-on-smoke.vdb --match smoke.vdb");
}

}  // namespace vdb::app
