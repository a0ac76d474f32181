// SPDX-License-Identifier: Apache-2.0
// Conversions between Python objects and the library's values and metadata; the Transform,
// GridClass and Metadata classes of the module.

#include <vdb/math/Mat4.h>
#include <vdb/math/Math.h>

#include "Common.h"

#include <cctype>
#include <sstream>
#include <variant>

namespace vdb::python {

bool sequence3(py::handle obj, py::object (&items)[3]) {
    if (!obj || PyUnicode_Check(obj.ptr()) || PyBytes_Check(obj.ptr()) ||
        !PySequence_Check(obj.ptr()))
        return false;
    const Py_ssize_t n = PySequence_Size(obj.ptr());
    if (n != 3) {
        PyErr_Clear();
        return false;
    }
    for (Py_ssize_t i = 0; i < 3; ++i) {
        PyObject* item = PySequence_GetItem(obj.ptr(), i);
        if (!item) {
            PyErr_Clear();
            return false;
        }
        items[i] = py::reinterpret_steal<py::object>(item);
    }
    return true;
}

Int32 toInt32(py::handle obj) {
    if (!PyIndex_Check(obj.ptr()))
        throw py::type_error("expected an integer coordinate, got " + typeNameOf(obj));
    py::int_ value = py::reinterpret_steal<py::int_>(PyNumber_Index(obj.ptr()));
    if (!value)
        throw py::error_already_set();
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow != 0 || v < std::numeric_limits<Int32>::min() ||
        v > std::numeric_limits<Int32>::max())
        throw py::index_error("coordinate " + std::string(py::str(value)) +
                              " is outside the 32-bit index space");
    return Int32(v);
}

std::string typeNameOf(py::handle obj) {
    return obj ? std::string(py::str(py::type::handle_of(obj).attr("__name__"))) : "nothing";
}

// ---- Metadata

py::object metaToPython(const MetaValue& value) {
    return std::visit(
        [](const auto& v) -> py::object {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, OpaqueMetadata>) {
                return py::cast(v);
            } else if constexpr (std::is_same_v<T, float>) {
                return py::float_(double(v));
            } else if constexpr (std::is_same_v<T, Vec3s>) {
                return py::make_tuple(double(v[0]), double(v[1]), double(v[2]));
            } else {
                return py::cast(v);
            }
        },
        value);
}

MetaValue metaFromPython(py::handle obj) {
    if (PyBool_Check(obj.ptr()))
        return obj.cast<bool>();
    if (py::isinstance<py::str>(obj))
        return obj.cast<std::string>();
    if (py::isinstance<OpaqueMetadata>(obj))
        return obj.cast<OpaqueMetadata>();
    if (PyLong_Check(obj.ptr()) ||
        (PyIndex_Check(obj.ptr()) && !PyFloat_Check(obj.ptr()) && !PySequence_Check(obj.ptr()))) {
        py::int_ value = py::reinterpret_steal<py::int_>(PyNumber_Index(obj.ptr()));
        if (!value)
            throw py::error_already_set();
        int overflow = 0;
        const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
        if (overflow != 0)
            throw py::value_error("metadata integer " + std::string(py::str(value)) +
                                  " does not fit in 64 bits");
        if (v >= std::numeric_limits<Int32>::min() && v <= std::numeric_limits<Int32>::max())
            return Int32(v);
        return Int64(v);
    }
    if (PyFloat_Check(obj.ptr()) ||
        py::isinstance(obj, py::module_::import("numpy").attr("floating")))
        return obj.cast<double>();
    py::object items[3];
    if (sequence3(obj, items)) {
        bool allInt = true;
        for (const auto& item : items) {
            if (!PyIndex_Check(item.ptr()) || PyBool_Check(item.ptr()))
                allInt = false;
        }
        if (allInt) {
            Vec3i v;
            for (int i = 0; i < 3; ++i)
                v[i] = toInt32(items[i]);
            return v;
        }
        py::detail::make_caster<Vec3d> caster;
        if (caster.load(obj, true))
            return py::detail::cast_op<Vec3d>(caster);
    }
    throw py::type_error(
        "metadata values are bool, int, float, str, 3-tuples of numbers or "
        "vdb.Metadata; got " +
        typeNameOf(obj));
}

