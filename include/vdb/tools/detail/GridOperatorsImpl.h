// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/GridOperators.h (not API): the map from index-space to world-space
/// derivatives, the operator kernels, and the one engine that applies a kernel at every active
/// voxel of a grid, leaf by leaf, reading each leaf's neighbourhood from a dense block.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/detail/LeafBuild.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <bit>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace vdb::tools::detail {

// ---- Index space to world space ---------------------------------------------------------------

/// How index-space derivatives become world-space derivatives under a linear transform
/// world = [ijk 1] M. With P the 3x3 block of M and Q = P^-1, the chain rule gives
///   world gradient = Q (index gradient),   world Hessian = Q H Q^T,
/// so the Laplacian is the sum of H[a][b] (Q^T Q)[a][b]. Scale maps (P diagonal) reduce to a
/// division by the voxel size per axis, uniform ones to a single division.
class DerivativeMap {
public:
    enum class Kind { Uniform, Diagonal, General };

    /// @throw ValueError for a frustum transform (`op` names the operator in the message).
    DerivativeMap(const math::Transform& xform, const char* op) {
        if (!xform.isLinear())
            throw ValueError(std::string(op) +
                             ": frustum transforms are not supported (the grid needs a linear "
                             "transform)");
        const Mat4d& m = xform.affineMatrix();
        const bool diagonal = m(0, 1) == 0.0 && m(0, 2) == 0.0 && m(1, 0) == 0.0 &&
                              m(1, 2) == 0.0 && m(2, 0) == 0.0 && m(2, 1) == 0.0;
        const Mat4d inv = m.inverse();
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i)
                mQ[j][i] = inv(j, i);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                mG[a][b] = mQ[0][a] * mQ[0][b] + mQ[1][a] * mQ[1][b] + mQ[2][a] * mQ[2][b];
        for (int a = 0; a < 3; ++a)
            mInvScale[a] = diagonal ? 1.0 / m(a, a) : 0.0;
        mKind = !diagonal                                    ? Kind::General
                : (m(0, 0) == m(1, 1) && m(0, 0) == m(2, 2)) ? Kind::Uniform
                                                             : Kind::Diagonal;
    }

    Kind kind() const { return mKind; }
    /// For scale maps: one over the voxel size along each axis.
    const Vec3d& invScale() const { return mInvScale; }

    /// The world-space image Q g of the index-space gradient `g`.
    template <typename T>
    math::Vec3<T> gradient(const math::Vec3<T>& g) const {
        switch (mKind) {
            case Kind::Uniform:
                return g * T(mInvScale[0]);
            case Kind::Diagonal:
                return math::Vec3<T>(g[0] * T(mInvScale[0]), g[1] * T(mInvScale[1]),
                                     g[2] * T(mInvScale[2]));
            default: {
                const double x = double(g[0]), y = double(g[1]), z = double(g[2]);
                return math::Vec3<T>(T(mQ[0][0] * x + mQ[0][1] * y + mQ[0][2] * z),
                                     T(mQ[1][0] * x + mQ[1][1] * y + mQ[1][2] * z),
                                     T(mQ[2][0] * x + mQ[2][1] * y + mQ[2][2] * z));
            }
        }
    }

    /// The world-space derivatives of index-space derivatives `d`.
    math::Derivatives<double> derivatives(const math::Derivatives<double>& d) const {
        const Vec3d g = gradient(Vec3d(d.dx, d.dy, d.dz));
        const double h[3][3] = {
            {d.dxx, d.dxy, d.dxz}, {d.dxy, d.dyy, d.dyz}, {d.dxz, d.dyz, d.dzz}};
        double w[3][3];  // Q H Q^T
        for (int j = 0; j < 3; ++j) {
            for (int k = j; k < 3; ++k) {
                double sum = 0.0;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        sum += q(j, a) * h[a][b] * q(k, b);
                w[j][k] = w[k][j] = sum;
            }
        }
        return {g[0], g[1], g[2], w[0][0], w[1][1], w[2][2], w[0][1], w[0][2], w[1][2]};
    }

    /// The world-space Laplacian, the trace of Q H Q^T, from index-space derivatives `d`.
    double laplacian(const math::Derivatives<double>& d) const {
        return d.dxx * mG[0][0] + d.dyy * mG[1][1] + d.dzz * mG[2][2] +
               2.0 * (d.dxy * mG[0][1] + d.dxz * mG[0][2] + d.dyz * mG[1][2]);
    }

