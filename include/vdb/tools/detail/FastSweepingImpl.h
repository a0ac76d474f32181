// SPDX-License-Identifier: Apache-2.0
/// @file
/// The machinery of tools/FastSweeping.h (not API): the boundary condition next to the
/// isosurface, the sweep orders (hyperplanes x +- y +- z = const, leaf by leaf), the upwind
/// update of one voxel, and the final extrema.
///
/// Sweeping works on the leaves directly: every leaf that holds voxels to solve for gets the
/// value arrays of its six face neighbours (or an array of +-max where there is no leaf, which
/// after init always stands for "unknown"), so a voxel reads its six neighbours without a tree
/// lookup. A sweep family (one sign pattern of x +- y +- z) sorts the leaves by the key of
/// their origin; the leaves that meet hyperplane s are then one contiguous run of that order,
/// and the voxels of a leaf on that hyperplane are its mask and one of 3 (DIM - 1) + 1 fixed
/// patterns.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Math.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tools/detail/MorphologyImpl.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools::detail {

/// The extension functor of a computation without extension field (never called).
template <typename ExtT>
struct NoExtensionOp {
    ExtT operator()(const Vec3d&) const { return ExtT{}; }
};

/// Zero of a scalar or vector extension value.
template <typename ExtT>
ExtT zeroExt() {
    if constexpr (std::is_arithmetic_v<ExtT>) {
        return ExtT(0);
    } else {
        return ExtT::zero();
    }
}

/// `v` times the scalar `s`, in the precision of `v`'s components.
template <typename ExtT, typename ScalarT>
ExtT scaleExt(ScalarT s, const ExtT& v) {
    if constexpr (std::is_arithmetic_v<ExtT>) {
        return ExtT(s * v);
    } else {
        return ExtT(v * typename ExtT::ValueType(s));
    }
}

/// The value an extension field carries from the neighbours (values e[i], upwind weights
/// w[i] = d[i] - phi, all <= 0) of a voxel: the weighted mean for floating-point and vector
/// fields, the nearest neighbour's value (the last of equal ones) for integer fields.
template <typename ExtT, typename ScalarT, int N>
ExtT blendExt(const std::array<ScalarT, N>& w, const std::array<ExtT, N>& e) {
    if constexpr (std::is_integral_v<ExtT>) {
        int best = N - 1;
        for (int i = N - 2; i >= 0; --i) {
            if (w[i] < w[best])
                best = i;
        }
        return e[best];
    } else {
        ScalarT sum = 0;
        for (int i = 0; i < N; ++i)
            sum += w[i];
        ExtT acc = scaleExt<ExtT>(w[0], e[0]);
        for (int i = 1; i < N; ++i)
            acc = acc + scaleExt<ExtT>(w[i], e[i]);
        return scaleExt<ExtT>(ScalarT(1) / sum, acc);
    }
}

/// One leaf that holds voxels to solve for, with the value arrays of its face neighbours in
/// the order -x, +x, -y, +y, -z, +z.
template <typename SdfValueT, typename ExtValueT, typename MaskT>
struct SweepLeaf {
    SdfValueT* sdf;
    std::array<const SdfValueT*, 6> sdfNbr;
    ExtValueT* ext;
    std::array<const ExtValueT*, 6> extNbr;
    Coord origin;
    MaskT mask;
};

/// The hyperplanes of one sweep family x + sy y + sz z = s over a set of leaves.
template <typename LeafT>
struct SweepFamily {
    using MaskT = typename LeafT::MaskType;
    static constexpr Int32 DIM = Int32(LeafT::DIM);
    struct Slice {
        Int64 key;
        uint32_t begin, end;  // run of `order` whose leaves meet the hyperplane
    };
    int sy = 1, sz = 1;
    Int64 tmin = 0;
    std::vector<MaskT> patterns;  // voxels of local key tmin + t
    std::vector<uint32_t> order;  // leaves sorted by the key of their origin
    std::vector<Int64> keys;      // those keys, ascending
    std::vector<Slice> slices;    // ascending keys

    Int64 key(const Coord& ijk) const {
        return Int64(ijk[0]) + sy * Int64(ijk[1]) + sz * Int64(ijk[2]);
    }

