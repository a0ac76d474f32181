// SPDX-License-Identifier: Apache-2.0
/// @file
/// Reconstruction of a continuous field from voxel values, with OpenVDB's samplers, names and
/// arithmetic: PointSampler (nearest voxel), BoxSampler (trilinear, 8 voxels),
/// QuadraticSampler (triquadratic, 27 voxels), their staggered forms for face-centred vector
/// grids, GridSampler (index or world space through a grid's transform), DualGridSampler
/// (one grid read at the voxel centres of another) and WorldSampler (a grid as a function of
/// world position, one accessor per copy, for the field extension of FastSweeping.h).
///
/// Index space is voxel-centred: the value of voxel (i, j, k) sits at the point (i, j, k), so
/// sampling at an integer point returns that voxel's value exactly. Any object with
/// `getValue(const Coord&)` serves as the accessor (a tree, a ValueAccessor); the forms that
/// report activity also need `probeValue(const Coord&, ValueT&)`. Values may be scalars or
/// vectors (Vec3s, Vec3d), which are interpolated component by component.
///
/// The arithmetic is OpenVDB 10's, so code ported from it gets the same numbers: the point
/// sampler rounds halves away from zero; the box sampler interpolates z, then y, then x, each
/// step a + ValueT((b - a) * w) with the product in double; the quadratic sampler fits, along
/// each axis, the parabola through the voxels floor - 1, floor and floor + 1 and evaluates it
/// at the fraction t in [0, 1), with its coefficients rounded to the value type.
///
/// @code
/// vdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
/// float v = vdb::tools::BoxSampler::sample(acc, vdb::Vec3d(1.25, -3.5, 0.75));
/// float w;
/// bool active = vdb::tools::QuadraticSampler::sample(acc, vdb::Vec3d(1.25, -3.5, 0.75), w);
/// vdb::tools::GridSampler<vdb::FloatGrid, vdb::tools::BoxSampler> sampler(*grid);
/// float u = sampler.wsSample(vdb::Vec3d(0.1, 0.2, 0.3));  // a world-space position
/// @endcode
///
/// Cost: 1, 8 and 27 accessor reads (three times that for the staggered forms). Threads: the
/// samplers are stateless; an accessor is not thread-safe, so use one per thread.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>

#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

namespace vdb::tools {

/// Nearest-voxel reconstruction: the value of the voxel whose centre is closest to the sample
/// point, halves rounded away from zero (2.5 reads voxel 3, -2.5 voxel -3).
struct PointSampler {
    static constexpr int RADIUS = 0;  ///< voxels read on each side of the sample point
    static constexpr const char* name() { return "point"; }
    static constexpr int radius() { return RADIUS; }
    static constexpr bool mipmap() { return false; }
    static constexpr bool consistent() { return true; }
    static constexpr bool staggered() { return false; }
    static constexpr size_t order() { return 0; }

    /// Stores the reconstruction at the index-space point `xyz` in `result`; returns whether
    /// the voxel read is active.
    template <typename AccT, typename ValueT>
    static bool sample(const AccT& acc, const Vec3d& xyz, ValueT& result);
    /// Returns the reconstruction at the index-space point `xyz`.
    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz);
};

/// Trilinear reconstruction from the 8 voxels around the sample point; exact for fields that
/// are linear in each coordinate.
struct BoxSampler {
    static constexpr int RADIUS = 1;
    static constexpr const char* name() { return "box"; }
    static constexpr int radius() { return RADIUS; }
    static constexpr bool mipmap() { return true; }
    static constexpr bool consistent() { return true; }
    static constexpr bool staggered() { return false; }
    static constexpr size_t order() { return 1; }

