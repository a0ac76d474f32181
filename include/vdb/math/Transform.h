// SPDX-License-Identifier: Apache-2.0
/// @file
/// Transform: the map from a grid's index space to world space, as one of the eight map types
/// the .vdb format stores (FORMAT.md section 1.6), with a fast path for scale plus translation.
///
/// @code
/// auto xform = vdb::math::Transform::createLinearTransform(0.1);  // 0.1 world units per voxel
/// xform->postTranslate(vdb::Vec3d(1, 2, 3));
/// vdb::Vec3d xyz = xform->indexToWorld(vdb::Coord(10, 0, 0));     // (2, 2, 3)
/// vdb::Coord ijk = xform->worldToIndexCellCentered(xyz);          // (10, 0, 0)
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

namespace vdb {
namespace math {

/// The map types of the .vdb format. Their file names come from mapTypeName().
enum class MapType : uint8_t {
    UniformScale,           ///< world = index * s (one s for all axes)
    UniformScaleTranslate,  ///< world = index * s + t
    Scale,                  ///< world = index ⊙ s (componentwise)
    ScaleTranslate,         ///< world = index ⊙ s + t
    Translation,            ///< world = index + t
    Affine,                 ///< world = [index 1] * M
    Unitary,                ///< world = [index 1] * M, M a rotation as stored in the file
    NonlinearFrustum,       ///< a tapered box (a camera frustum) followed by an affine map
};

/// Returns the name the .vdb format uses for `type`, e.g. "UniformScaleTranslateMap".
constexpr std::string_view mapTypeName(MapType type);
/// Returns the map type named `name` in a .vdb file, or nothing for an unknown name.
constexpr std::optional<MapType> mapTypeFromName(std::string_view name);

/// The parameters of one map, field for field as the .vdb format stores them.
///
/// Only the fields of `type` matter; the others keep their defaults:
/// - UniformScale, Scale: `scale`;
/// - UniformScaleTranslate, ScaleTranslate: `translation`, then `scale`;
/// - Translation: `translation` (`scale` stays (1, 1, 1));
/// - Affine, Unitary: `matrix`, row-major, row-vector convention;
/// - NonlinearFrustum: `frustumBBox`, `frustumTaper`, `frustumDepth`, and in `matrix` the linear
///   second map. Files store that second map as a nested map (OpenVDB writes an AffineMap);
///   a reader turns the nested map's parameters into a matrix with
///   `Transform(nestedParams).affineMatrix()`.
struct MapParams {
    MapType type = MapType::UniformScale;
    Vec3d scale{1.0};
    Vec3d translation{0.0};
    Mat4d matrix = Mat4d::identity();
    BBoxd frustumBBox{Vec3d(0.0), Vec3d(1.0)};
    double frustumTaper = 1.0;  // near-plane width / far-plane width
    double frustumDepth = 1.0;  // near-to-far distance, in near-plane widths

    /// The five vectors a scale map's body holds after its translation: scale, |scale|,
    /// 1/scale, (1/scale)², (1/scale)/2. Readers may ignore all but the first; writers must
    /// write them consistently, because OpenVDB reads them back as they are.
    std::array<Vec3d, 5> scaleVectors() const;
};

/// The map from a grid's index space (voxel centers at integer coordinates) to world space.
///
/// A transform holds one map of MapType. Linear maps are kept as an affine matrix
/// (affineMatrix()) plus its inverse; the scale and translation maps also keep their scale and
/// translation, and indexToWorld() is then one multiply-add per component. Editing a linear
/// transform (preScale(), postTranslate(), …) re-derives the simplest type that represents the
/// new matrix exactly: a matrix whose 3x3 block is exactly diagonal becomes a
/// (Uniform)Scale(Translate) map, anything else an Affine map (OpenVDB makes the same choice,
/// with tolerances). Transforms built from MapParams keep the type they were given
/// (Translation and Unitary maps included), so files round-trip unchanged.
///
/// A NonlinearFrustum map takes the index-space box frustumBBox to a frustum whose near face
/// (z = min z) is one unit wide, whose far face is 1/taper units wide, and which is `depth`
/// units deep; the second, affine map then places it in the world. Editing a frustum transform
/// edits only that second map (so preScale() scales after the frustum, as in OpenVDB).
///
/// Invariant: the affine matrix is invertible and its last column is (0, 0, 0, 1).
/// Threads: concurrent const calls are safe; editing needs exclusive access.
class Transform {
public:
    using Ptr = std::shared_ptr<Transform>;
    using ConstPtr = std::shared_ptr<const Transform>;

