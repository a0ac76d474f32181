// SPDX-License-Identifier: Apache-2.0
/// @file
/// Finite differences for level sets (paper 3.4 and 4.2): one-sided first, second and third
/// order differences, Hamilton-Jacobi WENO5 (Jiang and Peng 2000), Godunov's upwind norm of the
/// gradient for the Eikonal equation, and the scheme enums with OpenVDB's names; then the
/// second-order central differences of the operators (gradient, divergence, curl, Laplacian)
/// and Goldman's mean and Gaussian curvatures of implicit surfaces.
///
/// The upwind schemes work on one axis at a time, on a line of 7 samples centred on the voxel
/// of interest: `line[3]` is the centre, `line[3 + d]` the sample d voxels along the axis. The
/// central differences read a neighbourhood through a callable `at(i, j, k)`. All differences
/// are in index space (divide by the voxel size for world units). Costs are a few dozen flops
/// per axis; nothing allocates.
///
/// @code
/// std::array<float, 7> line = ...;                                   // phi(i-3) .. phi(i+3)
/// float dm, dp;
/// vdb::math::biasedDifferences<vdb::math::HJWENO5_BIAS>(line.data(), dm, dp);
/// float g2 = vdb::math::godunovNormSqrd(phi0 > 0, dmx, dpx, dmy, dpy, dmz, dpz);
/// @endcode

#pragma once

#include <vdb/math/Math.h>

#include <algorithm>
#include <cmath>
#include <string_view>