    /// Stores the reconstruction at `xyz` in `result`; returns whether any of the 8 voxels
    /// read is active.
    template <typename AccT, typename ValueT>
    static bool sample(const AccT& acc, const Vec3d& xyz, ValueT& result);
    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz);

    /// Reads the values of the voxels ijk + (a, b, c), a, b, c in {0, 1}, into v[a][b][c].
    template <typename AccT, typename ValueT>
    static void getValues(const AccT& acc, const Coord& ijk, ValueT (&v)[2][2][2]);
    /// As getValues(); returns whether any of the 8 voxels is active.
    template <typename AccT, typename ValueT>
    static bool probeValues(const AccT& acc, const Coord& ijk, ValueT (&v)[2][2][2]);
    /// Interpolates the corner values `v` at the fractional position `uvw` in [0, 1]^3.
    template <typename ValueT>
    static ValueT trilinear(const ValueT (&v)[2][2][2], const Vec3d& uvw);
    /// The gradient (per voxel) of the trilinear interpolant of scalar corner values `v` at
    /// `uvw`.
    template <typename ValueT>
    static Vec3d trilinearGradient(const ValueT (&v)[2][2][2], const Vec3d& uvw);
    /// The gradient (per voxel) of the trilinear interpolant of a scalar field at `xyz`.
    template <typename AccT>
    static Vec3d gradient(const AccT& acc, const Vec3d& xyz);
};

/// Triquadratic reconstruction from the 27 voxels floor(xyz) - 1 to floor(xyz) + 1: along
/// each axis, the parabola through three voxels evaluated at the fraction of the sample point,
/// as a tensor product. Exact for fields that are quadratic in each coordinate; not continuous
/// across voxel boundaries (OpenVDB calls it not "consistent").
struct QuadraticSampler {
    static constexpr int RADIUS = 1;
    static constexpr const char* name() { return "quadratic"; }
    static constexpr int radius() { return RADIUS; }
    static constexpr bool mipmap() { return true; }
    static constexpr bool consistent() { return false; }
    static constexpr bool staggered() { return false; }
    static constexpr size_t order() { return 2; }

    /// Stores the reconstruction at `xyz` in `result`; returns whether any of the 27 voxels
    /// read is active.
    template <typename AccT, typename ValueT>
    static bool sample(const AccT& acc, const Vec3d& xyz, ValueT& result);
    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz);

    /// Interpolates the values `v` of the voxels floor - 1 + (a, b, c) at the fraction `uvw`.
    template <typename ValueT>
    static ValueT triquadratic(const ValueT (&v)[3][3][3], const Vec3d& uvw);
};

/// Staggered reconstruction of a vector grid whose x, y and z components live on the faces
/// of the voxel at -x, -y and -z (a MAC grid): component c is read by `SamplerT` at the
/// sample point moved half a voxel along axis c. Values must be Vec3s or Vec3d.
template <typename SamplerT>
struct StaggeredSampler {
    static constexpr int RADIUS = SamplerT::RADIUS;
    static constexpr const char* name() { return SamplerT::name(); }
    static constexpr int radius() { return RADIUS; }
    static constexpr bool mipmap() { return SamplerT::mipmap(); }
    static constexpr bool consistent() { return false; }
    static constexpr bool staggered() { return true; }
    static constexpr size_t order() { return SamplerT::order(); }

    /// Stores the reconstruction at `xyz` in `result`; returns whether any voxel read is
    /// active.
    template <typename AccT, typename ValueT>
    static bool sample(const AccT& acc, const Vec3d& xyz, ValueT& result);
    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz);
};

using StaggeredPointSampler = StaggeredSampler<PointSampler>;
using StaggeredBoxSampler = StaggeredSampler<BoxSampler>;
using StaggeredQuadraticSampler = StaggeredSampler<QuadraticSampler>;

namespace detail {
template <typename T>
concept HasTransform = requires(const T& t) {
    t.transform();
};
template <typename T>
struct SamplerSource {
    using Type = T;
};
template <HasTransform GridT>
struct SamplerSource<GridT> {
    using Type = typename GridT::TreeType;
};
}  // namespace detail