    /// The identity: a UniformScaleMap of scale 1.
    Transform() = default;
    /// The transform whose map `params` describes, keeping params.type.
    /// @throw ValueError when the parameters are not a valid map of that type: a zero or
    /// non-finite scale, a singular or non-affine matrix, a UniformScale map with unequal
    /// components, a translation on a map type without one, or a frustum with an empty box or
    /// a non-positive taper or depth.
    explicit Transform(const MapParams& params);

    /// A UniformScaleMap: `voxelSize` world units per voxel along every axis.
    /// @throw ValueError when voxelSize is zero or not finite.
    static Ptr createLinearTransform(double voxelSize = 1.0);
    /// The linear map world = [index 1] * worldFromIndex, as its simplest map type.
    /// @throw ValueError when the matrix is singular or not affine.
    static Ptr createLinearTransform(const Mat4d& worldFromIndex);
    /// A NonlinearFrustumMap over the index box `bbox`, scaled by `voxelSize` after the frustum.
    /// @throw ValueError for an empty box, a non-positive taper or depth, or a zero voxelSize.
    static Ptr createFrustumTransform(const BBoxd& bbox, double taper, double depth,
                                      double voxelSize = 1.0);
    /// The transform whose map `params` describes; see Transform(const MapParams&).
    static Ptr createFromMap(const MapParams& params) {
        return std::make_shared<Transform>(params);
    }
    Ptr copy() const { return std::make_shared<Transform>(*this); }

    // ---- The map
    MapType mapType() const { return mType; }
    /// The map's name in a .vdb file, e.g. "UniformScaleMap".
    std::string_view mapTypeName() const { return math::mapTypeName(mType); }
    /// The map's parameters, ready to be written field by field.
    MapParams mapParams() const;
    bool isLinear() const { return mType != MapType::NonlinearFrustum; }
    /// True for a linear map whose matrix is exactly the identity, or for a frustum map that
    /// moves the origin and the three unit points by at most 1e-9.
    bool isIdentity() const;
    /// True when the map's linear part is a rotation times one scale (voxels are cubes); never
    /// for frustum maps. Relative tolerance 1e-8.
    bool hasUniformScale() const;
    /// The linear part as a row-vector affine matrix: the whole map for linear transforms, the
    /// second map (applied after the frustum) for frustum transforms.
    const Mat4d& affineMatrix() const { return mWorldFromIndex; }

    // ---- Points
    Vec3d indexToWorld(const Vec3d& ijk) const;
    Vec3d indexToWorld(const Coord& ijk) const { return indexToWorld(Vec3d(ijk)); }
    Vec3d worldToIndex(const Vec3d& xyz) const;
    /// Returns the voxel whose center is nearest to `xyz` (index coordinates rounded, halves
    /// up), saturated to the Int32 range.
    Coord worldToIndexCellCentered(const Vec3d& xyz) const {
        return roundToCoord(worldToIndex(xyz));
    }
    /// Returns the voxel whose cell [i, i+1) holds `xyz` (index coordinates floored), saturated
    /// to the Int32 range.
    Coord worldToIndexNodeCentered(const Vec3d& xyz) const {
        return floorToCoord(worldToIndex(xyz));
    }

    // ---- Directions (differences of points; linear maps only)
    /// Returns the world-space image of the index-space direction `v`.
    /// @throw ValueError for frustum transforms, whose Jacobian depends on the position.
    Vec3d indexToWorldDirection(const Vec3d& v) const;
    /// Returns the index-space image of the world-space direction `v`.
    /// @throw ValueError for frustum transforms.
    Vec3d worldToIndexDirection(const Vec3d& v) const;

