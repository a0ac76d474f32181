// SPDX-License-Identifier: Apache-2.0
/// @file
/// Reconstruction of a continuous field from voxel values, read through an accessor:
/// PointSampler (nearest voxel), BoxSampler (trilinear, 8 voxels) and QuadraticSampler
/// (triquadratic, 27 voxels).
///
/// Index space is voxel-centred here: the value of voxel (i, j, k) sits at the point (i, j, k),
/// so sampling at an integer point returns that voxel's value exactly. Any object with
/// `getValue(const Coord&)` serves as the accessor (a tree, a ValueAccessor). Values may be
/// scalars or vectors (Vec3s, Vec3d); weights are applied in the value's component type.
///
/// @code
/// vdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
/// float v = vdb::tools::BoxSampler::sample(acc, vdb::Vec3d(1.25, -3.5, 0.75));
/// vdb::Vec3d g = vdb::tools::BoxSampler::gradient(acc, vdb::Vec3d(1.25, -3.5, 0.75));
/// @endcode
///
/// Cost: 1, 8 and 27 accessor reads. Threads: the samplers are stateless; an accessor is not
/// thread-safe, so use one per thread.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>

#include <cmath>
#include <type_traits>

namespace vdb::tools {

namespace detail {

/// The scalar type weights take for a value: the value itself for floating-point scalars,
/// double for integers, the component type of vectors.
template <typename ValueT>
struct SamplerScalar {
    using Type = std::conditional_t<std::is_floating_point_v<ValueT>, ValueT, double>;
};
template <typename T>
struct SamplerScalar<math::Vec3<T>> {
    using Type = T;
};

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

}  // namespace detail

/// Nearest-voxel reconstruction: the value of the voxel whose centre is closest to `xyz`
/// (halves round up).
struct PointSampler {
    static constexpr int RADIUS = 0;  ///< voxels read on each side of the sample point
    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz) {
        return acc.getValue(roundToCoord(xyz));
    }
};

/// Trilinear reconstruction from the 8 voxels around the sample point; exact for fields that
/// are linear in each coordinate.
struct BoxSampler {
    static constexpr int RADIUS = 1;

    /// Reads the values of the voxels ijk + (a, b, c), a, b, c in {0, 1}, into v[a][b][c].
    template <typename AccT, typename ValueT>
    static void getValues(const AccT& acc, const Coord& ijk, ValueT (&v)[2][2][2]) {
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = 0; c < 2; ++c)
                    v[a][b][c] = acc.getValue(ijk.offsetBy(a, b, c));
    }
    /// Interpolates the corner values `v` at the fractional position `uvw` in [0, 1]^3.
    template <typename ValueT>
    static ValueT trilinear(const ValueT (&v)[2][2][2], const Vec3d& uvw) {
        using detail::lerp;
        const ValueT v00 = lerp(v[0][0][0], v[0][0][1], uvw[2]);
        const ValueT v01 = lerp(v[0][1][0], v[0][1][1], uvw[2]);
        const ValueT v10 = lerp(v[1][0][0], v[1][0][1], uvw[2]);
        const ValueT v11 = lerp(v[1][1][0], v[1][1][1], uvw[2]);
        return lerp(lerp(v00, v01, uvw[1]), lerp(v10, v11, uvw[1]), uvw[0]);
    }
    /// The gradient of the trilinear interpolant of scalar corner values `v` at `uvw`, per
    /// voxel.
    template <typename ValueT>
    static Vec3d trilinearGradient(const ValueT (&v)[2][2][2], const Vec3d& uvw) {
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

    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz) {
        using ValueT = std::decay_t<decltype(acc.getValue(Coord()))>;
        const Coord ijk = floorToCoord(xyz);
        ValueT v[2][2][2];
        getValues(acc, ijk, v);
        return trilinear(v, xyz - Vec3d(ijk));
    }
    /// The gradient (per voxel) of the trilinear interpolant of a scalar field at `xyz`.
    template <typename AccT>
    static Vec3d gradient(const AccT& acc, const Vec3d& xyz) {
        using ValueT = std::decay_t<decltype(acc.getValue(Coord()))>;
        const Coord ijk = floorToCoord(xyz);
        ValueT v[2][2][2];
        getValues(acc, ijk, v);
        return trilinearGradient(v, xyz - Vec3d(ijk));
    }
};

/// Triquadratic reconstruction: along each axis, the parabola through the nearest voxel and its
/// two neighbours, as a tensor product over the 27 voxels around the sample point. Exact for
/// fields that are quadratic in each coordinate; continuous only within a voxel's cell.
struct QuadraticSampler {
    static constexpr int RADIUS = 1;

    template <typename AccT>
    static auto sample(const AccT& acc, const Vec3d& xyz) {
        using ValueT = std::decay_t<decltype(acc.getValue(Coord()))>;
        const Coord c = roundToCoord(xyz);
        const Vec3d u = xyz - Vec3d(c);  // in [-0.5, 0.5]
        ValueT plane[3];
        for (int a = 0; a < 3; ++a) {
            ValueT line[3];
            for (int b = 0; b < 3; ++b) {
                const Coord ijk = c.offsetBy(a - 1, b - 1, 0);
                line[b] = parabola(acc.getValue(ijk.offsetBy(0, 0, -1)), acc.getValue(ijk),
                                   acc.getValue(ijk.offsetBy(0, 0, 1)), u[2]);
            }
            plane[a] = parabola(line[0], line[1], line[2], u[1]);
        }
        return parabola(plane[0], plane[1], plane[2], u[0]);
    }

    /// The parabola through (-1, m), (0, z), (1, p), evaluated at `t`.
    template <typename ValueT>
    static ValueT parabola(const ValueT& m, const ValueT& z, const ValueT& p, double t) {
        using ScalarT = typename detail::SamplerScalar<ValueT>::Type;
        const ScalarT s = ScalarT(t), half = ScalarT(0.5);
        return ValueT(z + (p - m) * (half * s) + (p + m - z - z) * (half * s * s));
    }
};

}  // namespace vdb::tools
