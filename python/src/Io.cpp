// SPDX-License-Identifier: Apache-2.0
// vdb.read, readAll, readAllGridMetadata, readGridMetadata, readMetadata and write: `.vdb`
// files through io::File.

#include <vdb/io/File.h>

#include "Common.h"

namespace vdb::python {

namespace {

/// The path of a str or os.PathLike argument.
std::string pathOf(py::handle obj) {
    py::object path = py::module_::import("os").attr("fspath")(obj);
    if (!py::isinstance<py::str>(path))
        throw py::type_error("expected a str path, got " + typeNameOf(path));
    return path.cast<std::string>();
}

py::list gridList(const GridPtrVecPtr& grids) {
    py::list out;
    if (grids)
        for (const auto& g : *grids)
            out.append(py::cast(g));
    return out;
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
            return file.readGrid(name);
        },
        py::arg("filename"), py::arg("gridname"),
        "read(filename, gridname) -> grid: one grid of a .vdb file. Leaf values load on first "
        "access (the file stays readable through the grid). Raises OSError for a missing or "
        "corrupt file or a missing grid.");
    m.def(
        "readAll",
        [](py::handle path) {
            const std::string p = pathOf(path);
            GridPtrVecPtr grids;
            MetaMap meta;
            {
                py::gil_scoped_release release;
                io::File file(p);
                file.open();
                grids = file.getGrids();
                meta = file.getMetadata();
            }
            return py::make_tuple(gridList(grids), metaMapToDict(meta));
        },
        py::arg("filename"),
        "readAll(filename) -> (grids, metadata): every grid of a .vdb file and the file's "
        "metadata dict.");
    m.def(
        "readAllGridMetadata",
        [](py::handle path) {
            const std::string p = pathOf(path);
            GridPtrVecPtr grids;
            {
                py::gil_scoped_release release;
                io::File file(p);
                file.open();
                grids = file.readAllGridMetadata();
            }
            return gridList(grids);
        },
        py::arg("filename"),
        "readAllGridMetadata(filename) -> list: every grid with its metadata and transform but "
        "an empty tree.");
    m.def(
        "readGridMetadata",
        [](py::handle path, const std::string& name) {
            const std::string p = pathOf(path);
            py::gil_scoped_release release;
            io::File file(p);
            file.open();
            return file.readGridMetadata(name);
        },
        py::arg("filename"), py::arg("gridname"),
        "readGridMetadata(filename, gridname) -> grid: one grid's metadata and transform, with "
        "an empty tree.");
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