private:
    double q(int j, int i) const {
        return mKind == Kind::General ? mQ[j][i] : (i == j ? mInvScale[i] : 0.0);
    }

    Kind mKind = Kind::Uniform;
    Vec3d mInvScale{1.0};
    double mQ[3][3] = {};
    double mG[3][3] = {};
};

// ---- Kernels ----------------------------------------------------------------------------------
//
// A stencil kernel maps a voxel's neighbourhood (a BlockPoint into a leaf's block) to the output
// value; a pointwise kernel maps the voxel's value. SHAPE says which neighbours the stencil reads
// (at distance 1).

template <typename T>
struct GradientKernel {
    using InValueT = T;
    using OutValueT = math::Vec3<T>;
    static constexpr bool POINTWISE = false;
    const DerivativeMap& map;
    BlockShape shape() const { return BlockShape::Cross; }
    OutValueT operator()(const BlockPoint<T>& p) const {
        return map.gradient(math::Vec3<T>(math::centralDiff<0>(p), math::centralDiff<1>(p),
                                          math::centralDiff<2>(p)));
    }
};

/// The partial derivatives along x, y and z of a vector field (vectors indexed by the axis of
/// differentiation), central or, for staggered grids, forward.
template <typename VecT>
void vectorDerivatives(const BlockPoint<VecT>& p, bool staggered, VecT (&d)[3]) {
    if (staggered) {
        d[0] = math::forwardDiff<0>(p);
        d[1] = math::forwardDiff<1>(p);
        d[2] = math::forwardDiff<2>(p);
    } else {
        d[0] = math::centralDiff<0>(p);
        d[1] = math::centralDiff<1>(p);
        d[2] = math::centralDiff<2>(p);
    }
}

/// The world-space Jacobian of a vector field: j[i][a] = d(v_i)/d(x_a).
template <typename T>
void worldJacobian(const DerivativeMap& map, const math::Vec3<T> (&d)[3], math::Vec3<T> (&j)[3]) {
    for (int i = 0; i < 3; ++i)
        j[i] = map.gradient(math::Vec3<T>(d[0][size_t(i)], d[1][size_t(i)], d[2][size_t(i)]));
}

template <typename T>
struct DivergenceKernel {
    using InValueT = math::Vec3<T>;
    using OutValueT = T;
    static constexpr bool POINTWISE = false;
    const DerivativeMap& map;
    bool staggered;
    BlockShape shape() const { return BlockShape::Cross; }
    OutValueT operator()(const BlockPoint<InValueT>& p) const {
        InValueT d[3];
        vectorDerivatives(p, staggered, d);
        if (map.kind() == DerivativeMap::Kind::General) {
            InValueT j[3];
            worldJacobian(map, d, j);
            return j[0][0] + j[1][1] + j[2][2];
        }
        const Vec3d& s = map.invScale();
        return d[0][0] * T(s[0]) + d[1][1] * T(s[1]) + d[2][2] * T(s[2]);
    }
};

template <typename T>
struct CurlKernel {
    using InValueT = math::Vec3<T>;
    using OutValueT = math::Vec3<T>;
    static constexpr bool POINTWISE = false;
    const DerivativeMap& map;
    BlockShape shape() const { return BlockShape::Cross; }
    OutValueT operator()(const BlockPoint<InValueT>& p) const {
        InValueT d[3], j[3];
        vectorDerivatives(p, false, d);
        worldJacobian(map, d, j);
        return OutValueT(j[2][1] - j[1][2], j[0][2] - j[2][0], j[1][0] - j[0][1]);
    }
};