    SweepFamily(int signY, int signZ, const std::vector<Coord>& origins) : sy(signY), sz(signZ) {
        tmin = std::min(0, sy * (DIM - 1)) + std::min(0, sz * (DIM - 1));
        const Int64 span = 3 * (DIM - 1);
        patterns.assign(size_t(span + 1), MaskT());
        for (Int32 x = 0; x < DIM; ++x) {
            for (Int32 y = 0; y < DIM; ++y) {
                for (Int32 z = 0; z < DIM; ++z)
                    patterns[size_t(key(Coord(x, y, z)) - tmin)].setOn(
                        LeafT::coordToOffset(Coord(x, y, z)));
            }
        }
        std::vector<std::pair<Int64, uint32_t>> sorted(origins.size());
        for (size_t i = 0; i < origins.size(); ++i)
            sorted[i] = {key(origins[i]), uint32_t(i)};
        std::sort(sorted.begin(), sorted.end());
        order.resize(sorted.size());
        keys.resize(sorted.size());
        for (size_t i = 0; i < sorted.size(); ++i) {
            keys[i] = sorted[i].first;
            order[i] = sorted[i].second;
        }
        // Every hyperplane that meets a leaf, once: the windows [key + tmin, key + tmin + span]
        // of the distinct keys, merged.
        Int64 next = std::numeric_limits<Int64>::min();
        for (size_t i = 0; i < keys.size(); ++i) {
            if (i > 0 && keys[i] == keys[i - 1])
                continue;
            for (Int64 s = std::max(next, keys[i] + tmin); s <= keys[i] + tmin + span; ++s) {
                const auto lo = std::lower_bound(keys.begin(), keys.end(), s - tmin - span);
                const auto hi = std::upper_bound(keys.begin(), keys.end(), s - tmin);
                slices.push_back({s, uint32_t(lo - keys.begin()), uint32_t(hi - keys.begin())});
            }
            next = keys[i] + tmin + span + 1;
        }
    }
};

/// The sweeps over prepared leaves: nIter times the four families, each forward then
/// backward, hyperplane after hyperplane, the leaves of one hyperplane in parallel.
template <typename LeafT, typename ExtValueT, bool WITH_EXT>
class Sweeper {
public:
    using SdfValueT = typename LeafT::ValueType;
    using MaskT = typename LeafT::MaskType;
    static constexpr Index LOG2DIM = LeafT::LOG2DIM;
    static constexpr Index DIM = LeafT::DIM;
    static constexpr Index SX = DIM * DIM, SY = DIM;
    using Leaf = SweepLeaf<SdfValueT, ExtValueT, MaskT>;
    /// `h` is the voxel size.
    Sweeper(std::vector<Leaf>& leaves, SdfValueT h) : mLeaves(leaves), mH(h) {
        mSqrt2h = std::sqrt(SdfValueT(2)) * h;
    }

