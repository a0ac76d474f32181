// SPDX-License-Identifier: Apache-2.0
/// @file
/// Grid: a tree, a transform from index space to world space, and metadata (name, class and
/// any user data). GridBase is the type-erased handle files and tools pass around.
///
/// @code
/// vdb::FloatGrid::Ptr grid = vdb::FloatGrid::create(/*background=*/3.0f);
/// grid->setName("density");
/// grid->setTransform(vdb::math::Transform::createLinearTransform(0.1));
/// auto acc = grid->getAccessor();
/// acc.setValue(vdb::Coord(0, 0, 0), 1.0f);
/// vdb::GridBase::Ptr base = grid;                       // type-erased
/// auto back = vdb::gridPtrCast<vdb::FloatGrid>(base);  // null if not a FloatGrid
/// @endcode

#pragma once

#include <vdb/Metadata.h>
#include <vdb/TypeName.h>
#include <vdb/Types.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace vdb {

/// The file strings of the grid classes: "level set", "fog volume", "staggered", "unknown".
inline std::string_view gridClassToString(GridClass c) {
    switch (c) {
        case GRID_LEVEL_SET:
            return "level set";
        case GRID_FOG_VOLUME:
            return "fog volume";
        case GRID_STAGGERED:
            return "staggered";
        default:
            return "unknown";
    }
}
inline GridClass stringToGridClass(std::string_view s) {
    if (s == "level set")
        return GRID_LEVEL_SET;
    if (s == "fog volume")
        return GRID_FOG_VOLUME;
    if (s == "staggered")
        return GRID_STAGGERED;
    return GRID_UNKNOWN;
}

/// The file strings of the vector types: "invariant", "covariant", "covariant normalize",
/// "contravariant relative", "contravariant absolute".
inline std::string_view vecTypeToString(VecType t) {
    switch (t) {
        case VEC_COVARIANT:
            return "covariant";
        case VEC_COVARIANT_NORMALIZE:
            return "covariant normalize";
        case VEC_CONTRAVARIANT_RELATIVE:
            return "contravariant relative";
        case VEC_CONTRAVARIANT_ABSOLUTE:
            return "contravariant absolute";
        default:
            return "invariant";
    }
}
/// The vector type named `s`; VEC_INVARIANT for any other string.
inline VecType stringToVecType(std::string_view s) {
    for (int t = 0; t < NUM_VEC_TYPES; ++t) {
        if (vecTypeToString(VecType(t)) == s)
            return VecType(t);
    }
    return VEC_INVARIANT;
}

/// A grid whose tree type is known only at run time: transform, metadata, and the tree
/// operations that need no value type. The name, the class, the vector type and the half-float
/// flag live in the metadata under the keys the `.vdb` format uses ("name", "class",
/// "vector_type", "is_saved_as_half_float").
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
class GridBase : public MetaMap {
public:
    using Ptr = std::shared_ptr<GridBase>;
    using ConstPtr = std::shared_ptr<const GridBase>;

    static constexpr std::string_view META_GRID_NAME = "name";
    static constexpr std::string_view META_GRID_CLASS = "class";
    static constexpr std::string_view META_SAVE_HALF_FLOAT = "is_saved_as_half_float";
    static constexpr std::string_view META_VECTOR_TYPE = "vector_type";

    virtual ~GridBase() = default;

    std::string getName() const {
        const auto* s = getMeta<std::string>(META_GRID_NAME);
        return s ? *s : std::string();
    }
    void setName(std::string_view name) { insertMeta(META_GRID_NAME, std::string(name)); }

    GridClass getGridClass() const {
        const auto* s = getMeta<std::string>(META_GRID_CLASS);
        return s ? stringToGridClass(*s) : GRID_UNKNOWN;
    }
    void setGridClass(GridClass c) {
        insertMeta(META_GRID_CLASS, std::string(gridClassToString(c)));
    }
    void clearGridClass() { removeMeta(META_GRID_CLASS); }

    /// How the values transform (meaningful for vector grids); VEC_INVARIANT when unset.
    VecType getVectorType() const {
        const auto* s = getMeta<std::string>(META_VECTOR_TYPE);
        return s ? stringToVecType(*s) : VEC_INVARIANT;
    }
    void setVectorType(VecType t) { insertMeta(META_VECTOR_TYPE, std::string(vecTypeToString(t))); }
    void clearVectorType() { removeMeta(META_VECTOR_TYPE); }

    /// Whether files store this grid's floating-point values as 16-bit halves.
    bool saveFloatAsHalf() const {
        const bool* b = getMeta<bool>(META_SAVE_HALF_FLOAT);
        return b && *b;
    }
    void setSaveFloatAsHalf(bool half) { insertMeta(META_SAVE_HALF_FLOAT, half); }