template <typename T>
struct LaplacianKernel {
    using InValueT = T;
    using OutValueT = T;
    static constexpr bool POINTWISE = false;
    const DerivativeMap& map;
    BlockShape shape() const {
        return map.kind() == DerivativeMap::Kind::General ? BlockShape::Full : BlockShape::Cross;
    }
    OutValueT operator()(const BlockPoint<T>& p) const {
        const Vec3d& s = map.invScale();
        switch (map.kind()) {
            case DerivativeMap::Kind::Uniform:
                return math::centralLaplacian(p) * T(s[0] * s[0]);
            case DerivativeMap::Kind::Diagonal:
                return math::centralDiff2<0>(p) * T(s[0] * s[0]) +
                       math::centralDiff2<1>(p) * T(s[1] * s[1]) +
                       math::centralDiff2<2>(p) * T(s[2] * s[2]);
            default:
                return T(map.laplacian(math::centralDerivatives<double>(p)));
        }
    }
};

template <typename T>
struct MeanCurvatureKernel {
    using InValueT = T;
    using OutValueT = T;
    static constexpr bool POINTWISE = false;
    const DerivativeMap& map;
    BlockShape shape() const { return BlockShape::Full; }
    OutValueT operator()(const BlockPoint<T>& p) const {
        return T(math::meanCurvature(map.derivatives(math::centralDerivatives<double>(p))));
    }
};

template <typename T>
struct MagnitudeKernel {
    using InValueT = math::Vec3<T>;
    using OutValueT = T;
    static constexpr bool POINTWISE = true;
    OutValueT operator()(const InValueT& v) const { return v.length(); }
    /// operator() over 64 values, in loops the compiler vectorises (the square roots aside).
    void row(const InValueT* in, OutValueT* out) const {
        T sq[64];
        for (int n = 0; n < 64; ++n)
            sq[n] = in[n].lengthSqr();
        for (int n = 0; n < 64; ++n)
            out[n] = std::sqrt(sq[n]);
    }
};

template <typename T>
struct NormalizeKernel {
    using InValueT = math::Vec3<T>;
    using OutValueT = math::Vec3<T>;
    static constexpr bool POINTWISE = true;
    OutValueT operator()(InValueT v) const { return v.normalize() ? v : InValueT(T(0)); }
    /// operator() over 64 values with the same arithmetic (Vec3::normalize divides each
    /// component by the length), in loops the compiler vectorises (the square roots aside):
    /// every lane divides, by 1 where the vector is too short, so no division is conditional.
    void row(const InValueT* in, OutValueT* out) const {
        T len[64];
        for (int n = 0; n < 64; ++n)
            len[n] = std::sqrt(in[n].lengthSqr());
        for (int n = 0; n < 64; ++n) {
            const bool ok = len[n] > math::Tolerance<T>::value();
            const T d = ok ? len[n] : T(1);
            const T x = in[n][0] / d, y = in[n][1] / d, z = in[n][2] / d;
            out[n] = InValueT(ok ? x : T(0), ok ? y : T(0), ok ? z : T(0));
        }
    }
};

// ---- The engine -------------------------------------------------------------------------------

/// The kernel's value on a field that is `value` everywhere: the output's background.
template <typename KernelT>
typename KernelT::OutValueT constantFieldValue(const KernelT& kernel,
                                               const typename KernelT::InValueT& value) {
    if constexpr (KernelT::POINTWISE) {
        return kernel(value);
    } else {
        typename KernelT::InValueT cube[27];
        std::fill_n(cube, 27, value);
        return kernel(BlockPoint<typename KernelT::InValueT>{cube + 13, 9, 3});
    }
}

/// The active states of the voxels of the leaf-sized cell at `origin` in `mask`'s tree.
template <typename MaskAccT, typename MaskWordsT>
void andMask(const MaskAccT& maskAcc, const Coord& origin, MaskWordsT& states) {
    if (const auto* leaf = maskAcc.probeConstLeaf(origin)) {
        states &= leaf->getValueMask();
    } else if (!maskAcc.isValueOn(origin)) {
        states.setOff();
    }
}

