// SPDX-License-Identifier: Apache-2.0
/// @file
/// Stencils (paper 3.4): the values of a fixed neighbourhood of one voxel, gathered through a
/// cached accessor, with the finite-difference operators that read them.
///
/// A stencil is moved either to a coordinate (random stencil access: ray marching, sampling) or
/// to a value iterator over a leaf (sequential stencil access): then the centre comes from the
/// iterator and only the neighbours go through the accessor, which for a compact stencil hits
/// the cached leaf or one of its neighbours almost always.
///
/// - SevenPointStencil: the centre and its 6 face neighbours; central gradient, normal,
///   laplacian, zero crossing.
/// - WenoStencil: the centre and 3 neighbours each way along each axis (19 points); upwind
///   HJ-WENO5 gradient and Godunov's |grad phi|^2 for the Eikonal equation.
/// - CurvatureStencil: the centre, 6 face and 12 edge neighbours (19 points); mean and Gaussian
///   curvature.
/// - BoxStencil: the 8 corners of the cell around a fractional index-space point; trilinear
///   interpolation.
///
/// Derivatives are in world units for grids with a uniform voxel size (voxelSize()[0]); the
/// formulas are those of FiniteDifference.h, which the leaf-block kernels of the tools share.
/// Threads: a stencil holds an accessor, so use one stencil per thread.
///
/// @code
/// vdb::math::WenoStencil<vdb::FloatGrid> stencil(grid);
/// for (auto it = grid.cbeginValueOn(); it; ++it) {
///     stencil.moveTo(it);
///     float g2 = stencil.normSqGrad();
/// }
/// @endcode

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/math/Vec3.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

namespace vdb::math {

/// The part every stencil shares: the accessor, the offsets of its points and their values.
/// `Offsets` is an array of Coord, the centre first.
template <typename GridT, size_t N>
class BaseStencil {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    using AccessorType = typename GridT::ConstAccessor;
    static constexpr size_t SIZE = N;

    /// Moves the stencil to `ijk` and reads all its points through the accessor.
    void moveTo(const Coord& ijk) {
        mCenter = ijk;
        for (size_t n = 0; n < N; ++n)
            mValues[n] = mAcc.getValue(ijk + mOffsets[n]);
    }
    /// Moves the stencil to the voxel of a value iterator: the centre value comes from the
    /// iterator, the neighbours from the accessor.
    template <typename IterT>
    requires requires(const IterT& it) {
        it.getCoord();
        it.getValue();
    }
    void moveTo(const IterT& it) {
        mCenter = it.getCoord();
        mValues[0] = it.getValue();
        for (size_t n = 1; n < N; ++n)
            mValues[n] = mAcc.getValue(mCenter + mOffsets[n]);
    }

    const Coord& getCenterCoord() const { return mCenter; }
    ValueType getValue() const { return mValues[0]; }
    /// The value of point `n` in the stencil's own order (0 is the centre).
    ValueType getValue(size_t n) const { return mValues[n]; }
    /// The value at offset (i, j, k) from the centre. @pre the offset is a point of the stencil
    ValueType getValue(int i, int j, int k) const {
        for (size_t n = 0; n < N; ++n) {
            if (mOffsets[n] == Coord(i, j, k))
                return mValues[n];
        }
        return mAcc.getValue(mCenter.offsetBy(i, j, k));
    }
    const AccessorType& accessor() const { return mAcc; }
    /// World units per voxel.
    ValueType voxelSize() const { return mDx; }

protected:
    BaseStencil(const GridT& grid, const std::array<Coord, N>& offsets)
        : mAcc(grid.tree()), mOffsets(offsets), mDx(ValueType(grid.voxelSize()[0])) {}

    /// The 7 samples of the line through the centre along `axis` (centre at index 3), read from
    /// stencil points `idx` (-3 .. +3 in order, idx[3] == 0).
    std::array<ValueType, 7> line(const std::array<size_t, 7>& idx) const {
        std::array<ValueType, 7> out;
        for (size_t d = 0; d < 7; ++d)
            out[d] = mValues[idx[d]];
        return out;
    }