    math::Transform& transform() { return *mTransform; }
    const math::Transform& transform() const { return *mTransform; }
    math::Transform::Ptr transformPtr() const { return mTransform; }
    /// Replaces the transform; a null pointer throws ValueError.
    void setTransform(math::Transform::Ptr xform) {
        if (!xform)
            throw ValueError("a grid's transform cannot be null");
        mTransform = std::move(xform);
    }
    /// World-space size of a voxel at the index origin.
    Vec3d voxelSize() const { return mTransform->voxelSize(); }
    Vec3d indexToWorld(const Vec3d& ijk) const { return mTransform->indexToWorld(ijk); }
    Vec3d worldToIndex(const Vec3d& xyz) const { return mTransform->worldToIndex(xyz); }

    /// The tree type string, e.g. "Tree_float_5_4_3".
    virtual std::string type() const = 0;
    /// The value type string, e.g. "float".
    virtual std::string valueType() const = 0;
    virtual bool empty() const = 0;
    virtual void clear() = 0;
    virtual Index64 activeVoxelCount() const = 0;
    virtual Index32 leafCount() const = 0;
    /// Bytes used by the tree, transform and metadata.
    virtual Index64 memUsage() const = 0;
    /// The bounding box of the active voxels and tiles (empty when there are none).
    virtual CoordBBox evalActiveVoxelBoundingBox() const = 0;
    /// A new grid with a copy of the tree, the transform and the metadata.
    virtual Ptr deepCopyGrid() const = 0;
    /// A new grid of the same type and background, sharing the transform, with no values.
    virtual Ptr copyGridWithNewTree() const = 0;
    /// A new grid of the same type that shares this grid's tree (an instance), with copies of
    /// the transform and the metadata (OpenVDB's GridBase::copyGrid).
    virtual Ptr copyGrid() const = 0;

protected:
    GridBase() : mTransform(math::Transform::createLinearTransform(1.0)) {}
    GridBase(const GridBase& other)
        : MetaMap(other), mTransform(std::make_shared<math::Transform>(*other.mTransform)) {}
    GridBase& operator=(const GridBase&) = delete;

private:
    math::Transform::Ptr mTransform;
};

/// Throws ValueError unless grids `a` and `b` share one index space: transforms that agree to
/// a relative 1e-6 (math::Transform::isApproxEqual), so that a voxel size rounded through
/// float on one side (0.012500000186 for 0.0125) still matches. `operation` names the caller
/// in the message, which shows both transforms.
inline void checkMatchingTransforms(const GridBase& a, const GridBase& b,
                                    std::string_view operation) {
    if (a.transform().isApproxEqual(b.transform()))
        return;
    std::ostringstream msg;
    msg << operation << ": grids \"" << a.getName() << "\" and \"" << b.getName()
        << "\" are not in one index space (transforms " << a.transform() << " and " << b.transform()
        << " differ by more than a relative 1e-6)";
    throw ValueError(msg.str());
}

using GridPtrVec = std::vector<GridBase::Ptr>;
using GridCPtrVec = std::vector<GridBase::ConstPtr>;
using GridPtrVecPtr = std::shared_ptr<GridPtrVec>;

/// A grid of tree type `TreeT`: the tree (shared, so grids can instance one tree), the
/// transform and the metadata.
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <typename TreeT>
class Grid : public GridBase {
public:
    using Ptr = std::shared_ptr<Grid>;
    using ConstPtr = std::shared_ptr<const Grid>;
    using TreeType = TreeT;
    using TreePtr = std::shared_ptr<TreeT>;
    using ValueType = typename TreeT::ValueType;
    using BuildType = typename TreeT::BuildType;
    using Accessor = tree::ValueAccessor<TreeT>;
    using ConstAccessor = tree::ValueAccessor<const TreeT>;
    using ValueOnIter = typename TreeT::ValueOnIter;
    using ValueOnCIter = typename TreeT::ValueOnCIter;
    using ValueOffIter = typename TreeT::ValueOffIter;
    using ValueOffCIter = typename TreeT::ValueOffCIter;
    using ValueAllIter = typename TreeT::ValueAllIter;
    using ValueAllCIter = typename TreeT::ValueAllCIter;
    /// The grid of the same tree configuration with values of type `OtherValueT`:
    /// `FloatGrid::ValueConverter<Vec3s>::Type` is Vec3SGrid.
    template <typename OtherValueT>
    struct ValueConverter {
        using Type = Grid<typename TreeT::template ValueConverter<OtherValueT>::Type>;
    };

    /// A grid with an empty tree of background `background` and a unit transform.
    static Ptr create(const ValueType& background) {
        return Ptr(new Grid(std::make_shared<TreeT>(background)));
    }
    static Ptr create() { return create(ValueType{}); }
    /// A grid around an existing tree (shared, not copied); a null tree throws ValueError.
    static Ptr create(TreePtr tree) {
        if (!tree)
            throw ValueError("a grid's tree cannot be null");
        return Ptr(new Grid(std::move(tree)));
    }

