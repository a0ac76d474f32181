// SPDX-License-Identifier: Apache-2.0
/// @file
/// Resampling a grid under a linear map of index space: GridTransformer applies a matrix (or a
/// pivot, scale, rotation and translation) to a grid's voxels, and resampleToMatch() resamples
/// one grid into the index space of another, with OpenVDB's names and meanings.
///
/// Every output voxel is reconstructed by the sampler (tools/Interpolation.h) at the point of
/// the input it maps back to, and it is active exactly when the sampler read an active input
/// voxel. The voxels considered are those OpenVDB's resampler visits (the mapped box of each
/// input leaf and tile, grown by the sampler's radius), so both libraries give the same active
/// voxels; when upsampling by more than 2, a layer of voxels whose stencil reaches an isolated
/// leaf only from below is not visited, in both. Downscaling by more than half along an axis with a
/// mipmapping sampler (box, quadratic) goes through successive halvings first, as in OpenVDB, so no
/// input voxel is skipped. Equal transforms, or transforms that differ by a whole-voxel
/// translation, copy the values exactly (no interpolation).
///
/// Level sets. transformGrid() samples a level set's band like any grid (with the input's
/// background) and flood-fills the signs beyond it, as OpenVDB's GridTransformer does; under a
/// scale the values are then no longer distances in the output's units. resampleToMatch()
/// instead rebuilds it in the output's index space, as OpenVDB's does, for any linear output
/// transform: the surface is meshed, mapped through the output's transform and scan-converted
/// with the output's first voxel size (tools/LevelSetRebuild.h), into a clean band with the
/// output's background. When the output's scale is not uniform (unequal scales or a shear), the
/// result holds index-space distances times voxelSize()[0], not world distances: the zero
/// crossing is the surface and the band is as many index units wide along every axis.
///
/// Cost: one sample per voxel of each output leaf the input reaches, in parallel over output
/// leaves (oneTBB); each leaf reads its footprint of the input once into a dense block. The
/// result does not depend on the thread count. Before anything is allocated, the number of
/// output voxels is bounded and checked against a limit (2^34 by default).
///
/// @code
/// // Half the resolution of a fog volume, trilinearly.
/// auto coarse = vdb::FloatGrid::create();
/// coarse->setTransform(vdb::math::Transform::createLinearTransform(2.0 * fog->voxelSize()[0]));
/// vdb::tools::resampleToMatch<vdb::tools::BoxSampler>(*fog, *coarse);
///
/// // Rotate a grid by 30 degrees about z around the index point (10, 0, 0).
/// vdb::tools::GridTransformer xform(vdb::Vec3R(10, 0, 0), vdb::Vec3R(1),
///                                   vdb::Vec3R(0, 0, 0.5236), vdb::Vec3R(0));
/// auto rotated = vdb::FloatGrid::create();
/// xform.transformGrid<vdb::tools::QuadraticSampler>(*grid, *rotated);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Interpolation.h>
#include <vdb/tools/LevelSetRebuild.h>

#include <cmath>
#include <memory>
#include <string>
#include <type_traits>

namespace vdb::tools {

/// The default bound on the voxels one resampling pass may produce: 2^34.
inline constexpr Index64 DEFAULT_MAX_RESAMPLE_VOXELS = Index64(1) << 34;

/// A linear map of index space applied to grids: the voxel at index point p of the input
/// goes to p * getTransform() (row vectors, OpenVDB's convention) in the output.
///
/// Threads: transformGrid() runs in parallel over output leaves (setThreaded(false) for one
/// thread); one transformer may be used from several threads at once.
class GridTransformer {
public:
    using Ptr = std::shared_ptr<GridTransformer>;