    // ---- Boxes: the bounding box of the images of the eight corners
    BBoxd indexToWorld(const CoordBBox& indexBBox) const { return indexToWorld(BBoxd(indexBBox)); }
    /// Exact for every map type: the image of a box under a frustum map has planar faces.
    BBoxd indexToWorld(const BBoxd& indexBBox) const;
    /// Exact for linear maps; for frustum maps, the box of the corners' pre-images.
    BBoxd worldToIndex(const BBoxd& worldBBox) const;
    CoordBBox worldToIndexCellCentered(const BBoxd& worldBBox) const;
    CoordBBox worldToIndexNodeCentered(const BBoxd& worldBBox) const;

    // ---- Voxel size
    /// The world-space lengths of the images of the three index-space unit steps. For frustum
    /// maps, measured at the center of the near face of the frustum box.
    Vec3d voxelSize() const { return mVoxelSize; }
    /// The same, measured at the index-space position `ijk` (the same everywhere for linear
    /// maps).
    Vec3d voxelSize(const Vec3d& ijk) const;
    /// The world-space volume of one voxel: |det| of the Jacobian (at the center of the near
    /// face of the frustum box for frustum maps).
    double voxelVolume() const;
    /// The same, at the index-space position `ijk`.
    double voxelVolume(const Vec3d& ijk) const;

    // ---- Editing; "pre" acts in index space before the map, "post" in world space after it.
    // Each edit throws ValueError, leaving the transform unchanged, when the result would be
    // singular.
    void preTranslate(const Vec3d& t) { preMult(Mat4d::translation(t)); }
    void postTranslate(const Vec3d& t) { postMult(Mat4d::translation(t)); }
    void preScale(double s) { preScale(Vec3d(s)); }
    void preScale(const Vec3d& s) { preMult(Mat4d::scale(s)); }
    void postScale(double s) { postScale(Vec3d(s)); }
    void postScale(const Vec3d& s) { postMult(Mat4d::scale(s)); }
    void preRotate(double radians, Axis axis = Axis::X) { preMult(Mat4d::rotation(axis, radians)); }
    void postRotate(double radians, Axis axis = Axis::X) {
        postMult(Mat4d::rotation(axis, radians));
    }
    /// Composes `m` before the map's linear part: world = [index 1] * m * M.
    void preMult(const Mat4d& m);
    /// Composes `m` after the map: world = [index 1] * M * m.
    void postMult(const Mat4d& m);

    /// Exact comparison of what the maps compute: linear maps are equal when their matrices
    /// are (whatever their types), frustum maps when all their parameters are. To decide
    /// whether two grids line up, use isApproxEqual(): voxel sizes that went through float
    /// on one side (0.0125 and 0.012500000186) are the same grid spacing.
    bool operator==(const Transform& other) const;
    /// True when the two maps agree to a relative `relTol`: each entry of the linear part
    /// within relTol times the largest entry of either linear part (about the voxel size),
    /// each translation within relTol times the larger of that and the translation's own
    /// magnitude, and for frustum maps each frustum parameter (index-space box, taper, depth)
    /// within relTol times the largest of 1 and the two values. Map types do not matter, only what
    /// the maps compute.
    bool isApproxEqual(const Transform& other, double relTol = 1e-6) const;

private:
    // The frustum part of a NonlinearFrustumMap and the constants derived from it.
    struct Frustum {
        BBoxd bbox{Vec3d(0.0), Vec3d(1.0)};
        double taper = 1, depth = 1;
        double lx = 1, ly = 1, lz = 1;  // the box's extents
        double gamma = 0;               // (1/taper - 1) / depth: width growth per unit depth
        double depthOnLz = 1;           // depth / lz
    };

