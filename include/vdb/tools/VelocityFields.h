// SPDX-License-Identifier: Apache-2.0
/// @file
/// Velocity fields for level set advection (LevelSetAdvect.h): the Enright test field, a
/// constant field, and a field sampled from a vector grid.
///
/// A field is any type with `Vec3<T> operator()(const Vec3d& xyz, double time) const` giving the
/// velocity at the world-space point `xyz` (world units per unit time). A field may also offer
/// `sampler()`, returning a per-thread object with the same call operator (DiscreteField does,
/// so that each thread reads the velocity grid through its own accessor), and may declare
/// `static constexpr bool TIME_DEPENDENT = false` when its velocity does not change with time
/// (fields that do not say are treated as time-dependent; see LevelSetAdvection::step()).
///
/// @code
/// vdb::tools::EnrightField<float> field;                 // period 3
/// vdb::Vec3s v = field(vdb::Vec3d(0.35, 0.35, 0.35), 0.0);
/// vdb::tools::DiscreteField<vdb::Vec3SGrid> sampled(*velocityGrid);  // trilinear
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Stencils.h>
#include <vdb/math/Vec3.h>

#include <cmath>
#include <numbers>
#include <type_traits>

namespace vdb::tools {

/// The divergence-free, time-reversing test field of Enright et al. 2002 (after LeVeque 1996),
/// in the unit box:
///   u =  2 sin^2(pi x) sin(2 pi y) sin(2 pi z) c(t)
///   v = -sin(2 pi x) sin^2(pi y) sin(2 pi z) c(t)
///   w = -sin(2 pi x) sin(2 pi y) sin^2(pi z) c(t),     c(t) = cos(pi t / PERIOD),
/// with PERIOD = 3: a shape advected from t = 0 to t = PERIOD returns to where it started.
/// Threads: a plain value; concurrent calls are safe.
template <typename ScalarT = float>
class EnrightField {
public:
    using ScalarType = ScalarT;
    using VectorType = math::Vec3<ScalarT>;
    static constexpr double PERIOD = 3.0;
    static constexpr bool TIME_DEPENDENT = true;

    VectorType operator()(const Vec3d& xyz, double time) const {
        constexpr ScalarT pi = std::numbers::pi_v<ScalarT>;
        const ScalarT px = pi * ScalarT(xyz[0]), py = pi * ScalarT(xyz[1]),
                      pz = pi * ScalarT(xyz[2]);
        const ScalarT c = std::cos(ScalarT(time) * pi / ScalarT(PERIOD));
        const ScalarT sx = std::sin(px), sy = std::sin(py), sz = std::sin(pz);
        const ScalarT s2x = std::sin(ScalarT(2) * px), s2y = std::sin(ScalarT(2) * py),
                      s2z = std::sin(ScalarT(2) * pz);
        return VectorType(c * ScalarT(2) * sx * sx * s2y * s2z, -c * s2x * sy * sy * s2z,
                          -c * s2x * s2y * sz * sz);
    }
};

/// The same velocity everywhere and at all times.
template <typename ScalarT = float>
class ConstantVelocityField {
public:
    using ScalarType = ScalarT;
    using VectorType = math::Vec3<ScalarT>;

    static constexpr bool TIME_DEPENDENT = false;

    /// @throw ValueError for a velocity that is not finite.
    explicit ConstantVelocityField(const VectorType& velocity) : mVelocity(velocity) {
        if (!std::isfinite(velocity[0]) || !std::isfinite(velocity[1]) ||
            !std::isfinite(velocity[2]))
            throw ValueError("ConstantVelocityField: the velocity must be finite");
    }
    VectorType operator()(const Vec3d&, double) const { return mVelocity; }
    const VectorType& velocity() const { return mVelocity; }

private:
    VectorType mVelocity;
};

/// A steady velocity field sampled from a vector grid (world units per unit time) by trilinear
/// interpolation, in one of two interpretations:
/// - collocated: the vector of voxel (i, j, k) is the velocity at the voxel centre;
/// - staggered (MAC): component c of voxel (i, j, k) is the velocity component on the face of
///   the voxel's cell below it along axis c, at (i, j, k) - 0.5 e_c in index space. Each
///   component is then interpolated on its own lattice.
/// The default interpretation follows the grid class (GRID_STAGGERED is staggered).
/// The grid must outlive the field. Threads: operator() reads the tree top-down and is safe to
/// call concurrently; sampler() gives a faster per-thread sampler with a cached accessor.
template <typename VelGridT>
class DiscreteField {
public:
    using VectorType = typename VelGridT::ValueType;
    using ScalarType = typename VectorType::ValueType;
    static constexpr bool TIME_DEPENDENT = false;

    explicit DiscreteField(const VelGridT& grid)
        : DiscreteField(grid, grid.getGridClass() == GRID_STAGGERED) {}
    DiscreteField(const VelGridT& grid, bool staggered) : mGrid(&grid), mStaggered(staggered) {}

    bool isStaggered() const { return mStaggered; }

    /// A sampler for one thread: the same values as the field, through a cached accessor.
    class Sampler {
    public:
        explicit Sampler(const DiscreteField& field)
            : mGrid(field.mGrid), mStaggered(field.mStaggered), mBox(*field.mGrid) {}
        VectorType operator()(const Vec3d& xyz, double /*time*/) {
            const Vec3d p = mGrid->worldToIndex(xyz);
            if (!mStaggered)
                return mBox.interpolation(p);
            VectorType v;
            for (size_t c = 0; c < 3; ++c) {
                Vec3d q = p;
                q[c] += 0.5;
                v[c] = mBox.interpolation(q)[c];
            }
            return v;
        }

    private:
        const VelGridT* mGrid;
        bool mStaggered;
        math::BoxStencil<VelGridT> mBox;
    };
    Sampler sampler() const { return Sampler(*this); }

    VectorType operator()(const Vec3d& xyz, double time) const {
        Sampler s(*this);
        return s(xyz, time);
    }

private:
    const VelGridT* mGrid;
    bool mStaggered;
};

}  // namespace vdb::tools