    /// Maps input index space to output index space by `xform`.
    /// @throw ValueError when `xform` is not affine (last column other than (0, 0, 0, 1)),
    ///        not finite, or singular.
    explicit GridTransformer(const Mat4R& xform);
    /// Maps by a scale, a rotation (Euler angles in radians about x, y, z, composed in
    /// `rotOrder`) and a translation, the scale and rotation about `pivot`, composed in
    /// `xformOrder` ("tsr": translate, then scale, then rotate, as OpenVDB composes them).
    /// @throw ValueError when an order string is not a permutation of "tsr" or "xyz", or the
    ///        map is singular or not finite.
    GridTransformer(const Vec3R& pivot, const Vec3R& scale, const Vec3R& rotate,
                    const Vec3R& translate, const std::string& xformOrder = "tsr",
                    const std::string& rotOrder = "zyx");

    /// The map from input to output index space.
    const Mat4R& getTransform() const { return mTransform; }
    /// The number of halvings applied along x, y and z before the rest of the map.
    const Vec3i& getMipLevels() const { return mMipLevels; }

    void setThreaded(bool threaded) { mThreaded = threaded; }
    bool threaded() const { return mThreaded; }
    /// Bounds the voxels of each resampling pass: transformGrid() throws before allocating
    /// when the output leaves the input reaches hold more voxels than `count`.
    void setMaxVoxelCount(Index64 count) { mMaxVoxels = count; }
    Index64 maxVoxelCount() const { return mMaxVoxels; }

    /// Replaces the tree of `out` by `in` resampled under getTransform() with `SamplerT`; the
    /// result has the background of `in`, and `out` keeps its transform and metadata. A level
    /// set (by `in`'s grid class) is resampled over its band and flood-filled.
    /// @throw ValueError when the output would hold more than maxVoxelCount() voxels or leave
    ///        the index range.
    template <typename SamplerT, typename GridT>
    void transformGrid(const GridT& in, GridT& out) const;

private:
    void initMipmap(const Vec3R& pivot, const Vec3R& scale, const std::string& xformOrder,
                    const Vec3R& rotate, const std::string& rotOrder, const Vec3R& translate);

    Mat4R mTransform = Mat4R::identity();
    Mat4R mPreScale = Mat4R::identity();   // applied before the halvings
    Mat4R mPostScale = Mat4R::identity();  // applied after them
    Vec3R mPivot{0.0};
    Vec3i mMipLevels{0};
    bool mThreaded = true;
    Index64 mMaxVoxels = DEFAULT_MAX_RESAMPLE_VOXELS;
};

/// Resamples `in` into the index space of `out` (out's transform is kept; its tree is
/// replaced). Equal transforms, or transforms differing by a whole-voxel translation, copy the
/// values exactly. A float or double level set (by `in`'s grid class) is otherwise rebuilt in
/// out's index space (see the file comment), whatever out's scale: its band is
/// out.background() / out.voxelSize()[0] voxels wide on each side when `out` is a level set
/// (and the result keeps out's background), else in.background() / in.voxelSize()[0] (the
/// background is then that width times out.voxelSize()[0]); 3 voxels when that width is below
/// 1 or not finite. With unequal scales its values are index-space distances times
/// out.voxelSize()[0], as OpenVDB's. Other grids are resampled by `SamplerT` (GridTransformer).
/// @throw ValueError when a transform is not linear (a frustum), or the output would hold more
///        than `maxVoxelCount` voxels.
template <typename SamplerT, typename GridT>
void resampleToMatch(const GridT& in, GridT& out,
                     Index64 maxVoxelCount = DEFAULT_MAX_RESAMPLE_VOXELS);

}  // namespace vdb::tools

#include <vdb/tools/detail/GridTransformerImpl.h>

// ---- Implementation ---------------------------------------------------------------------------

