// SPDX-License-Identifier: Apache-2.0
// vdb.read, readAll, readAllGridMetadata, readGridMetadata, readMetadata and write: `.vdb`
// files through io::File.

#include <vdb/Exceptions.h>
#include <vdb/io/File.h>

#include "Common.h"

#include <string>
#include <vector>

namespace vdb::python {

namespace {

/// The path of a str or os.PathLike argument.
std::string pathOf(py::handle obj) {
    py::object path = py::module_::import("os").attr("fspath")(obj);
    if (!py::isinstance<py::str>(path))
        throw py::type_error("expected a str path, got " + typeNameOf(path));
    return path.cast<std::string>();
}

/// Whether the module has a Python class for the grid's C++ type.
bool representable(const GridBase& grid) {
    return py::detail::get_type_info(typeid(grid)) != nullptr;
}

/// The message for a grid of `file` that the module cannot return.
std::string skippedText(const io::File& file, const std::string& name, const std::string& type) {
    return file.filename() + ": grid \"" + name + "\" has type " + type +
           ", which this module cannot represent";
}

/// The grids of `file` in a list. Each grid the module cannot represent (of a type the library
/// cannot read, or without a Python class) is left out with a UserWarning naming it, as the
/// command-line tool warns.
py::list gridList(const io::File& file, const GridPtrVecPtr& grids) {
    std::vector<std::string> skipped;
    for (const auto& u : file.unsupportedGrids())
        skipped.push_back(skippedText(file, u.name, u.type));
    py::list out;
    if (grids) {
        for (const auto& g : *grids) {
            if (representable(*g))
                out.append(py::cast(g));
            else
                skipped.push_back(skippedText(file, g->getName(), g->type()));
        }
    }
    for (const auto& text : skipped)
        if (PyErr_WarnEx(PyExc_UserWarning, ("skipped: " + text).c_str(), 1) != 0)
            throw py::error_already_set();  // the warnings filter made it an error
    return out;
}

/// The grid `name` of the open `file`, with its tree or with metadata only.
/// @throw TypeError when the grid is of a type the module cannot represent, IoError when the
/// file has no grid of that name.
GridBase::Ptr readNamed(const io::File& file, const std::string& name, bool withTree) {
    if (!file.hasGrid(name))
        for (const auto& u : file.unsupportedGrids())
            if (u.name == name)
                throw TypeError(skippedText(file, u.name, u.type));
    GridBase::Ptr grid = withTree ? file.readGrid(name) : file.readGridMetadata(name);
    if (!representable(*grid))
        throw TypeError(skippedText(file, name, grid->type()));
    return grid;
}

}  // namespace

void bindIo(py::module_& m) {
    m.def(
        "read",
        [](py::handle path, const std::string& name) {
            const std::string p = pathOf(path);
            py::gil_scoped_release release;
            io::File file(p);
            file.open();
            return readNamed(file, name, true);
        },
        py::arg("filename"), py::arg("gridname"),
        "read(filename, gridname) -> grid: one grid of a .vdb file. Leaf values load on first "
        "access (the file stays readable through the grid). Raises OSError for a missing or "
        "corrupt file or a missing grid, TypeError for a grid of a type this module cannot "
        "represent (a points grid, ...).");
    m.def(
        "readAll",
        [](py::handle path) {
            io::File file(pathOf(path));
            GridPtrVecPtr grids;
            MetaMap meta;
            {
                py::gil_scoped_release release;
                file.open();
                grids = file.getGrids();
                meta = file.getMetadata();
            }
            return py::make_tuple(gridList(file, grids), metaMapToDict(meta));
        },
        py::arg("filename"),
        "readAll(filename) -> (grids, metadata): every grid of a .vdb file and the file's "
        "metadata dict. A grid of a type this module cannot represent (a points grid, ...) is "
        "left out with a UserWarning that names it.");
    m.def(
        "readAllGridMetadata",
        [](py::handle path) {
            io::File file(pathOf(path));
            GridPtrVecPtr grids;
            {
                py::gil_scoped_release release;
                file.open();
                grids = file.readAllGridMetadata();
            }
            return gridList(file, grids);
        },
        py::arg("filename"),
        "readAllGridMetadata(filename) -> list: every grid with its metadata and transform but "
        "an empty tree. A grid of a type this module cannot represent is left out with a "
        "UserWarning that names it.");
    m.def(
        "readGridMetadata",
        [](py::handle path, const std::string& name) {
            const std::string p = pathOf(path);
            py::gil_scoped_release release;
            io::File file(p);
            file.open();
            return readNamed(file, name, false);
        },
        py::arg("filename"), py::arg("gridname"),
        "readGridMetadata(filename, gridname) -> grid: one grid's metadata and transform, with "
        "an empty tree. Raises TypeError for a grid of a type this module cannot represent.");
    m.def(
        "readMetadata",
        [](py::handle path) {
            const std::string p = pathOf(path);
            MetaMap meta;
            {
                py::gil_scoped_release release;
                io::File file(p);
                file.open();
                meta = file.getMetadata();
            }
            return metaMapToDict(meta);
        },
        py::arg("filename"), "readMetadata(filename) -> dict: the file-level metadata.");
    m.def(
        "write",
        [](py::handle path, py::handle grids, py::object metadata) {
            const std::string p = pathOf(path);
            GridCPtrVec list;
            if (py::isinstance<GridBase>(grids)) {
                list.push_back(grids.cast<GridBase::Ptr>());
            } else {
                if (!py::isinstance<py::iterable>(grids) || py::isinstance<py::str>(grids))
                    throw py::type_error("write: expected a grid or a sequence of grids, got " +
                                         typeNameOf(grids));
                for (py::handle g : grids) {
                    if (!py::isinstance<GridBase>(g))
                        throw py::type_error("write: expected grids, got " + typeNameOf(g));
                    list.push_back(g.cast<GridBase::Ptr>());
                }
            }
            MetaMap meta;
            if (!metadata.is_none())
                updateMetaMap(meta, metadata);
            py::gil_scoped_release release;
            io::File(p).write(list, meta);
        },
        py::arg("filename"), py::arg("grids"), py::arg("metadata") = py::none(),
        "write(filename, grids, metadata=None): write a grid or a sequence of grids, and a "
        "dict of file metadata, to a .vdb file (replaced atomically). Raises OSError when the "
        "file cannot be written.");
}

}  // namespace vdb::python