    /// `extRule.local()` gives each task a rule: `keep(sign)` is true where the swept
    /// extension value is kept, elsewhere the voxel takes `input(ijk)`.
    template <typename ExtRuleT>
    void run(int nIter, const ExtRuleT& extRule) {
        std::vector<Coord> origins(mLeaves.size());
        for (size_t i = 0; i < mLeaves.size(); ++i)
            origins[i] = mLeaves[i].origin;
        std::vector<std::unique_ptr<SweepFamily<LeafT>>> families(4);
        const int signs[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
        util::parallelFor(
            4,
            [&](size_t f) {
                families[f] =
                    std::make_unique<SweepFamily<LeafT>>(signs[f][0], signs[f][1], origins);
            },
            true, 1);
        for (int it = 0; it < nIter; ++it) {
            for (const auto& family : families) {
                for (size_t s = 0; s < family->slices.size(); ++s)
                    sweepSlice(*family, family->slices[s], extRule);
                for (size_t s = family->slices.size(); s-- > 0;)
                    sweepSlice(*family, family->slices[s], extRule);
            }
        }
    }

private:
    struct Nbr {
        SdfValueT v;
        int dir;
        bool operator<(const Nbr& o) const { return v < o.v; }
    };

    template <typename ExtRuleT>
    void sweepSlice(const SweepFamily<LeafT>& family,
                    const typename SweepFamily<LeafT>::Slice& slice, const ExtRuleT& extRule) {
        util::parallelForRange(
            slice.end - slice.begin,
            [&](size_t b, size_t e) {
                auto rule = extRule.local();
                for (size_t i = slice.begin + b; i < slice.begin + e; ++i) {
                    Leaf& leaf = mLeaves[family.order[i]];
                    const size_t t = size_t(slice.key - family.keys[i] - family.tmin);
                    const MaskT voxels = leaf.mask & family.patterns[t];
                    const auto* words = voxels.words();
                    for (Index w = 0; w < MaskT::WORD_COUNT; ++w) {
                        for (uint64_t bits = words[w]; bits; bits &= bits - 1)
                            update(leaf, (w << 6) + Index(std::countr_zero(bits)), rule);
                    }
                }
            },
            true, 8);
    }

    /// The value of the neighbour of voxel n in direction `dir` in arrays `own` / `nbr`.
    template <typename T>
    static T neighbor(const T* own, const std::array<const T*, 6>& nbr, Index n, int dir) {
        const Index x = n >> (2 * LOG2DIM), y = (n >> LOG2DIM) & (DIM - 1), z = n & (DIM - 1);
        switch (dir) {
            case 0:
                return x > 0 ? own[n - SX] : nbr[0][n + (DIM - 1) * SX];
            case 1:
                return x < DIM - 1 ? own[n + SX] : nbr[1][n - (DIM - 1) * SX];
            case 2:
                return y > 0 ? own[n - SY] : nbr[2][n + (DIM - 1) * SY];
            case 3:
                return y < DIM - 1 ? own[n + SY] : nbr[3][n - (DIM - 1) * SY];
            case 4:
                return z > 0 ? own[n - 1] : nbr[4][n + (DIM - 1)];
            default:
                return z < DIM - 1 ? own[n + 1] : nbr[5][n - (DIM - 1)];
        }
    }

    /// Godunov's upwind update of voxel n: the solution of
    /// sum_a [phi - d_a]_+^2 = h^2 over the closest neighbours d1 <= d2 <= d3 along the axes,
    /// kept when it lowers |phi|.
    template <typename RuleT>
    void update(Leaf& leaf, Index n, RuleT& rule) const {
        constexpr SdfValueT UNKNOWN = std::numeric_limits<SdfValueT>::max();
        const SdfValueT* v = leaf.sdf;
        const auto& nb = leaf.sdfNbr;
        const Nbr a0{std::abs(neighbor(v, nb, n, 0)), 0}, a1{std::abs(neighbor(v, nb, n, 1)), 1};
        const Nbr a2{std::abs(neighbor(v, nb, n, 2)), 2}, a3{std::abs(neighbor(v, nb, n, 3)), 3};
        const Nbr a4{std::abs(neighbor(v, nb, n, 4)), 4}, a5{std::abs(neighbor(v, nb, n, 5)), 5};
        Nbr d1 = a1 < a0 ? a1 : a0, d2 = a3 < a2 ? a3 : a2, d3 = a5 < a4 ? a5 : a4;
        if (!(d1.v < UNKNOWN || d2.v < UNKNOWN || d3.v < UNKNOWN))
            return;
        SdfValueT& value = leaf.sdf[n];
        const SdfValueT sign = value >= SdfValueT(0) ? SdfValueT(1) : SdfValueT(-1);
        const SdfValueT absV = std::abs(value);
        if (d2 < d1)
            std::swap(d1, d2);
        if (d3 < d2)
            std::swap(d2, d3);
        if (d2 < d1)
            std::swap(d1, d2);
        const SdfValueT h = mH;

        // One neighbour: (phi - d1)^2 = h^2.
        SdfValueT phi = d1.v + h;
        if (phi <= d2.v) {
            if (phi < absV) {
                value = sign * phi;
                if constexpr (WITH_EXT) {
                    setExt(leaf, n, sign, rule, neighbor(leaf.ext, leaf.extNbr, n, d1.dir));
                }
            }
            return;
        }
        // Two neighbours: (phi - d1)^2 + (phi - d2)^2 = h^2.
        if (d2.v <= mSqrt2h + d1.v) {
            const SdfValueT diff = d1.v - d2.v;
            const SdfValueT disc = SdfValueT(2) * h * h - diff * diff;
            phi = SdfValueT(0.5) * (d1.v + d2.v + std::sqrt(disc));
            if (phi > d2.v && phi <= d3.v) {
                if (phi < absV) {
                    value = sign * phi;
                    if constexpr (WITH_EXT) {
                        const std::array<SdfValueT, 2> w{d1.v - phi, d2.v - phi};
                        const std::array<ExtValueT, 2> e{
                            neighbor(leaf.ext, leaf.extNbr, n, d1.dir),
                            neighbor(leaf.ext, leaf.extNbr, n, d2.dir)};
                        setExt(leaf, n, sign, rule, blendExt<ExtValueT, SdfValueT, 2>(w, e));
                    }
                }
                return;
            }
        }
        // Three neighbours: 3 phi^2 - 2 (d1 + d2 + d3) phi + d1^2 + d2^2 + d3^2 - h^2 = 0.
        if (!(d3.v < UNKNOWN))
            return;
        const SdfValueT d123 = d1.v + d2.v + d3.v;
        const SdfValueT disc =
            d123 * d123 - SdfValueT(3) * (d1.v * d1.v + d2.v * d2.v + d3.v * d3.v - h * h);
        if (disc >= SdfValueT(0)) {
            phi = SdfValueT(1.0 / 3.0) * (d123 + std::sqrt(disc));
            if (phi < absV) {
                value = sign * phi;
                if constexpr (WITH_EXT) {
                    const std::array<SdfValueT, 3> w{d1.v - phi, d2.v - phi, d3.v - phi};
                    const std::array<ExtValueT, 3> e{neighbor(leaf.ext, leaf.extNbr, n, d1.dir),
                                                     neighbor(leaf.ext, leaf.extNbr, n, d2.dir),
                                                     neighbor(leaf.ext, leaf.extNbr, n, d3.dir)};
                    setExt(leaf, n, sign, rule, blendExt<ExtValueT, SdfValueT, 3>(w, e));
                }
            }
        }
    }

    template <typename RuleT>
    static void setExt(Leaf& leaf, Index n, SdfValueT sign, RuleT& rule, const ExtValueT& swept) {
        leaf.ext[n] =
            rule.keep(sign) ? swept : rule.input(leaf.origin + LeafT::offsetToLocalCoord(n));
    }

    std::vector<Leaf>& mLeaves;
    SdfValueT mH, mSqrt2h;
};

/// Whether a swept extension value is kept on the side of `sign`, and otherwise the value of
/// the input extension grid: one rule per task (it holds an accessor).
template <typename ExtTreeT>
class ExtSideRule {
public:
    ExtSideRule(const ExtTreeT* input, FastSweepingDomain mode, bool isInputSdf)
        : mInput(input),
          mMode(mode),
          mKeepPositive((mode == FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE) == isInputSdf) {}