namespace vdb::tools {

template <typename SamplerT, typename GridT>
void GridTransformer::transformGrid(const GridT& in, GridT& out) const {
    using TreeT = typename GridT::TreeType;
    using Resampler = detail::TreeResampler<SamplerT, TreeT>;
    const auto mode = in.getGridClass() == GRID_LEVEL_SET ? detail::ResampleMode::LevelSet
                                                          : detail::ResampleMode::Sample;
    const auto pass = [&](const TreeT& tree, const Mat4R& outFromIn) {
        return Resampler::run(tree, outFromIn, mode, mThreaded, mMaxVoxels);
    };
    if (!SamplerT::mipmap() || mMipLevels == Vec3i(0)) {
        out.setTree(pass(in.tree(), mTransform));
        return;
    }
    std::shared_ptr<TreeT> tree;
    const TreeT* current = &in.tree();
    if (!(mPreScale == Mat4R::identity())) {
        tree = pass(*current, mPreScale);
        current = tree.get();
    }
    // Halve the resolution about the pivot along the axes with halvings left.
    for (Vec3i count = mMipLevels; count != Vec3i(0);) {
        Mat4R half = Mat4R::translation(-mPivot);
        half.postScale(
            Vec3R(count[0] > 0 ? 0.5 : 1.0, count[1] > 0 ? 0.5 : 1.0, count[2] > 0 ? 0.5 : 1.0));
        half.postTranslate(mPivot);
        tree = pass(*current, half);
        current = tree.get();
        for (int i = 0; i < 3; ++i)
            count[i] = count[i] > 0 ? count[i] - 1 : 0;
    }
    if (!(mPostScale == Mat4R::identity()))
        tree = pass(*current, mPostScale);
    out.setTree(tree);
}

template <typename SamplerT, typename GridT>
void resampleToMatch(const GridT& in, GridT& out, Index64 maxVoxelCount) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    const math::Transform& inXform = in.transform();
    const math::Transform& outXform = out.transform();
    if (!inXform.isLinear() || !outXform.isLinear()) {
        throw ValueError(
            "resampleToMatch: frustum transforms are not supported; both grids need linear "
            "transforms");
    }
    const Mat4R outFromIn = inXform.affineMatrix() * outXform.affineMatrix().inverse();

    // Equal transforms, or a whole-voxel translation: copy the values.
    if (const auto offset = detail::wholeVoxelTranslation(outFromIn)) {
        if (*offset == Coord(0)) {
            out.setTree(std::make_shared<TreeT>(in.tree()));
        } else {
            out.setTree(detail::TreeResampler<PointSampler, TreeT>::run(
                in.tree(), Mat4R::translation(Vec3R(*offset)), detail::ResampleMode::Copy, true,
                maxVoxelCount));
        }
        return;
    }
    if constexpr (std::is_floating_point_v<ValueT>) {
        if (in.getGridClass() == GRID_LEVEL_SET) {
            detail::checkResampleSize(in.tree(), outFromIn, maxVoxelCount);
            const bool outIsLevelSet = out.getGridClass() == GRID_LEVEL_SET;
            const double width = outIsLevelSet ? double(out.background()) / outXform.voxelSize()[0]
                                               : double(in.background()) / inXform.voxelSize()[0];
            const bool validWidth = std::isfinite(width) && width >= 1.0;
            const float halfWidth = validWidth ? float(width) : 3.0f;  // OpenVDB's default
            auto rebuilt = levelSetRebuild(in, 0.0f, halfWidth, halfWidth, &outXform);
            // The width went through a division and back: an output level set keeps its own
            // background exactly, not one rounded away from it.
            if (outIsLevelSet && validWidth && rebuilt->background() != out.background())
                changeLevelSetBackground(rebuilt->tree(), out.background());
            out.setTree(rebuilt->treePtr());
            return;
        }
    }
    GridTransformer transformer(outFromIn);
    transformer.setMaxVoxelCount(maxVoxelCount);
    transformer.template transformGrid<SamplerT>(in, out);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/GridTransformer.cpp

namespace vdb::tools::detail {
extern template class TreeResampler<PointSampler, FloatTree>;
extern template class TreeResampler<BoxSampler, FloatTree>;
extern template class TreeResampler<QuadraticSampler, FloatTree>;
extern template class TreeResampler<PointSampler, DoubleTree>;
extern template class TreeResampler<BoxSampler, DoubleTree>;
extern template class TreeResampler<QuadraticSampler, DoubleTree>;
extern template class TreeResampler<PointSampler, Vec3STree>;
extern template class TreeResampler<BoxSampler, Vec3STree>;
extern template class TreeResampler<QuadraticSampler, Vec3STree>;
}  // namespace vdb::tools::detail
