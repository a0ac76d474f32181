// SPDX-License-Identifier: Apache-2.0
// The extension module vdb._vdb: exception translation, the grid base class with the methods
// every grid type shares, and the module's contents.

#include <vdb/Exceptions.h>
#include <vdb/GridTypes.h>
#include <vdb/io/Format.h>
#include <vdb/tools/LevelSetSphere.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <array>
#include <cctype>
#include <sstream>
#include <string_view>

namespace vdb::python {

namespace {

void translateExceptions(std::exception_ptr p) {
    try {
        if (p)
            std::rethrow_exception(p);
    } catch (const IoError& e) {
        PyErr_SetString(PyExc_OSError, e.what());
    } catch (const TypeError& e) {
        PyErr_SetString(PyExc_TypeError, e.what());
    } catch (const ValueError& e) {
        PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IndexError& e) {
        PyErr_SetString(PyExc_IndexError, e.what());
    } catch (const CancelledError& e) {
        PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const Exception& e) {
        PyErr_SetString(PyExc_RuntimeError, e.what());
    }
}

GridClass gridClassFromPython(py::handle obj) {
    if (!py::isinstance<py::str>(obj))
        throw py::type_error("gridClass is a str (vdb.GridClass.LEVEL_SET, ...), got " +
                             typeNameOf(obj));
    const std::string s = obj.cast<std::string>();
    const GridClass c = stringToGridClass(s);
    if (c == GRID_UNKNOWN && s != "unknown")
        throw py::value_error("unknown grid class \"" + s +
                              "\" (expected \"level set\", \"fog volume\", \"staggered\" or "
                              "\"unknown\")");
    return c;
}

/// The names of the vector types, as the vectorType property accepts them.
std::string vecTypeNames() {
    std::string names;
    for (int t = 0; t < NUM_VEC_TYPES; ++t)
        names += (t ? ", \"" : "\"") + std::string(vecTypeToString(VecType(t))) + "\"";
    return names;
}

/// Sets the vector type of `g` from a name (vdb.VectorType.COVARIANT, ...); None removes the
/// metadata, so that the type reads as "invariant".
void setVectorTypeFromPython(GridBase& g, py::handle obj) {
    if (obj.is_none()) {
        g.clearVectorType();
        return;
    }
    if (!py::isinstance<py::str>(obj))
        throw py::type_error("vectorType is a str (vdb.VectorType.COVARIANT, ...), got " +
                             typeNameOf(obj));
    const std::string s = obj.cast<std::string>();
    for (int t = 0; t < NUM_VEC_TYPES; ++t) {
        if (vecTypeToString(VecType(t)) == s) {
            g.setVectorType(VecType(t));
            return;
        }
    }
    throw py::value_error("unknown vector type \"" + s + "\" (expected one of " + vecTypeNames() +
                          ")");
}

/// The metadata addStatsMetadata() writes, with the names the file format gives them.
constexpr std::array<std::string_view, 4> STATS_META_NAMES{"file_bbox_min", "file_bbox_max",
                                                           "file_mem_bytes", "file_voxel_count"};

/// pyopenvdb's vectorType, addStatsMetadata and getStatsMetadata.
void bindVectorTypeAndStats(py::class_<GridBase, GridBase::Ptr>& base) {
    base.def_property(
            "vectorType",
            [](const GridBase& g) { return std::string(vecTypeToString(g.getVectorType())); },
            &setVectorTypeFromPython,
            "how transforms apply to this grid's values (vdb.VectorType.INVARIANT, COVARIANT, "
            "COVARIANT_NORMALIZE, CONTRAVARIANT_RELATIVE, CONTRAVARIANT_ABSOLUTE); "
            "\"invariant\" when unset. Setting None removes it; an unknown name raises "
            "ValueError.")
        .def(
            "addStatsMetadata",
            [](GridBase& g) {
                std::pair<Coord, Coord> box;
                Int64 voxels = 0;
                {
                    py::gil_scoped_release release;
                    box = bboxCorners(g.evalActiveVoxelBoundingBox());
                    voxels = Int64(g.activeVoxelCount());
                }
                const auto vec = [](const Coord& c) { return Vec3i(c[0], c[1], c[2]); };
                g.insertMeta(STATS_META_NAMES[0], vec(box.first));
                g.insertMeta(STATS_META_NAMES[1], vec(box.second));
                g.insertMeta(STATS_META_NAMES[3], voxels);
                // memUsage() counts the metadata: measure with all four entries in place.
                g.insertMeta(STATS_META_NAMES[2], MetaValue(Int64(0)));
                g.insertMeta(STATS_META_NAMES[2], Int64(g.memUsage()));
            },
            "addStatsMetadata(): store the active voxel bounding box, the memory use (as "
            "memUsage(), these entries included) and the active voxel count as the metadata "
            "file_bbox_min, file_bbox_max, file_mem_bytes and file_voxel_count (not kept up to "
            "date as the grid changes).")
        .def(
            "getStatsMetadata",
            [](const GridBase& g) {
                py::dict out;
                for (std::string_view name : STATS_META_NAMES)
                    if (const MetaValue* v = g.findMeta(name))
                        out[py::str(std::string(name))] = metaToPython(*v);
                return out;
            },
            "getStatsMetadata() -> dict: the metadata of those four names that this grid "
            "holds (from addStatsMetadata() or from a file), possibly none.");
}

/// The logging threshold and program name that pyopenvdb scripts set. The library writes no
/// log messages (errors are exceptions; the module's warnings go through Python's warnings
/// module), so they are only kept and returned.
struct Settings {
    std::string loggingLevel = "warn";
    std::string programName;
    bool color = true;
};
Settings& settings() {
    static Settings s;  // read and written with the GIL held
    return s;
}

/// LIBRARY_VERSION, getLoggingLevel, setLoggingLevel and setProgramName.
void bindSettings(py::module_& m) {
    // The OpenVDB library version whose API and files this library follows, as file headers
    // record it.
    m.attr("LIBRARY_VERSION") =
        py::make_tuple(io::WRITER_LIBRARY_MAJOR, io::WRITER_LIBRARY_MINOR, 0);
    m.def(
        "getLoggingLevel", [] { return settings().loggingLevel; },
        "getLoggingLevel() -> str: the severity threshold (\"debug\", \"info\", \"warn\", "
        "\"error\" or \"fatal\") set by setLoggingLevel().");
    m.def(
        "setLoggingLevel",
        [](py::handle level) {
            const std::string given = py::str(level);
            std::string name = given;
            for (char& c : name)
                c = char(std::tolower(static_cast<unsigned char>(c)));
            for (const char* known : {"debug", "info", "warn", "error", "fatal"}) {
                if (name == known) {
                    settings().loggingLevel = name;
                    return;
                }
            }
            throw py::value_error(
                "expected logging level \"debug\", \"info\", \"warn\", \"error\", or "
                "\"fatal\", got \"" +
                given + "\"");
        },
        py::arg("level"),
        "setLoggingLevel(level): set the severity threshold (\"debug\", \"info\", \"warn\", "
        "\"error\" or \"fatal\", in any case). The library logs nothing, so the level is only "
        "kept; the module's own warnings are Python warnings (see the warnings module).");
    m.def(
        "setProgramName",
        [](py::handle name, bool color) {
            if (!py::isinstance<py::str>(name))
                throw py::type_error("expected string as program name, got \"" +
                                     std::string(py::str(name)) + "\" of type " + typeNameOf(name));
            settings().programName = name.cast<std::string>();
            settings().color = color;
        },
        py::arg("name"), py::arg("color") = true,
        "setProgramName(name, color=True): the program name for log messages, and whether "
        "they are in colour (kept only: the library logs nothing).");
}

}  // namespace

std::pair<Coord, Coord> bboxCorners(const CoordBBox& bbox) {
    if (bbox.empty())  // pyopenvdb's empty box: max corner below min corner
        return {Coord(std::numeric_limits<Int32>::max()), Coord(std::numeric_limits<Int32>::min())};
    return {bbox.min(), bbox.max()};
}

void bindGridBase(py::module_& m) {
    py::class_<GridBase, GridBase::Ptr> base(
        m, "GridBase",
        "The methods every grid type shares: name, class, transform, metadata and statistics.");
    base.def_property(
            "name", &GridBase::getName,
            [](GridBase& g, const std::string& name) { g.setName(name); }, "this grid's name")
        .def_property(
            "gridClass",
            [](const GridBase& g) { return std::string(gridClassToString(g.getGridClass())); },
            [](GridBase& g, py::handle c) { g.setGridClass(gridClassFromPython(c)); },
            "the class of volumetric data (vdb.GridClass.LEVEL_SET, FOG_VOLUME, STAGGERED, "
            "UNKNOWN)")
        .def_property(
            "creator",
            [](const GridBase& g) {
                const auto* s = g.getMeta<std::string>("creator");
                return s ? *s : std::string();
            },
            [](GridBase& g, const std::string& s) { g.insertMeta("creator", s); },
            "description of this grid's creator")
        .def_property("saveFloatAsHalf", &GridBase::saveFloatAsHalf, &GridBase::setSaveFloatAsHalf,
                      "if True, files store floating-point values as 16-bit halves")
        .def_property(
            "transform", &GridBase::transformPtr,
            [](GridBase& g, math::Transform::Ptr t) {
                if (!t)
                    throw py::type_error("transform: expected a vdb.Transform, got None");
                g.setTransform(t);
            },
            "transform associated with this grid (shared: changing it changes the grid)")
        .def_property(
            "metadata", [](const GridBase& g) { return metaMapToDict(g); },
            [](GridBase& g, py::handle d) {
                MetaMap fresh;
                updateMetaMap(fresh, d);
                g.clearMetadata();
                for (const auto& [name, value] : fresh.metadata())
                    g.insertMeta(name, value);
            },
            "dict of this grid's metadata (a copy; setting it replaces all metadata)")
        .def(
            "updateMetadata", [](GridBase& g, py::handle d) { updateMetaMap(g, d); },
            py::arg("metadata"), "updateMetadata(dict): add or replace the given metadata items.")
        .def("__getitem__",
             [](const GridBase& g, const std::string& key) {
                 const MetaValue* v = g.findMeta(key);
                 if (!v)
                     throw py::key_error(key);
                 return metaToPython(*v);
             })
        .def("__setitem__",
             [](GridBase& g, const std::string& key, py::handle value) {
                 if (auto v = metaFromPython(value))
                     g.insertMeta(key, *v);
             })
        .def("__delitem__",
             [](GridBase& g, const std::string& key) {
                 if (!g.hasMeta(key))
                     throw py::key_error(key);
                 g.removeMeta(key);
             })
        .def("__contains__",
             [](const GridBase& g, py::handle key) {
                 return py::isinstance<py::str>(key) && g.hasMeta(key.cast<std::string>());
             })
        .def("__iter__",
             [](const GridBase& g) { return py::iter(metaMapToDict(g).attr("keys")()); })
        .def("__len__", &GridBase::metaCount)
        .def(
            "iterkeys", [](const GridBase& g) { return py::iter(metaMapToDict(g).attr("keys")()); },
            "iterkeys() -> iterator over the metadata names")
        .def("keys", [](const GridBase& g) { return metaMapToDict(g).attr("keys")(); })
        .def("activeVoxelCount", &GridBase::activeVoxelCount,
             "activeVoxelCount() -> int: active voxels, those of active tiles included.")
        .def("leafCount", &GridBase::leafCount, "leafCount() -> int")
        .def("memUsage", &GridBase::memUsage, "memUsage() -> int: bytes used by this grid.")
        .def("empty", &GridBase::empty, "empty() -> bool: True if the grid holds only background.")
        .def(
            "evalActiveVoxelBoundingBox",
            [](const GridBase& g) {
                py::gil_scoped_release release;
                return bboxCorners(g.evalActiveVoxelBoundingBox());
            },
            "evalActiveVoxelBoundingBox() -> (min, max): the corners of the bounding box of "
            "the active voxels ((2^31-1,)*3, (-2^31,)*3 when there are none).")
        .def(
            "evalActiveVoxelDim",
            [](const GridBase& g) {
                const CoordBBox b = g.evalActiveVoxelBoundingBox();
                return b.empty() ? Coord(0) : b.dim();
            },
            "evalActiveVoxelDim() -> (x, y, z): the dimensions of that box.")
        .def_property_readonly("valueType", &GridBase::valueType,
                               "the value type name, e.g. \"float\"")
        .def_property_readonly("type", &GridBase::type,
                               "the tree type name, e.g. \"Tree_float_5_4_3\"")
        .def(
            "info",
            [](const GridBase& g, int verbosity) {
                std::ostringstream s;
                s << g.type() << " \"" << g.getName() << "\"";
                if (verbosity > 0) {
                    const CoordBBox b = g.evalActiveVoxelBoundingBox();
                    s << ": " << g.activeVoxelCount() << " active voxels, " << g.leafCount()
                      << " leaves, class " << gridClassToString(g.getGridClass()) << ", voxel size "
                      << g.voxelSize();
                    if (!b.empty())
                        s << ", active bbox " << b.min() << " - " << b.max();
                    s << ", " << g.memUsage() << " bytes";
                }
                return s.str();
            },
            py::arg("verbosity") = 1, "info(verbosity=1) -> str: a description of this grid.")
        .def("__repr__", [](py::object self) {
            const auto& g = self.cast<const GridBase&>();
            return "<vdb." + std::string(py::str(py::type::handle_of(self).attr("__name__"))) +
                   " \"" + g.getName() + "\": " + std::to_string(g.activeVoxelCount()) +
                   " active voxels>";
        });
    bindVectorTypeAndStats(base);
}

}  // namespace vdb::python

