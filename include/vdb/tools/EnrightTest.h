// SPDX-License-Identifier: Apache-2.0
/// @file
/// The Enright test (Enright et al. 2002; the paper's section 5.2) as a library function: the
/// sphere of radius 0.15 around (0.35, 0.35, 0.35) in the unit box, at voxel size 1/resolution,
/// advected through EnrightField from t = 0 to the end time (a full period, 3, by default),
/// with the volume enclosed by the level set and the active voxel count reported at the start
/// and after each frame. After a full period the sphere should be back where it started; the
/// volume it lost measures the numerical dissipation of the schemes.
///
/// The volume is smearedHeavisideVolume() (tools/LevelSetMeasure.h): the sum over every voxel
/// (and tile) of a smeared Heaviside H(-phi) of width 1.5 voxels, times the voxel volume.
///
/// The library never prints: the caller receives each sample (and the grid, to write frames).
///
/// @code
/// vdb::tools::EnrightTestOptions options;
/// options.resolution = 128;
/// options.frames = 12;
/// auto result = vdb::tools::runEnrightTest(options, [](const auto& sample, const auto& grid) {
///     std::printf("t=%.3f volume=%.6f voxels=%llu\n", sample.time, sample.volume, ...);
/// });
/// double loss = result.volumeLoss();  // relative
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/LevelSetMeasure.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/VelocityFields.h>

#include <cstddef>
#include <functional>

namespace vdb::tools {

/// Settings of one Enright test run; the defaults are the paper's Table III schemes.
struct EnrightTestOptions {
    int resolution = 128;    ///< voxels per unit length (voxel size 1/resolution)
    float halfWidth = 5.0f;  ///< narrow band half width in voxels (band 2 x halfWidth)
    double endTime = EnrightField<float>::PERIOD;  ///< advect from 0 to this time
    int frames = 1;  ///< samples taken at endTime * f / frames, f = 1 .. frames
    math::BiasedGradientScheme spatialScheme = math::HJWENO5_BIAS;
    math::TemporalIntegrationScheme temporalScheme = math::TVD_RK3;
    math::BiasedGradientScheme trackerSpatialScheme = math::HJWENO5_BIAS;
    math::TemporalIntegrationScheme trackerTemporalScheme = math::TVD_RK1;
    int normCount = 3;  ///< renormalisation steps per rebuild
    double cfl = 0.5;   ///< CFL number of the advection steps
    bool threaded = true;
};

/// The state of the test at one time.
struct EnrightSample {
    double time = 0.0;
    size_t steps = 0;     ///< advection steps taken since t = 0
    double volume = 0.0;  ///< smearedHeavisideVolume() of the grid
    Index64 activeVoxels = 0;
};

/// The first and last samples of a run.
struct EnrightResult {
    EnrightSample initial;
    EnrightSample final;
    /// Relative volume loss (V0 - V1) / V0; negative when the volume grew.
    double volumeLoss() const { return (initial.volume - final.volume) / initial.volume; }
};

/// Runs the Enright test with `options`, calling `onSample(sample, grid)` at t = 0 and after
/// each frame (the grid may be written to a file there).
/// @throw ValueError for a resolution below 8, a non-positive end time or frame count.
template <typename GridT = FloatGrid>
EnrightResult runEnrightTest(
    const EnrightTestOptions& options,
    const std::function<void(const EnrightSample&, const GridT&)>& onSample = {});

// ---- Implementation ---------------------------------------------------------------------------

template <typename GridT>
EnrightResult runEnrightTest(
    const EnrightTestOptions& options,
    const std::function<void(const EnrightSample&, const GridT&)>& onSample) {
    if (options.resolution < 8)
        throw ValueError("runEnrightTest: the resolution must be at least 8");
    if (!(options.endTime > 0.0) || options.frames < 1)
        throw ValueError("runEnrightTest: the end time and the frame count must be positive");
    auto grid = createEnrightSphere<GridT>(options.resolution, options.halfWidth, options.threaded);
    const EnrightField<typename GridT::ValueType> field;
    LevelSetAdvection<GridT, EnrightField<typename GridT::ValueType>> advection(*grid, field);
    advection.setSpatialScheme(options.spatialScheme);
    advection.setTemporalScheme(options.temporalScheme);
    advection.setTrackerSpatialScheme(options.trackerSpatialScheme);
    advection.setTrackerTemporalScheme(options.trackerTemporalScheme);
    advection.setNormCount(options.normCount);
    advection.setCFL(typename GridT::ValueType(options.cfl));
    advection.setThreaded(options.threaded);

    EnrightResult result;
    EnrightSample sample;
    const auto measure = [&](double time) {
        sample.time = time;
        sample.volume = smearedHeavisideVolume(*grid, 1.5, options.threaded);
        sample.activeVoxels = grid->activeVoxelCount();
        if (onSample)
            onSample(sample, *grid);
    };
    measure(0.0);
    result.initial = sample;
    double t = 0.0;
    for (int f = 1; f <= options.frames; ++f) {
        const double next = options.endTime * double(f) / double(options.frames);
        sample.steps += advection.advect(t, next);
        t = next;
        measure(t);
    }
    result.final = sample;
    return result;
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetAdvect.cpp

namespace vdb::tools {

extern template EnrightResult runEnrightTest<FloatGrid>(
    const EnrightTestOptions&, const std::function<void(const EnrightSample&, const FloatGrid&)>&);

}  // namespace vdb::tools