py::dict metaMapToDict(const MetaMap& map) {
    py::dict d;
    for (const auto& [name, value] : map.metadata())
        d[py::str(name)] = metaToPython(value);
    return d;
}

void updateMetaMap(MetaMap& map, py::handle dict) {
    if (!py::isinstance<py::dict>(dict))
        throw py::type_error("expected a dict of metadata, got " + typeNameOf(dict));
    // Convert everything first, so that a bad entry leaves the map unchanged.
    std::vector<std::pair<std::string, MetaValue>> entries;
    for (auto [key, value] : py::reinterpret_borrow<py::dict>(dict)) {
        if (!py::isinstance<py::str>(key))
            throw py::type_error("metadata names are str, got " + typeNameOf(key));
        entries.emplace_back(key.cast<std::string>(), metaFromPython(value));
    }
    for (auto& [name, value] : entries)
        map.insertMeta(name, value);
}

// ---- Module-level classes

math::Mat4d matrixFromPython(py::handle obj) {
    auto rows = py::reinterpret_borrow<py::object>(obj);
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(rows);
    } catch (const py::error_already_set&) {
        a = {};
    }
    if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
        throw py::type_error("expected a 4 x 4 matrix of numbers, got " + typeNameOf(obj));
    math::Mat4d m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            m(r, c) = a.at(r, c);
    return m;
}