    struct Local {
        std::optional<tree::ValueAccessor<const ExtTreeT>> acc;
        FastSweepingDomain mode;
        bool keepPositive;
        template <typename T>
        bool keep(T sign) const {
            return mode == FastSweepingDomain::SWEEP_ALL || ((sign > T(0)) == keepPositive);
        }
        typename ExtTreeT::ValueType input(const Coord& ijk) { return acc->getValue(ijk); }
    };
    Local local() const {
        Local l{std::nullopt, mMode, mKeepPositive};
        if (mInput)
            l.acc.emplace(*mInput);
        return l;
    }

private:
    const ExtTreeT* mInput;
    FastSweepingDomain mMode;
    bool mKeepPositive;
};

}  // namespace vdb::tools::detail

namespace vdb::tools {

// ---- FastSweeping ----

template <typename SdfGridT, typename ExtValueT>
void FastSweeping<SdfGridT, ExtValueT>::clear() {
    mSdfGrid.reset();
    mExtGrid.reset();
    mExtGridInput.reset();
    mLeaves.clear();
    mSweepMasks.clear();
    mSweepingVoxelCount = mBoundaryVoxelCount = 0;
    mSweepDirection = FastSweepingDomain::SWEEP_ALL;
    mIsInputSdf = true;
}

template <typename SdfGridT, typename ExtValueT>
void FastSweeping<SdfGridT, ExtValueT>::collectLeaves() {
    tree::LeafManager<SdfTreeT> leaves(mSdfGrid->tree());
    mLeaves.assign(leaves.data(), leaves.data() + leaves.leafCount());
    mSweepMasks.assign(mLeaves.size(), MaskT());
}

template <typename SdfGridT, typename ExtValueT>
bool FastSweeping<SdfGridT, ExtValueT>::initSdf(const SdfGridT& sdfGrid, SdfValueT isoValue,
                                                bool isInputSdf) {
    clear();
    mIsInputSdf = isInputSdf;
    mSdfGrid = sdfGrid.deepCopy();
    detail::TreeTileOps<SdfTreeT>::voxelizeActiveTiles(mSdfGrid->tree(), true);
    initBoundary<detail::NoExtensionOp<ExtValueT>>(sdfGrid, isoValue, nullptr);
    return isValid();
}

template <typename SdfGridT, typename ExtValueT>
template <typename ExtOpT>
bool FastSweeping<SdfGridT, ExtValueT>::initExt(const SdfGridT& sdfGrid, const ExtOpT& op,
                                                const ExtValueT& background, SdfValueT isoValue,
                                                bool isInputSdf, FastSweepingDomain mode,
                                                const typename ExtGridT::ConstPtr extGrid) {
    static_assert(std::is_convertible_v<decltype(op(Vec3d(0.0))), ExtValueT>,
                  "the extension functor must map a Vec3d to a value convertible to ExtValueT");
    if (mode != FastSweepingDomain::SWEEP_ALL) {
        if (!extGrid)
            throw ValueError(
                "FastSweeping: extending on one side of the surface needs an extension grid "
                "for the other side");
        checkMatchingTransforms(sdfGrid, *extGrid, "FastSweeping");
    }
    clear();
    mIsInputSdf = isInputSdf;
    mSweepDirection = mode;
    mExtGridInput = mode != FastSweepingDomain::SWEEP_ALL ? extGrid : nullptr;
    mSdfGrid = sdfGrid.deepCopy();
    detail::TreeTileOps<SdfTreeT>::voxelizeActiveTiles(mSdfGrid->tree(), true);
    mExtGrid = ExtGridT::create(background);
    mExtGrid->setTransform(std::make_shared<math::Transform>(sdfGrid.transform()));
    mExtGrid->tree().topologyUnion(mSdfGrid->tree());
    detail::TreeTileOps<ExtTreeT>::voxelizeActiveTiles(mExtGrid->tree(), true);
    initBoundary(sdfGrid, isoValue, &op);
    return isValid();
}

template <typename SdfGridT, typename ExtValueT>
template <typename ExtOpT>
void FastSweeping<SdfGridT, ExtValueT>::initBoundary(const SdfGridT& input, SdfValueT isoValue,
                                                     const ExtOpT* op) {
    constexpr SdfValueT MAX = std::numeric_limits<SdfValueT>::max();
    const SdfValueT aboveSign = mIsInputSdf ? SdfValueT(1) : SdfValueT(-1);
    const SdfValueT above = aboveSign * MAX;
    const SdfValueT h = aboveSign * SdfValueT(mSdfGrid->voxelSize()[0]);
    const SdfValueT iso = isoValue;
    SdfTreeT& tree = mSdfGrid->tree();
    collectLeaves();

    // The extension leaves, one per leaf of the distance field that holds an active voxel.
    std::vector<ExtLeafT*> extLeaves;
    if (op) {
        extLeaves.assign(mLeaves.size(), nullptr);
        for (size_t i = 0; i < mLeaves.size(); ++i) {
            if (mLeaves[i]->isEmpty())
                continue;
            ExtLeafT* leaf = mExtGrid->tree().probeLeaf(mLeaves[i]->origin());
            if (!leaf)
                leaf = mExtGrid->tree().touchLeaf(mLeaves[i]->origin());
            extLeaves[i] = leaf;
        }
    }
    using OpCopies = tbb::enumerable_thread_specific<ExtOpT>;
    std::optional<OpCopies> ops;
    if (op)
        ops.emplace(*op);
    const math::Transform& xform = input.transform();

    // Each active voxel with a face neighbour on the other side of the isovalue gets its
    // distance from the crossings along the axes: h / sqrt(sum_a 1 / t_a^2), t_a the nearer
    // crossing along axis a in voxels (linear interpolation); every other voxel +-max.
    util::parallelForRange(
        mLeaves.size(),
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const SdfTreeT> acc(input.tree());
            detail::NeighborhoodBlock<SdfTreeT> block(Coord(1), detail::BlockShape::Cross);
            const int sx = block.sx(), sy = block.sy();
            const int strides[3] = {sx, sy, 1};
            for (size_t i = begin; i < end; ++i) {
                LeafT& leaf = *mLeaves[i];
                block.gather(leaf.origin(), acc.probeConstLeaf(leaf.origin()), 0, acc);
                SdfValueT* out = leaf.buffer(0).data();
                ExtValueT* ext = op && extLeaves[i] ? extLeaves[i]->buffer(0).data() : nullptr;
                MaskT& sweep = mSweepMasks[i];
                sweep = leaf.getValueMask();
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                    const SdfValueT* c = block.atOffset(n);
                    const SdfValueT value = *c;
                    const SdfValueT far = value > iso ? above : -above;
                    if (!sweep.isOn(n)) {
                        out[n] = far;
                        continue;
                    }
                    const bool less = value < iso;
                    bool crossing = false;
                    for (int a = 0; a < 3 && !crossing; ++a) {
                        crossing =
                            (less != (c[-strides[a]] < iso)) || (less != (c[strides[a]] < iso));
                    }
                    if (!crossing) {
                        out[n] = far;
                        continue;
                    }
                    sweep.setOff(n);
                    const SdfValueT delta = value - iso;
                    const Coord ijk = leaf.offsetToGlobalCoord(n);
                    if (math::isApproxZero(delta)) {
                        out[n] = 0;
                        if (ext)
                            ext[n] = ExtValueT(ops->local()(xform.indexToWorld(ijk)));
                        continue;
                    }
                    SdfValueT sum = 0, minT = MAX;
                    ExtValueT extSum = detail::zeroExt<ExtValueT>();
                    for (int a = 0; a < 3; ++a) {
                        SdfValueT t = MAX;
                        int side = 0;
                        for (int s : {-1, 1}) {
                            const SdfValueT nv = c[s * strides[a]];
                            if (less == (nv < iso))
                                continue;
                            const SdfValueT ta = std::abs(delta / (value - nv));
                            if (ta < t) {
                                t = ta;
                                side = s;
                            }
                        }
                        if (!(t < MAX))
                            continue;
                        const SdfValueT w = SdfValueT(1) / (t * t);
                        sum += w;
                        if (ext) {
                            Vec3d p(ijk);
                            p[a] += double(t) * side;
                            const ExtValueT e = ExtValueT(ops->local()(xform.indexToWorld(p)));
                            if constexpr (std::is_integral_v<ExtValueT>) {
                                if (t < minT)
                                    extSum = e;
                            } else {
                                extSum = extSum + detail::scaleExt<ExtValueT>(w, e);
                            }
                            minT = std::min(minT, t);
                        }
                    }
                    out[n] = h / std::sqrt(sum) * (value > iso ? SdfValueT(1) : SdfValueT(-1));
                    if (ext) {
                        if constexpr (std::is_integral_v<ExtValueT>) {
                            ext[n] = extSum;
                        } else {
                            ext[n] = detail::scaleExt<ExtValueT>(SdfValueT(1) / sum, extSum);
                        }
                    }
                }
            }
        },
        true, 8);

    // Tiles (all inactive now) and the background stand for +-max.
    detail::forEachTile(
        tree, [&](SdfValueT& v, bool&) { v = v > iso ? above : -above; }, true);
    tree.setBackground(MAX);
    Index64 sweeping = 0;
    for (const MaskT& m : mSweepMasks)
        sweeping += m.countOn();
    mSweepingVoxelCount = size_t(sweeping);
    mBoundaryVoxelCount = size_t(tree.activeVoxelCount() - sweeping);
}

}  // namespace vdb::tools