    AccessorType mAcc;
    std::array<Coord, N> mOffsets;
    std::array<ValueType, N> mValues{};
    Coord mCenter;
    ValueType mDx;
};

/// The centre and its 6 face neighbours (-x, +x, -y, +y, -z, +z).
template <typename GridT>
class SevenPointStencil : public BaseStencil<GridT, 7> {
    using Base = BaseStencil<GridT, 7>;

public:
    using ValueType = typename Base::ValueType;
    using VecType = Vec3<ValueType>;

    explicit SevenPointStencil(const GridT& grid)
        : Base(grid, {Coord(0), Coord(-1, 0, 0), Coord(1, 0, 0), Coord(0, -1, 0), Coord(0, 1, 0),
                      Coord(0, 0, -1), Coord(0, 0, 1)}) {}

    /// Second-order central gradient (world units).
    VecType gradient() const {
        const auto at = [this](int i, int j, int k) { return this->mValues[pos(i, j, k)]; };
        return VecType(math::centralDiff<0>(at), math::centralDiff<1>(at),
                       math::centralDiff<2>(at)) /
               this->mDx;
    }
    /// The unit normal: the gradient normalised (zero where the gradient vanishes).
    VecType normal() const {
        VecType g = gradient();
        if (!g.normalize())
            return VecType(ValueType(0));
        return g;
    }
    /// Second-order central laplacian (world units).
    ValueType laplacian() const {
        const auto at = [this](int i, int j, int k) { return this->mValues[pos(i, j, k)]; };
        return math::centralLaplacian(at) / (this->mDx * this->mDx);
    }
    /// The stencil's index of the point at offset (i, j, k). @pre a face neighbour or the centre
    static constexpr size_t pos(int i, int j, int k) {
        return i != 0 ? (i < 0 ? 1 : 2) : j != 0 ? (j < 0 ? 3 : 4) : k != 0 ? (k < 0 ? 5 : 6) : 0;
    }
    /// True when the centre and one of its face neighbours lie on opposite sides of zero.
    bool zeroCrossing() const {
        const auto& v = this->mValues;
        const bool in = v[0] < ValueType(0);
        for (size_t n = 1; n < 7; ++n) {
            if ((v[n] < ValueType(0)) != in)
                return true;
        }
        return false;
    }
};

/// The 19-point stencil of HJ-WENO5: the centre and 3 neighbours each way along each axis.
template <typename GridT>
class WenoStencil : public BaseStencil<GridT, 19> {
    using Base = BaseStencil<GridT, 19>;

public:
    using ValueType = typename Base::ValueType;
    using VecType = Vec3<ValueType>;

    explicit WenoStencil(const GridT& grid) : Base(grid, offsets()) {}

    /// Backward and forward index-space derivatives along `axis` under `Scheme`.
    template <BiasedGradientScheme Scheme = HJWENO5_BIAS>
    void differences(int axis, ValueType& dm, ValueType& dp) const {
        const auto l = this->line(lineIndices(axis));
        biasedDifferences<Scheme>(l.data(), dm, dp);
    }
    /// The gradient upwind-biased for the velocity `v`: along each axis D- where the component
    /// is positive, D+ otherwise (world units).
    template <BiasedGradientScheme Scheme = HJWENO5_BIAS>
    VecType gradient(const VecType& v) const {
        VecType g;
        for (int a = 0; a < 3; ++a) {
            ValueType dm, dp;
            differences<Scheme>(a, dm, dp);
            g[size_t(a)] = upwind(v[size_t(a)], dm, dp) / this->mDx;
        }
        return g;
    }
    /// Godunov's upwind |grad phi|^2 (world units), as the Eikonal equation needs it.
    template <BiasedGradientScheme Scheme = HJWENO5_BIAS>
    ValueType normSqGrad() const {
        ValueType d[6];
        for (int a = 0; a < 3; ++a)
            differences<Scheme>(a, d[2 * a], d[2 * a + 1]);
        const ValueType g2 =
            godunovNormSqrd(this->mValues[0] > ValueType(0), d[0], d[1], d[2], d[3], d[4], d[5]);
        return g2 / (this->mDx * this->mDx);
    }
    /// Fourth-order central laplacian.
    ValueType laplacian() const {
        ValueType sum(0);
        for (int a = 0; a < 3; ++a) {
            const auto l = this->line(lineIndices(a));
            sum += (-l[1] + ValueType(16) * l[2] - ValueType(30) * l[3] + ValueType(16) * l[4] -
                    l[5]) /
                   ValueType(12);
        }
        return sum / (this->mDx * this->mDx);
    }

private:
    // Point order: centre, then per axis the offsets -3, -2, -1, +1, +2, +3.
    static std::array<Coord, 19> offsets() {
        std::array<Coord, 19> o;
        o[0] = Coord(0);
        size_t n = 1;
        for (int a = 0; a < 3; ++a) {
            for (int d : {-3, -2, -1, 1, 2, 3}) {
                Coord c(0);
                c[size_t(a)] = d;
                o[n++] = c;
            }
        }
        return o;
    }
    static std::array<size_t, 7> lineIndices(int axis) {
        const size_t b = 1 + 6 * size_t(axis);
        return {b, b + 1, b + 2, 0, b + 3, b + 4, b + 5};
    }
};

/// The centre, its 6 face and its 12 edge neighbours: second derivatives with mixed terms, so
/// mean curvature.
template <typename GridT>
class CurvatureStencil : public BaseStencil<GridT, 19> {
    using Base = BaseStencil<GridT, 19>;

public:
    using ValueType = typename Base::ValueType;
    using VecType = Vec3<ValueType>;