    // Each builder validates and computes into a new Transform, so a failed edit leaves the
    // transform it was called on unchanged.
    static Transform makeLinear(const Mat4d& worldFromIndex);
    static Transform makeScaleTranslate(MapType type, const Vec3d& scale, const Vec3d& translation);
    static Transform makeAffine(MapType type, const Mat4d& worldFromIndex);
    static Transform makeFrustum(const BBoxd& bbox, double taper, double depth,
                                 const Mat4d& second);
    static Mat4d checkedInverse(const Mat4d& m);

    Vec3d frustumFromIndex(const Vec3d& ijk) const;
    Vec3d indexFromFrustum(const Vec3d& uvw) const;
    Vec3d nearFaceCenter() const;

    MapType mType = MapType::UniformScale;
    bool mScaleTranslate = true;  // true <=> world = index * mScale + mTranslation exactly
    Vec3d mScale{1.0}, mInvScale{1.0}, mTranslation{0.0};  // valid when mScaleTranslate
    Mat4d mWorldFromIndex = Mat4d::identity();  // the linear part (frustum: the second map)
    Mat4d mIndexFromWorld = Mat4d::identity();  // its inverse
    Vec3d mVoxelSize{1.0};
    Frustum mFrustum;  // valid when mType == NonlinearFrustum
};

/// Prints the map type and its parameters on one line.
std::ostream& operator<<(std::ostream& os, const Transform& xform);

// ---- Implementation ---------------------------------------------------------------------------

constexpr std::string_view mapTypeName(MapType type) {
    switch (type) {
        case MapType::UniformScale:
            return "UniformScaleMap";
        case MapType::UniformScaleTranslate:
            return "UniformScaleTranslateMap";
        case MapType::Scale:
            return "ScaleMap";
        case MapType::ScaleTranslate:
            return "ScaleTranslateMap";
        case MapType::Translation:
            return "TranslationMap";
        case MapType::Affine:
            return "AffineMap";
        case MapType::Unitary:
            return "UnitaryMap";
        case MapType::NonlinearFrustum:
            return "NonlinearFrustumMap";
    }
    return "";
}

constexpr std::optional<MapType> mapTypeFromName(std::string_view name) {
    for (auto type : {MapType::UniformScale, MapType::UniformScaleTranslate, MapType::Scale,
                      MapType::ScaleTranslate, MapType::Translation, MapType::Affine,
                      MapType::Unitary, MapType::NonlinearFrustum}) {
        if (mapTypeName(type) == name)
            return type;
    }
    return std::nullopt;
}

inline std::array<Vec3d, 5> MapParams::scaleVectors() const {
    const Vec3d inv = Vec3d(1.0) / scale;
    return {scale, Abs(scale), inv, inv * inv, inv / 2.0};
}

namespace detail {

inline bool isFinite(const Vec3d& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

inline bool isFinite(const Mat4d& m) {
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(m.data()[i]))
            return false;
    }
    return true;
}

/// The eight corners of `b`.
inline std::array<Vec3d, 8> corners(const BBoxd& b) {
    const Vec3d &lo = b.min(), &hi = b.max();
    return {lo,
            Vec3d(hi[0], lo[1], lo[2]),
            Vec3d(lo[0], hi[1], lo[2]),
            Vec3d(hi[0], hi[1], lo[2]),
            Vec3d(lo[0], lo[1], hi[2]),
            Vec3d(hi[0], lo[1], hi[2]),
            Vec3d(lo[0], hi[1], hi[2]),
            hi};
}

[[noreturn]] inline void frustumUnsupported(const char* what) {
    throw ValueError(std::string("frustum transforms are not supported for ") + what);
}

}  // namespace detail

inline Transform::Transform(const MapParams& p) {
    const bool uniform = p.scale[0] == p.scale[1] && p.scale[0] == p.scale[2];
    const bool translated = p.translation != Vec3d(0.0);
    switch (p.type) {
        case MapType::UniformScale:
        case MapType::UniformScaleTranslate:
            if (!uniform) {
                throw ValueError("Transform: a " + std::string(math::mapTypeName(p.type)) +
                                 " needs three equal scale components");
            }
            [[fallthrough]];
        case MapType::Scale:
        case MapType::ScaleTranslate:
            if (translated && (p.type == MapType::UniformScale || p.type == MapType::Scale)) {
                throw ValueError("Transform: a " + std::string(math::mapTypeName(p.type)) +
                                 " has no translation");
            }
            *this = makeScaleTranslate(p.type, p.scale, p.translation);
            return;
        case MapType::Translation:
            if (p.scale != Vec3d(1.0)) {
                throw ValueError("Transform: a TranslationMap has no scale");
            }
            *this = makeScaleTranslate(p.type, p.scale, p.translation);
            return;
        case MapType::Affine:
        case MapType::Unitary:
            *this = makeAffine(p.type, p.matrix);
            return;
        case MapType::NonlinearFrustum:
            *this = makeFrustum(p.frustumBBox, p.frustumTaper, p.frustumDepth, p.matrix);
            return;
    }
    throw ValueError("Transform: unknown map type");
}

inline Transform::Ptr Transform::createLinearTransform(double voxelSize) {
    return std::make_shared<Transform>(
        makeScaleTranslate(MapType::UniformScale, Vec3d(voxelSize), Vec3d(0.0)));
}

inline Transform::Ptr Transform::createLinearTransform(const Mat4d& worldFromIndex) {
    return std::make_shared<Transform>(makeLinear(worldFromIndex));
}

inline Transform::Ptr Transform::createFrustumTransform(const BBoxd& bbox, double taper,
                                                        double depth, double voxelSize) {
    return std::make_shared<Transform>(
        makeFrustum(bbox, taper, depth, Mat4d::scale(Vec3d(voxelSize))));
}

inline Mat4d Transform::checkedInverse(const Mat4d& m) {
    if (!m.isAffine()) {
        throw ValueError("Transform: the matrix is not affine (its last column must be 0 0 0 1)");
    }
    if (!detail::isFinite(m))
        throw ValueError("Transform: the matrix is not finite");
    try {
        return m.inverse();
    } catch (const ValueError&) {
        throw ValueError("Transform: the matrix is singular");
    }
}

inline Transform Transform::makeLinear(const Mat4d& m) {
    const bool diagonal = m(0, 1) == 0 && m(0, 2) == 0 && m(1, 0) == 0 && m(1, 2) == 0 &&
                          m(2, 0) == 0 && m(2, 1) == 0;
    if (!diagonal || !m.isAffine())
        return makeAffine(MapType::Affine, m);

    const Vec3d scale(m(0, 0), m(1, 1), m(2, 2));
    const Vec3d translation = m.getTranslation();
    const bool uniform = scale[0] == scale[1] && scale[0] == scale[2];
    const bool translated = translation != Vec3d(0.0);
    const MapType type = uniform
                             ? (translated ? MapType::UniformScaleTranslate : MapType::UniformScale)
                             : (translated ? MapType::ScaleTranslate : MapType::Scale);
    return makeScaleTranslate(type, scale, translation);
}

inline Transform Transform::makeScaleTranslate(MapType type, const Vec3d& scale,
                                               const Vec3d& translation) {
    if (!detail::isFinite(scale) || scale[0] == 0 || scale[1] == 0 || scale[2] == 0) {
        throw ValueError("Transform: scale components must be finite and non-zero");
    }
    if (!detail::isFinite(translation)) {
        throw ValueError("Transform: the translation is not finite");
    }
    Transform x;
    x.mType = type;
    x.mScaleTranslate = true;
    x.mScale = scale;
    x.mInvScale = Vec3d(1.0) / scale;
    x.mTranslation = translation;
    x.mWorldFromIndex = Mat4d::scale(scale);
    x.mWorldFromIndex.setTranslation(translation);
    x.mIndexFromWorld = Mat4d::scale(x.mInvScale);
    x.mIndexFromWorld.setTranslation(-translation * x.mInvScale);
    x.mVoxelSize = Abs(scale);
    return x;
}

inline Transform Transform::makeAffine(MapType type, const Mat4d& m) {
    Transform x;
    x.mType = type;
    x.mScaleTranslate = false;
    x.mIndexFromWorld = checkedInverse(m);
    x.mWorldFromIndex = m;
    // Row i of the matrix is the image of index-space axis i.
    x.mVoxelSize =
        Vec3d(Vec3d(m(0, 0), m(0, 1), m(0, 2)).length(), Vec3d(m(1, 0), m(1, 1), m(1, 2)).length(),
              Vec3d(m(2, 0), m(2, 1), m(2, 2)).length());
    return x;
}

inline Transform Transform::makeFrustum(const BBoxd& bbox, double taper, double depth,
                                        const Mat4d& second) {
    const Vec3d extents = bbox.max() - bbox.min();
    if (!detail::isFinite(bbox.min()) || !detail::isFinite(bbox.max()) || !(extents[0] > 0) ||
        !(extents[1] > 0) || !(extents[2] > 0)) {
        throw ValueError("Transform: a frustum box needs finite corners and positive extents");
    }
    if (!(taper > 0) || !(depth > 0) || !std::isfinite(taper) || !std::isfinite(depth)) {
        throw ValueError("Transform: a frustum needs a positive, finite taper and depth");
    }
    Transform x = makeAffine(MapType::NonlinearFrustum, second);
    Frustum& f = x.mFrustum;
    f.bbox = bbox;
    f.taper = taper;
    f.depth = depth;
    f.lx = extents[0];
    f.ly = extents[1];
    f.lz = extents[2];
    f.gamma = (1.0 / taper - 1.0) / depth;
    f.depthOnLz = depth / f.lz;
    x.mVoxelSize = x.voxelSize(x.nearFaceCenter());
    return x;
}

inline Vec3d Transform::frustumFromIndex(const Vec3d& ijk) const {
    const Frustum& f = mFrustum;
    // Center the near face on the z axis, scale z to [0, depth], then taper x and y: the near
    // face becomes one unit wide, a face at depth z is (1 + gamma z) units wide.
    const Vec3d p = ijk - f.bbox.min();
    const double z = p[2] * f.depthOnLz;
    const double s = (f.gamma * z + 1.0) / f.lx;
    return Vec3d((p[0] - 0.5 * f.lx) * s, (p[1] - 0.5 * f.ly) * s, z);
}

inline Vec3d Transform::indexFromFrustum(const Vec3d& uvw) const {
    const Frustum& f = mFrustum;
    const double invS = f.lx / (f.gamma * uvw[2] + 1.0);
    return Vec3d(uvw[0] * invS + 0.5 * f.lx, uvw[1] * invS + 0.5 * f.ly, uvw[2] / f.depthOnLz) +
           f.bbox.min();
}

inline Vec3d Transform::nearFaceCenter() const {
    const BBoxd& b = mFrustum.bbox;
    return Vec3d(0.5 * (b.min()[0] + b.max()[0]), 0.5 * (b.min()[1] + b.max()[1]), b.min()[2]);
}

inline Vec3d Transform::indexToWorld(const Vec3d& ijk) const {
    if (mScaleTranslate)
        return ijk * mScale + mTranslation;
    if (mType != MapType::NonlinearFrustum)
        return mWorldFromIndex.transformPoint(ijk);
    return mWorldFromIndex.transformPoint(frustumFromIndex(ijk));
}

inline Vec3d Transform::worldToIndex(const Vec3d& xyz) const {
    if (mScaleTranslate)
        return (xyz - mTranslation) * mInvScale;
    const Vec3d ijk = mIndexFromWorld.transformPoint(xyz);
    return mType != MapType::NonlinearFrustum ? ijk : indexFromFrustum(ijk);
}

inline Vec3d Transform::indexToWorldDirection(const Vec3d& v) const {
    if (mScaleTranslate)
        return v * mScale;
    if (!isLinear())
        detail::frustumUnsupported("indexToWorldDirection");
    return mWorldFromIndex.transformDirection(v);
}

inline Vec3d Transform::worldToIndexDirection(const Vec3d& v) const {
    if (mScaleTranslate)
        return v * mInvScale;
    if (!isLinear())
        detail::frustumUnsupported("worldToIndexDirection");
    return mIndexFromWorld.transformDirection(v);
}

inline BBoxd Transform::indexToWorld(const BBoxd& indexBBox) const {
    BBoxd result;
    if (indexBBox.empty())
        return result;
    for (const Vec3d& corner : detail::corners(indexBBox))
        result.expand(indexToWorld(corner));
    return result;
}

inline BBoxd Transform::worldToIndex(const BBoxd& worldBBox) const {
    BBoxd result;
    if (worldBBox.empty())
        return result;
    for (const Vec3d& corner : detail::corners(worldBBox))
        result.expand(worldToIndex(corner));
    return result;
}

inline CoordBBox Transform::worldToIndexCellCentered(const BBoxd& worldBBox) const {
    const BBoxd b = worldToIndex(worldBBox);
    if (b.empty())
        return CoordBBox();
    return CoordBBox(roundToCoord(b.min()), roundToCoord(b.max()));
}

inline CoordBBox Transform::worldToIndexNodeCentered(const BBoxd& worldBBox) const {
    const BBoxd b = worldToIndex(worldBBox);
    if (b.empty())
        return CoordBBox();
    return CoordBBox(floorToCoord(b.min()), floorToCoord(b.max()));
}

inline Vec3d Transform::voxelSize(const Vec3d& ijk) const {
    if (isLinear())
        return mVoxelSize;
    const Vec3d p = indexToWorld(ijk);
    return Vec3d((indexToWorld(ijk + Vec3d(1, 0, 0)) - p).length(),
                 (indexToWorld(ijk + Vec3d(0, 1, 0)) - p).length(),
                 (indexToWorld(ijk + Vec3d(0, 0, 1)) - p).length());
}

inline double Transform::voxelVolume() const {
    return isLinear() ? std::abs(mWorldFromIndex.determinant3()) : voxelVolume(nearFaceCenter());
}

inline double Transform::voxelVolume(const Vec3d& ijk) const {
    const double linear = std::abs(mWorldFromIndex.determinant3());
    if (isLinear())
        return linear;
    // The frustum's Jacobian is triangular with diagonal (s, s, depth / lz), where s is the
    // x-y scale at the depth of ijk.
    const Frustum& f = mFrustum;
    const double z = (ijk[2] - f.bbox.min()[2]) * f.depthOnLz;
    const double s = (f.gamma * z + 1.0) / f.lx;
    return linear * s * s * f.depthOnLz;
}

inline MapParams Transform::mapParams() const {
    MapParams p;
    p.type = mType;
    switch (mType) {
        case MapType::UniformScale:
        case MapType::Scale:
            p.scale = mScale;
            break;
        case MapType::UniformScaleTranslate:
        case MapType::ScaleTranslate:
            p.scale = mScale;
            p.translation = mTranslation;
            break;
        case MapType::Translation:
            p.translation = mTranslation;
            break;
        case MapType::Affine:
        case MapType::Unitary:
            p.matrix = mWorldFromIndex;
            break;
        case MapType::NonlinearFrustum:
            p.matrix = mWorldFromIndex;
            p.frustumBBox = mFrustum.bbox;
            p.frustumTaper = mFrustum.taper;
            p.frustumDepth = mFrustum.depth;
            break;
    }
    return p;
}

inline bool Transform::isIdentity() const {
    if (isLinear())
        return mWorldFromIndex.isIdentity();
    if (mFrustum.taper != 1.0)
        return false;
    for (const Vec3d& p : {Vec3d(0.0), Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1)}) {
        if (!math::isApproxEqual(indexToWorld(p), p, 1e-9))
            return false;
    }
    return true;
}

