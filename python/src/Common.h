// SPDX-License-Identifier: Apache-2.0
/// @file
/// Shared by the sources of the Python extension vdb._vdb: the conversions between Python
/// objects and the library's vectors, coordinates, values and metadata, the NumPy dtype of each
/// value type, and the declarations of the binding functions each source defines.

#pragma once

#include <vdb/Grid.h>
#include <vdb/Metadata.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

namespace py = pybind11;

namespace vdb::python {

/// Reads `obj` as a sequence of exactly three items (a tuple, a list, a NumPy array...);
/// false for anything else, strings included.
bool sequence3(py::handle obj, py::object (&items)[3]);

/// Raises the Python exception `type` (PyExc_OverflowError, ...) with `message`: for the
/// built-in types pybind11 has no C++ exception for.
[[noreturn]] void raisePython(PyObject* type, const std::string& message);

/// The Python integer `obj` (or an object with __index__), or nothing when it does not fit
/// in 64 bits. @throw the Python error of __index__.
std::optional<Int64> indexValue(py::handle obj);

/// The Python integer `obj` (or an object with __index__) as an Int32.
/// @throw OverflowError when it lies outside [-2^31, 2^31 - 1] (as pyopenvdb), TypeError when
/// not an integer.
Int32 toInt32(py::handle obj);

}  // namespace vdb::python

namespace pybind11::detail {

/// math::Vec3<T> from any sequence of three numbers, to a tuple.
template <typename T>
struct type_caster<vdb::math::Vec3<T>> {
    PYBIND11_TYPE_CASTER(vdb::math::Vec3<T>, const_name("tuple[") + make_caster<T>::name +
                                                 const_name(", ") + make_caster<T>::name +
                                                 const_name(", ") + make_caster<T>::name +
                                                 const_name("]"));
    bool load(handle src, bool convert) {
        py::object items[3];
        if (!vdb::python::sequence3(src, items))
            return false;
        for (int i = 0; i < 3; ++i) {
            make_caster<T> c;
            if (!c.load(items[i], convert))
                return false;
            value[i] = cast_op<T>(c);
        }
        return true;
    }
    static handle cast(const vdb::math::Vec3<T>& v, return_value_policy, handle) {
        return py::make_tuple(v[0], v[1], v[2]).release();
    }
};

/// Coord from any sequence of three integers (OverflowError beyond 32 bits), to a tuple.
template <>
struct type_caster<vdb::Coord> {
    PYBIND11_TYPE_CASTER(vdb::Coord, const_name("tuple[int, int, int]"));
    bool load(handle src, bool) {
        py::object items[3];
        if (!vdb::python::sequence3(src, items))
            return false;
        for (int i = 0; i < 3; ++i) {
            if (!PyIndex_Check(items[i].ptr()) || PyBool_Check(items[i].ptr()))
                return false;
            value[i] = vdb::python::toInt32(items[i]);
        }
        return true;
    }
    static handle cast(const vdb::Coord& c, return_value_policy, handle) {
        return py::make_tuple(c[0], c[1], c[2]).release();
    }
};

}  // namespace pybind11::detail