namespace vdb::tools {

template <typename SdfGridT, typename ExtValueT>
bool FastSweeping<SdfGridT, ExtValueT>::initDilate(const SdfGridT& sdfGrid, int dilation,
                                                   NearestNeighbors nn, FastSweepingDomain mode) {
    if (dilation < 0)
        throw ValueError("dilateSdf: the dilation cannot be negative");
    clear();
    mSweepDirection = mode;
    mSdfGrid = sdfGrid.deepCopy();
    SdfTreeT& tree = mSdfGrid->tree();
    detail::TreeTileOps<SdfTreeT>::voxelizeActiveTiles(tree, true);
    changeLevelSetBackground(tree, std::numeric_limits<SdfValueT>::max());
    dilateActiveValues(tree, dilation, nn, IGNORE_TILES);
    initFromBand(sdfGrid, sdfGrid.background());
    return isValid();
}

template <typename SdfGridT, typename ExtValueT>
template <typename MaskTreeT>
bool FastSweeping<SdfGridT, ExtValueT>::initMask(const SdfGridT& sdfGrid,
                                                 const Grid<MaskTreeT>& mask,
                                                 bool ignoreActiveTiles) {
    using TopoTreeT = typename SdfTreeT::template ValueConverter<ValueMask>::Type;
    checkMatchingTransforms(sdfGrid, mask, "maskSdf");
    clear();
    mSdfGrid = sdfGrid.deepCopy();
    SdfTreeT& tree = mSdfGrid->tree();
    detail::TreeTileOps<SdfTreeT>::voxelizeActiveTiles(tree, true);
    changeLevelSetBackground(tree, std::numeric_limits<SdfValueT>::max());
    // The voxels to add: a level set's interior, else the mask's active voxels (and its
    // active tiles unless they are ignored), as a tree without active tiles.
    TopoTreeT topology;
    bool interior = false;
    if constexpr (std::is_floating_point_v<typename MaskTreeT::ValueType>) {
        if (mask.getGridClass() == GRID_LEVEL_SET) {
            topology.topologyUnion(sdfInteriorMask(mask)->tree());
            interior = true;
        }
    }
    if (!interior)
        topology.topologyUnion(mask.tree());
    if (ignoreActiveTiles && !interior) {
        detail::forEachTile(
            topology, [](bool&, bool& active) { active = false; }, true);
    }
    detail::TreeTileOps<TopoTreeT>::voxelizeActiveTiles(topology, true);
    tree.topologyUnion(topology);
    initFromBand(sdfGrid, std::numeric_limits<SdfValueT>::max());
    return isValid();
}

template <typename SdfGridT, typename ExtValueT>
void FastSweeping<SdfGridT, ExtValueT>::initFromBand(const SdfGridT& input,
                                                     SdfValueT boundaryBelow) {
    constexpr SdfValueT MAX = std::numeric_limits<SdfValueT>::max();
    const FastSweepingDomain mode = mSweepDirection;
    collectLeaves();
    // Active voxels with |value| below `boundaryBelow` keep their distance; the others are
    // solved for on the swept side, and take back their input value (or turn inactive) on the
    // other.
    util::parallelForRange(
        mLeaves.size(),
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const SdfTreeT> acc(input.tree());
            for (size_t i = begin; i < end; ++i) {
                LeafT& leaf = *mLeaves[i];
                SdfValueT* values = leaf.buffer(0).data();
                MaskT& sweep = mSweepMasks[i];
                sweep = leaf.getValueMask();
                for (Index n : leaf.getValueMask().onBits()) {
                    const SdfValueT v = values[n];
                    if (std::abs(v) < boundaryBelow) {
                        sweep.setOff(n);
                        continue;
                    }
                    const bool swept =
                        mode == FastSweepingDomain::SWEEP_ALL ||
                        (mode == FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE ? v > 0 : v < 0);
                    if (swept) {
                        values[n] = v > 0 ? MAX : -MAX;
                        continue;
                    }
                    sweep.setOff(n);
                    SdfValueT in;
                    if (acc.probeValue(leaf.offsetToGlobalCoord(n), in)) {
                        values[n] = in;
                    } else {
                        leaf.setValueOff(n);
                    }
                }
            }
        },
        true, 8);
    Index64 sweeping = 0;
    for (const MaskT& m : mSweepMasks)
        sweeping += m.countOn();
    mSweepingVoxelCount = size_t(sweeping);
    mBoundaryVoxelCount = size_t(mSdfGrid->tree().activeVoxelCount() - sweeping);
}