inline bool Transform::hasUniformScale() const {
    if (!isLinear())
        return false;
    // The linear part is a rotation times one scale when its rows (the images of the axes)
    // are mutually orthogonal and of equal length.
    const Mat4d& m = mWorldFromIndex;
    const Vec3d r0(m(0, 0), m(0, 1), m(0, 2)), r1(m(1, 0), m(1, 1), m(1, 2)),
        r2(m(2, 0), m(2, 1), m(2, 2));
    const double lenSqr = (r0.lengthSqr() + r1.lengthSqr() + r2.lengthSqr()) / 3.0;
    const double tol = 1e-8 * lenSqr;
    return math::isApproxEqual(r0.lengthSqr(), lenSqr, tol) &&
           math::isApproxEqual(r1.lengthSqr(), lenSqr, tol) &&
           math::isApproxEqual(r2.lengthSqr(), lenSqr, tol) &&
           math::isApproxZero(r0.dot(r1), tol) && math::isApproxZero(r1.dot(r2), tol) &&
           math::isApproxZero(r2.dot(r0), tol);
}

inline void Transform::preMult(const Mat4d& m) {
    const Mat4d linear = m * mWorldFromIndex;
    if (isLinear()) {
        *this = makeLinear(linear);
    } else {
        *this = makeFrustum(mFrustum.bbox, mFrustum.taper, mFrustum.depth, linear);
    }
}

