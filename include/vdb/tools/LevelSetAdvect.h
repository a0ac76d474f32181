// SPDX-License-Identifier: Apache-2.0
/// @file
/// LevelSetAdvection: moves a narrow-band level set through a velocity field by solving
///   phi_t + V . grad phi = 0
/// on its active voxels (paper 4.2 and 5.2), with upwind-biased first-order to HJ-WENO5 spatial
/// differences and TVD Runge-Kutta time integration in the leaves' temporal buffers (RK1 and
/// RK2 use one auxiliary buffer per leaf, RK3 two; buffers are swapped or written in place,
/// never copied grid-wide). Each time step is CFL-limited, dt <= CFL * dx / max |V| over the
/// active voxels (CFL 0.5 by default); after every step a LevelSetTracker rebuilds the band
/// (dilate, renormalise, trim, prune).
///
/// Time-dependent fields: the velocity driving a step is sampled once, at the middle of the
/// step, and the step is short enough for the CFL condition to hold with the speeds at its
/// start, middle and end. A field that vanishes at some instant (Enright's at t = 1.5) thus
/// still gets steps sized by the speed it reaches within them, rather than one step that
/// spans the whole interval with the vanishing velocity. Speeds are only looked at at those
/// three instants: a field whose speed on the band is zero at all three but not in between
/// is under-resolved unless the caller bounds the step (maxDt, or frames).
///
/// Cost per step: one sampling pass over the active voxels for a time-independent field
/// (declaring `TIME_DEPENDENT = false`), three for a time-dependent one (start speed, middle
/// velocities, end speed; more in the rare step that the middle or end speed shortens), then
/// per Runge-Kutta stage one pass over the active voxels (one-sided differences along each
/// axis, chosen by the sign of the velocity), then the tracker's rebuild. Threads: parallel
/// over leaves; results are bit-identical for any number of threads.
///
/// @code
/// auto grid = vdb::tools::createEnrightSphere<vdb::FloatGrid>(256);
/// vdb::tools::EnrightField<float> field;
/// vdb::tools::LevelSetAdvection<vdb::FloatGrid, vdb::tools::EnrightField<float>> advect(*grid,
///                                                                                    field);
/// advect.setSpatialScheme(vdb::math::HJWENO5_BIAS);
/// advect.setTemporalScheme(vdb::math::TVD_RK3);
/// size_t steps = advect.advect(0.0, 0.5);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/LevelSetTracker.h>
#include <vdb/tools/VelocityFields.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <string>
#include <vector>

namespace vdb::tools {

/// A velocity field: the world-space velocity at a world-space point and a time.
template <typename FieldT>
concept VelocityField = requires(const FieldT& field, const Vec3d& xyz, double t) {
    { field(xyz, t)[0] } -> std::convertible_to<double>;
};

/// Advects the level set of one grid through `FieldT`.
///
/// The grid follows LevelSetTracker's requirements. The advection keeps references to the grid
/// and the field, which must outlive it.
/// Threads: one call at a time; each call runs parallel over leaves.
template <typename GridT, VelocityField FieldT>
class LevelSetAdvection {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    using VectorType = math::Vec3<ValueType>;
    using TrackerType = LevelSetTracker<GridT>;

    /// @throw ValueError when the voxels are not cubes or the background is not positive.
    LevelSetAdvection(GridT& grid, const FieldT& field) : mTracker(grid), mField(&field) {}

    /// The tracker that rebuilds the band after each step (its schemes, norm count, threading).
    TrackerType& tracker() { return mTracker; }

    math::BiasedGradientScheme getSpatialScheme() const { return mSpatialScheme; }
    /// @throw ValueError for a scheme this library does not implement.
    void setSpatialScheme(math::BiasedGradientScheme s) {
        detail::checkSupported(s);
        mSpatialScheme = s;
    }
    math::TemporalIntegrationScheme getTemporalScheme() const { return mTemporalScheme; }
    /// @throw ValueError for UNKNOWN_TIS.
    void setTemporalScheme(math::TemporalIntegrationScheme s) {
        detail::checkSupported(s);
        mTemporalScheme = s;
    }
    math::BiasedGradientScheme getTrackerSpatialScheme() const {
        return mTracker.getSpatialScheme();
    }
    void setTrackerSpatialScheme(math::BiasedGradientScheme s) { mTracker.setSpatialScheme(s); }
    math::TemporalIntegrationScheme getTrackerTemporalScheme() const {
        return mTracker.getTemporalScheme();
    }
    void setTrackerTemporalScheme(math::TemporalIntegrationScheme s) {
        mTracker.setTemporalScheme(s);
    }
    /// Renormalisation steps per rebuild (the tracker's norm count; default 3).
    int getNormCount() const { return mTracker.getNormCount(); }
    void setNormCount(int n) { mTracker.setNormCount(n); }
    /// CFL number of the advection step (default 0.5).
    ValueType getCFL() const { return mCfl; }
    /// @throw ValueError unless 0 < cfl <= 1.
    void setCFL(ValueType cfl) {
        if (!(cfl > ValueType(0) && cfl <= ValueType(1)))
            throw ValueError("LevelSetAdvection: the CFL number must lie in (0, 1]");
        mCfl = cfl;
    }
    bool isThreaded() const { return mTracker.isThreaded(); }
    /// Parallel over leaves or not (also for the tracker); results are the same either way.
    void setThreaded(bool threaded) { mTracker.setThreaded(threaded); }