template <typename SdfGridT, typename ExtValueT>
void FastSweeping<SdfGridT, ExtValueT>::sweep(int nIter, bool finalize) {
    if (!mSdfGrid || mBoundaryVoxelCount == 0)
        throw ValueError(
            "FastSweeping::sweep: no boundary voxels (call an init method that succeeds first)");
    if (mExtGrid && mSweepDirection != FastSweepingDomain::SWEEP_ALL && !mExtGridInput)
        throw ValueError("FastSweeping::sweep: one-sided extension needs an input extension grid");
    using Leaf = detail::SweepLeaf<SdfValueT, ExtValueT, MaskT>;
    constexpr SdfValueT MAX = std::numeric_limits<SdfValueT>::max();
    if (mSweepingVoxelCount > 0 && nIter > 0) {
        // The leaves to solve in, with their neighbours' value arrays; "unknown" where there is
        // no leaf (every value outside the leaves is +-max after init).
        const std::vector<SdfValueT> unknown(LeafT::NUM_VALUES, MAX);
        const ExtValueT extBackground =
            mExtGrid ? mExtGrid->background() : detail::zeroExt<ExtValueT>();
        const std::vector<ExtValueT> extUnknown(LeafT::NUM_VALUES, extBackground);
        std::vector<size_t> active;
        for (size_t i = 0; i < mLeaves.size(); ++i) {
            if (!mSweepMasks[i].isOff())
                active.push_back(i);
        }
        std::vector<Leaf> leaves(active.size());
        const SdfTreeT& tree = mSdfGrid->tree();
        ExtTreeT* extTree = mExtGrid ? &mExtGrid->tree() : nullptr;
        constexpr Int32 DIM = Int32(LeafT::DIM);
        const Coord steps[6] = {Coord(-DIM, 0, 0), Coord(DIM, 0, 0),  Coord(0, -DIM, 0),
                                Coord(0, DIM, 0),  Coord(0, 0, -DIM), Coord(0, 0, DIM)};
        util::parallelFor(
            active.size(),
            [&](size_t j) {
                LeafT& leaf = *mLeaves[active[j]];
                Leaf& out = leaves[j];
                out.origin = leaf.origin();
                out.mask = mSweepMasks[active[j]];
                out.sdf = leaf.buffer(0).data();
                out.ext = nullptr;
                if (extTree) {
                    ExtLeafT* e = extTree->probeLeaf(out.origin);
                    out.ext = e ? e->buffer(0).data() : nullptr;
                }
                for (int d = 0; d < 6; ++d) {
                    const LeafT* nbr = tree.probeConstLeaf(out.origin + steps[d]);
                    out.sdfNbr[d] = nbr ? nbr->buffer(0).data() : unknown.data();
                    out.extNbr[d] = extUnknown.data();
                    if (extTree) {
                        const ExtLeafT* e = extTree->probeConstLeaf(out.origin + steps[d]);
                        if (e)
                            out.extNbr[d] = e->buffer(0).data();
                    }
                }
            },
            true, 64);
        const SdfValueT h = SdfValueT(mSdfGrid->voxelSize()[0]);
        if (mExtGrid) {
            detail::Sweeper<LeafT, ExtValueT, true> sweeper(leaves, h);
            sweeper.run(nIter, detail::ExtSideRule<ExtTreeT>(
                                   mExtGridInput ? &mExtGridInput->tree() : nullptr,
                                   mSweepDirection, mIsInputSdf));
        } else {
            struct NoExt {
                struct Local {};
                Local local() const { return {}; }
            };
            detail::Sweeper<LeafT, ExtValueT, false> sweeper(leaves, h);
            sweeper.run(nIter, NoExt{});
        }
    }
    if (finalize)
        finalizeValues();
}

