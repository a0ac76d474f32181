// SPDX-License-Identifier: Apache-2.0
/// @file
/// bindGrid<GridT>(): the Python class of one grid type (FloatGrid, Vec3SGrid, ...) with
/// pyopenvdb's methods and the bulk NumPy transfers, and its nested Accessor, ConstAccessor,
/// ValueIter and Value classes. Included by one source file per group of grid types.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Math.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/Dense.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tools/VolumeToMesh.h>
#include <vdb/util/Parallel.h>

#include "Common.h"
#include "GridStructure.h"
#include "TreeBlocks.h"
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace vdb::python {

// ---- Value helpers

/// Strict weak order of values for evalMinMax(): numbers by value, vectors lexicographically
/// (as pyopenvdb orders them).
template <typename ValueT>
bool valueLess(const ValueT& a, const ValueT& b) {
    if constexpr (ValueTraits<ValueT>::N == 3) {
        return std::make_tuple(a[0], a[1], a[2]) < std::make_tuple(b[0], b[1], b[2]);
    } else {
        return a < b;
    }
}

/// A tolerance from a number (also for vectors: every component) or a value.
template <typename ValueT>
ValueT toTolerance(py::handle obj) {
    if constexpr (ValueTraits<ValueT>::N == 3) {
        if (PyNumber_Check(obj.ptr()) && !PySequence_Check(obj.ptr()))
            return ValueT(toValue<typename ValueTraits<ValueT>::Scalar>(obj, "tolerance"));
    }
    return toValue<ValueT>(obj, "tolerance");
}

/// The values of leaf `leaf` (loaded if out of core) into `out`, NUM_VALUES of them.
template <typename LeafT, typename ValueT>
void readLeaf(const LeafT& leaf, ValueT* out) {
    if constexpr (requires {
                      { leaf.buffer(0).data() } -> std::convertible_to<const ValueT*>;
                  }) {
        std::memcpy(out, leaf.buffer(0).data(), sizeof(ValueT) * LeafT::NUM_VALUES);
    } else {
        for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
            out[n] = leaf.getValue(n);
    }
}

/// True for leaves whose values are an array that NumPy can view.
template <typename LeafT>
constexpr bool HAS_VALUE_BUFFER = requires(LeafT& leaf) {
    { leaf.buffer(0).data() } -> std::convertible_to<typename LeafT::ValueType*>;
};

// ---- NumPy arrays as dense boxes

/// A tools::Dense over a NumPy array: a view of its memory when the dtype is the grid's and the
/// strides are whole values, else over a converted C-ordered copy (`converted`), which
/// copyToArray writes back into `target`.
template <typename ValueT>
struct ArrayBox {
    py::array keep;                  // the array whose memory `dense` views
    py::object target = py::none();  // for a converted copy being written: the caller's array
    std::unique_ptr<tools::Dense<ValueT>> dense;  // null for an empty array
};

template <typename ValueT>
ArrayBox<ValueT> arrayBox(py::handle obj, const Coord& origin, bool forWriting, const char* op) {
    using Traits = ValueTraits<ValueT>;
    using Scalar = typename Traits::Scalar;
    if (!py::isinstance<py::array>(obj))
        throw py::type_error(std::string(op) + ": expected a NumPy array, got " + typeNameOf(obj));
    auto array = py::reinterpret_borrow<py::array>(obj);
    const py::ssize_t rank = Traits::N == 1 ? 3 : 4;
    if (array.ndim() != rank || (Traits::N == 3 && array.shape(3) != 3)) {
        std::ostringstream msg;
        msg << op << ": expected a " << rank << "-dimensional array"
            << (Traits::N == 3 ? " of shape (X, Y, Z, 3)" : "") << ", found one of shape (";
        for (py::ssize_t i = 0; i < array.ndim(); ++i)
            msg << (i ? ", " : "") << array.shape(i);
        msg << (array.ndim() == 1 ? ",)" : ")");
        throw py::value_error(msg.str());
    }
    const char kind = array.dtype().kind();
    if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
        throw py::type_error(std::string(op) +
                             ": expected an array of numbers or bools, got dtype " +
                             std::string(py::str(array.dtype())));
    if (forWriting && !array.writeable())
        throw py::value_error(std::string(op) + ": the array is read-only");
    ArrayBox<ValueT> box;
    if (array.size() == 0)
        return box;
    Coord max;
    for (int i = 0; i < 3; ++i) {
        const Int64 hi = Int64(origin[i]) + Int64(array.shape(i)) - 1;
        if (hi > std::numeric_limits<Int32>::max())
            throw py::index_error(std::string(op) +
                                  ": the array reaches beyond the 32-bit index "
                                  "space from (i, j, k) = " +
                                  std::string(py::str(py::cast(origin))));
        max[i] = Int32(hi);
    }
    const CoordBBox bbox(origin, max);

    bool direct = array.dtype().equal(py::dtype::of<Scalar>()) &&
                  reinterpret_cast<uintptr_t>(array.data()) % alignof(Scalar) == 0;
    for (int i = 0; i < 3 && direct; ++i)
        direct = array.strides(i) % py::ssize_t(sizeof(ValueT)) == 0;
    if (Traits::N == 3 && direct)
        direct = array.strides(3) == py::ssize_t(sizeof(Scalar));
    if (direct) {
        box.keep = array;
    } else if (forWriting) {
        std::vector<py::ssize_t> shape(array.shape(), array.shape() + array.ndim());
        box.keep = py::array_t<Scalar, py::array::c_style>(shape);
        box.target = array;
    } else {
        box.keep = py::array_t<Scalar, py::array::c_style | py::array::forcecast>::ensure(array);
        if (!box.keep)
            throw py::error_already_set();
    }
    const std::array<std::ptrdiff_t, 3> strides{
        std::ptrdiff_t(box.keep.strides(0) / py::ssize_t(sizeof(ValueT))),
        std::ptrdiff_t(box.keep.strides(1) / py::ssize_t(sizeof(ValueT))),
        std::ptrdiff_t(box.keep.strides(2) / py::ssize_t(sizeof(ValueT)))};
    auto* data = static_cast<ValueT*>(const_cast<void*>(box.keep.data()));
    box.dense = std::make_unique<tools::Dense<ValueT>>(bbox, data, strides);
    return box;
}

/// Checks an (N, 3) array of integer coordinates and returns them as int64, converting when
/// needed. @throw TypeError for other dtypes, ValueError for other shapes.
inline py::array_t<Int64, py::array::c_style> coordArray(py::handle obj, const char* op) {
    py::object held = py::isinstance<py::array>(obj)
                          ? py::reinterpret_borrow<py::object>(obj)
                          : py::object(py::module_::import("numpy").attr("asarray")(obj));
    auto array = py::reinterpret_borrow<py::array>(held);
    const char kind = array.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw py::type_error(std::string(op) + ": coordinates must be integers, got dtype " +
                             std::string(py::str(array.dtype())));
    if (array.ndim() != 2 || array.shape(1) != 3)
        throw py::value_error(std::string(op) + ": expected coordinates of shape (N, 3), got " +
                              std::string(py::str(array.attr("shape"))));
    auto result = py::array_t<Int64, py::array::c_style | py::array::forcecast>::ensure(array);
    if (!result)
        throw py::error_already_set();
    return result;
}

// ---- Accessors, value proxies and iterators

template <typename GridT, bool IsConst>
struct PyAccessor {
    using TreeT = typename GridT::TreeType;
    using AccT = tree::ValueAccessor<std::conditional_t<IsConst, const TreeT, TreeT>>;
    typename GridT::Ptr grid;
    typename GridT::TreePtr tree;  // kept alive with the accessor
    AccT acc;
    explicit PyAccessor(typename GridT::Ptr g) : grid(g), tree(g->treePtr()), acc(*tree) {}
};

/// A voxel or tile of a grid, as the value iterators yield it: reads and writes go to the
/// grid at the time of the call.
template <typename GridT>
struct PyValue {
    typename GridT::Ptr grid;
    Coord min;
    Index level = 0;
    bool writable = false;
};

template <typename GridT>
struct PyValueIter {
    using TreeT = typename GridT::TreeType;
    typename GridT::Ptr grid;
    std::vector<Block<TreeT>> blocks;  // leaves by origin only; re-found at each step
    ValueFilter filter = ValueFilter::On;
    bool writable = false;
    size_t block = 0;
    Index pos = 0;  // next voxel offset in the current leaf
};

/// The next item of `it`, or null when done. Leaves are found again by origin at each step,
/// so that the grid may change under the iterator (a leaf freed meanwhile is skipped).
template <typename GridT>
std::optional<PyValue<GridT>> nextValue(PyValueIter<GridT>& it) {
    using TreeT = typename GridT::TreeType;
    using LeafT = typename TreeT::LeafNodeType;
    TreeT& tree = it.grid->tree();
    while (it.block < it.blocks.size()) {
        const Block<TreeT>& b = it.blocks[it.block];
        if (b.level > 0) {
            ++it.block;
            return PyValue<GridT>{it.grid, b.origin, b.level, it.writable};
        }
        if (const LeafT* leaf = tree.probeConstLeaf(b.origin)) {
            const auto& mask = leaf->getValueMask();
            for (; it.pos < LeafT::NUM_VALUES; ++it.pos) {
                const bool on = mask.isOn(it.pos);
                if (it.filter == ValueFilter::All || on == (it.filter == ValueFilter::On)) {
                    const Index n = it.pos++;
                    return PyValue<GridT>{it.grid, leaf->offsetToGlobalCoord(n), 0, it.writable};
                }
            }
        }
        ++it.block;
        it.pos = 0;
    }
    return std::nullopt;
}

/// Sets the value (and state) of a block of `level` at `ijk`: a voxel, or a tile.
template <typename TreeT>
void setBlock(TreeT& tree, Index level, const Coord& ijk, const typename TreeT::ValueType& value,
              bool active) {
    if (level == 0) {
        if (active)
            tree.setValueOn(ijk, value);
        else
            tree.setValueOff(ijk, value);
    } else {
        tree.addTile(level, ijk, value, active);
    }
}

// ---- The grid class

template <typename GridT>
void bindGrid(py::module_& m, const char* name, const char* doc) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    using LeafT = typename TreeT::LeafNodeType;
    using Traits = ValueTraits<ValueT>;
    using Scalar = typename Traits::Scalar;
    using GridPtr = typename GridT::Ptr;
    constexpr bool IS_MASK = tree::IS_MASK_NODE<typename TreeT::LeafNodeType>;
    constexpr bool IS_FLOAT = std::is_floating_point_v<ValueT>;
    constexpr Index DEPTH = TreeT::DEPTH;

    py::class_<GridT, GridBase, GridPtr> cls(m, name, doc);

    // Value arrays of `count` values: shape (count,) or (count, 3), or with leaf dims.
    const auto valueShape = [](std::vector<py::ssize_t> shape) {
        if (Traits::N == 3)
            shape.push_back(3);
        return shape;
    };

    cls.def(py::init([name](py::object background) {
                return GridT::create(background.is_none() ? ValueT{}
                                                          : toValue<ValueT>(background, name));
            }),
            py::arg("background") = py::none(),
            "Creates an empty grid with the given background value (default zero).");

    // ---- Values
    cls.def_property(
        "background", [](const GridT& g) { return g.background(); },
        [](GridT& g, py::handle value) {
            const ValueT bg = toValue<ValueT>(value, "background");
            const ValueT old = g.background();
            TreeT& tree = g.tree();
            py::gil_scoped_release release;
            // pyopenvdb's meaning (OpenVDB's tools::changeBackground): inactive values equal to
            // the old background become the new one, and for signed values, those equal to
            // minus the old background become minus the new one; in leaves and in tiles.
            const auto replacement = [&](const ValueT& v, ValueT& out) {
                if (math::isApproxEqual(v, old, math::Tolerance<ValueT>::value())) {
                    out = bg;
                    return true;
                }
                if constexpr (!std::is_same_v<ValueT, bool> && std::is_signed_v<Scalar>) {
                    if (math::isApproxEqual(v, ValueT(-old), math::Tolerance<ValueT>::value())) {
                        out = ValueT(-bg);
                        return true;
                    }
                }
                return false;
            };
            std::vector<Block<TreeT>> blocks = collectBlocks(tree, ValueFilter::Off, true);
            util::parallelFor(blocks.size(), [&](size_t i) {
                if (LeafT* leaf = blocks[i].leaf) {
                    ValueT out;
                    for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                        if (!leaf->isValueOn(n) && replacement(ValueT(leaf->getValue(n)), out))
                            leaf->setValueOnly(n, out);
                }
            });
            for (const auto& b : blocks) {
                ValueT out;
                if (!b.leaf && replacement(b.value, out))
                    tree.addTile(b.level, b.origin, out, false);
            }
            tree.setBackground(bg);
        },
        "value of this grid's background voxels; setting it also replaces the inactive values "
        "equal to the old background");
    cls.def_property_readonly_static("zeroValue", [](py::object) { return ValueT{}; });
    cls.def_property_readonly_static("oneValue", [](py::object) {
        if constexpr (std::is_same_v<ValueT, bool>)
            return true;
        else
            return ValueT(1);
    });
    cls.def_property_readonly_static("valueTypeName", [](py::object) {
        return std::string(typeName<typename TreeT::BuildType>());
    });
    cls.def_property_readonly_static(
        "dtype", [](py::object) { return scalarDtype<ValueT>(); },
        "the NumPy dtype of this grid's values (of one component "
        "for vector grids)");
    cls.def_property_readonly(
        "treeDepth", [](const GridT&) { return DEPTH; },
        "depth of this grid's tree from root node to leaf node");
    bindGridStructure<GridT>(cls);

    cls.def(
        "getAccessor", [](GridPtr g) { return PyAccessor<GridT, false>(g); },
        "getAccessor() -> Accessor: random read and write access by (i, j, k).");
    cls.def(
        "getConstAccessor", [](GridPtr g) { return PyAccessor<GridT, true>(g); },
        "getConstAccessor() -> ConstAccessor: random read-only access by (i, j, k).");

    cls.def(
        "activeLeafVoxelCount", [](const GridT& g) { return g.tree().activeLeafVoxelCount(); },
        "activeLeafVoxelCount() -> int: active voxels stored in leaves.");
    cls.def(
        "nonLeafCount", [](const GridT& g) { return g.tree().nonLeafCount(); },
        "nonLeafCount() -> int");
    cls.def(
        "evalMinMax",
        [](const GridT& g) {
            const TreeT& tree = g.tree();
            std::pair<ValueT, ValueT> r{};
            {
                py::gil_scoped_release release;
                const auto blocks = collectBlocks(tree, ValueFilter::On, true);
                struct MinMax {
                    bool any = false;
                    ValueT lo{}, hi{};
                    void add(const ValueT& v) {
                        if (!any) {
                            lo = hi = v;
                            any = true;
                        } else {
                            if (valueLess(v, lo))
                                lo = v;
                            if (valueLess(hi, v))
                                hi = v;
                        }
                    }
                };
                const MinMax mm = util::parallelReduce(
                    blocks.size(), MinMax{},
                    [&](size_t begin, size_t end) {
                        MinMax acc;
                        for (size_t i = begin; i < end; ++i) {
                            const auto& b = blocks[i];
                            if (!b.leaf) {
                                acc.add(b.value);
                                continue;
                            }
                            for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                                if (b.leaf->isValueOn(n))
                                    acc.add(ValueT(b.leaf->getValue(n)));
                        }
                        return acc;
                    },
                    [](MinMax x, const MinMax& y) {
                        if (y.any) {
                            x.add(y.lo);
                            x.add(y.hi);
                        }
                        return x;
                    });
                if (mm.any)
                    r = {mm.lo, mm.hi};
            }
            return py::make_tuple(r.first, r.second);
        },
        "evalMinMax() -> (min, max): the least and greatest active values (vectors compare "
        "lexicographically); zero for a grid without active values.");

    cls.def(
        "prune",
        [](GridT& g, py::object tolerance) {
            checkUnpinned(&g.tree(), "prune");
            const ValueT tol = tolerance.is_none() ? ValueT{} : toTolerance<ValueT>(tolerance);
            py::gil_scoped_release release;
            tools::prune(g.tree(), tol);
        },
        py::arg("tolerance") = 0,
        "prune(tolerance=0): replace nodes whose values share one active state and lie "
        "within the tolerance of each other with tiles.");
    cls.def(
        "pruneInactive",
        [](GridT& g, py::object value) {
            checkUnpinned(&g.tree(), "pruneInactive");
            if (value.is_none()) {
                py::gil_scoped_release release;
                tools::pruneInactive(g.tree());
            } else {
                const ValueT v = toValue<ValueT>(value, "pruneInactive");
                py::gil_scoped_release release;
                tools::pruneInactiveWithValue(g.tree(), v);
            }
        },
        py::arg("value") = py::none(),
        "pruneInactive(value=None): replace nodes whose values are all inactive with "
        "inactive tiles of the background (or of the given value).");
    cls.def(
        "signedFloodFill",
        [name](GridT& g) {
            if constexpr (tools::SignedVdbTree<TreeT>) {
                py::gil_scoped_release release;
                tools::signedFloodFill(g.tree());
            } else {
                throw py::type_error(std::string("signedFloodFill needs a grid of signed "
                                                 "values, not a ") +
                                     name);
            }
        },
        "signedFloodFill(): propagate the sign of a narrow-band level set into its "
        "inactive voxels and tiles.");
    cls.def(
        "fill",
        [](GridT& g, const Coord& min, const Coord& max, py::handle value, bool active) {
            checkUnpinned(&g.tree(), "fill");
            const ValueT v = toValue<ValueT>(value, "fill");
            const CoordBBox box(min, max);
            if (box.empty())
                return;
            py::gil_scoped_release release;
            g.tree().fill(box, v, active);
        },
        py::arg("min"), py::arg("max"), py::arg("value"), py::arg("active") = true,
        "fill(min, max, value, active=True): set every voxel of the inclusive box "
        "[min, max] to the value and state (whole nodes become tiles).");

    cls.def(
        "clear",
        [](GridT& g) {
            checkUnpinned(&g.tree(), "clear");
            g.clear();
        },
        "clear(): remove every node and tile.");
    cls.def(
        "copy", [](const GridT& g) { return g.copy(); },
        "copy() -> grid: a shallow copy that shares this grid's tree.");
    cls.def(
        "deepCopy",
        [](const GridT& g) {
            py::gil_scoped_release release;
            return g.deepCopy();
        },
        "deepCopy() -> grid: a copy with its own tree.");
    // pickle (every protocol) and copy.deepcopy: the grid as a one-grid .vdb archive at full
    // precision, so that values, states, tiles, metadata, transform and class all come back.
    cls.def(
        "__reduce__", [](const GridPtr& g) { return reduceGrid(g); },
        "__reduce__() -> (vdb._restore_grid, (bytes,)): for pickle and copy.deepcopy.");
    cls.def(
        "sharesWith",
        [](const GridT& g, py::handle other) {
            return py::isinstance<GridT>(other) &&
                   other.cast<const GridT&>().treePtr() == g.treePtr();
        },
        py::arg("other"), "sharesWith(grid) -> bool: True if the grids share one tree.");

    cls.def(
        "combine",
        [](GridT& g, GridT& other, py::function fn) {
            checkUnpinned(&g.tree(), "combine");
            checkUnpinned(&other.tree(), "combine");
            if (g.treePtr() == other.treePtr())
                throw py::value_error("combine: the grids share one tree");
            // pyopenvdb's combine: Tree::combine with pruning, one Python call per value.
            tools::combine(
                g.tree(), other.tree(),
                [&](const ValueT& a, const ValueT& b, ValueT& result) {
                    result = toValue<ValueT>(fn(a, b), "combine");
                },
                /*prune=*/true, /*threaded=*/false);
        },
        py::arg("grid"), py::arg("function"),
        "combine(grid, function): set every value (tile or voxel, and the background) of "
        "this grid to function(a, b) of it and the other grid's value there; a value is "
        "active where either was; then prunes nodes left constant, as pyopenvdb does. Empties "
        "the other grid.\n"
        "Example: grid.combine(other, lambda a, b: min(a, b))");
    cls.def(
        "merge",
        [](GridT& g, GridT& other) {
            checkUnpinned(&g.tree(), "merge");
            checkUnpinned(&other.tree(), "merge");
            if (g.treePtr() == other.treePtr())
                throw py::value_error("merge: the grids share one tree");
            py::gil_scoped_release release;
            tools::combineExtended(g.tree(), other.tree(), [](CombineArgs<ValueT>& args) {
                const bool takeB = !args.aIsActive() && args.bIsActive();
                args.setResult(takeB ? args.b() : args.a());
                args.setResultIsActive(args.aIsActive() || takeB);
            });
        },
        py::arg("other"),
        "merge(grid): take the other grid's active values (voxels and tiles) wherever this "
        "grid's values are inactive (OpenVDB's MERGE_ACTIVE_STATES). Empties the other "
        "grid.");

    // ---- Iterators
    const auto makeIter = [](GridPtr g, ValueFilter filter, bool writable) {
        PyValueIter<GridT> it;
        it.grid = g;
        it.filter = filter;
        it.writable = writable;
        it.blocks = collectBlocks(g->tree(), filter, true);
        for (auto& b : it.blocks)
            b.leaf = nullptr;  // found again by origin at each step
        return it;
    };
    struct IterDef {
        const char* name;
        ValueFilter filter;
        bool writable;
        const char* doc;
    };
    for (const IterDef& d : {
             IterDef{"iterOnValues", ValueFilter::On, true,
                     "iterOnValues() -> iterator: read/write iterator over the active values "
                     "(tiles and voxels)."},
             IterDef{"iterOffValues", ValueFilter::Off, true,
                     "iterOffValues() -> iterator: read/write iterator over the inactive values."},
             IterDef{"iterAllValues", ValueFilter::All, true,
                     "iterAllValues() -> iterator: read/write iterator over all stored values."},
             IterDef{"citerOnValues", ValueFilter::On, false,
                     "citerOnValues() -> iterator: read-only iterator over the active values."},
             IterDef{"citerOffValues", ValueFilter::Off, false,
                     "citerOffValues() -> iterator: read-only iterator over the inactive values."},
             IterDef{"citerAllValues", ValueFilter::All, false,
                     "citerAllValues() -> iterator: read-only iterator over all stored values."},
         }) {
        const ValueFilter filter = d.filter;
        const bool writable = d.writable;
        cls.def(
            d.name, [=](GridPtr g) { return makeIter(g, filter, writable); }, d.doc);
    }
    for (const IterDef& d : {
             IterDef{"mapOn", ValueFilter::On, true,
                     "mapOn(function): replace every active value v with function(v)."},
             IterDef{"mapOff", ValueFilter::Off, true,
                     "mapOff(function): replace every inactive value v with function(v)."},
             IterDef{"mapAll", ValueFilter::All, true,
                     "mapAll(function): replace every stored value v with function(v)."},
         }) {
        const ValueFilter filter = d.filter;
        cls.def(
            d.name,
            [=](GridPtr g, py::function fn) {
                auto it = makeIter(g, filter, true);
                TreeT& tree = g->tree();
                while (auto v = nextValue(it)) {
                    const ValueT result = toValue<ValueT>(fn(tree.getValue(v->min)), d.name);
                    setBlock(tree, v->level, v->min, result, tree.isValueOn(v->min));
                }
            },
            py::arg("function"), d.doc);
    }

    // ---- Dense arrays
    cls.def(
        "copyFromArray",
        [](GridT& g, py::handle array, const Coord& ijk, py::object tolerance) {
            checkUnpinned(&g.tree(), "copyFromArray");
            const ValueT tol = tolerance.is_none() ? ValueT{} : toTolerance<ValueT>(tolerance);
            ArrayBox<ValueT> box = arrayBox<ValueT>(array, ijk, false, "copyFromArray");
            if (!box.dense)
                return;
            py::gil_scoped_release release;
            tools::copyFromDense(*box.dense, g, tol);
        },
        py::arg("array"), py::arg("ijk") = Coord(0), py::arg("tolerance") = ValueT{},
        "copyFromArray(array, ijk=(0, 0, 0), tolerance=0): set the voxels of the box that "
        "starts at ijk from a 3-D array (4-D, last axis 3, for vector grids) indexed [x][y][z]; "
        "voxels within the tolerance of the background become inactive background.\n"
        "No copy is made when the array's dtype is the grid's (dtype) and its strides are "
        "whole values (any order, slices and negative steps included); other numeric dtypes "
        "are converted through a temporary copy. Raises TypeError for a non-numeric array, "
        "ValueError for a wrong shape, IndexError beyond the 32-bit index space.");
    cls.def(
        "copyToArray",
        [](const GridT& g, py::handle array, const Coord& ijk) {
            ArrayBox<ValueT> box = arrayBox<ValueT>(array, ijk, true, "copyToArray");
            if (!box.dense)
                return;
            {
                py::gil_scoped_release release;
                tools::copyToDense(g, *box.dense);
            }
            if (!box.target.is_none())
                py::module_::import("numpy").attr("copyto")(box.target, box.keep,
                                                            py::arg("casting") = "unsafe");
        },
        py::arg("array"), py::arg("ijk") = Coord(0),
        "copyToArray(array, ijk=(0, 0, 0)): fill a writable 3-D array (4-D, last axis 3, for "
        "vector grids) indexed [x][y][z] with the grid's values over the box that starts at "
        "ijk. Written in place when the dtype is the grid's and the strides are whole values; "
        "other numeric dtypes are filled through a temporary copy (unsafe casting, as "
        "numpy.copyto).");

    // ---- Bulk transfers
    cls.def(
        "activeVoxels",
        [valueShape](const GridT& g) {
            const TreeT& tree = g.tree();
            std::vector<Block<TreeT>> blocks;
            std::vector<Index64> offsets;
            {
                py::gil_scoped_release release;
                blocks = collectBlocks(tree, ValueFilter::On, true);
                offsets.resize(blocks.size() + 1, 0);
                for (size_t i = 0; i < blocks.size(); ++i) {
                    const Int64 dim = blockDim<TreeT>(blocks[i].level);
                    offsets[i + 1] = offsets[i] + (blocks[i].leaf ? blocks[i].leaf->onVoxelCount()
                                                                  : Index64(dim * dim * dim));
                }
            }
            const Index64 total = offsets.back();
            if (total > Index64(std::numeric_limits<py::ssize_t>::max() / 24))
                throw py::value_error("activeVoxels: " + std::to_string(total) +
                                      " active voxels are more than an array can hold");
            py::array_t<Int32> coords({py::ssize_t(total), py::ssize_t(3)});
            py::array_t<Scalar> values(valueShape({py::ssize_t(total)}));
            Int32* c = coords.mutable_data();
            ValueT* v = reinterpret_cast<ValueT*>(values.mutable_data());
            {
                py::gil_scoped_release release;
                util::parallelFor(
                    blocks.size(),
                    [&](size_t i) {
                        const auto& b = blocks[i];
                        Index64 k = offsets[i];
                        if (b.leaf) {
                            const auto& mask = b.leaf->getValueMask();
                            for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
                                if (!mask.isOn(n))
                                    continue;
                                const Coord ijk = b.leaf->offsetToGlobalCoord(n);
                                std::memcpy(c + 3 * k, &ijk, sizeof(Int32) * 3);
                                v[k++] = ValueT(b.leaf->getValue(n));
                            }
                            return;
                        }
                        const Int64 dim = blockDim<TreeT>(b.level);
                        for (Int64 x = 0; x < dim; ++x)
                            for (Int64 y = 0; y < dim; ++y)
                                for (Int64 z = 0; z < dim; ++z, ++k) {
                                    c[3 * k] = Int32(b.origin[0] + x);
                                    c[3 * k + 1] = Int32(b.origin[1] + y);
                                    c[3 * k + 2] = Int32(b.origin[2] + z);
                                    v[k] = b.value;
                                }
                    },
                    true, 16);
            }
            return py::make_tuple(coords, values);
        },
        "activeVoxels() -> (coords, values): every active voxel, as an (N, 3) int32 array of "
        "(i, j, k) and an (N,) array of values ((N, 3) for vector grids) of the grid's dtype. "
        "Order: leaf by leaf in the order of iterOnValues(), voxels in z-fastest order within a "
        "leaf, and each active tile as its voxels in [x][y][z] order at its place in that "
        "sequence. New arrays (a copy).");

    cls.def_static(
        "fromCoords",
        [name](py::handle coordsObj, py::object valuesObj, py::object background) {
            const ValueT bg =
                background.is_none() ? ValueT{} : toValue<ValueT>(background, "background");
            auto coords = coordArray(coordsObj, "fromCoords");
            const size_t count = size_t(coords.shape(0));
            py::array_t<Scalar, py::array::c_style | py::array::forcecast> values;
            if constexpr (IS_MASK) {
                if (!valuesObj.is_none())
                    throw py::type_error("fromCoords: a MaskGrid has no values; pass None");
            } else {
                if (valuesObj.is_none())
                    throw py::type_error("fromCoords: values are required for a " +
                                         std::string(name));
                if (!py::isinstance<py::array>(valuesObj))
                    valuesObj = py::module_::import("numpy").attr("asarray")(valuesObj);
                auto arr = py::reinterpret_borrow<py::array>(valuesObj);
                const char kind = arr.dtype().kind();
                if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
                    throw py::type_error("fromCoords: values must be numbers or bools, got dtype " +
                                         std::string(py::str(arr.dtype())));
                const bool shapeOk =
                    Traits::N == 1
                        ? arr.ndim() == 1 && size_t(arr.shape(0)) == count
                        : arr.ndim() == 2 && size_t(arr.shape(0)) == count && arr.shape(1) == 3;
                if (!shapeOk)
                    throw py::value_error("fromCoords: expected values of shape (" +
                                          std::to_string(count) + (Traits::N == 3 ? ", 3)" : ",)") +
                                          ", got " + std::string(py::str(arr.attr("shape"))));
                values =
                    py::array_t<Scalar, py::array::c_style | py::array::forcecast>::ensure(arr);
                if (!values)
                    throw py::error_already_set();
            }
            const Int64* c = coords.data();
            const ValueT* v = IS_MASK ? nullptr : reinterpret_cast<const ValueT*>(values.data());
            GridPtr grid = GridT::create(bg);
            {
                py::gil_scoped_release release;
                for (size_t i = 0; i < 3 * count; ++i)
                    if (c[i] < std::numeric_limits<Int32>::min() ||
                        c[i] > std::numeric_limits<Int32>::max()) {
                        py::gil_scoped_acquire acquire;
                        throw py::index_error("fromCoords: coordinate " + std::to_string(c[i]) +
                                              " (row " + std::to_string(i / 3) +
                                              ") is outside the 32-bit index space");
                    }
                // Sort the points by leaf (then by input order, so the last of repeated
                // coordinates wins), build the leaves in parallel, then link them in order.
                const auto leafOf = [c](size_t i) {
                    return Coord{Int32(c[3 * i]), Int32(c[3 * i + 1]), Int32(c[3 * i + 2])}
                        .alignedDown(LeafT::LOG2DIM);
                };
                std::vector<std::pair<Coord, uint64_t>> order(count);
                util::parallelFor(
                    count,
                    [&](size_t i) {
                        order[i] = {leafOf(i), i};
                    },
                    true, 4096);
                tbb::parallel_sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
                    const Coord &x = a.first, &y = b.first;
                    return std::make_tuple(x[0], x[1], x[2], a.second) <
                           std::make_tuple(y[0], y[1], y[2], b.second);
                });
                std::vector<size_t> starts;
                for (size_t i = 0; i < count; ++i)
                    if (i == 0 || order[i].first != order[i - 1].first)
                        starts.push_back(i);
                starts.push_back(count);
                std::vector<std::unique_ptr<LeafT>> leaves(starts.size() - 1);
                util::parallelFor(
                    leaves.size(),
                    [&](size_t l) {
                        auto leaf = std::make_unique<LeafT>(order[starts[l]].first, bg, false);
                        for (size_t s = starts[l]; s < starts[l + 1]; ++s) {
                            const size_t i = order[s].second;
                            const Coord ijk{Int32(c[3 * i]), Int32(c[3 * i + 1]),
                                            Int32(c[3 * i + 2])};
                            if constexpr (IS_MASK)
                                leaf->setValueOn(LeafT::coordToOffset(ijk));
                            else
                                leaf->setValueOn(LeafT::coordToOffset(ijk), v[i]);
                        }
                        leaves[l] = std::move(leaf);
                    },
                    true, 16);
                for (auto& leaf : leaves)
                    grid->tree().addLeaf(std::move(leaf));
            }
            return grid;
        },
        py::arg("coords"), py::arg("values") = py::none(), py::arg("background") = py::none(),
        "fromCoords(coords, values, background=0) -> grid: a grid whose active voxels are the "
        "(N, 3) integer coords with the (N,) values ((N, 3) for vector grids; None for a "
        "MaskGrid); of repeated coordinates the last wins. Built leaf by leaf in parallel; the "
        "arrays are read in place when they have the grid's dtypes and are C-ordered, else "
        "converted. Raises TypeError for non-integer coords or non-numeric values, ValueError "
        "for wrong shapes, IndexError for coordinates beyond 32 bits.");

    cls.def(
        "leafOrigins",
        [](const GridT& g) {
            const auto blocks = collectBlocks(g.tree(), ValueFilter::On, true);
            std::vector<Coord> origins;
            for (const auto& b : blocks)
                if (b.leaf)
                    origins.push_back(b.origin);
            py::array_t<Int32> out({py::ssize_t(origins.size()), py::ssize_t(3)});
            if (!origins.empty())
                std::memcpy(out.mutable_data(), origins.data(), origins.size() * sizeof(Coord));
            return out;
        },
        "leafOrigins() -> (L, 3) int32 array: the origin of every leaf, in the order of "
        "leafValues() and leafBuffers(). A new array.");
    cls.def(
        "leafValues",
        [valueShape](const GridT& g) {
            std::vector<const LeafT*> leaves;
            for (const auto& b : collectBlocks(g.tree(), ValueFilter::On, true))
                if (b.leaf)
                    leaves.push_back(b.leaf);
            constexpr py::ssize_t D = LeafT::DIM;
            py::array_t<Scalar> out(valueShape({py::ssize_t(leaves.size()), D, D, D}));
            ValueT* dst = reinterpret_cast<ValueT*>(out.mutable_data());
            py::gil_scoped_release release;
            util::parallelFor(leaves.size(),
                              [&](size_t i) { readLeaf(*leaves[i], dst + i * LeafT::NUM_VALUES); });
            return out;
        },
        "leafValues() -> (L, 8, 8, 8) array ((L, 8, 8, 8, 3) for vector grids): the values of "
        "every leaf, indexed [leaf][x][y][z] relative to its origin (leafOrigins()). A new "
        "array (a copy): leaves are separate blocks of memory. For views without a copy see "
        "leafBuffers(); to write values back, setLeafValues().");
    cls.def(
        "setLeafValues",
        [](GridT& g, py::handle array) {
            std::vector<LeafT*> leaves;
            for (const auto& b : collectBlocks(g.tree(), ValueFilter::On, true))
                if (b.leaf)
                    leaves.push_back(b.leaf);
            if (!py::isinstance<py::array>(array))
                throw py::type_error("setLeafValues: expected a NumPy array, got " +
                                     typeNameOf(array));
            auto arr = py::reinterpret_borrow<py::array>(array);
            const char kind = arr.dtype().kind();
            if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
                throw py::type_error(
                    "setLeafValues: expected an array of numbers or bools, got dtype " +
                    std::string(py::str(arr.dtype())));
            constexpr py::ssize_t D = LeafT::DIM;
            bool shapeOk = arr.ndim() == (Traits::N == 3 ? 5 : 4) &&
                           size_t(arr.shape(0)) == leaves.size() && arr.shape(1) == D &&
                           arr.shape(2) == D && arr.shape(3) == D &&
                           (Traits::N == 1 || arr.shape(4) == 3);
            if (!shapeOk)
                throw py::value_error("setLeafValues: expected an array of shape (" +
                                      std::to_string(leaves.size()) + ", 8, 8, 8" +
                                      (Traits::N == 3 ? ", 3)" : ")") + ", got " +
                                      std::string(py::str(arr.attr("shape"))));
            auto src = py::array_t<Scalar, py::array::c_style | py::array::forcecast>::ensure(arr);
            if (!src)
                throw py::error_already_set();
            const ValueT* s = reinterpret_cast<const ValueT*>(src.data());
            py::gil_scoped_release release;
            util::parallelFor(leaves.size(), [&](size_t i) {
                for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                    leaves[i]->setValueOnly(n, s[i * LeafT::NUM_VALUES + n]);
            });
        },
        py::arg("array"),
        "setLeafValues(array): write an array shaped like leafValues() back into the leaves "
        "(in leafOrigins() order); active states are unchanged.");
    cls.def(
        "leafBuffers",
        [name](GridPtr g) {
            if constexpr (!HAS_VALUE_BUFFER<LeafT>) {
                throw py::type_error(std::string("leafBuffers: the leaves of a ") + name +
                                     " store their values as bits, which NumPy cannot view; "
                                     "use leafValues()");
                return py::list();
            } else {
                std::vector<LeafT*> leaves;
                for (const auto& b : collectBlocks(g->tree(), ValueFilter::On, true))
                    if (b.leaf)
                        leaves.push_back(b.leaf);
                {
                    py::gil_scoped_release release;
                    util::parallelFor(leaves.size(), [&](size_t i) { leaves[i]->loadValues(); });
                }
                // One owner keeps the grid alive and the tree pinned while any view lives.
                struct Owner {
                    GridPtr grid;
                    explicit Owner(GridPtr g) : grid(std::move(g)) { Pins::add(&grid->tree()); }
                    ~Owner() { Pins::remove(&grid->tree()); }
                };
                py::list out;
                constexpr py::ssize_t D = LeafT::DIM;
                const py::ssize_t s = sizeof(ValueT);
                std::vector<py::ssize_t> shape{D, D, D}, strides{D * D * s, D * s, s};
                if (Traits::N == 3) {
                    shape.push_back(3);
                    strides.push_back(sizeof(Scalar));
                }
                for (LeafT* leaf : leaves) {
                    auto* owner = new Owner(g);
                    py::capsule base(owner, [](void* p) { delete static_cast<Owner*>(p); });
                    out.append(py::array_t<Scalar>(
                        shape, strides, reinterpret_cast<Scalar*>(leaf->buffer(0).data()), base));
                }
                return out;
            }
        },
        "leafBuffers() -> list of (8, 8, 8) arrays ((8, 8, 8, 3) for vector grids): writable "
        "views, without a copy, of the values of every leaf, in leafOrigins() order; writes "
        "through a view change the grid and changes made through the grid show in the view. "
        "Each view keeps the grid alive; while any exists, operations that can free leaves "
        "(prune, fill, copyFromArray, merge, combine, tools) raise RuntimeError. Not available "
        "for BoolGrid and MaskGrid, whose leaves store bits (TypeError).");

    // ---- Meshes
    if constexpr (IS_FLOAT || (std::is_same_v<ValueT, bool> && !IS_MASK)) {
        // A BoolGrid is meshed as pyopenvdb meshes it (OpenVDB's volumeToMesh on bools): true
        // is inside whatever the isovalue, and each edge crossing lies at
        // t = (isovalue - v0) / (v1 - v0) with the values as 0 and 1: on the outside voxel for
        // isovalue 0, halfway for 0.5. A FloatGrid of the same topology holding -1 for true and
        // 0 for false, meshed at -isovalue (isovalue kept in [0, 1)), has those crossings.
        const auto meshable = [](const GridT& g, double& isovalue) {
            if constexpr (IS_FLOAT) {
                return std::shared_ptr<const GridT>(std::shared_ptr<const GridT>{}, &g);
            } else {
                isovalue = -std::clamp(isovalue, 0.0, 1.0 - 1e-6);
                auto f = FloatGrid::create(0.0f);
                f->setTransform(g.transformPtr());
                FloatTree& ft = f->tree();
                ft.topologyUnion(g.tree(), /*preserveTiles=*/true);
                visitBlocks(g.tree(), ValueFilter::All, true, [&](const Block<TreeT>& b) {
                    if (b.leaf) {
                        auto* fl = ft.touchLeaf(b.origin);  // inactive-only leaves too
                        for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
                            fl->setValueOnly(n, b.leaf->getValue(n) ? -1.0f : 0.0f);
                    } else if (b.value || b.active) {
                        ft.addTile(b.level, b.origin, b.value ? -1.0f : 0.0f, b.active);
                    }
                });
                return std::shared_ptr<const FloatGrid>(f);
            }
        };
        cls.def(
            "convertToPolygons",
            [meshable](const GridT& g, double isovalue, double adaptivity) {
                std::vector<Vec3s> points;
                std::vector<Vec3I> triangles;
                std::vector<Vec4I> quads;
                {
                    py::gil_scoped_release release;
                    const auto grid = meshable(g, isovalue);
                    tools::volumeToMesh(static_cast<const GridBase&>(*grid), points, triangles,
                                        quads, isovalue, adaptivity);
                }
                py::array_t<float> p({py::ssize_t(points.size()), py::ssize_t(3)});
                py::array_t<uint32_t> t({py::ssize_t(triangles.size()), py::ssize_t(3)});
                py::array_t<uint32_t> q({py::ssize_t(quads.size()), py::ssize_t(4)});
                std::memcpy(p.mutable_data(), points.data(), points.size() * sizeof(Vec3s));
                std::memcpy(t.mutable_data(), triangles.data(), triangles.size() * sizeof(Vec3I));
                std::memcpy(q.mutable_data(), quads.data(), quads.size() * sizeof(Vec4I));
                return py::make_tuple(p, t, q);
            },
            py::arg("isovalue") = 0.0, py::arg("adaptivity") = 0.0,
            "convertToPolygons(isovalue=0, adaptivity=0) -> points, triangles, quads: mesh the "
            "isosurface; world-space float32 points (P, 3) and uint32 index arrays (T, 3) and "
            "(Q, 4). Adaptivity 0 gives quads only; up to 1 merges flat regions. A BoolGrid's "
            "surface bounds its true voxels, as in pyopenvdb.");
        cls.def(
            "convertToQuads",
            [meshable](const GridT& g, double isovalue) {
                std::vector<Vec3s> points;
                std::vector<Vec4I> quads;
                {
                    py::gil_scoped_release release;
                    const auto grid = meshable(g, isovalue);
                    tools::volumeToMesh(*grid, points, quads, isovalue);
                }
                py::array_t<float> p({py::ssize_t(points.size()), py::ssize_t(3)});
                py::array_t<uint32_t> q({py::ssize_t(quads.size()), py::ssize_t(4)});
                std::memcpy(p.mutable_data(), points.data(), points.size() * sizeof(Vec3s));
                std::memcpy(q.mutable_data(), quads.data(), quads.size() * sizeof(Vec4I));
                return py::make_tuple(p, q);
            },
            py::arg("isovalue") = 0.0,
            "convertToQuads(isovalue=0) -> points, quads: mesh the isosurface with quads.");
    }
    if constexpr (IS_FLOAT) {
        cls.def_static(
            "createLevelSetFromPolygons",
            [](py::handle pointsObj, py::handle trianglesObj, py::handle quadsObj,
               std::shared_ptr<math::Transform> xform, double halfWidth) {
                auto numpy = py::module_::import("numpy");
                // Points: any array or nested sequence of numbers (not bools), shape (N, 3).
                // Faces: of integers of any dtype, or of floats holding whole numbers (pyopenvdb
                // takes those too). Wrong dtypes and shapes are TypeError, as in pyopenvdb.
                const auto rows = [&](py::handle obj, int width, const char* what, bool isIndex) {
                    py::array arr;
                    try {
                        arr = numpy.attr("asarray")(obj);
                    } catch (const py::error_already_set&) {
                        throw py::type_error(std::string("createLevelSetFromPolygons: ") + what +
                                             " must be an array of numbers, got " +
                                             typeNameOf(obj));
                    }
                    const char kind = arr.dtype().kind();
                    if (kind != 'i' && kind != 'u' && kind != 'f')
                        throw py::type_error(std::string("createLevelSetFromPolygons: ") + what +
                                             (isIndex ? " must be integers" : " must be numbers") +
                                             ", got dtype " + std::string(py::str(arr.dtype())));
                    if (isIndex && kind == 'f' &&
                        !numpy.attr("array_equal")(arr, numpy.attr("floor")(arr)).cast<bool>())
                        throw py::type_error(std::string("createLevelSetFromPolygons: ") + what +
                                             " must be integers, got fractional or non-finite "
                                             "values of dtype " +
                                             std::string(py::str(arr.dtype())));
                    if (arr.size() == 0)
                        return arr;
                    if (arr.ndim() != 2 || arr.shape(1) != width)
                        throw py::type_error(std::string("createLevelSetFromPolygons: ") + what +
                                             " must have shape (N, " + std::to_string(width) +
                                             "), got " + std::string(py::str(arr.attr("shape"))));
                    return arr;
                };
                std::vector<Vec3s> points;
                std::vector<Vec3I> triangles;
                std::vector<Vec4I> quads;
                {
                    py::array p = rows(pointsObj, 3, "points", false);
                    auto pf =
                        py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(p);
                    points.resize(size_t(pf.size() / 3));
                    std::memcpy(static_cast<void*>(points.data()), pf.data(),
                                points.size() * sizeof(Vec3s));
                }
                const auto indices = [&](py::handle obj, int width, const char* what, auto& out) {
                    if (obj.is_none())
                        return;
                    py::array a = rows(obj, width, what, true);
                    auto ai =
                        py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
                    const int64_t* d = ai.data();
                    for (py::ssize_t i = 0; i < ai.size(); ++i)
                        if (d[i] < 0 || uint64_t(d[i]) >= points.size())
                            throw py::index_error(std::string("createLevelSetFromPolygons: ") +
                                                  what + " index " + std::to_string(d[i]) +
                                                  " is out of range for " +
                                                  std::to_string(points.size()) + " points");
                    out.resize(size_t(ai.size() / width));
                    for (size_t i = 0; i < out.size(); ++i)
                        for (int k = 0; k < width; ++k)
                            out[i][k] = Index32(d[i * width + k]);
                };
                indices(trianglesObj, 3, "triangles", triangles);
                indices(quadsObj, 4, "quads", quads);
                if (!xform)
                    xform = math::Transform::createLinearTransform(1.0);
                if (!(halfWidth >= 1.0) || !std::isfinite(halfWidth))
                    throw py::value_error(
                        "createLevelSetFromPolygons: halfWidth must be at least 1");
                py::gil_scoped_release release;
                return tools::meshToLevelSet<GridT>(*xform, points, triangles, quads,
                                                    float(halfWidth));
            },
            py::arg("points"), py::arg("triangles") = py::none(), py::arg("quads") = py::none(),
            py::arg("transform") = py::none(), py::arg("halfWidth") = 3.0,
            "createLevelSetFromPolygons(points, triangles=None, quads=None, transform=None, "
            "halfWidth=3) -> grid: the narrow-band level set of a mesh of world-space points "
            "(N, 3) and (T, 3) / (Q, 4) index arrays, sampled with the transform (identity if "
            "None). Meshes with holes are signed by winding numbers.");
    } else {
        // pyopenvdb's grid classes all have these; on grids of other values they raise
        // TypeError (a BoolGrid meshes, above).
        const std::string meshing = std::string("volume to mesh conversion needs a grid of ") +
                                    "floating-point values or bools, not a " + name;
        const std::string leveling = std::string("mesh to volume conversion needs a grid of ") +
                                     "floating-point values (FloatGrid or DoubleGrid), not a " +
                                     name;
        if constexpr (!std::is_same_v<ValueT, bool> || IS_MASK) {
            cls.def(
                "convertToPolygons",
                [meshing](const GridT&, py::object, py::object) -> py::tuple {
                    throw py::type_error(meshing);
                },
                py::arg("isovalue") = 0.0, py::arg("adaptivity") = 0.0,
                "Raises TypeError: only grids of floating-point values or bools are meshed.");
            cls.def(
                "convertToQuads",
                [meshing](const GridT&, py::object) -> py::tuple { throw py::type_error(meshing); },
                py::arg("isovalue") = 0.0,
                "Raises TypeError: only grids of floating-point values or bools are meshed.");
        }
        cls.def_static(
            "createLevelSetFromPolygons",
            [leveling](py::object, py::object, py::object, py::object, py::object) -> py::object {
                throw py::type_error(leveling);
            },
            py::arg("points"), py::arg("triangles") = py::none(), py::arg("quads") = py::none(),
            py::arg("transform") = py::none(), py::arg("halfWidth") = 3.0,
            "Raises TypeError: level sets are grids of floating-point values.");
    }

    // ---- Nested classes
    using Acc = PyAccessor<GridT, false>;
    using CAcc = PyAccessor<GridT, true>;
    const auto bindReads = [](auto& c) {
        using A = typename std::remove_reference_t<decltype(c)>::type;
        c.def(
             "getValue", [](const A& a, const Coord& ijk) { return ValueT(a.acc.getValue(ijk)); },
             py::arg("ijk"), "getValue(ijk) -> value")
            .def(
                "isValueOn", [](const A& a, const Coord& ijk) { return a.acc.isValueOn(ijk); },
                py::arg("ijk"), "isValueOn(ijk) -> bool")
            .def(
                "probeValue",
                [](const A& a, const Coord& ijk) {
                    ValueT v;
                    const bool on = a.acc.probeValue(ijk, v);
                    return py::make_tuple(v, on);
                },
                py::arg("ijk"), "probeValue(ijk) -> (value, active)")
            .def(
                "getValueDepth",
                [](const A& a, const Coord& ijk) {
                    // The background outside the root's entries is stored by no node: -1.
                    using TopT = typename std::decay_t<decltype(a.grid->tree())>::TopNodeType;
                    const TopT& top = a.grid->tree().topNode();
                    if constexpr (tree::IS_ROOT_NODE<TopT>) {
                        if (!top.findEntry(TopT::coordToKey(ijk)))
                            return -1;
                    }
                    return int(DEPTH) - 1 - int(valueLevel(a.grid->tree(), ijk));
                },
                py::arg("ijk"),
                "getValueDepth(ijk) -> int: the depth of the node that stores the value "
                "(0: root, treeDepth - 1: leaf voxel, -1: the background outside every root "
                "entry)")
            .def(
                "isVoxel",
                [](const A& a, const Coord& ijk) { return valueLevel(a.grid->tree(), ijk) == 0; },
                py::arg("ijk"), "isVoxel(ijk) -> bool: whether a leaf stores the value")
            .def(
                "isCached", [](const A& a, const Coord& ijk) { return a.acc.isCached(ijk); },
                py::arg("ijk"), "isCached(ijk) -> bool")
            .def(
                "clear", [](A& a) { a.acc.clear(); }, "clear(): empty the cache")
            .def_property_readonly(
                "parent", [](const A& a) { return a.grid; }, "the grid this accessor reads");
    };
    py::class_<CAcc> cacc(cls, "ConstAccessor", "Read-only access by (i, j, k) to the voxels.");
    bindReads(cacc);
    py::class_<Acc> acc(cls, "Accessor", "Read/write access by (i, j, k) to the voxels.");
    bindReads(acc);
    acc.def(
           "setValueOn",
           [](Acc& a, const Coord& ijk, py::object value) {
               if (value.is_none())
                   a.acc.setValueOn(ijk);
               else
                   a.acc.setValueOn(ijk, toValue<ValueT>(value, "setValueOn"));
           },
           py::arg("ijk"), py::arg("value") = py::none(),
           "setValueOn(ijk, value=None): set the value (if given) and activate the voxel.")
        .def(
            "setValueOff",
            [](Acc& a, const Coord& ijk, py::object value) {
                if (value.is_none())
                    a.acc.setValueOff(ijk);
                else
                    a.acc.setValueOff(ijk, toValue<ValueT>(value, "setValueOff"));
            },
            py::arg("ijk"), py::arg("value") = py::none(),
            "setValueOff(ijk, value=None): set the value (if given) and deactivate the voxel.")
        .def(
            "setValueOnly",
            [](Acc& a, const Coord& ijk, py::handle value) {
                a.acc.setValueOnly(ijk, toValue<ValueT>(value, "setValueOnly"));
            },
            py::arg("ijk"), py::arg("value"), "setValueOnly(ijk, value): keep the active state.")
        .def(
            "setActiveState",
            [](Acc& a, const Coord& ijk, bool on) { a.acc.setActiveState(ijk, on); },
            py::arg("ijk"), py::arg("on"), "setActiveState(ijk, on)")
        .def(
            "copy", [](const Acc& a) { return Acc(a.grid); }, "copy() -> Accessor");
    cacc.def(
        "copy", [](const CAcc& a) { return CAcc(a.grid); }, "copy() -> ConstAccessor");
    // pyopenvdb's ConstAccessor has the setters, with the Accessor's keywords, and refuses
    // them with TypeError.
    const auto readOnly = [](const CAcc&, py::handle, py::handle) {
        throw py::type_error("accessor is read-only");
    };
    cacc.def("setValueOn", readOnly, py::arg("ijk"), py::arg("value") = py::none(),
             "Raises TypeError: a ConstAccessor cannot write.")
        .def("setValueOff", readOnly, py::arg("ijk"), py::arg("value") = py::none(),
             "Raises TypeError: a ConstAccessor cannot write.")
        .def("setValueOnly", readOnly, py::arg("ijk"), py::arg("value"),
             "Raises TypeError: a ConstAccessor cannot write.")
        .def("setActiveState", readOnly, py::arg("ijk"), py::arg("on"),
             "Raises TypeError: a ConstAccessor cannot write.");

    using PV = PyValue<GridT>;
    py::class_<PV> value(cls, "Value", "A tile or voxel value of the grid (from an iterator).");
    // Writing through an item of a const iterator (citer...) is AttributeError, as setting a
    // read-only attribute is, and as in pyopenvdb.
    const auto checkWritable = [](const PV& v, const char* attribute) {
        if (!v.writable)
            throw py::attribute_error(std::string("can't set attribute '") + attribute +
                                      "': this value comes from a read-only iterator (citer...)");
    };
    value
        .def_property(
            "value", [](const PV& v) { return v.grid->tree().getValue(v.min); },
            [checkWritable](PV& v, py::handle x) {
                checkWritable(v, "value");
                TreeT& tree = v.grid->tree();
                setBlock(tree, v.level, v.min, toValue<ValueT>(x, "value"), tree.isValueOn(v.min));
            })
        .def_property(
            "active", [](const PV& v) { return v.grid->tree().isValueOn(v.min); },
            [checkWritable](PV& v, bool on) {
                checkWritable(v, "active");
                TreeT& tree = v.grid->tree();
                setBlock(tree, v.level, v.min, tree.getValue(v.min), on);
            })
        .def_property_readonly("min", [](const PV& v) { return v.min; })
        .def_property_readonly(
            "max",
            [](const PV& v) {
                return v.level == 0 ? v.min : v.min.offsetBy(Int32(blockDim<TreeT>(v.level) - 1));
            })
        .def_property_readonly("depth", [](const PV& v) { return int(DEPTH) - 1 - int(v.level); })
        .def_property_readonly("count",
                               [](const PV& v) {
                                   if (v.level == 0)
                                       return Index64(1);
                                   const Int64 d = blockDim<TreeT>(v.level);
                                   return Index64(d * d * d);
                               })
        .def_property_readonly("parent", [](const PV& v) { return v.grid; })
        .def(
            "copy", [](const PV& v) { return v; },
            "copy() -> Value: another item for the same voxel or tile (reading the grid live)")
        .def_static("keys",
                    [] {
                        return std::vector<std::string>{"value", "active", "depth",
                                                        "min",   "max",    "count"};
                    })
        .def("__eq__",
             [](py::object self, py::object other) -> py::object {
                 // Equal items: the same value, state, depth and box (as pyopenvdb compares).
                 if (!py::isinstance<PV>(other))
                     return py::reinterpret_borrow<py::object>(Py_NotImplemented);
                 for (const char* k : {"value", "active", "depth", "min", "max", "count"})
                     if (!self.attr(k).equal(other.attr(k)))
                         return py::bool_(false);
                 return py::bool_(true);
             })
        .def("__ne__",
             [](py::object self, py::object other) -> py::object {
                 py::object eq = self.attr("__eq__")(other);
                 if (eq.is(py::reinterpret_borrow<py::object>(Py_NotImplemented)))
                     return eq;
                 return py::bool_(!eq.cast<bool>());
             })
        .def("__contains__",
             [](py::object, py::handle key) {
                 for (const char* k : {"value", "active", "depth", "min", "max", "count"})
                     if (py::str(key).equal(py::str(k)))
                         return true;
                 return false;
             })
        .def("__getitem__",
             [](py::object self, const std::string& key) {
                 for (const char* k : {"value", "active", "depth", "min", "max", "count"})
                     if (key == k)
                         return self.attr(k);
                 throw py::key_error(key);
             })
        .def("__repr__", [](py::object self) {
            return "{'value': " + std::string(py::repr(self.attr("value"))) +
                   ", 'active': " + std::string(py::repr(self.attr("active"))) +
                   ", 'depth': " + std::string(py::repr(self.attr("depth"))) +
                   ", 'min': " + std::string(py::repr(self.attr("min"))) +
                   ", 'max': " + std::string(py::repr(self.attr("max"))) +
                   ", 'count': " + std::string(py::repr(self.attr("count"))) + "}";
        });

    using PI = PyValueIter<GridT>;
    py::class_<PI>(cls, "ValueIter", "An iterator over a grid's values (tiles and voxels).")
        .def(
            "__iter__", [](PI& it) -> PI& { return it; },
            py::return_value_policy::reference_internal)
        .def("__next__",
             [](PI& it) {
                 auto v = nextValue(it);
                 if (!v)
                     throw py::stop_iteration();
                 return *v;
             })
        .def("next",
             [](PI& it) {
                 auto v = nextValue(it);
                 if (!v)
                     throw py::stop_iteration();
                 return *v;
             })
        .def_property_readonly("parent", [](const PI& it) { return it.grid; });
    // pyopenvdb's names of its six iterator classes: here one class serves them all.
    for (const char* alias : {"ValueOnIter", "ValueOffIter", "ValueAllIter", "ValueOnCIter",
                              "ValueOffCIter", "ValueAllCIter"})
        cls.attr(alias) = cls.attr("ValueIter");
}

}  // namespace vdb::python