    explicit CurvatureStencil(const GridT& grid) : Base(grid, offsets()) {}

    /// Second-order central gradient (world units).
    VecType gradient() const {
        const auto d = derivatives();
        return VecType(ValueType(d.dx), ValueType(d.dy), ValueType(d.dz)) / this->mDx;
    }
    /// Second-order central laplacian (world units).
    ValueType laplacian() const {
        const auto at = [this](int i, int j, int k) { return this->mValues[pos(i, j, k)]; };
        return math::centralLaplacian(at) / (this->mDx * this->mDx);
    }
    /// Mean curvature H = div(grad phi / |grad phi|) / 2 (world units: 1/R on a sphere of radius
    /// R), from second-order central differences; 0 where the gradient vanishes.
    ValueType meanCurvature() const {
        double alphaM, alphaG, normGrad;
        if (!math::curvatureTerms(derivatives(), alphaM, alphaG, normGrad))
            return ValueType(0);
        return ValueType(alphaM / (2.0 * normGrad * normGrad * normGrad * double(this->mDx)));
    }
    /// Gaussian curvature K (world units: 1/R^2 on a sphere of radius R); 0 where the gradient
    /// vanishes.
    ValueType gaussianCurvature() const {
        double alphaM, alphaG, normGrad;
        if (!math::curvatureTerms(derivatives(), alphaM, alphaG, normGrad))
            return ValueType(0);
        const double dx = double(this->mDx);
        return ValueType(alphaG / (normGrad * normGrad * normGrad * normGrad * dx * dx));
    }
    /// Both curvatures at once (world units); both 0 where the gradient vanishes.
    void curvatures(ValueType& mean, ValueType& gauss) const {
        double alphaM, alphaG, normGrad;
        if (!math::curvatureTerms(derivatives(), alphaM, alphaG, normGrad)) {
            mean = gauss = ValueType(0);
            return;
        }
        const double dx = double(this->mDx), g3 = normGrad * normGrad * normGrad;
        mean = ValueType(alphaM / (2.0 * g3 * dx));
        gauss = ValueType(alphaG / (g3 * normGrad * dx * dx));
    }
    /// The mean curvature times |grad phi| (world units), the speed of mean-curvature flow.
    ValueType meanCurvatureNormGrad() const {
        double alphaM, alphaG, normGrad;
        if (!math::curvatureTerms(derivatives(), alphaM, alphaG, normGrad))
            return ValueType(0);
        const double dx = double(this->mDx);
        return ValueType(alphaM / (2.0 * normGrad * normGrad * dx * dx));
    }
    /// The index-space central derivatives at the centre, in double precision.
    math::Derivatives<double> derivatives() const {
        return math::centralDerivatives<double>(
            [this](int i, int j, int k) { return this->mValues[pos(i, j, k)]; });
    }
    /// The stencil's index of the point at offset (i, j, k). @pre a point of the stencil
    static constexpr size_t pos(int i, int j, int k) {
        if (i == 0 || j == 0 || k == 0) {
            const int zeros = (i == 0) + (j == 0) + (k == 0);
            if (zeros >= 2)
                return SevenPointStencil<GridT>::pos(i, j, k);
        }
        if (k == 0)
            return 7 + size_t(i < 0) * 2 + size_t(j < 0);
        if (j == 0)
            return 11 + size_t(i < 0) * 2 + size_t(k < 0);
        return 15 + size_t(j < 0) * 2 + size_t(k < 0);
    }

private:
    // Point order: centre, 6 faces (as SevenPointStencil), then the 12 edges.
    static std::array<Coord, 19> offsets() {
        return {Coord(0),        Coord(-1, 0, 0), Coord(1, 0, 0),   Coord(0, -1, 0),
                Coord(0, 1, 0),  Coord(0, 0, -1), Coord(0, 0, 1),   Coord(1, 1, 0),
                Coord(1, -1, 0), Coord(-1, 1, 0), Coord(-1, -1, 0), Coord(1, 0, 1),
                Coord(1, 0, -1), Coord(-1, 0, 1), Coord(-1, 0, -1), Coord(0, 1, 1),
                Coord(0, 1, -1), Coord(0, -1, 1), Coord(0, -1, -1)};
    }
};

namespace detail {
/// The component type of a vector value, or the value type itself for scalars.
template <typename T>
struct ScalarOf {
    using type = T;
};
template <typename T>
requires requires {
    typename T::ValueType;
}
struct ScalarOf<T> {
    using type = typename T::ValueType;
};
}  // namespace detail

/// Trilinear interpolation of the 8 corner values `v` (index ((i << 2) | (j << 1) | k) for the
/// corner at offset (i, j, k)) at the fractional position `t` in [0, 1]^3.
template <typename ValueT, typename RealT>
inline ValueT trilinear(const std::array<ValueT, 8>& v, const Vec3<RealT>& t) {
    using ScalarT = typename detail::ScalarOf<ValueT>::type;
    const auto lerp = [](const ValueT& a, const ValueT& b, RealT w) -> ValueT {
        return a + (b - a) * ScalarT(w);
    };
    const ValueT x00 = lerp(v[0], v[4], t[0]), x01 = lerp(v[1], v[5], t[0]);
    const ValueT x10 = lerp(v[2], v[6], t[0]), x11 = lerp(v[3], v[7], t[0]);
    return lerp(lerp(x00, x10, t[1]), lerp(x01, x11, t[1]), t[2]);
}

/// The 8 corners of the cell that holds a fractional index-space point: trilinear interpolation
/// (random stencil access, for sampling and ray marching). Works for scalar and vector grids.
template <typename GridT>
class BoxStencil {
public:
    using ValueType = typename GridT::ValueType;
    using AccessorType = typename GridT::ConstAccessor;

    explicit BoxStencil(const GridT& grid) : mAcc(grid.tree()) {}
    /// Reads the corners of the cell whose lowest corner is `ijk`.
    void moveTo(const Coord& ijk) {
        if (ijk == mBase && mValid)
            return;
        mBase = ijk;
        mValid = true;
        for (int n = 0; n < 8; ++n)
            mValues[size_t(n)] = mAcc.getValue(ijk.offsetBy(n >> 2, (n >> 1) & 1, n & 1));
    }
    /// Trilinear interpolation at the index-space point `xyz`.
    ValueType interpolation(const Vec3d& xyz) {
        const Vec3d f(std::floor(xyz[0]), std::floor(xyz[1]), std::floor(xyz[2]));
        moveTo(Coord(Int32(f[0]), Int32(f[1]), Int32(f[2])));
        return trilinear(mValues, xyz - f);
    }
    const std::array<ValueType, 8>& values() const { return mValues; }

private:
    AccessorType mAcc;
    std::array<ValueType, 8> mValues{};
    Coord mBase;
    bool mValid = false;
};

}  // namespace vdb::math