    static std::string gridType() { return treeTypeName<TreeT>(); }
    std::string type() const override { return gridType(); }
    std::string valueType() const override { return std::string(typeName<BuildType>()); }

    TreeT& tree() { return *mTree; }
    const TreeT& tree() const { return *mTree; }
    const TreeT& constTree() const { return *mTree; }
    TreePtr treePtr() const { return mTree; }
    /// Replaces the tree (shared, not copied); a null tree throws ValueError.
    void setTree(TreePtr tree) {
        if (!tree)
            throw ValueError("a grid's tree cannot be null");
        mTree = std::move(tree);
    }
    const ValueType& background() const { return mTree->background(); }

    Accessor getAccessor() { return Accessor(*mTree); }
    ConstAccessor getConstAccessor() const { return ConstAccessor(*mTree); }
    ConstAccessor getAccessor() const { return ConstAccessor(*mTree); }

    ValueOnIter beginValueOn() { return mTree->beginValueOn(); }
    ValueOnCIter beginValueOn() const { return mTree->cbeginValueOn(); }
    ValueOnCIter cbeginValueOn() const { return mTree->cbeginValueOn(); }
    ValueOffIter beginValueOff() { return mTree->beginValueOff(); }
    ValueOffCIter beginValueOff() const { return mTree->cbeginValueOff(); }
    ValueOffCIter cbeginValueOff() const { return mTree->cbeginValueOff(); }
    ValueAllIter beginValueAll() { return mTree->beginValueAll(); }
    ValueAllCIter beginValueAll() const { return mTree->cbeginValueAll(); }
    ValueAllCIter cbeginValueAll() const { return mTree->cbeginValueAll(); }

    bool empty() const override { return mTree->empty(); }
    void clear() override { mTree->clear(); }
    Index64 activeVoxelCount() const override { return mTree->activeVoxelCount(); }
    Index32 leafCount() const override { return mTree->leafCount(); }
    Index64 memUsage() const override {
        Index64 bytes = sizeof(Grid) + sizeof(math::Transform) + mTree->memUsage();
        for (const auto& [name, value] : metadata()) {
            bytes += sizeof(typename Map::value_type) + name.capacity();
            if (const auto* s = std::get_if<std::string>(&value))
                bytes += s->capacity();
            if (const auto* o = std::get_if<OpaqueMetadata>(&value))
                bytes += o->bytes.capacity();
        }
        return bytes;
    }
    CoordBBox evalActiveVoxelBoundingBox() const override {
        CoordBBox bbox;
        mTree->evalActiveVoxelBoundingBox(bbox);
        return bbox;
    }
    void pruneGrid(const ValueType& tolerance = ValueType{}) { mTree->prune(tolerance); }

    /// A new grid with a deep copy of the tree, the transform and the metadata.
    Ptr deepCopy() const { return Ptr(new Grid(*this, std::make_shared<TreeT>(*mTree))); }
    GridBase::Ptr deepCopyGrid() const override { return deepCopy(); }
    /// A new grid sharing this grid's tree (an instance), with copies of transform and metadata.
    Ptr copy() const { return Ptr(new Grid(*this, mTree)); }
    GridBase::Ptr copyGrid() const override { return copy(); }
    GridBase::Ptr copyGridWithNewTree() const override {
        return Ptr(new Grid(*this, std::make_shared<TreeT>(background())));
    }

private:
    explicit Grid(TreePtr tree) : mTree(std::move(tree)) {}
    Grid(const Grid& other, TreePtr tree) : GridBase(other), mTree(std::move(tree)) {}

    TreePtr mTree;
};

/// Returns `grid` as a GridT, or null when it is of another type.
template <typename GridT>
std::shared_ptr<GridT> gridPtrCast(const GridBase::Ptr& grid) {
    return std::dynamic_pointer_cast<GridT>(grid);
}
template <typename GridT>
std::shared_ptr<const GridT> gridConstPtrCast(const GridBase::ConstPtr& grid) {
    return std::dynamic_pointer_cast<const GridT>(grid);
}

// ---- Standard trees and grids

using FloatGrid = Grid<FloatTree>;
using DoubleGrid = Grid<DoubleTree>;
using Int32Grid = Grid<Int32Tree>;
using Int64Grid = Grid<Int64Tree>;
using BoolGrid = Grid<BoolTree>;
using MaskGrid = Grid<MaskTree>;
using Vec3SGrid = Grid<Vec3STree>;
using Vec3DGrid = Grid<Vec3DTree>;
using Vec3IGrid = Grid<Vec3ITree>;
using Vec3fGrid = Vec3SGrid;

}  // namespace vdb

// ---- Instantiated once in src/instantiate/Trees.cpp

namespace vdb {

#define VDB_STANDARD_GRID_EXTERN(ValueT, Name) extern template class Grid<Name##Tree>;
VDB_FOR_EACH_STANDARD_TREE(VDB_STANDARD_GRID_EXTERN)
#undef VDB_STANDARD_GRID_EXTERN

}  // namespace vdb