namespace vdb::math {

/// Upwind-biased discretisations of a first derivative (OpenVDB's names). This library
/// implements FIRST_BIAS, SECOND_BIAS, THIRD_BIAS and HJWENO5_BIAS.
enum BiasedGradientScheme {
    UNKNOWN_BIAS,
    FIRST_BIAS,   ///< first-order one-sided differences, 3-point stencil per axis
    SECOND_BIAS,  ///< second-order one-sided differences (5 points per axis)
    THIRD_BIAS,   ///< third-order upwind-biased differences (5 points per axis)
    WENO5_BIAS,   ///< listed for OpenVDB compatibility; not implemented here
    HJWENO5_BIAS  ///< fifth-order Hamilton-Jacobi WENO, 7 points per axis (19 in 3D)
};

/// Explicit total-variation-diminishing Runge-Kutta schemes (Shu and Osher 1988).
enum TemporalIntegrationScheme {
    UNKNOWN_TIS,
    TVD_RK1,  ///< forward Euler
    TVD_RK2,  ///< Heun: two Euler stages and a convex combination
    TVD_RK3   ///< third-order, three Euler stages
};

/// True for the schemes this library implements.
constexpr bool isSupported(BiasedGradientScheme s) {
    return s == FIRST_BIAS || s == SECOND_BIAS || s == THIRD_BIAS || s == HJWENO5_BIAS;
}
constexpr bool isSupported(TemporalIntegrationScheme s) {
    return s == TVD_RK1 || s == TVD_RK2 || s == TVD_RK3;
}

/// Number of Runge-Kutta stages (and of auxiliary buffers the integrator needs: RK1 and RK2
/// one, RK3 two).
constexpr int stageCount(TemporalIntegrationScheme s) {
    return s == TVD_RK3 ? 3 : s == TVD_RK2 ? 2 : 1;
}
constexpr int auxBufferCount(TemporalIntegrationScheme s) {
    return s == TVD_RK3 ? 2 : 1;
}

/// Half the width of the stencil a scheme reads along each axis.
constexpr int stencilRadius(BiasedGradientScheme s) {
    return s == FIRST_BIAS ? 1 : s == HJWENO5_BIAS ? 3 : 2;
}

inline std::string_view biasedGradientSchemeToString(BiasedGradientScheme s) {
    switch (s) {
        case FIRST_BIAS:
            return "first";
        case SECOND_BIAS:
            return "second";
        case THIRD_BIAS:
            return "third";
        case WENO5_BIAS:
            return "weno5";
        case HJWENO5_BIAS:
            return "hjweno5";
        default:
            return "unknown";
    }
}

inline std::string_view temporalIntegrationSchemeToString(TemporalIntegrationScheme s) {
    switch (s) {
        case TVD_RK1:
            return "tvd rk1";
        case TVD_RK2:
            return "tvd rk2";
        case TVD_RK3:
            return "tvd rk3";
        default:
            return "unknown";
    }
}

/// The fifth-order WENO combination of the five consecutive differences v1..v5 (v3 the one
/// ending at the centre for the backward derivative): three third-order candidates weighted by
/// their smoothness, with ideal weights 0.1, 0.6 and 0.3.
///
/// The smoothness regulariser is OpenVDB's: 1e-6 * scale2, with `scale2` a squared magnitude of
/// the values in their own units (OpenVDB's default and ours, 0.01, for level sets in world
/// units), so that schemes built on it give OpenVDB's results. It is kept above a floor (1e-9
/// for float, 1e-30 for double) so that the weights stay finite where the differences vanish
/// even for scale2 = 0. The weights are normalised with one division, in double precision
/// (their products, of fourth powers of smoothness indicators, would underflow a float).
template <typename T>
inline T weno5(T v1, T v2, T v3, T v4, T v5, T scale2 = T(0.01)) {
    const T c13 = T(13) / T(12);
    const T floor = sizeof(T) <= 4 ? T(1.0e-9) : T(1.0e-30);
    const T eps = std::max(T(1.0e-6) * scale2, floor);
    const T a = v1 - T(2) * v2 + v3, b = v1 - T(4) * v2 + T(3) * v3;
    const T c = v2 - T(2) * v3 + v4, d = v2 - v4;
    const T e = v3 - T(2) * v4 + v5, f = T(3) * v3 - T(4) * v4 + v5;
    const double s1 = double(c13 * a * a + T(0.25) * b * b + eps);
    const double s2 = double(c13 * c * c + T(0.25) * d * d + eps);
    const double s3 = double(c13 * e * e + T(0.25) * f * f + eps);
    // alpha_k = ideal_k / s_k^2, normalised: multiplied through by (s1 s2 s3)^2.
    const double q1 = s1 * s1, q2 = s2 * s2, q3 = s3 * s3;
    const double w1 = 0.1 * q2 * q3, w2 = 0.6 * q1 * q3, w3 = 0.3 * q1 * q2;
    const T p1 = v1 * (T(2) / T(6)) - v2 * (T(7) / T(6)) + v3 * (T(11) / T(6));
    const T p2 = -v2 * (T(1) / T(6)) + v3 * (T(5) / T(6)) + v4 * (T(2) / T(6));
    const T p3 = v3 * (T(2) / T(6)) + v4 * (T(5) / T(6)) - v5 * (T(1) / T(6));
    return T((w1 * double(p1) + w2 * double(p2) + w3 * double(p3)) / (w1 + w2 + w3));
}

/// The backward (D-) and forward (D+) index-space derivatives at `line[3]` under `Scheme`.
/// `line` points at 7 samples; FIRST_BIAS reads line[2..4], SECOND and THIRD line[1..5].
template <BiasedGradientScheme Scheme, typename T>
inline void biasedDifferences(const T* line, T& dm, T& dp) {
    static_assert(Scheme == FIRST_BIAS || Scheme == SECOND_BIAS || Scheme == THIRD_BIAS ||
                      Scheme == HJWENO5_BIAS,
                  "biasedDifferences implements FIRST_BIAS, SECOND_BIAS, THIRD_BIAS, HJWENO5_BIAS");
    if constexpr (Scheme == FIRST_BIAS) {
        dm = line[3] - line[2];
        dp = line[4] - line[3];
    } else if constexpr (Scheme == SECOND_BIAS) {
        dm = T(0.5) * (T(3) * line[3] - T(4) * line[2] + line[1]);
        dp = T(0.5) * (-T(3) * line[3] + T(4) * line[4] - line[5]);
    } else if constexpr (Scheme == THIRD_BIAS) {
        dm = (T(2) * line[4] + T(3) * line[3] - T(6) * line[2] + line[1]) / T(6);
        dp = (-T(2) * line[2] - T(3) * line[3] + T(6) * line[4] - line[5]) / T(6);
    } else {
        const T d0 = line[1] - line[0], d1 = line[2] - line[1], d2 = line[3] - line[2];
        const T d3 = line[4] - line[3], d4 = line[5] - line[4], d5 = line[6] - line[5];
        dm = weno5(d0, d1, d2, d3, d4);
        dp = weno5(d5, d4, d3, d2, d1);
    }
}

/// The upwind derivative for a velocity component `v`: D- where v > 0, D+ otherwise.
template <typename T>
inline T upwind(T v, T dm, T dp) {
    return v > T(0) ? dm : dp;
}

/// Godunov's Hamiltonian for |grad phi|^2 from the one-sided derivatives of the three axes
/// (Rouy and Tourin; Peng et al. 1999): where phi > 0 (`outside`) information flows outward,
/// so each axis takes max(max(D-, 0)^2, min(D+, 0)^2); inside the signs swap. Both sums are
/// formed and one is selected, without a branch, so that a loop over voxels runs in vector
/// lanes.
template <typename T>
inline T godunovNormSqrd(bool outside, T dmx, T dpx, T dmy, T dpy, T dmz, T dpz) {
    const T z(0);
    const auto axis = [z](T dm, T dp, T& out, T& in) {
        const T dmOut = std::max(dm, z), dpOut = std::min(dp, z);
        const T dmIn = std::min(dm, z), dpIn = std::max(dp, z);
        out = std::max(dmOut * dmOut, dpOut * dpOut);
        in = std::max(dmIn * dmIn, dpIn * dpIn);
    };
    T ox, ix, oy, iy, oz, iz;
    axis(dmx, dpx, ox, ix);
    axis(dmy, dpy, oy, iy);
    axis(dmz, dpz, oz, iz);
    return outside ? ox + oy + oz : ix + iy + iz;
}

/// Difference formulas on a point's neighbourhood, read through `at(i, j, k)`: the value at
/// offset (i, j, k) from the point (a stencil, a dense block of a leaf's neighbourhood). Values
/// may be scalars or vectors; everything is in index space (divide by the voxel size, or apply
/// the transform's inverse Jacobian, for world units).

/// The point one step along `axis` (0, 1, 2 for x, y, z) in direction `d` (-1 or +1).
template <int Axis, typename AtT>
inline auto atStep(const AtT& at, int d) {
    return at(Axis == 0 ? d : 0, Axis == 1 ? d : 0, Axis == 2 ? d : 0);
}

/// Second-order central first difference along `Axis`: (f(+1) - f(-1)) / 2.
template <int Axis, typename AtT>
inline auto centralDiff(const AtT& at) {
    return (atStep<Axis>(at, 1) - atStep<Axis>(at, -1)) * 0.5f;
}

/// First-order forward difference along `Axis`: f(+1) - f(0) (the staggered, MAC-grid
/// difference: a face value at i stands between cells i - 1 and i).
template <int Axis, typename AtT>
inline auto forwardDiff(const AtT& at) {
    return atStep<Axis>(at, 1) - at(0, 0, 0);
}

/// Second-order central second difference along `Axis`: f(+1) + f(-1) - 2 f(0).
template <int Axis, typename AtT>
inline auto centralDiff2(const AtT& at) {
    return atStep<Axis>(at, 1) + atStep<Axis>(at, -1) - at(0, 0, 0) * 2.0f;
}

/// Second-order central mixed difference in axes `A` and `B` (A != B):
/// (f(+1,+1) + f(-1,-1) - f(+1,-1) - f(-1,+1)) / 4.
template <int A, int B, typename AtT>
inline auto centralDiffMixed(const AtT& at) {
    const auto f = [&at](int a, int b) {
        int o[3] = {0, 0, 0};
        o[A] = a;
        o[B] = b;
        return at(o[0], o[1], o[2]);
    };
    return (f(1, 1) + f(-1, -1) - f(1, -1) - f(-1, 1)) * 0.25f;
}

/// The second-order central Laplacian: the sum of the six face neighbours minus 6 f(0).
template <typename AtT>
inline auto centralLaplacian(const AtT& at) {
    return centralDiff2<0>(at) + centralDiff2<1>(at) + centralDiff2<2>(at);
}

/// The first and second derivatives of a scalar field at one point: the gradient (dx, dy, dz)
/// and the Hessian's six distinct entries. From centralDerivatives() they are in index space;
/// scaled by a transform (tools/GridOperators.h) they are in world space.
template <typename T>
struct Derivatives {
    T dx, dy, dz;
    T dxx, dyy, dzz;
    T dxy, dxz, dyz;
};

/// The second-order central differences at a point of the 19-point curvature stencil (the
/// centre, its 6 face and its 12 edge neighbours), in precision `T`.
template <typename T, typename AtT>
inline Derivatives<T> centralDerivatives(const AtT& at) {
    const auto f = [&at](int i, int j, int k) { return T(at(i, j, k)); };
    return {centralDiff<0>(f),         centralDiff<1>(f),         centralDiff<2>(f),
            centralDiff2<0>(f),        centralDiff2<1>(f),        centralDiff2<2>(f),
            centralDiffMixed<0, 1>(f), centralDiffMixed<0, 2>(f), centralDiffMixed<1, 2>(f)};
}

/// The two parts of the mean curvature H = div(grad f / |grad f|) / 2 = alpha / (2 |grad f|^3)
/// and of the Gaussian curvature K = alphaG / |grad f|^4 (Goldman's formulas for the curvatures
/// of an implicit surface), from the derivatives `d`: `alphaM`, `alphaG` and `normGrad` =
/// |grad f|. False, with all three 0, where |grad f|^2 is at most `tolerance` (OpenVDB's: 1e-15
/// in double, 1e-8 in float; the surface has no normal there). The units follow `d`'s: index or
/// world space.
template <typename T>
inline bool curvatureTerms(const Derivatives<T>& d, T& alphaM, T& alphaG, T& normGrad,
                           T tolerance = Tolerance<T>::value()) {
    const T x2 = d.dx * d.dx, y2 = d.dy * d.dy, z2 = d.dz * d.dz;
    const T g2 = x2 + y2 + z2;
    if (!(g2 > tolerance)) {
        alphaM = alphaG = normGrad = T(0);
        return false;
    }
    alphaM = x2 * (d.dyy + d.dzz) + y2 * (d.dxx + d.dzz) + z2 * (d.dxx + d.dyy) -
             T(2) * (d.dx * (d.dy * d.dxy + d.dz * d.dxz) + d.dy * d.dz * d.dyz);
    alphaG = x2 * (d.dyy * d.dzz - d.dyz * d.dyz) + y2 * (d.dxx * d.dzz - d.dxz * d.dxz) +
             z2 * (d.dxx * d.dyy - d.dxy * d.dxy) +
             T(2) * (d.dy * d.dz * (d.dxy * d.dxz - d.dyz * d.dxx) +
                     d.dx * d.dz * (d.dxy * d.dyz - d.dxz * d.dyy) +
                     d.dx * d.dy * (d.dxz * d.dyz - d.dxy * d.dzz));
    normGrad = std::sqrt(g2);
    return true;
}

/// The mean curvature alpha / (2 |grad f|^3) of the level sets of the field with derivatives
/// `d` (1/R on a sphere of radius R; 0 where the gradient vanishes), in d's units.
template <typename T>
inline T meanCurvature(const Derivatives<T>& d) {
    T alphaM, alphaG, normGrad;
    if (!curvatureTerms(d, alphaM, alphaG, normGrad))
        return T(0);
    return alphaM / (T(2) * normGrad * normGrad * normGrad);
}

}  // namespace vdb::math