inline void Transform::postMult(const Mat4d& m) {
    const Mat4d linear = mWorldFromIndex * m;
    if (isLinear()) {
        *this = makeLinear(linear);
    } else {
        *this = makeFrustum(mFrustum.bbox, mFrustum.taper, mFrustum.depth, linear);
    }
}

inline bool Transform::operator==(const Transform& other) const {
    if (isLinear() != other.isLinear())
        return false;
    if (mWorldFromIndex != other.mWorldFromIndex)
        return false;
    if (isLinear())
        return true;
    return mFrustum.bbox == other.mFrustum.bbox && mFrustum.taper == other.mFrustum.taper &&
           mFrustum.depth == other.mFrustum.depth;
}

inline bool Transform::isApproxEqual(const Transform& other, double relTol) const {
    if (isLinear() != other.isLinear() || !(relTol >= 0.0))
        return false;
    const Mat4d& a = mWorldFromIndex;
    const Mat4d& b = other.mWorldFromIndex;
    double scale = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            scale = std::max({scale, std::abs(a(i, j)), std::abs(b(i, j))});
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            // Rows 0-2 are the linear part, row 3 the translation; column 3 is (0 0 0 1).
            const double tol =
                relTol * (i < 3 ? scale : std::max({scale, std::abs(a(i, j)), std::abs(b(i, j))}));
            if (!math::isApproxEqual(a(i, j), b(i, j), tol))
                return false;
        }
    }
    if (isLinear())
        return true;
    const auto near = [relTol](double x, double y) {
        return math::isApproxEqual(x, y, relTol * std::max({1.0, std::abs(x), std::abs(y)}));
    };
    for (int i = 0; i < 3; ++i) {
        if (!near(mFrustum.bbox.min()[i], other.mFrustum.bbox.min()[i]) ||
            !near(mFrustum.bbox.max()[i], other.mFrustum.bbox.max()[i]))
            return false;
    }
    return near(mFrustum.taper, other.mFrustum.taper) && near(mFrustum.depth, other.mFrustum.depth);
}

inline std::ostream& operator<<(std::ostream& os, const Transform& xform) {
    const MapParams p = xform.mapParams();
    os << xform.mapTypeName() << ':';
    switch (p.type) {
        case MapType::UniformScale:
        case MapType::Scale:
            return os << " scale " << p.scale;
        case MapType::UniformScaleTranslate:
        case MapType::ScaleTranslate:
            return os << " scale " << p.scale << " translation " << p.translation;
        case MapType::Translation:
            return os << " translation " << p.translation;
        case MapType::Affine:
        case MapType::Unitary:
            return os << ' ' << p.matrix;
        case MapType::NonlinearFrustum:
            return os << " box " << p.frustumBBox << " taper " << p.frustumTaper << " depth "
                      << p.frustumDepth << " then " << p.matrix;
    }
    return os;
}

}  // namespace math

using math::Transform;

}  // namespace vdb