void bindConvert(py::module_& m) {
    py::enum_<math::Axis>(m, "Axis", "A coordinate axis, for Transform.rotate and shear.")
        .value("X", math::Axis::X)
        .value("Y", math::Axis::Y)
        .value("Z", math::Axis::Z);

    py::class_<OpaqueMetadata>(m, "Metadata",
                               "A metadata value of a type with no Python equivalent, kept as "
                               "the bytes a file stores so that it survives a round trip.")
        .def(
            "type", [](const OpaqueMetadata& o) { return o.typeName; },
            "type() -> str: the name of this value's type.")
        .def(
            "size", [](const OpaqueMetadata& o) { return o.bytes.size(); },
            "size() -> int: the size of this value in bytes.")
        .def(
            "bytes",
            [](const OpaqueMetadata& o) {
                return py::bytes(reinterpret_cast<const char*>(o.bytes.data()), o.bytes.size());
            },
            "bytes() -> bytes: the value as stored in a file.")
        .def(
            "copy", [](const OpaqueMetadata& o) { return o; }, "copy() -> Metadata")
        .def("__eq__", [](const OpaqueMetadata& a, const OpaqueMetadata& b) { return a == b; })
        .def("__repr__", [](const OpaqueMetadata& o) {
            return "vdb.Metadata(type=" + o.typeName + ", " + std::to_string(o.bytes.size()) +
                   " bytes)";
        });

    using math::Transform;
    py::class_<Transform, Transform::Ptr>(
        m, "Transform", "The map from index space (i, j, k) to world space (x, y, z) of a grid.")
        .def(py::init([] { return Transform::createLinearTransform(1.0); }),
             "The identity transform (voxel size 1).")
        .def(
            "deepCopy", [](const Transform& t) { return std::make_shared<Transform>(t); },
            "deepCopy() -> Transform: a copy of this transform.")
        .def(
            "indexToWorld",
            [](const Transform& t, const Vec3d& ijk) { return t.indexToWorld(ijk); },
            py::arg("ijk"), "indexToWorld((i, j, k)) -> (x, y, z)")
        .def(
            "worldToIndex",
            [](const Transform& t, const Vec3d& xyz) { return t.worldToIndex(xyz); },
            py::arg("xyz"), "worldToIndex((x, y, z)) -> (i, j, k) as floats")
        .def(
            "worldToIndexCellCentered",
            [](const Transform& t, const Vec3d& xyz) { return t.worldToIndexCellCentered(xyz); },
            py::arg("xyz"),
            "worldToIndexCellCentered((x, y, z)) -> (i, j, k): rounded to the nearest voxel.")
        .def(
            "worldToIndexNodeCentered",
            [](const Transform& t, const Vec3d& xyz) { return t.worldToIndexNodeCentered(xyz); },
            py::arg("xyz"), "worldToIndexNodeCentered((x, y, z)) -> (i, j, k): rounded down.")
        .def(
            "voxelSize", [](const Transform& t) { return t.voxelSize(); },
            "voxelSize() -> (dx, dy, dz): the world-space size of a voxel.")
        .def(
            "voxelSize", [](const Transform& t, const Vec3d& ijk) { return t.voxelSize(ijk); },
            py::arg("xyz"), "voxelSize((i, j, k)) -> (dx, dy, dz): the size at an index point.")
        .def(
            "voxelVolume", [](const Transform& t) { return t.voxelVolume(); },
            "voxelVolume() -> float")
        .def(
            "voxelVolume", [](const Transform& t, const Vec3d& ijk) { return t.voxelVolume(ijk); },
            py::arg("xyz"), "voxelVolume((i, j, k)) -> float")
        .def(
            "rotate",
            [](Transform& t, double radians, math::Axis axis) { t.preRotate(radians, axis); },
            py::arg("radians"), py::arg("axis") = math::Axis::X,
            "rotate(radians, axis): accumulate a rotation about Axis.X, Axis.Y or Axis.Z, in "
            "index space (before the map), as pyopenvdb does.")
        .def(
            "translate", [](Transform& t, const Vec3d& v) { t.postTranslate(v); }, py::arg("xyz"),
            "translate((x, y, z)): accumulate a translation.")
        .def(
            "scale", [](Transform& t, double s) { t.preScale(s); }, py::arg("s"),
            "scale(s): accumulate a uniform scale (in index space, as pyopenvdb does).")
        .def(
            "scale", [](Transform& t, const Vec3d& s) { t.preScale(s); }, py::arg("s"),
            "scale((sx, sy, sz)): accumulate a nonuniform scale (in index space).")
        .def(
            "matrix",
            [](const Transform& t) {
                const math::Mat4d m = t.mapParams().matrix;
                py::list rows;
                for (int r = 0; r < 4; ++r)
                    rows.append(py::make_tuple(m(r, 0), m(r, 1), m(r, 2), m(r, 3)));
                return rows;
            },
            "matrix() -> list of 4 rows: the 4 x 4 world-from-index matrix of a linear map "
            "(row vectors; the last row is the translation).")
        .def_property_readonly("isLinear", &Transform::isLinear, "True if this transform is linear")
        .def_property_readonly(
            "typeName",
            [](const Transform& t) { return std::string(math::mapTypeName(t.mapType())); },
            "name of this transform's map type")
        .def(
            "info",
            [](const Transform& t) {
                std::ostringstream s;
                s << t;
                return s.str();
            },
            "info() -> str: a description of this transform.")
        .def("__repr__",
             [](const Transform& t) {
                 std::ostringstream s;
                 s << "vdb.Transform(" << t << ")";
                 return s.str();
             })
        .def("__eq__", [](const Transform& a, const Transform& b) { return a == b; })
        .def("__ne__", [](const Transform& a, const Transform& b) { return !(a == b); })
        .def("isApproxEqual", &Transform::isApproxEqual, py::arg("other"), py::arg("relTol") = 1e-6,
             "isApproxEqual(other, relTol=1e-6) -> bool: the same map to a relative tolerance.");

    m.def(
        "createLinearTransform",
        [](py::object arg) -> Transform::Ptr {
            if (PyFloat_Check(arg.ptr()) || (PyLong_Check(arg.ptr()) && !PyBool_Check(arg.ptr())) ||
                py::isinstance(arg, py::module_::import("numpy").attr("number"))) {
                const double voxelSize = arg.cast<double>();
                if (!std::isfinite(voxelSize) || voxelSize <= 0.0)
                    throw py::value_error(
                        "createLinearTransform: the voxel size must be "
                        "positive and finite, got " +
                        std::string(py::repr(arg)));
                return Transform::createLinearTransform(voxelSize);
            }
            return Transform::createLinearTransform(matrixFromPython(arg));
        },
        py::arg("voxelSize") = 1.0,
        "createLinearTransform(voxelSize=1.0) -> Transform: a uniform scale.\n"
        "createLinearTransform(matrix) -> Transform: from a 4 x 4 matrix given as rows\n"
        "[[a, b, c, 0], [d, e, f, 0], [g, h, i, 0], [tx, ty, tz, 1]].");
    m.def(
        "createFrustumTransform",
        [](const Vec3d& xyzMin, const Vec3d& xyzMax, double taper, double depth, double voxelSize) {
            return Transform::createFrustumTransform(math::BBoxd(xyzMin, xyzMax), taper, depth,
                                                     voxelSize);
        },
        py::arg("xyzMin"), py::arg("xyzMax"), py::arg("taper"), py::arg("depth"),
        py::arg("voxelSize") = 1.0,
        "createFrustumTransform(xyzMin, xyzMax, taper, depth, voxelSize=1.0) -> Transform");

    // pyopenvdb's GridClass: string constants with dict-like access.
    py::module_ gc = m.def_submodule("GridClass", "Classes of volumetric data.");
    gc.attr("UNKNOWN") = "unknown";
    gc.attr("LEVEL_SET") = "level set";
    gc.attr("FOG_VOLUME") = "fog volume";
    gc.attr("STAGGERED") = "staggered";

    // pyopenvdb's VectorType: a class whose attributes are the vector type names, with keys()
    // and, on an instance, len(), iteration over the keys and lookup by key.
    struct VectorTypeNames {};
    py::class_<VectorTypeNames> vt(
        m, "VectorType",
        "How transforms apply to the values of a vector grid (the grid's vectorType):\n"
        "  INVARIANT: not transformed (a colour, a tuple)\n"
        "  COVARIANT: by the inverse transpose, without translation (a gradient, a normal)\n"
        "  COVARIANT_NORMALIZE: as COVARIANT, then normalised (a unit normal)\n"
        "  CONTRAVARIANT_RELATIVE: by the linear part, without translation (a velocity)\n"
        "  CONTRAVARIANT_ABSOLUTE: as a point, translation included (a position)");
    py::dict names;
    for (int t = 0; t < NUM_VEC_TYPES; ++t) {
        const std::string value(vecTypeToString(VecType(t)));
        std::string key = value;  // "covariant normalize" -> "COVARIANT_NORMALIZE"
        for (char& c : key)
            c = c == ' ' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
        names[py::str(key)] = value;
        vt.attr(key.c_str()) = value;
    }
    vt.def(py::init<>())
        .def_static(
            "keys", [names]() { return names.attr("keys")(); },
            "keys() -> the names of the vector types (INVARIANT, COVARIANT, ...)")
        .def("__len__", [names](const VectorTypeNames&) { return py::len(names); })
        .def("__iter__", [names](const VectorTypeNames&) { return py::iter(names); })
        .def("__getitem__", [names](const VectorTypeNames&, py::handle key) -> py::object {
            if (!names.contains(key)) {
                PyErr_SetObject(PyExc_KeyError, key.ptr());  // KeyError(key), as dict raises
                throw py::error_already_set();
            }
            return names[key];
        });
}

}  // namespace vdb::python