template <typename SdfGridT, typename ExtValueT>
void FastSweeping<SdfGridT, ExtValueT>::finalizeValues() {
    constexpr SdfValueT MAX = std::numeric_limits<SdfValueT>::max();
    using Range = std::pair<SdfValueT, SdfValueT>;
    // The extrema of the distances found (values still at +-max left out).
    const Range e = util::parallelReduce(
        mLeaves.size(), Range(MAX, -MAX),
        [&](size_t b, size_t end) {
            Range r(MAX, -MAX);
            for (size_t i = b; i < end; ++i) {
                const SdfValueT* values = mLeaves[i]->buffer(0).data();
                for (Index n : mLeaves[i]->getValueMask().onBits()) {
                    const SdfValueT v = values[n];
                    if (v == MAX || v == -MAX)
                        continue;
                    r.first = std::min(r.first, v);
                    r.second = std::max(r.second, v);
                }
            }
            return r;
        },
        [](const Range& a, const Range& b) {
            return Range(std::min(a.first, b.first), std::max(a.second, b.second));
        });
    const SdfValueT h = SdfValueT(mSdfGrid->voxelSize()[0]);
    const SdfValueT outside = e.second >= SdfValueT(0) ? e.second : h;
    const SdfValueT inside = e.first < SdfValueT(0) ? e.first : -h;
    util::parallelFor(
        mLeaves.size(),
        [&](size_t i) {
            SdfValueT* values = mLeaves[i]->buffer(0).data();
            for (Index n : mLeaves[i]->getValueMask().onBits()) {
                if (values[n] == MAX)
                    values[n] = outside;
                else if (values[n] == -MAX)
                    values[n] = inside;
            }
        },
        true, 8);
    changeAsymmetricLevelSetBackground(mSdfGrid->tree(), outside, inside);
}

