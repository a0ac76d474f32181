// SPDX-License-Identifier: Apache-2.0
// The extension module vdb._vdb: exception translation, the grid base class with the methods
// every grid type shares, and the module's contents.

#include <vdb/Exceptions.h>
#include <vdb/GridTypes.h>
#include <vdb/io/Format.h>
#include <vdb/tools/LevelSetSphere.h>

#include "Common.h"
#include "TreeBlocks.h"

#include <sstream>

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

std::pair<Coord, Coord> bboxCorners(const CoordBBox& bbox) {
    if (bbox.empty())  // pyopenvdb's empty box: max corner below min corner
        return {Coord(std::numeric_limits<Int32>::max()), Coord(std::numeric_limits<Int32>::min())};
    return {bbox.min(), bbox.max()};
}

}  // namespace

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
        .def("__setitem__", [](GridBase& g, const std::string& key,
                               py::handle value) { g.insertMeta(key, metaFromPython(value)); })
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