/// A sampler bound to a tree (or an accessor of one) and a transform: isSample() reads index
/// space, wsSample() world space.
///
/// @tparam TreeOrAccessorT  a Grid (the sampler then reads its tree and transform), a tree, or
///                          a ValueAccessor (faster for coherent reads; not thread-safe).
/// @tparam SamplerT         PointSampler, BoxSampler, QuadraticSampler or a staggered form.
///
/// The sampler keeps pointers: the tree (or accessor) and the transform must outlive it.
/// Threads: as thread-safe as the source it reads (a tree: yes; an accessor: no).
template <typename TreeOrAccessorT, typename SamplerT>
class GridSampler {
public:
    /// The object read: the grid's tree for a Grid, else TreeOrAccessorT itself.
    using SourceType = typename detail::SamplerSource<TreeOrAccessorT>::Type;
    using ValueType = typename SourceType::ValueType;

    /// Reads `grid`'s tree through `grid`'s transform.
    explicit GridSampler(const TreeOrAccessorT& grid) requires detail::HasTransform<TreeOrAccessorT>
        : mSource(&grid.tree()), mTransform(&grid.transform()) {}
    /// Reads `source` (a tree or accessor); world positions map through `xform`.
    GridSampler(const SourceType& source, const math::Transform& xform)
        : mSource(&source), mTransform(&xform) {}

    const math::Transform& transform() const { return *mTransform; }

    /// The value of voxel `ijk`.
    ValueType isSample(const Coord& ijk) const { return mSource->getValue(ijk); }
    /// The reconstruction at the index-space point `ijk`.
    ValueType isSample(const Vec3d& ijk) const { return SamplerT::sample(*mSource, ijk); }
    /// The reconstruction at the world-space point `xyz`.
    ValueType wsSample(const Vec3d& xyz) const {
        return SamplerT::sample(*mSource, mTransform->worldToIndex(xyz));
    }

private:
    const SourceType* mSource;
    const math::Transform* mTransform;
};

/// Reads a source grid at the voxel centres of a target grid: `sampler(ijk)` is the source's
/// reconstruction at the world position of the target's voxel `ijk`. When the two transforms
/// are equal, it reads the source's voxel `ijk` directly (isAligned()).
///
/// @tparam TreeOrAccessorT  the source: a Grid, a tree or a ValueAccessor.
/// The source, its transform and the target transform must outlive the sampler.
template <typename TreeOrAccessorT, typename SamplerT>
class DualGridSampler {
public:
    using SourceType = typename detail::SamplerSource<TreeOrAccessorT>::Type;
    using ValueType = typename SourceType::ValueType;

    /// Reads `sourceGrid` at the voxel centres of grids with transform `targetXform`.
    DualGridSampler(const TreeOrAccessorT& sourceGrid, const math::Transform& targetXform) requires
        detail::HasTransform<TreeOrAccessorT>
        : DualGridSampler(sourceGrid.tree(), sourceGrid.transform(), targetXform) {}
    /// Reads `source` (a tree or accessor) whose grid has `sourceXform`.
    DualGridSampler(const SourceType& source, const math::Transform& sourceXform,
                    const math::Transform& targetXform)
        : mSource(&source),
          mSourceXform(&sourceXform),
          mTargetXform(&targetXform),
          mAligned(sourceXform == targetXform) {}

    /// The source's value at the centre of the target's voxel `ijk`.
    ValueType operator()(const Coord& ijk) const {
        if (mAligned)
            return mSource->getValue(ijk);
        return SamplerT::sample(*mSource,
                                mSourceXform->worldToIndex(mTargetXform->indexToWorld(ijk)));
    }
    /// True when the two transforms are equal, so that voxels are read without interpolation.
    bool isAligned() const { return mAligned; }

private:
    const SourceType* mSource;
    const math::Transform* mSourceXform;
    const math::Transform* mTargetXform;
    bool mAligned;
};