    /// Advects from time `t0` to `t1` (backwards when t1 < t0) in CFL-limited steps, rebuilding
    /// the band after each, and returns the number of steps. Always reaches t1: a step over
    /// which the velocity vanishes on every active voxel advances the time and leaves the grid
    /// as it is.
    size_t advect(double t0, double t1);

    /// Advects by one step of at most |maxDt| time units from time `t` (backwards when maxDt is
    /// negative) and returns the length of the step taken (0 only when maxDt is 0). With
    /// `rebuild`, the band is rebuilt afterwards (as advect() does). When the velocity vanishes
    /// on every active voxel at the start, middle and end of the step, the step takes all of
    /// |maxDt| and changes nothing.
    double step(double t, double maxDt, bool rebuild = true);

private:
    template <math::BiasedGradientScheme Scheme>
    void integrate(ValueType dt);
    /// The field at the active voxels (as counted in mOffsets) at `time`, negated when
    /// `backward`: stored into mVelocity when `store`; returns max |V|^2 over them.
    ValueType sampleField(double time, bool backward, bool store);

    TrackerType mTracker;
    const FieldT* mField;
    math::BiasedGradientScheme mSpatialScheme = math::HJWENO5_BIAS;
    math::TemporalIntegrationScheme mTemporalScheme = math::TVD_RK2;
    ValueType mCfl = ValueType(0.5);
    std::vector<size_t> mOffsets;
    std::vector<VectorType> mVelocity;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// A per-thread sampler of `field`: its sampler() when it has one, else the field itself.
template <typename FieldT>
auto makeFieldSampler(const FieldT& field) {
    if constexpr (requires { field.sampler(); }) {
        return field.sampler();
    } else {
        return [&field](const Vec3d& xyz, double t) { return field(xyz, t); };
    }
}

/// Whether the velocity of `FieldT` may change with time (true unless the field declares
/// `TIME_DEPENDENT = false`).
template <typename FieldT>
constexpr bool isTimeDependent() {
    if constexpr (requires { FieldT::TIME_DEPENDENT; }) {
        return bool(FieldT::TIME_DEPENDENT);
    } else {
        return true;
    }
}

}  // namespace detail

template <typename GridT, VelocityField FieldT>
size_t LevelSetAdvection<GridT, FieldT>::advect(double t0, double t1) {
    if (!std::isfinite(t0) || !std::isfinite(t1))
        throw ValueError("LevelSetAdvection::advect: the times must be finite, not " +
                         std::to_string(t0) + " and " + std::to_string(t1));
    size_t count = 0;
    const bool forward = t0 < t1;
    double t = t0;
    while (forward ? t < t1 : t > t1) {
        const double dt = step(t, t1 - t);
        if (dt == 0.0)
            break;
        // Land exactly on t1 when the step took all the time that was left.
        t = std::abs(t1 - t) <= dt ? t1 : t + (forward ? dt : -dt);
        ++count;
    }
    return count;
}

template <typename GridT, VelocityField FieldT>
double LevelSetAdvection<GridT, FieldT>::step(double t, double maxDt, bool rebuild) {
    if (!std::isfinite(t) || !std::isfinite(maxDt))
        throw ValueError("LevelSetAdvection::step: the time and the step must be finite, not " +
                         std::to_string(t) + " and " + std::to_string(maxDt));
    if (maxDt == 0.0)
        return 0.0;
    const bool backward = maxDt < 0.0;
    const double direction = backward ? -1.0 : 1.0;
    auto& leaves = mTracker.leafs();
    leaves.rebuild();
    mOffsets = detail::activeVoxelOffsets(leaves);
    // dt * speed <= limit for every speed looked at, and dt <= |maxDt|.
    const double limit = double(mCfl) * double(mTracker.voxelSize());
    double dt = std::abs(maxDt);
    const auto shorten = [&](ValueType speed2) {
        const double speed = std::sqrt(double(speed2));
        if (speed * dt > limit) {
            dt = limit / speed;
            return true;
        }
        return false;
    };
    ValueType maxV2(0);
    if constexpr (detail::isTimeDependent<FieldT>()) {
        shorten(sampleField(t, backward, false));
        // The middle velocities drive the step; the middle and end speeds may shorten it,
        // which moves the middle: sample again. Each round shortens dt, and after the
        // first few rounds the step is accepted as it is.
        constexpr int kRounds = 8;
        for (int round = 0; round < kRounds; ++round) {
            maxV2 = sampleField(t + direction * 0.5 * dt, backward, true);
            const bool shorterForMiddle = shorten(maxV2);
            const bool shorterForEnd = shorten(sampleField(t + direction * dt, backward, false));
            if (!shorterForMiddle && !shorterForEnd)
                break;
        }
    } else {
        maxV2 = sampleField(t, backward, true);
        shorten(maxV2);
    }
    if (maxV2 > math::Delta<ValueType>::value()) {
        detail::dispatchSpatialScheme(
            mSpatialScheme, [&]<math::BiasedGradientScheme S>() { integrate<S>(ValueType(dt)); });
        if (rebuild)
            mTracker.track();
    }
    mVelocity.clear();
    return dt;
}

template <typename GridT, VelocityField FieldT>
auto LevelSetAdvection<GridT, FieldT>::sampleField(double time, bool backward, bool store)
    -> ValueType {
    auto& leaves = mTracker.leafs();
    if (store)
        mVelocity.resize(mOffsets.back());
    const math::Transform& xform = mTracker.grid().transform();
    const ValueType sign = backward ? ValueType(-1) : ValueType(1);
    // A non-finite velocity anywhere is reported instead of spreading NaN through the band.
    const ValueType maxV2 = util::parallelReduce(
        leaves.leafCount(), ValueType(0),
        [&](size_t begin, size_t end) {
            auto sampler = detail::makeFieldSampler(*mField);
            ValueType maxV2(0);
            for (size_t li = begin; li < end; ++li) {
                const auto& leaf = leaves.leaf(li);
                size_t n = mOffsets[li];
                for (auto it = leaf.cbeginValueOn(); it; ++it, ++n) {
                    const Vec3d xyz = xform.indexToWorld(Vec3d(it.getCoord()));
                    const auto v = sampler(xyz, time);
                    const VectorType vel(sign * ValueType(v[0]), sign * ValueType(v[1]),
                                         sign * ValueType(v[2]));
                    if (store)
                        mVelocity[n] = vel;
                    const ValueType v2 = vel.lengthSqr();
                    // NaN wins the maximum, so that the check below sees it.
                    maxV2 = v2 > maxV2 || v2 != v2 ? v2 : maxV2;
                }
            }
            return maxV2;
        },
        [](ValueType a, ValueType b) { return b > a || b != b ? b : a; }, isThreaded(), 16);
    if (!std::isfinite(maxV2))
        throw ValueError(
            "LevelSetAdvection: the velocity field is not finite (NaN, infinite or "
            "too fast for the value type) on the band at time " +
            std::to_string(time));
    return maxV2;
}

template <typename GridT, VelocityField FieldT>
template <math::BiasedGradientScheme Scheme>
void LevelSetAdvection<GridT, FieldT>::integrate(ValueType dt) {
    constexpr int R = math::stencilRadius(Scheme);
    using Block = detail::LeafNeighborhood<TreeType, R>;
    auto& leaves = mTracker.leafs();
    const ValueType dtInvDx = dt / mTracker.voxelSize();
    const VectorType* vel = mVelocity.data();
    const size_t* offsets = mOffsets.data();
    // phi_t = -v . grad phi with upwind differences, a row of voxels at a time: the velocities
    // of the row's active voxels are spread out first (zero at inactive ones).
    constexpr int DIM = Block::DIM;
    const auto advection = [=](size_t li, Index ordinal, uint64_t rowBits, const ValueType* c,
                               ValueType* res) {
        ValueType v[3][DIM], dm[3][DIM], dp[3][DIM];
        const VectorType* next = vel + offsets[li] + ordinal;
        for (int k = 0; k < DIM; ++k) {
            const bool on = (rowBits >> k) & 1;
            for (int a = 0; a < 3; ++a)
                v[a][k] = on ? (*next)[size_t(a)] : ValueType(0);
            next += on;
        }
        detail::rowDifferences<Scheme>(c, Block::SX, Block::SY, dm, dp);
        for (int k = 0; k < DIM; ++k) {
            ValueType dot(0);
            for (int a = 0; a < 3; ++a)
                dot += v[a][k] * math::upwind(v[a][k], dm[a][k], dp[a][k]);
            res[k] = c[k] - dtInvDx * dot;
        }
    };
    const bool threaded = isThreaded();
    const auto stage = [&](Index src, Index dst, ValueType alpha) {
        detail::eulerStage<R>(leaves, src, dst, alpha, advection, threaded);
    };
    leaves.setAuxBufferCount(Index(math::auxBufferCount(mTemporalScheme)), threaded);
    detail::rungeKuttaStep(leaves, mTemporalScheme, stage, threaded);
    leaves.setAuxBufferCount(0, threaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetAdvect.cpp

namespace vdb::tools {

extern template class LevelSetAdvection<FloatGrid, EnrightField<float>>;
extern template class LevelSetAdvection<FloatGrid, ConstantVelocityField<float>>;
extern template class LevelSetAdvection<FloatGrid, DiscreteField<Vec3SGrid>>;
extern template class LevelSetAdvection<DoubleGrid, ConstantVelocityField<double>>;

}  // namespace vdb::tools
