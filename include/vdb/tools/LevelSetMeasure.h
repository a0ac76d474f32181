// SPDX-License-Identifier: Apache-2.0
/// @file
/// Measures of the surface of a narrow-band level set, with OpenVDB 10's names and meanings:
/// area, enclosed volume, total and average mean and Gaussian curvature, Euler characteristic
/// and genus.
///
/// Each measure is an integral over the surface written as a volume integral with a smeared
/// Dirac delta of the distance, D(x) = (1 + cos(pi x / e)) / (2e) for |x| < e, e = 1.5 voxels:
///   area    = sum over active voxels of D(phi) |grad phi|,
///   volume  = 1/3 sum of D(phi) x . grad phi   (the divergence theorem, x in voxel units),
///   total mean curvature     = sum of D(phi) |grad phi| H,
///   total Gaussian curvature = sum of D(phi) |grad phi| K,
/// with second-order central differences (math/FiniteDifference.h), times the voxel's area,
/// volume or length in world units. The Euler characteristic is the total Gaussian curvature
/// over 2 pi rounded to an integer (Gauss-Bonnet), the genus 1 - chi/2 (for one connected
/// surface). Each leaf's sums are kept apart and added in ascending order, so results are the
/// same for any thread count and cancellation between far-apart leaves stays small.
///
/// smearedHeavisideVolume() is a second estimate of the volume, from the values alone: the sum
/// over every voxel and tile of a smeared Heaviside of -phi. The Enright test reports it.
///
/// Cost: one pass over the active voxels for area and volume, another for the curvatures (each
/// leaf near the surface gathers its neighbourhood into a dense block). Threads: parallel over
/// leaves.
///
/// @code
/// double a = vdb::tools::levelSetArea(*sphere);     // 4 pi r^2, world units
/// double v = vdb::tools::levelSetVolume(*sphere);   // 4/3 pi r^3
/// int g = vdb::tools::levelSetGenus(*torus);        // 1
/// vdb::tools::LevelSetMeasure<vdb::FloatGrid> m(*grid);
/// double h = m.avgMeanCurvature();                  // 1/r on a sphere
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// The surface area of a narrow-band level set, in world units (voxel units when
/// `useWorldSpace` is false).
/// @throw TypeError for a grid whose values are not floating-point scalars, naming its type;
/// ValueError for a grid that is not a level set, is empty or has non-cubic voxels.
template <typename GridT>
double levelSetArea(const GridT& grid, bool useWorldSpace = true);

/// The volume enclosed by a narrow-band level set (see levelSetArea() for the errors).
template <typename GridT>
double levelSetVolume(const GridT& grid, bool useWorldSpace = true);

/// The Euler characteristic of the surface of a narrow-band level set (2 for a sphere, 0 for a
/// torus; the sum over the connected surfaces). See levelSetArea() for the errors.
template <typename GridT>
int levelSetEulerCharacteristic(const GridT& grid);

/// The genus of the surface of a narrow-band level set (0 for a sphere, 1 for a torus); only
/// meaningful for one connected surface. See levelSetArea() for the errors.
template <typename GridT>
int levelSetGenus(const GridT& grid);

/// The volume inside the level set of `grid`: the voxel volume times the sum over all voxels
/// and tiles of a smeared Heaviside of -phi, H(x) = 1/2 + x/(2e) + sin(pi x/e)/(2 pi) for
/// |x| < e, with e = `smearing` voxels. Deterministic for any thread count.
template <typename GridT>
double smearedHeavisideVolume(const GridT& grid, double smearing = 1.5, bool threaded = true);

/// Area, volume and curvatures of a narrow-band level set, each computed on first request and
/// kept (area and volume together, then both curvatures together).
///
/// The grid must be of class GRID_LEVEL_SET, not empty, with cubic voxels and values in world
/// units; it must outlive the measure and not change while it is used (call init() after a
/// change). Threads: one call at a time; each computation runs in parallel over leaves unless
/// the grain size is 0.
template <typename GridT>
class LevelSetMeasure {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    static_assert(std::is_floating_point_v<ValueType>,
                  "LevelSetMeasure needs a level set grid with floating-point values");

    /// @throw ValueError when the grid is not a level set, is empty or has non-cubic voxels.
    explicit LevelSetMeasure(const GridT& grid) { init(grid); }
    /// Measures `grid` from now on, forgetting earlier results.
    void init(const GridT& grid);

    /// The number of leaves per task; 0 runs serially.
    int getGrainSize() const { return mGrainSize; }
    void setGrainSize(int grainSize) { mGrainSize = grainSize < 0 ? 0 : grainSize; }

    /// The surface area (world units, else voxel units).
    double area(bool useWorldUnits = true);
    /// The enclosed volume.
    double volume(bool useWorldUnits = true);
    /// The integral of the mean curvature over the surface (4 pi r on a sphere: a length).
    double totMeanCurvature(bool useWorldUnits = true);
    /// The integral of the Gaussian curvature over the surface (4 pi on a sphere; no unit).
    double totGaussianCurvature(bool useWorldUnits = true);
    /// totMeanCurvature() / area(): 1/r on a sphere.
    double avgMeanCurvature(bool useWorldUnits = true) {
        return totMeanCurvature(useWorldUnits) / area(useWorldUnits);
    }
    /// totGaussianCurvature() / area(): 1/r^2 on a sphere.
    double avgGaussianCurvature(bool useWorldUnits = true) {
        return totGaussianCurvature(useWorldUnits) / area(useWorldUnits);
    }
    /// The total Gaussian curvature over 2 pi, rounded (Gauss-Bonnet).
    int eulerCharacteristic();
    /// 1 - eulerCharacteristic() / 2; meaningful for one connected surface.
    int genus() { return 1 - eulerCharacteristic() / 2; }

private:
    void measureAreaAndVolume();
    void measureCurvatures();

    const GridT* mGrid = nullptr;
    double mDx = 1.0;
    double mArea = 0.0, mVolume = 0.0, mTotMeanCurvature = 0.0, mTotGaussCurvature = 0.0;
    bool mHasArea = false, mHasCurvature = false;
    int mGrainSize = 1;
};

}  // namespace vdb::tools

// ---- Implementation ---------------------------------------------------------------------------

#include <vdb/tools/detail/LevelSetMeasureImpl.h>

// ---- Instantiated once in src/instantiate/LevelSetMeasure.cpp

namespace vdb::tools {

extern template class LevelSetMeasure<FloatGrid>;
extern template class LevelSetMeasure<DoubleGrid>;
extern template double smearedHeavisideVolume(const FloatGrid&, double, bool);
extern template double smearedHeavisideVolume(const DoubleGrid&, double, bool);

}  // namespace vdb::tools