/// Applies `kernel` at every voxel active in both `in` and `mask` (when not null) and returns
/// the tree of the results, with the background the kernel gives a constant field of `in`'s
/// background. Active tiles become dense leaves first when `densify` (or when there is a mask),
/// and the result is then pruned; otherwise they stay tiles, of the kernel's value.
template <typename OutTreeT, typename InTreeT, typename MaskTreeT, typename KernelT>
std::shared_ptr<OutTreeT> applyKernel(const InTreeT& in, const MaskTreeT* mask,
                                      const KernelT& kernel, bool densify, bool threaded) {
    using InLeafT = typename InTreeT::LeafNodeType;
    using OutLeafT = typename OutTreeT::LeafNodeType;
    using OutValueT = typename OutTreeT::ValueType;
    using InValueT = typename InTreeT::ValueType;
    static_assert(InLeafT::LOG2DIM == OutLeafT::LOG2DIM &&
                      InLeafT::LOG2DIM == MaskTreeT::LeafNodeType::LOG2DIM,
                  "the input, the output and the mask must have leaves of one size");
    constexpr Int32 DIM = Int32(InLeafT::DIM);

    const OutValueT background = constantFieldValue(kernel, in.background());

    // The cells to compute: every leaf with an active voxel, then the leaves of active tiles.
    struct Job {
        Coord origin;
        const InLeafT* leaf;  // null: a cell of an active tile
    };
    std::vector<Job> jobs;
    const tree::LeafManager<const InTreeT> leaves(in);
    jobs.reserve(leaves.leafCount());
    for (size_t i = 0; i < leaves.leafCount(); ++i) {
        if (!leaves.leaf(i).isEmpty())
            jobs.push_back({leaves.leaf(i).origin(), &leaves.leaf(i)});
    }
    std::vector<TileRef> keptTiles;
    for (const TileRef& tile : TreeTileOps<InTreeT>::activeTiles(in)) {
        if (!densify && !mask) {
            keptTiles.push_back(tile);
            continue;
        }
        for (Int32 x = 0; x < tile.dim; x += DIM)
            for (Int32 y = 0; y < tile.dim; y += DIM)
                for (Int32 z = 0; z < tile.dim; z += DIM)
                    jobs.push_back({tile.origin.offsetBy(x, y, z), nullptr});
    }

    // One output leaf per cell, in parallel.
    std::vector<std::unique_ptr<OutLeafT>> out(jobs.size());
    util::parallelForRange(
        jobs.size(),
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const InTreeT> acc(in);
            std::unique_ptr<tree::ValueAccessor<const MaskTreeT>> maskAcc;
            if (mask)
                maskAcc = std::make_unique<tree::ValueAccessor<const MaskTreeT>>(*mask);
            std::unique_ptr<NeighborhoodBlock<InTreeT>> block;
            if constexpr (!KernelT::POINTWISE)
                block = std::make_unique<NeighborhoodBlock<InTreeT>>(Coord(1), kernel.shape());
            for (size_t i = begin; i < end; ++i) {
                const Job& job = jobs[i];
                typename InLeafT::MaskType states(true);
                if (job.leaf)
                    states = job.leaf->getValueMask();
                if (maskAcc)
                    andMask(*maskAcc, job.origin, states);
                if (states.isOff())
                    continue;
                // Every value is written once: the kernel's where active, the background
                // elsewhere (as a topology copy of the input would hold).
                auto leaf = std::make_unique<OutLeafT>(tree::PartialCreate{}, job.origin);
                leaf->setBufferCount(1);
                leaf->setValueMask(states);
                OutValueT* values = leaf->buffer(0).data();
                const auto* words = states.words();
                if constexpr (KernelT::POINTWISE) {
                    if (!job.leaf) {
                        const OutValueT tile = kernel(acc.getValue(job.origin));
                        for (Index n = 0; n < OutLeafT::NUM_VALUES; ++n)
                            values[n] = states.isOn(n) ? tile : background;
                    } else {
                        const InValueT* src = job.leaf->buffer(0).data();
                        for (Index w = 0; w < states.WORD_COUNT; ++w) {
                            const uint64_t bits = words[w];
                            OutValueT* row = values + (w << 6);
                            const InValueT* in = src + (w << 6);
                            if (bits == ~uint64_t(0)) {
                                kernel.row(in, row);
                            } else {
                                for (Index n = 0; n < 64; ++n)
                                    row[n] = (bits >> n) & 1u ? kernel(in[n]) : background;
                            }
                        }
                    }
                } else {
                    block->gather(job.origin, job.leaf, 0, acc);
                    const int sx = block->sx(), sy = block->sy();
                    for (Index w = 0; w < states.WORD_COUNT; ++w) {
                        const uint64_t bits = words[w];
                        if (bits != ~uint64_t(0))
                            std::fill_n(values + (w << 6), 64, background);
                        for (uint64_t b = bits; b; b &= b - 1) {
                            const Index n = (w << 6) + Index(std::countr_zero(b));
                            values[n] = kernel(BlockPoint<InValueT>{block->atOffset(n), sx, sy});
                        }
                    }
                }
                out[i] = std::move(leaf);
            }
        },
        threaded, 8);

    auto result = std::make_shared<OutTreeT>(background);
    linkLeaves(*result, out, threaded);
    for (const TileRef& tile : keptTiles) {
        result->addTile(tile.level, tile.origin,
                        constantFieldValue(kernel, in.getValue(tile.origin)), true);
    }
    if (densify)
        prune(*result, OutValueT{}, threaded);
    return result;
}

