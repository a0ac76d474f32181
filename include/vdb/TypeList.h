// SPDX-License-Identifier: Apache-2.0
/// @file
/// TypeList: a compile-time list of types, with OpenVDB's name, for the lists of grid types
/// that code dispatches over (vdb::GridTypes and its subsets in Grid.h).
///
/// @code
/// using Scalars = vdb::TypeList<float, double>::Append<vdb::Int32, vdb::Int64>;
/// static_assert(Scalars::Size == 4 && Scalars::Contains<double>);
/// using Floats = Scalars::Filter<std::is_floating_point>;  // TypeList<float, double>
/// Scalars::forEach([]<typename T>() { std::cout << sizeof(T) << '\n'; });
/// @endcode

#pragma once

#include <cstddef>
#include <type_traits>

namespace vdb {

template <typename... Ts>
struct TypeList;

namespace detail {

template <typename ListT, typename... Ts>
struct TypeListAppend;
template <typename... Ts, typename... Us>
struct TypeListAppend<TypeList<Ts...>, Us...> {
    using Type = TypeList<Ts..., Us...>;
};
template <typename... Ts, typename... Us>
struct TypeListAppend<TypeList<Ts...>, TypeList<Us...>> {
    using Type = TypeList<Ts..., Us...>;
};

template <template <typename> class PredT, typename... Ts>
struct TypeListFilter {
    using Type = TypeList<>;
};
template <template <typename> class PredT, typename T, typename... Ts>
struct TypeListFilter<PredT, T, Ts...> {
    using Rest = typename TypeListFilter<PredT, Ts...>::Type;
    using Type =
        std::conditional_t<PredT<T>::value, typename TypeListAppend<TypeList<T>, Rest>::Type, Rest>;
};

template <typename... Removed>
struct TypeListNotIn {
    template <typename T>
    struct Pred : std::bool_constant<!(std::is_same_v<T, Removed> || ...)> {};
};

}  // namespace detail

/// The types `Ts...`, in order.
template <typename... Ts>
struct TypeList {
    static constexpr size_t Size = sizeof...(Ts);
    /// Whether `T` is one of the types.
    template <typename T>
    static constexpr bool Contains = (std::is_same_v<T, Ts> || ...);
    /// This list followed by the types `Us...`, or by the types of one TypeList `Us`.
    template <typename... Us>
    using Append = typename detail::TypeListAppend<TypeList, Us...>::Type;
    /// The types `T` for which `PredT<T>::value` is true, in order.
    template <template <typename> class PredT>
    using Filter = typename detail::TypeListFilter<PredT, Ts...>::Type;
    /// This list without the types `Us...`.
    template <typename... Us>
    using Remove = Filter<detail::TypeListNotIn<Us...>::template Pred>;

    /// Calls `f.template operator()<T>()` for each type T in order (a lambda
    /// `[]<typename T>() {...}`).
    template <typename F>
    static void forEach(F&& f) {
        (f.template operator()<Ts>(), ...);
    }
    /// Calls `f.template operator()<T>()` for each type T in order until one returns true;
    /// returns whether one did.
    template <typename F>
    static bool any(F&& f) {
        return (f.template operator()<Ts>() || ...);
    }
};

}  // namespace vdb