// ---- Free functions ----

namespace detail {

/// Sweeps `fs` after a successful init (at least one boundary voxel) and returns it.
template <typename FastSweepingT>
FastSweepingT& sweepIfBounded(FastSweepingT& fs, int nIter) {
    if (fs.boundaryVoxelCount() > 0)
        fs.sweep(nIter);
    return fs;
}

}  // namespace detail

template <typename GridT>
typename GridT::Ptr fogToSdf(const GridT& fogGrid, typename GridT::ValueType isoValue, int nIter) {
    FastSweeping<GridT> fs;
    fs.initSdf(fogGrid, isoValue, /*isInputSdf=*/false);
    auto sdf = detail::sweepIfBounded(fs, nIter).sdfGrid();
    sdf->setGridClass(GRID_LEVEL_SET);
    return sdf;
}

template <typename GridT>
typename GridT::Ptr sdfToSdf(const GridT& sdfGrid, typename GridT::ValueType isoValue, int nIter) {
    FastSweeping<GridT> fs;
    fs.initSdf(sdfGrid, isoValue, /*isInputSdf=*/true);
    return detail::sweepIfBounded(fs, nIter).sdfGrid();
}

template <typename FogGridT, typename ExtOpT, typename ExtValueT>
typename FogGridT::template ValueConverter<ExtValueT>::Type::Ptr fogToExt(
    const FogGridT& fogGrid, const ExtOpT& op, const ExtValueT& background,
    typename FogGridT::ValueType isoValue, int nIter, FastSweepingDomain mode,
    const typename FogGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid) {
    return fogToSdfAndExt(fogGrid, op, background, isoValue, nIter, mode, extGrid).second;
}

template <typename SdfGridT, typename ExtOpT, typename ExtValueT>
typename SdfGridT::template ValueConverter<ExtValueT>::Type::Ptr sdfToExt(
    const SdfGridT& sdfGrid, const ExtOpT& op, const ExtValueT& background,
    typename SdfGridT::ValueType isoValue, int nIter, FastSweepingDomain mode,
    const typename SdfGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid) {
    return sdfToSdfAndExt(sdfGrid, op, background, isoValue, nIter, mode, extGrid).second;
}

template <typename FogGridT, typename ExtOpT, typename ExtValueT>
std::pair<typename FogGridT::Ptr, typename FogGridT::template ValueConverter<ExtValueT>::Type::Ptr>
fogToSdfAndExt(
    const FogGridT& fogGrid, const ExtOpT& op, const ExtValueT& background,
    typename FogGridT::ValueType isoValue, int nIter, FastSweepingDomain mode,
    const typename FogGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid) {
    FastSweeping<FogGridT, ExtValueT> fs;
    fs.initExt(fogGrid, op, background, isoValue, /*isInputSdf=*/false, mode, extGrid);
    detail::sweepIfBounded(fs, nIter);
    fs.sdfGrid()->setGridClass(GRID_LEVEL_SET);
    return {fs.sdfGrid(), fs.extGrid()};
}

template <typename SdfGridT, typename ExtOpT, typename ExtValueT>
std::pair<typename SdfGridT::Ptr, typename SdfGridT::template ValueConverter<ExtValueT>::Type::Ptr>
sdfToSdfAndExt(
    const SdfGridT& sdfGrid, const ExtOpT& op, const ExtValueT& background,
    typename SdfGridT::ValueType isoValue, int nIter, FastSweepingDomain mode,
    const typename SdfGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid) {
    FastSweeping<SdfGridT, ExtValueT> fs;
    fs.initExt(sdfGrid, op, background, isoValue, /*isInputSdf=*/true, mode, extGrid);
    detail::sweepIfBounded(fs, nIter);
    return {fs.sdfGrid(), fs.extGrid()};
}

template <typename GridT>
typename GridT::Ptr dilateSdf(const GridT& sdfGrid, int dilation, NearestNeighbors nn, int nIter,
                              FastSweepingDomain mode) {
    FastSweeping<GridT> fs;
    fs.initDilate(sdfGrid, dilation, nn, mode);
    return detail::sweepIfBounded(fs, nIter).sdfGrid();
}

template <typename GridT, typename MaskTreeT>
typename GridT::Ptr maskSdf(const GridT& sdfGrid, const Grid<MaskTreeT>& mask,
                            bool ignoreActiveTiles, int nIter) {
    FastSweeping<GridT> fs;
    fs.initMask(sdfGrid, mask, ignoreActiveTiles);
    return detail::sweepIfBounded(fs, nIter).sdfGrid();
}

}  // namespace vdb::tools