/// A field of world position read from a grid, for the tools that take a function
/// `op(const Vec3d& xyz) -> value` (the field extension of FastSweeping.h: fogToExt, sdfToExt):
/// `sampler(xyz)` is `SamplerT`'s reconstruction of `grid` at the world position `xyz`, the
/// same number as `GridSampler<GridT, SamplerT>(grid).wsSample(xyz)`, read through an accessor.
///
/// Each copy reads through its own accessor, made on its first call, so that tools that copy
/// the functor once per thread read without locks; one object must not be called from two
/// threads at once. The grid must outlive the sampler and its copies.
///
/// @code
/// auto ext = vdb::tools::sdfToExt(surface, vdb::tools::WorldSampler(velocity),
///                                 velocity.background());
/// @endcode
template <typename GridT, typename SamplerT = BoxSampler>
class WorldSampler {
public:
    using ValueType = typename GridT::ValueType;

    explicit WorldSampler(const GridT& grid) : mGrid(&grid) {}
    /// A sampler of the same grid with an accessor of its own.
    WorldSampler(const WorldSampler& other) : mGrid(other.mGrid) {}
    WorldSampler& operator=(const WorldSampler&) = delete;

    /// The reconstruction at the world position `xyz`.
    ValueType operator()(const Vec3d& xyz) const {
        if (!mAcc)
            mAcc.emplace(mGrid->tree());
        return ValueType(SamplerT::sample(*mAcc, mGrid->transform().worldToIndex(xyz)));
    }

    const GridT& grid() const { return *mGrid; }

private:
    const GridT* mGrid;
    mutable std::optional<typename GridT::ConstAccessor> mAcc;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// The value type an accessor (or tree) reads.
template <typename AccT>
using SampledValue = std::decay_t<decltype(std::declval<const AccT&>().getValue(Coord()))>;

/// The index-space coordinate nearest to `xyz`, halves rounded away from zero (std::round),
/// saturated to the Int32 range.
inline Coord nearestCoord(const Vec3d& xyz) {
    return Coord(math::floorToInt32(std::round(xyz[0])), math::floorToInt32(std::round(xyz[1])),
                 math::floorToInt32(std::round(xyz[2])));
}

/// Converts a double to an integer type, truncating toward zero and saturating at the ends of
/// its range (NaN gives 0).
template <typename IntT>
IntT saturatingCast(double x) {
    // 2^(bits - 1) for signed types, 2^bits for unsigned ones: the first value that does not fit.
    constexpr double end = 2.0 * double(std::numeric_limits<IntT>::max() / 2 + 1);
    constexpr double lo = double(std::numeric_limits<IntT>::min());
    if (!(x == x))
        return IntT(0);
    if (x <= lo)
        return std::numeric_limits<IntT>::min();
    if (x >= end)
        return std::numeric_limits<IntT>::max();
    return static_cast<IntT>(x);
}

/// OpenVDB's interpolation step a + ValueT((b - a) * w): the difference times the weight in
/// double, converted to the value type (integers truncate toward zero) and added to `a`;
/// vectors component by component. Integer differences are exact (no overflow for values of
/// opposite sign near the extremes of the type), so for w in [0, 1] the result lies between
/// `a` and `b`.
template <typename ValueT>
ValueT lerp(const ValueT& a, const ValueT& b, double w) {
    if constexpr (std::is_integral_v<ValueT> && sizeof(ValueT) <= 4) {
        return ValueT(Int64(a) + Int64((double(Int64(b) - Int64(a))) * w));
    } else if constexpr (std::is_integral_v<ValueT>) {
        // 64-bit integers: long double holds every difference to within one unit.
        const long double d = (static_cast<long double>(b) - static_cast<long double>(a)) * w;
        const long double r = static_cast<long double>(a) + std::trunc(d);
        const long double lo = static_cast<long double>(a < b ? a : b);
        const long double hi = static_cast<long double>(a < b ? b : a);
        return r <= lo ? (a < b ? a : b) : r >= hi ? (a < b ? b : a) : ValueT(r);
    } else if constexpr (std::is_arithmetic_v<ValueT>) {
        return ValueT(a + ValueT(double(b - a) * w));
    } else {
        ValueT out;
        for (int i = 0; i < 3; ++i)
            out[i] = lerp(a[i], b[i], w);
        return out;
    }
}

/// OpenVDB's quadratic step: the parabola through (-1, m), (0, z), (1, p), with coefficients
/// a = (m + p) / 2 - z and b = (p - m) / 2 rounded to the value type, evaluated at `t` in
/// double as t (t a + b) + z; vectors component by component.
template <typename ValueT>
ValueT parabola(const ValueT& m, const ValueT& z, const ValueT& p, double t) {
    if constexpr (std::is_integral_v<ValueT>) {
        // Sums of two values are exact in double for 32-bit types.
        const ValueT a = saturatingCast<ValueT>(0.5 * (double(m) + double(p)) - double(z));
        const ValueT b = saturatingCast<ValueT>(0.5 * (double(p) - double(m)));
        return saturatingCast<ValueT>(t * (t * double(a) + double(b)) + double(z));
    } else if constexpr (std::is_arithmetic_v<ValueT>) {
        const ValueT a = ValueT(0.5 * double(m + p) - double(z));
        const ValueT b = ValueT(0.5 * double(p - m));
        return ValueT(t * (t * double(a) + double(b)) + double(z));
    } else {
        ValueT out;
        for (int i = 0; i < 3; ++i)
            out[i] = parabola(m[i], z[i], p[i], t);
        return out;
    }
}

}  // namespace detail