namespace vdb::python {

// ---- Value types

/// The NumPy element type and component count of a grid value type: float -> float32 x 1,
/// Vec3s -> float32 x 3, bool -> bool x 1, ...
template <typename ValueT>
struct ValueTraits {
    using Scalar = ValueT;
    static constexpr int N = 1;
    static Scalar* scalars(ValueT* v) { return v; }
};
template <typename T>
struct ValueTraits<math::Vec3<T>> {
    using Scalar = T;
    static constexpr int N = 3;
    static Scalar* scalars(math::Vec3<T>* v) { return reinterpret_cast<T*>(v); }
};
static_assert(sizeof(Vec3s) == 3 * sizeof(float) && sizeof(Vec3d) == 3 * sizeof(double) &&
              sizeof(Vec3i) == 3 * sizeof(Int32));

/// The NumPy dtype of grid values of type ValueT (of one component for vectors).
template <typename ValueT>
py::dtype scalarDtype() {
    return py::dtype::of<typename ValueTraits<ValueT>::Scalar>();
}

/// The corners of `bbox` as pyopenvdb returns them: for an empty box, ((2^31-1,)*3, (-2^31,)*3).
std::pair<Coord, Coord> bboxCorners(const CoordBBox& bbox);

/// A human-readable name of a Python object's type, for error messages.
std::string typeNameOf(py::handle obj);

/// Converts a Python value to ValueT with the rules of pybind11 (numbers to numbers, any
/// sequence of three numbers to a vector). @throw TypeError naming `what` and the object.
template <typename ValueT>
ValueT toValue(py::handle obj, const char* what) {
    if constexpr (std::is_same_v<ValueT, bool>) {
        // As pyopenvdb: bools, NumPy bools and integers (nonzero is true), not floats or
        // strings, which pybind11's caster would take by their truth value.
        const bool integral =
            PyIndex_Check(obj.ptr()) && !PyFloat_Check(obj.ptr()) && !PySequence_Check(obj.ptr());
        if (!PyBool_Check(obj.ptr()) && !integral &&
            !py::isinstance(obj, py::module_::import("numpy").attr("bool_")))
            throw py::type_error(std::string(what) + ": expected a value of type bool, got " +
                                 typeNameOf(obj));
        return PyObject_IsTrue(obj.ptr()) == 1;
    }
    py::detail::make_caster<ValueT> caster;
    if (!caster.load(obj, true))
        throw py::type_error(std::string(what) + ": expected a value of type " +
                             std::string(typeName<ValueT>()) + ", got " + typeNameOf(obj));
    return py::detail::cast_op<ValueT>(caster);
}

// ---- Metadata

py::object metaToPython(const MetaValue& value);
/// As pyopenvdb: bool -> bool, int -> int32 or int64 by range, float -> double, str and
/// bytes -> string, 2-, 3- or 4-sequences of ints (bools count as ints) -> vec2i, vec3i,
/// vec4i, of other numbers -> vec2d, vec3d, vec4d, four rows of four numbers -> mat4d,
/// vdb.Metadata -> its opaque value, None -> nothing (nothing is stored).
/// @throw TypeError for other objects, OverflowError for an int beyond 64 bits or a vector
/// component beyond 32 bits.
std::optional<MetaValue> metaFromPython(py::handle obj);
py::dict metaMapToDict(const MetaMap& map);
/// Replaces the entries of `map` named by the keys of `dict`.
void updateMetaMap(MetaMap& map, py::handle dict);

// ---- Tool arguments

/// A 4 x 4 matrix from any nested sequence or NumPy array of numbers (rows).
/// @throw TypeError for anything else.
math::Mat4d matrixFromPython(py::handle obj);

/// The active topology of the grid `obj` (any grid type) as a MaskGrid with a copy of its
/// transform; the grid itself when it is a MaskGrid. @throw TypeError naming `op` when `obj`
/// is not a grid.
std::shared_ptr<const MaskGrid> activeMask(py::handle obj, const char* op);

/// `grid`, or TypeError naming `op` when Python's None arrived as a null grid pointer.
template <typename PtrT>
const PtrT& requireGrid(const PtrT& grid, const char* op) {
    if (!grid)
        throw py::type_error(std::string(op) + ": expected a grid, got None");
    return grid;
}

// ---- Pickling

/// The bytes of a one-grid `.vdb` archive (io::Stream) of `grid`, with statistics metadata left
/// out and `half` (the half flag to restore) as archive metadata.
py::bytes archiveBytes(const GridBase::Ptr& grid, bool half);
/// The grid of bytes that archiveBytes made, its half flag restored.
/// @throw ValueError for other objects, OSError (IoError) for damaged bytes.
GridBase::Ptr gridFromArchive(py::handle state);
/// A grid's __reduce__: (vdb._restore_grid, (bytes,)), values at full precision.
py::tuple reduceGrid(const GridBase::Ptr& grid);

// ---- Binding functions, one per source file

void bindConvert(py::module_& m);
void bindGridBase(py::module_& m);
void bindFloatGrids(py::module_& m);
void bindIntGrids(py::module_& m);
void bindBoolGrids(py::module_& m);
void bindVecGrids(py::module_& m);
void bindIo(py::module_& m);
void bindTools(py::module_& m, py::module_& tools);
void bindToolsFilter(py::module_& tools);
void bindToolsLevelSet(py::module_& tools);
void bindToolsSample(py::module_& tools);
void bindToolsClip(py::module_& tools);

}  // namespace vdb::python