PYBIND11_MODULE(_vdb, m) {
    using namespace vdb;
    using namespace vdb::python;
    m.doc() = "Sparse volumes after Museth's VDB, with pyopenvdb's names and bulk NumPy transfers.";
    py::register_exception_translator(&translateExceptions);

    bindConvert(m);
    bindGridBase(m);
    bindFloatGrids(m);
    bindIntGrids(m);
    bindBoolGrids(m);
    bindVecGrids(m);
    bindIo(m);
    py::module_ tools = m.def_submodule(
        "tools", "Level set, filtering, sampling, statistics, clipping and compositing tools.");
    bindTools(m, tools);
    bindToolsFilter(tools);
    bindToolsLevelSet(tools);
    bindToolsSample(tools);
    bindToolsClip(tools);

    py::list types;
    GridTypes::forEach([&]<typename GridT>() { types.append(py::type::of<GridT>()); });
    m.attr("GridTypes") = types;
    m.attr("LEVEL_SET_HALF_WIDTH") = 3.0;
    m.attr("FILE_FORMAT_VERSION") = io::FILE_VERSION;
    bindSettings(m);
    m.attr("COORD_MIN") =
        py::make_tuple(std::numeric_limits<Int32>::min(), std::numeric_limits<Int32>::min(),
                       std::numeric_limits<Int32>::min());
    m.attr("COORD_MAX") =
        py::make_tuple(std::numeric_limits<Int32>::max(), std::numeric_limits<Int32>::max(),
                       std::numeric_limits<Int32>::max());

    m.def(
        "createLevelSetSphere",
        [](double radius, const Vec3d& center, double voxelSize, double halfWidth) {
            py::gil_scoped_release release;
            return tools::createLevelSetSphere<FloatGrid>(radius, center, voxelSize, halfWidth);
        },
        py::arg("radius"), py::arg("center") = Vec3d(0.0), py::arg("voxelSize") = 1.0,
        py::arg("halfWidth") = 3.0,
        "createLevelSetSphere(radius, center=(0, 0, 0), voxelSize=1, halfWidth=3) -> FloatGrid: "
        "the narrow-band level set of a sphere (world units; half width in voxels). Raises "
        "ValueError for a radius or voxel size that is not positive and finite.");
}