// ---- PointSampler

template <typename AccT, typename ValueT>
bool PointSampler::sample(const AccT& acc, const Vec3d& xyz, ValueT& result) {
    return acc.probeValue(detail::nearestCoord(xyz), result);
}

template <typename AccT>
auto PointSampler::sample(const AccT& acc, const Vec3d& xyz) {
    return detail::SampledValue<AccT>(acc.getValue(detail::nearestCoord(xyz)));
}

// ---- BoxSampler

template <typename AccT, typename ValueT>
void BoxSampler::getValues(const AccT& acc, const Coord& ijk, ValueT (&v)[2][2][2]) {
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                v[a][b][c] = acc.getValue(ijk.offsetBy(a, b, c));
}

template <typename AccT, typename ValueT>
bool BoxSampler::probeValues(const AccT& acc, const Coord& ijk, ValueT (&v)[2][2][2]) {
    bool active = false;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                active |= acc.probeValue(ijk.offsetBy(a, b, c), v[a][b][c]);
    return active;
}

template <typename ValueT>
ValueT BoxSampler::trilinear(const ValueT (&v)[2][2][2], const Vec3d& uvw) {
    using detail::lerp;
    const ValueT v00 = lerp(v[0][0][0], v[0][0][1], uvw[2]);
    const ValueT v01 = lerp(v[0][1][0], v[0][1][1], uvw[2]);
    const ValueT v10 = lerp(v[1][0][0], v[1][0][1], uvw[2]);
    const ValueT v11 = lerp(v[1][1][0], v[1][1][1], uvw[2]);
    return lerp(lerp(v00, v01, uvw[1]), lerp(v10, v11, uvw[1]), uvw[0]);
}

template <typename ValueT>
Vec3d BoxSampler::trilinearGradient(const ValueT (&v)[2][2][2], const Vec3d& uvw) {
    static_assert(std::is_arithmetic_v<ValueT>, "gradients are of scalar fields");
    const double u = uvw[0], w1 = uvw[1], w2 = uvw[2];
    // Differences along each axis, bilinearly weighted over the other two.
    auto bilerp = [](double a, double b, double c, double d, double s, double t) {
        return (a * (1 - t) + b * t) * (1 - s) + (c * (1 - t) + d * t) * s;
    };
    const double dx =
        bilerp(double(v[1][0][0]) - v[0][0][0], double(v[1][0][1]) - v[0][0][1],
               double(v[1][1][0]) - v[0][1][0], double(v[1][1][1]) - v[0][1][1], w1, w2);
    const double dy =
        bilerp(double(v[0][1][0]) - v[0][0][0], double(v[0][1][1]) - v[0][0][1],
               double(v[1][1][0]) - v[1][0][0], double(v[1][1][1]) - v[1][0][1], u, w2);
    const double dz =
        bilerp(double(v[0][0][1]) - v[0][0][0], double(v[0][1][1]) - v[0][1][0],
               double(v[1][0][1]) - v[1][0][0], double(v[1][1][1]) - v[1][1][0], u, w1);
    return Vec3d(dx, dy, dz);
}