/// Applies `kernel` to `grid` (see applyKernel()) and wraps the result in a grid of type
/// OutGridT with a copy of `grid`'s transform.
template <typename OutGridT, typename InGridT, typename MaskGridT, typename KernelT>
typename OutGridT::Ptr applyOperator(const InGridT& grid, const MaskGridT* mask,
                                     const KernelT& kernel, bool densify, bool threaded) {
    using MaskTreeT = typename MaskGridT::TreeType;
    auto tree = applyKernel<typename OutGridT::TreeType>(
        grid.tree(), mask ? &mask->tree() : static_cast<const MaskTreeT*>(nullptr), kernel, densify,
        threaded);
    auto result = OutGridT::create(tree);
    result->setTransform(grid.transform().copy());
    return result;
}

/// The mask type of the operators called without a mask.
template <typename GridT>
using NoMaskGrid = typename GridT::template ValueConverter<ValueMask>::Type;

template <typename GridT, typename MaskT>
auto gradientImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType;
    const DerivativeMap map(grid.transform(), "gradient");
    auto result = applyOperator<typename ScalarToVectorConverter<GridT>::Type>(
        grid, mask, GradientKernel<T>{map}, true, threaded);
    result->setVectorType(VEC_COVARIANT);
    return result;
}

template <typename GridT, typename MaskT>
auto divergenceImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType::value_type;
    const DerivativeMap map(grid.transform(), "divergence");
    const bool staggered = grid.getGridClass() == GRID_STAGGERED;
    return applyOperator<typename VectorToScalarConverter<GridT>::Type>(
        grid, mask, DivergenceKernel<T>{map, staggered}, true, threaded);
}

template <typename GridT, typename MaskT>
auto curlImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType::value_type;
    const DerivativeMap map(grid.transform(), "curl");
    auto result = applyOperator<GridT>(grid, mask, CurlKernel<T>{map}, true, threaded);
    result->setVectorType(VEC_COVARIANT);
    return result;
}

template <typename GridT, typename MaskT>
auto laplacianImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType;
    const DerivativeMap map(grid.transform(), "laplacian");
    auto result = applyOperator<GridT>(grid, mask, LaplacianKernel<T>{map}, true, threaded);
    result->setVectorType(VEC_COVARIANT);
    return result;
}

