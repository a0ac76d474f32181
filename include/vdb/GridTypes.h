// SPDX-License-Identifier: Apache-2.0
/// @file
/// The one list of the standard grid types (GridTypes) and its subsets, with OpenVDB's names,
/// and dispatchGrid(): a GridBase handed to a generic function as the grid type it is.
///
/// @code
/// vdb::GridBase::Ptr base = file.readGrid("density");
/// vdb::dispatchGrid(*base, [](auto& grid) { grid.pruneGrid(); });  // any standard grid
/// double bg = vdb::dispatchGrid<vdb::RealGridTypes>(*base, [](const auto& grid) {
///     return double(grid.background());
/// });  // TypeError unless a FloatGrid or DoubleGrid
/// if (vdb::gridIsOneOf<vdb::Vec3GridTypes>(*base)) { ... }
/// @endcode
///
/// Cost: including this adds no instantiation beyond Grid.h; a dispatch instantiates its
/// function once per type of its list and tests the types in order (one dynamic_cast each).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/TypeList.h>
#include <vdb/TypeName.h>
#include <vdb/tree/TreeConfigs.h>

#include <optional>
#include <string>
#include <type_traits>

namespace vdb {

namespace detail {
template <typename First, typename... Ts>
struct DropFirstType {
    using Type = TypeList<Ts...>;
};
#define VDB_STANDARD_GRID_TYPE(ValueT, Name) , Name##Grid
using StandardGridTypes =
    DropFirstType<void VDB_FOR_EACH_STANDARD_TREE(VDB_STANDARD_GRID_TYPE)>::Type;
#undef VDB_STANDARD_GRID_TYPE
}  // namespace detail

/// The standard grid types, those of the standard trees (VDB_FOR_EACH_STANDARD_TREE in
/// tree/TreeConfigs.h, in its order): FloatGrid, DoubleGrid, Int32Grid, Int64Grid, BoolGrid,
/// MaskGrid, Vec3SGrid, Vec3DGrid and Vec3IGrid. Files always hold them (io/Archive.h), and
/// dispatchGrid() tries them unless given a subset.
using GridTypes = detail::StandardGridTypes;
/// Floating-point scalars.
using RealGridTypes = TypeList<FloatGrid, DoubleGrid>;
/// Integer scalars.
using IntegerGridTypes = TypeList<Int32Grid, Int64Grid>;
/// Floating-point and integer scalars (not bool or mask).
using NumericGridTypes = RealGridTypes::Append<IntegerGridTypes>;
/// Three-component vectors.
using Vec3GridTypes = TypeList<Vec3IGrid, Vec3SGrid, Vec3DGrid>;
/// Floating-point scalars and vectors: FloatGrid, DoubleGrid, Vec3SGrid and Vec3DGrid (the
/// grids the value filters, resampling and field extension take).
using FloatingPointGridTypes = RealGridTypes::Append<Vec3SGrid, Vec3DGrid>;

/// Calls `f(typedGrid)` with `grid` as a `GridT&` (a `const GridT&` for a const grid), GridT
/// the first type of the TypeList `GridListT` that `grid` is; returns whether there was one
/// (OpenVDB's GridBase::apply).
template <typename GridListT, typename GridBaseT, typename F>
requires std::is_base_of_v<GridBase, std::remove_const_t<GridBaseT>>
bool tryDispatchGrid(GridBaseT& grid, F&& f);

/// Calls `f(typedGrid)` as tryDispatchGrid() does, with every standard grid type unless
/// `GridListT` names a subset, and returns what `f` returns (void, or one value type for every
/// GridT).
/// @throw TypeError naming the grid, its type and the value types of `GridListT` when `grid` is
///        none of them.
template <typename GridListT = GridTypes, typename GridBaseT, typename F>
requires std::is_base_of_v<GridBase, std::remove_const_t<GridBaseT>>
auto dispatchGrid(GridBaseT& grid, F&& f);

/// Whether `grid` is one of the types of the TypeList `GridListT`.
template <typename GridListT>
bool gridIsOneOf(const GridBase& grid) {
    return tryDispatchGrid<GridListT>(grid, [](const auto&) {});
}

/// The value type names of the grids of `GridListT`, comma-separated ("float, double").
template <typename GridListT>
std::string gridTypeNames() {
    std::string names;
    GridListT::forEach([&]<typename GridT>() {
        if (!names.empty())
            names += ", ";
        names += typeName<typename GridT::BuildType>();
    });
    return names;
}

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {
/// Throws the TypeError of dispatchGrid().
[[noreturn]] inline void throwGridTypeError(const GridBase& grid, const std::string& expected) {
    throw TypeError("grid \"" + grid.getName() + "\" has type " + grid.type() +
                    ", which is not one of the grid types " + expected);
}
template <typename ListT>
struct FirstType;
template <typename T, typename... Ts>
struct FirstType<TypeList<T, Ts...>> {
    using Type = T;
};
}  // namespace detail

template <typename GridListT, typename GridBaseT, typename F>
requires std::is_base_of_v<GridBase, std::remove_const_t<GridBaseT>>
bool tryDispatchGrid(GridBaseT& grid, F&& f) {
    return GridListT::any([&]<typename GridT>() {
        using TypedT = std::conditional_t<std::is_const_v<GridBaseT>, const GridT, GridT>;
        auto* typed = dynamic_cast<TypedT*>(&grid);
        if (typed)
            f(*typed);
        return typed != nullptr;
    });
}

template <typename GridListT, typename GridBaseT, typename F>
requires std::is_base_of_v<GridBase, std::remove_const_t<GridBaseT>>
auto dispatchGrid(GridBaseT& grid, F&& f) {
    using FirstGridT = typename detail::FirstType<GridListT>::Type;
    using TypedT = std::conditional_t<std::is_const_v<GridBaseT>, const FirstGridT, FirstGridT>;
    using ResultT = std::invoke_result_t<F&, TypedT&>;
    if constexpr (std::is_void_v<ResultT>) {
        if (!tryDispatchGrid<GridListT>(grid, f))
            detail::throwGridTypeError(grid, gridTypeNames<GridListT>());
    } else {
        std::optional<ResultT> result;
        if (!tryDispatchGrid<GridListT>(grid, [&](auto& typed) { result.emplace(f(typed)); }))
            detail::throwGridTypeError(grid, gridTypeNames<GridListT>());
        return std::move(*result);
    }
}

}  // namespace vdb