template <typename AccT, typename ValueT>
bool BoxSampler::sample(const AccT& acc, const Vec3d& xyz, ValueT& result) {
    const Coord ijk = floorToCoord(xyz);
    ValueT v[2][2][2];
    const bool active = probeValues(acc, ijk, v);
    result = trilinear(v, xyz - Vec3d(ijk));
    return active;
}

template <typename AccT>
auto BoxSampler::sample(const AccT& acc, const Vec3d& xyz) {
    using ValueT = detail::SampledValue<AccT>;
    const Coord ijk = floorToCoord(xyz);
    ValueT v[2][2][2];
    getValues(acc, ijk, v);
    return trilinear(v, xyz - Vec3d(ijk));
}

template <typename AccT>
Vec3d BoxSampler::gradient(const AccT& acc, const Vec3d& xyz) {
    using ValueT = detail::SampledValue<AccT>;
    const Coord ijk = floorToCoord(xyz);
    ValueT v[2][2][2];
    getValues(acc, ijk, v);
    return trilinearGradient(v, xyz - Vec3d(ijk));
}

// ---- QuadraticSampler

template <typename ValueT>
ValueT QuadraticSampler::triquadratic(const ValueT (&v)[3][3][3], const Vec3d& uvw) {
    using detail::parabola;
    ValueT vx[3];
    for (int a = 0; a < 3; ++a) {
        ValueT vy[3];
        for (int b = 0; b < 3; ++b)
            vy[b] = parabola(v[a][b][0], v[a][b][1], v[a][b][2], uvw[2]);
        vx[a] = parabola(vy[0], vy[1], vy[2], uvw[1]);
    }
    return parabola(vx[0], vx[1], vx[2], uvw[0]);
}

template <typename AccT, typename ValueT>
bool QuadraticSampler::sample(const AccT& acc, const Vec3d& xyz, ValueT& result) {
    const Coord ijk = floorToCoord(xyz);
    const Coord lo = ijk.offsetBy(-1, -1, -1);
    ValueT v[3][3][3];
    bool active = false;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c)
                active |= acc.probeValue(lo.offsetBy(a, b, c), v[a][b][c]);
    result = triquadratic(v, xyz - Vec3d(ijk));
    return active;
}

template <typename AccT>
auto QuadraticSampler::sample(const AccT& acc, const Vec3d& xyz) {
    using ValueT = detail::SampledValue<AccT>;
    const Coord ijk = floorToCoord(xyz);
    const Coord lo = ijk.offsetBy(-1, -1, -1);
    ValueT v[3][3][3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c)
                v[a][b][c] = acc.getValue(lo.offsetBy(a, b, c));
    return triquadratic(v, xyz - Vec3d(ijk));
}

// ---- StaggeredSampler

template <typename SamplerT>
template <typename AccT, typename ValueT>
bool StaggeredSampler<SamplerT>::sample(const AccT& acc, const Vec3d& xyz, ValueT& result) {
    bool active = false;
    for (int c = 0; c < 3; ++c) {
        Vec3d p = xyz;
        p[c] += 0.5;
        ValueT v;
        active |= SamplerT::sample(acc, p, v);
        result[c] = v[c];
    }
    return active;
}

template <typename SamplerT>
template <typename AccT>
auto StaggeredSampler<SamplerT>::sample(const AccT& acc, const Vec3d& xyz) {
    using ValueT = detail::SampledValue<AccT>;
    ValueT result;
    for (int c = 0; c < 3; ++c) {
        Vec3d p = xyz;
        p[c] += 0.5;
        result[c] = ValueT(SamplerT::sample(acc, p))[c];
    }
    return result;
}

}  // namespace vdb::tools
