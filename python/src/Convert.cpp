// SPDX-License-Identifier: Apache-2.0
// Conversions between Python objects and the library's values and metadata; the Transform,
// GridClass and Metadata classes of the module.

#include <vdb/io/File.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Math.h>

#include "Common.h"

#include <cctype>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
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

void raisePython(PyObject* type, const std::string& message) {
    PyErr_SetString(type, message.c_str());
    throw py::error_already_set();
}

std::optional<Int64> indexValue(py::handle obj) {
    py::int_ value = py::reinterpret_steal<py::int_>(PyNumber_Index(obj.ptr()));
    if (!value)
        throw py::error_already_set();
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow != 0)
        return std::nullopt;
    return Int64(v);
}

Int32 toInt32(py::handle obj) {
    if (!PyIndex_Check(obj.ptr()))
        throw py::type_error("expected an integer coordinate, got " + typeNameOf(obj));
    const auto v = indexValue(obj);
    if (!v || *v < std::numeric_limits<Int32>::min() || *v > std::numeric_limits<Int32>::max())
        raisePython(
            PyExc_OverflowError,  // as pyopenvdb, for a coordinate beyond 32 bits
            "coordinate " + std::string(py::str(obj)) + " is outside the 32-bit index space");
    return Int32(*v);
}

std::string typeNameOf(py::handle obj) {
    return obj ? std::string(py::str(py::type::handle_of(obj).attr("__name__"))) : "nothing";
}

// ---- Metadata

namespace {

// Metadata types that the library keeps as opaque bytes but Python users store (pyopenvdb
// writes 2- and 4-tuples as vec2i/vec2d/vec4i/vec4d and 4 x 4 nested lists as mat4d): their
// payloads are the components, little-endian, row by row for matrices.
struct FixedMetaType {
    const char* name;
    int count;    // components
    char scalar;  // 'i': int32, 's': float, 'd': double
    bool matrix;  // a 4 x 4 matrix, returned as a list of lists
};
constexpr FixedMetaType FIXED_META_TYPES[] = {{"vec2i", 2, 'i', false}, {"vec2s", 2, 's', false},
                                              {"vec2d", 2, 'd', false}, {"vec4i", 4, 'i', false},
                                              {"vec4s", 4, 's', false}, {"vec4d", 4, 'd', false},
                                              {"mat4s", 16, 's', true}, {"mat4d", 16, 'd', true}};

const FixedMetaType* fixedMetaType(std::string_view name) {
    for (const auto& t : FIXED_META_TYPES)
        if (name == t.name)
            return &t;
    return nullptr;
}

size_t scalarSize(char scalar) {
    return scalar == 'd' ? 8 : 4;
}

/// The components of an opaque value of a fixed type, or None when its size is wrong.
py::object fixedMetaToPython(const FixedMetaType& t, const std::vector<uint8_t>& bytes) {
    if (bytes.size() != size_t(t.count) * scalarSize(t.scalar))
        return py::none();
    std::vector<py::object> items;
    for (int i = 0; i < t.count; ++i) {
        const uint8_t* p = bytes.data() + size_t(i) * scalarSize(t.scalar);
        if (t.scalar == 'i') {
            Int32 v;
            std::memcpy(&v, p, 4);
            items.push_back(py::int_(v));
        } else if (t.scalar == 's') {
            float v;
            std::memcpy(&v, p, 4);
            items.push_back(py::float_(double(v)));
        } else {
            double v;
            std::memcpy(&v, p, 8);
            items.push_back(py::float_(v));
        }
    }
    if (!t.matrix) {
        py::tuple out(items.size());
        for (size_t i = 0; i < items.size(); ++i)
            out[i] = items[i];
        return out;
    }
    py::list rows;
    for (int r = 0; r < 4; ++r) {
        py::list row;
        for (int c = 0; c < 4; ++c)
            row.append(items[size_t(r * 4 + c)]);
        rows.append(row);
    }
    return rows;
}

OpaqueMetadata fixedMeta(const char* type, const std::vector<double>& values, bool integers) {
    OpaqueMetadata meta{type, {}};
    for (double v : values) {
        if (integers) {
            const Int32 i = Int32(v);
            const auto* p = reinterpret_cast<const uint8_t*>(&i);
            meta.bytes.insert(meta.bytes.end(), p, p + 4);
        } else {
            const auto* p = reinterpret_cast<const uint8_t*>(&v);
            meta.bytes.insert(meta.bytes.end(), p, p + 8);
        }
    }
    return meta;
}

[[noreturn]] void refuseMeta(py::handle obj) {
    throw py::type_error("metadata value \"" + std::string(py::str(obj)) + "\" of type " +
                         typeNameOf(obj) +
                         " is not allowed (metadata values are bool, int, float, str, tuples "
                         "of 2 to 4 numbers, 4 x 4 nested sequences of numbers or "
                         "vdb.Metadata)");
}

/// An int as int32 or int64 by range. @throw OverflowError beyond 64 bits.
MetaValue metaInteger(py::handle obj) {
    const auto v = indexValue(obj);
    if (!v)
        raisePython(PyExc_OverflowError,
                    "metadata integer " + std::string(py::str(obj)) + " does not fit in 64 bits");
    if (*v >= std::numeric_limits<Int32>::min() && *v <= std::numeric_limits<Int32>::max())
        return Int32(*v);
    return *v;
}

/// The items of a list or tuple (or of a 1- or 2-dimensional NumPy array, as lists), or
/// nothing for other objects.
std::optional<std::vector<py::object>> metaItems(py::handle obj) {
    py::object seq = py::reinterpret_borrow<py::object>(obj);
    if (py::isinstance<py::array>(obj))
        seq = seq.attr("tolist")();
    if (!PyList_Check(seq.ptr()) && !PyTuple_Check(seq.ptr()))
        return std::nullopt;
    std::vector<py::object> items;
    for (py::handle item : seq)
        items.push_back(py::reinterpret_borrow<py::object>(item));
    return items;
}

/// A Python int or bool (not a float), as pyopenvdb counts vector components.
bool isIntegral(py::handle obj) {
    return PyLong_Check(obj.ptr()) || (PyIndex_Check(obj.ptr()) && !PyFloat_Check(obj.ptr()) &&
                                       !PySequence_Check(obj.ptr()));  // not a NumPy array
}

bool isNumber(py::handle obj) {
    return isIntegral(obj) || PyFloat_Check(obj.ptr()) ||
           py::isinstance(obj, py::module_::import("numpy").attr("floating"));
}

}  // namespace