template <typename GridT, typename MaskT>
auto meanCurvatureImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType;
    const DerivativeMap map(grid.transform(), "meanCurvature");
    auto result = applyOperator<GridT>(grid, mask, MeanCurvatureKernel<T>{map}, true, threaded);
    result->setVectorType(VEC_COVARIANT);
    return result;
}

template <typename GridT, typename MaskT>
auto magnitudeImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType::value_type;
    return applyOperator<typename VectorToScalarConverter<GridT>::Type>(
        grid, mask, MagnitudeKernel<T>{}, false, threaded);
}

template <typename GridT, typename MaskT>
auto normalizeImpl(const GridT& grid, const MaskT* mask, bool threaded) {
    using T = typename GridT::ValueType::value_type;
    auto result = applyOperator<GridT>(grid, mask, NormalizeKernel<T>{}, false, threaded);
    const VecType type = grid.getVectorType();
    result->setVectorType(type == VEC_COVARIANT ? VEC_COVARIANT_NORMALIZE : type);
    return result;
}

}  // namespace vdb::tools::detail

namespace vdb::tools {

template <ScalarGridType GridT>
typename ScalarToVectorConverter<GridT>::Type::Ptr gradient(const GridT& grid, bool threaded) {
    return detail::gradientImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                threaded);
}
template <ScalarGridType GridT, MaskGridLike MaskT>
typename ScalarToVectorConverter<GridT>::Type::Ptr gradient(const GridT& grid, const MaskT& mask,
                                                            bool threaded) {
    return detail::gradientImpl(grid, &mask, threaded);
}

template <VectorGridType GridT>
typename VectorToScalarConverter<GridT>::Type::Ptr divergence(const GridT& grid, bool threaded) {
    return detail::divergenceImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                  threaded);
}
template <VectorGridType GridT, MaskGridLike MaskT>
typename VectorToScalarConverter<GridT>::Type::Ptr divergence(const GridT& grid, const MaskT& mask,
                                                              bool threaded) {
    return detail::divergenceImpl(grid, &mask, threaded);
}

template <VectorGridType GridT>
typename GridT::Ptr curl(const GridT& grid, bool threaded) {
    return detail::curlImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr), threaded);
}
template <VectorGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr curl(const GridT& grid, const MaskT& mask, bool threaded) {
    return detail::curlImpl(grid, &mask, threaded);
}

template <ScalarGridType GridT>
typename GridT::Ptr laplacian(const GridT& grid, bool threaded) {
    return detail::laplacianImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                 threaded);
}
template <ScalarGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr laplacian(const GridT& grid, const MaskT& mask, bool threaded) {
    return detail::laplacianImpl(grid, &mask, threaded);
}

template <ScalarGridType GridT>
typename GridT::Ptr meanCurvature(const GridT& grid, bool threaded) {
    return detail::meanCurvatureImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                     threaded);
}
template <ScalarGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr meanCurvature(const GridT& grid, const MaskT& mask, bool threaded) {
    return detail::meanCurvatureImpl(grid, &mask, threaded);
}

template <VectorGridType GridT>
typename VectorToScalarConverter<GridT>::Type::Ptr magnitude(const GridT& grid, bool threaded) {
    return detail::magnitudeImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                 threaded);
}
template <VectorGridType GridT, MaskGridLike MaskT>
typename VectorToScalarConverter<GridT>::Type::Ptr magnitude(const GridT& grid, const MaskT& mask,
                                                             bool threaded) {
    return detail::magnitudeImpl(grid, &mask, threaded);
}

template <VectorGridType GridT>
typename GridT::Ptr normalize(const GridT& grid, bool threaded) {
    return detail::normalizeImpl(grid, static_cast<const detail::NoMaskGrid<GridT>*>(nullptr),
                                 threaded);
}
template <VectorGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr normalize(const GridT& grid, const MaskT& mask, bool threaded) {
    return detail::normalizeImpl(grid, &mask, threaded);
}

}  // namespace vdb::tools