py::object metaToPython(const MetaValue& value) {
    return std::visit(
        [](const auto& v) -> py::object {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, OpaqueMetadata>) {
                if (const FixedMetaType* t = fixedMetaType(v.typeName)) {
                    py::object o = fixedMetaToPython(*t, v.bytes);
                    if (!o.is_none())
                        return o;
                }
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

std::optional<MetaValue> metaFromPython(py::handle obj) {
    if (obj.is_none())
        return std::nullopt;  // pyopenvdb stores nothing for None
    if (PyBool_Check(obj.ptr()))
        return MetaValue(obj.cast<bool>());
    if (py::isinstance<py::str>(obj))
        return MetaValue(obj.cast<std::string>());
    if (PyBytes_Check(obj.ptr()))
        return MetaValue(std::string(PyBytes_AsString(obj.ptr()), size_t(PyBytes_Size(obj.ptr()))));
    if (py::isinstance<OpaqueMetadata>(obj))
        return MetaValue(obj.cast<OpaqueMetadata>());
    if (isIntegral(obj))
        return metaInteger(obj);
    if (isNumber(obj))
        return MetaValue(obj.cast<double>());
    const auto items = metaItems(obj);
    if (!items)
        refuseMeta(obj);
    const size_t n = items->size();
    // A 4 x 4 matrix: four rows of four numbers.
    if (n == 4 && metaItems((*items)[0])) {
        std::vector<double> values;
        for (const auto& row : *items) {
            const auto cells = metaItems(row);
            if (!cells || cells->size() != 4)
                refuseMeta(obj);
            for (const auto& c : *cells) {
                if (!isNumber(c))
                    refuseMeta(obj);
                values.push_back(c.cast<double>());
            }
        }
        return MetaValue(fixedMeta("mat4d", values, false));
    }
    if (n < 2 || n > 4)
        refuseMeta(obj);
    bool allInt = true;
    for (const auto& item : *items) {
        if (!isNumber(item))
            refuseMeta(obj);
        allInt = allInt && isIntegral(item);
    }
    std::vector<double> values;
    if (allInt) {
        Vec3i v3;
        for (size_t i = 0; i < n; ++i) {
            const auto wide = indexValue((*items)[i]);  // a bool reads as 0 or 1
            if (!wide || *wide < std::numeric_limits<Int32>::min() ||
                *wide > std::numeric_limits<Int32>::max())
                raisePython(PyExc_OverflowError, "metadata vector component " +
                                                     std::string(py::str((*items)[i])) +
                                                     " does not fit in 32 bits");
            const Int32 c = Int32(*wide);
            values.push_back(double(c));
            if (i < 3)
                v3[int(i)] = c;
        }
        if (n == 3)
            return MetaValue(v3);
        return MetaValue(fixedMeta(n == 2 ? "vec2i" : "vec4i", values, true));
    }
    for (const auto& item : *items)
        values.push_back(item.cast<double>());
    if (n == 3)
        return MetaValue(Vec3d(values[0], values[1], values[2]));
    return MetaValue(fixedMeta(n == 2 ? "vec2d" : "vec4d", values, false));
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
        if (auto v = metaFromPython(value))
            entries.emplace_back(key.cast<std::string>(), std::move(*v));
    }
    for (auto& [name, value] : entries)
        map.insertMeta(name, value);
}

// ---- Pickling

namespace {
constexpr const char* PICKLE_HALF = "vdb_pickle_save_float_as_half";
}

py::bytes archiveBytes(const GridBase::Ptr& grid, bool half) {
    MetaMap meta;
    if (half)
        meta.insertMeta(PICKLE_HALF, true);
    std::ostringstream os;
    {
        py::gil_scoped_release release;
        io::Stream out(os);
        out.setGridStatsMetadataEnabled(false);
        out.write(GridCPtrVec{grid}, meta);
    }
    return py::bytes(os.str());
}

GridBase::Ptr gridFromArchive(py::handle state) {
    if (!PyBytes_Check(state.ptr()))
        throw py::value_error("unpickling: expected the bytes that pickling wrote, got " +
                              typeNameOf(state));
    const std::string bytes = state.cast<std::string>();
    GridPtrVecPtr grids;
    MetaMap meta;
    {
        py::gil_scoped_release release;
        std::istringstream is(bytes);
        io::Stream in(is);
        grids = in.getGrids();
        meta = in.getMetadata();
    }
    if (!grids || grids->size() != 1)
        throw py::value_error("unpickling: the bytes do not hold one grid");
    GridBase::Ptr grid = grids->front();
    if (const bool* half = meta.getMeta<bool>(PICKLE_HALF); half && *half)
        grid->setSaveFloatAsHalf(true);
    return grid;
}

py::tuple reduceGrid(const GridBase::Ptr& grid) {
    // A shallow copy (sharing the tree) written at full precision: a pickle is a copy, not a
    // file, so values are not rounded to halves; the half flag travels as archive metadata.
    GridBase::Ptr copy = grid;
    const bool half = grid->saveFloatAsHalf();
    if (half) {
        copy = grid->copyGrid();
        copy->setSaveFloatAsHalf(false);
    }
    return py::make_tuple(py::module_::import("vdb").attr("_restore_grid"),
                          py::make_tuple(archiveBytes(copy, half)));
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

namespace {
/// pyopenvdb's createLinearTransform(matrix): ValueError for anything but 4 x 4 numbers,
/// ArithmeticError for a matrix that is not affine.
math::Transform::Ptr linearTransformFromMatrix(py::handle matrix) {
    math::Mat4d m;
    try {
        m = matrixFromPython(matrix);
    } catch (const py::type_error&) {
        throw py::value_error("createLinearTransform: expected a 4 x 4 sequence of numbers, got " +
                              std::string(py::repr(matrix)));
    }
    if (!m.isAffine())
        raisePython(PyExc_ArithmeticError,
                    "createLinearTransform: the matrix is not affine (its last column must be "
                    "(0, 0, 0, 1))");
    return math::Transform::createLinearTransform(m);
}
}  // namespace

void bindConvert(py::module_& m) {
    py::enum_<math::Axis>(m, "Axis", "A coordinate axis, for Transform.rotate and shear.")
        .value("X", math::Axis::X)
        .value("Y", math::Axis::Y)
        .value("Z", math::Axis::Z);
    {
        // pyopenvdb's Axis.names and Axis.values.
        py::object axis = m.attr("Axis");
        py::dict names, values;
        for (const auto& [key, value] : {std::pair{"X", 0}, std::pair{"Y", 1}, std::pair{"Z", 2}}) {
            names[key] = axis.attr(key);
            values[py::int_(value)] = axis.attr(key);
        }
        axis.attr("names") = names;
        axis.attr("values") = values;
    }

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
            py::arg("xyz"), "indexToWorld((i, j, k)) -> (x, y, z)")
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
            "scale", [](Transform& t, const Vec3d& s) { t.preScale(s); }, py::arg("sxyz"),
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
        .def(
            "shear",
            [](Transform& t, double s, math::Axis axis0, math::Axis axis1) {
                // Row axis1 gains s times row axis0, in index space (before the map), as
                // pyopenvdb's shear (OpenVDB's preShear).
                math::Mat4d m = math::Mat4d::identity();
                m(int(axis1), int(axis0)) = s;
                t.preMult(m);
            },
            py::arg("s"), py::arg("axis0"), py::arg("axis1"),
            "shear(s, axis0, axis1): accumulate a shear of axis0 by s times axis1 (Axis.X, "
            "Axis.Y or Axis.Z), in index space, as pyopenvdb does.")
        .def(
            "__eq__", [](const Transform& a, const Transform& b) { return a == b; },
            py::is_operator())
        .def(
            "__ne__", [](const Transform& a, const Transform& b) { return !(a == b); },
            py::is_operator())
        .def("__reduce__",
             [](const Transform& t) {
                 // pickle (every protocol) and copy.deepcopy: the transform as the archive of an
                 // empty grid, restored by _restoreTransform.
                 auto holder = FloatGrid::create();
                 holder->setTransform(std::make_shared<Transform>(t));
                 return py::make_tuple(py::module_::import("vdb").attr("_restore_transform"),
                                       py::make_tuple(archiveBytes(holder, false)));
             })
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
            return linearTransformFromMatrix(arg);
        },
        py::arg("voxelSize") = 1.0,
        "createLinearTransform(voxelSize=1.0) -> Transform: a uniform scale.\n"
        "createLinearTransform(matrix) -> Transform: from a 4 x 4 matrix given as rows\n"
        "[[a, b, c, 0], [d, e, f, 0], [g, h, i, 0], [tx, ty, tz, 1]].");
    m.def(
        "createLinearTransform",
        [](py::object matrix) { return linearTransformFromMatrix(matrix); }, py::arg("matrix"),
        "createLinearTransform(matrix=[[...], [...], [...], [...]]) -> Transform: from a 4 x 4 "
        "matrix given as rows (the last row is the translation).");
    m.def(
        "_restoreGrid", [](py::handle state) { return gridFromArchive(state); }, py::arg("state"),
        "_restoreGrid(bytes) -> grid: unpickles a grid (see vdb._restore_grid).");
    m.def(
        "_restoreTransform",
        [](py::handle state) { return gridFromArchive(state)->transformPtr(); }, py::arg("state"),
        "_restoreTransform(bytes) -> Transform: unpickles a transform.");
    m.def(
        "createFrustumTransform",
        [](const Vec3d& xyzMin, const Vec3d& xyzMax, double taper, double depth, double voxelSize) {
            return Transform::createFrustumTransform(math::BBoxd(xyzMin, xyzMax), taper, depth,
                                                     voxelSize);
        },
        py::arg("xyzMin"), py::arg("xyzMax"), py::arg("taper"), py::arg("depth"),
        py::arg("voxelSize") = 1.0,
        "createFrustumTransform(xyzMin, xyzMax, taper, depth, voxelSize=1.0) -> Transform");

    // pyopenvdb's GridClass and VectorType: classes whose attributes are the names' values,
    // with keys() and, on an instance, len(), iteration over the keys and lookup by key.
    const auto nameClass = [&m](auto tag, const char* name, const char* doc,
                                const std::vector<std::pair<std::string, std::string>>& items) {
        using Tag = decltype(tag);
        py::class_<Tag> c(m, name, doc);
        py::dict names;
        for (const auto& [key, value] : items) {
            names[py::str(key)] = value;
            c.attr(key.c_str()) = value;
        }
        c.def(py::init<>())
            .def_static(
                "keys", [names]() { return names.attr("keys")(); }, "keys() -> the names")
            .def("__len__", [names](const Tag&) { return py::len(names); })
            .def("__iter__", [names](const Tag&) { return py::iter(names); })
            .def("__getitem__", [names](const Tag&, py::handle key) -> py::object {
                if (!names.contains(key)) {
                    PyErr_SetObject(PyExc_KeyError, key.ptr());  // KeyError(key), as dict raises
                    throw py::error_already_set();
                }
                return names[key];
            });
    };
    struct GridClassNames {};
    nameClass(GridClassNames{}, "GridClass",
              "Classes of volumetric data (a grid's gridClass): UNKNOWN, LEVEL_SET, FOG_VOLUME, "
              "STAGGERED.",
              {{"UNKNOWN", "unknown"},
               {"LEVEL_SET", "level set"},
               {"FOG_VOLUME", "fog volume"},
               {"STAGGERED", "staggered"}});
    struct VectorTypeNames {};
    std::vector<std::pair<std::string, std::string>> vecTypes;
    for (int t = 0; t < NUM_VEC_TYPES; ++t) {
        const std::string value(vecTypeToString(VecType(t)));
        std::string key = value;  // "covariant normalize" -> "COVARIANT_NORMALIZE"
        for (char& c : key)
            c = c == ' ' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
        vecTypes.emplace_back(key, value);
    }
    nameClass(VectorTypeNames{}, "VectorType",
              "How transforms apply to the values of a vector grid (the grid's vectorType):\n"
              "  INVARIANT: not transformed (a colour, a tuple)\n"
              "  COVARIANT: by the inverse transpose, without translation (a gradient, a "
              "normal)\n"
              "  COVARIANT_NORMALIZE: as COVARIANT, then normalised (a unit normal)\n"
              "  CONTRAVARIANT_RELATIVE: by the linear part, without translation (a velocity)\n"
              "  CONTRAVARIANT_ABSOLUTE: as a point, translation included (a position)",
              vecTypes);
}

}  // namespace vdb::python
