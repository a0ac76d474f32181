# SPDX-License-Identifier: Apache-2.0
"""pyopenvdb 10's behaviours that existing scripts rely on: iterator items, metadata of every
type pyopenvdb stores, meshes in, transforms, pickling and accessors. Each test body runs on
both modules (the `mod` fixture: vdb, and pyopenvdb where it is installed), so that what is
asserted is pyopenvdb's own behaviour; a few tests then hold vdb to what it accepts beyond
pyopenvdb, and the audit at the end compares the two modules' names and keywords."""

import copy
import inspect
import pickle
import re

import numpy as np
import pytest

import vdb

try:
    import pyopenvdb
except ImportError:
    pyopenvdb = None

MODULES = ["vdb", "pyopenvdb"]


@pytest.fixture(params=MODULES)
def mod(request):
    if request.param == "vdb":
        return vdb
    if pyopenvdb is None:
        pytest.skip("pyopenvdb (python3-openvdb) is not installed")
    return pyopenvdb


def grid_classes(mod):
    return [mod.FloatGrid, mod.BoolGrid, mod.Vec3SGrid]


def value_of(cls, x):
    """`x` as a value of the grid class `cls` (a number, a bool or a vector of it)."""
    zero = cls.zeroValue
    if isinstance(zero, tuple):
        return (type(zero[0])(x),) * len(zero)
    return type(zero)(x)


def nested_fill(grid):
    """A tile of the upper internal level holding boxes of shrinking width, alternately
    inactive and active: tiles of both internal levels, whole leaves and partial ones."""
    grid.fill((0, 0, 0), (127, 127, 127), value_of(type(grid), 1), True)
    active = False
    for width in range(23, 0, -6):
        grid.fill((0, 0, 0), (width,) * 3, value_of(type(grid), width % 2 + 1), active)
        active = not active
    return grid


def items(iterator):
    return [(v.value, v.active, v.depth, v.min, v.max, v.count) for v in iterator]


# ---- 1. Iterators


def test_const_iterator_items_cannot_be_written(mod):
    for cls in grid_classes(mod):
        grid = nested_fill(cls())
        before = items(grid.citerAllValues())
        for make in (grid.citerOnValues, grid.citerOffValues, grid.citerAllValues):
            item = make().next()
            for name, value in [("active", 0), ("depth", 0), ("value", cls.oneValue),
                                ("min", (0, 0, 0)), ("max", (1, 1, 1)), ("count", 1)]:
                with pytest.raises(AttributeError):
                    setattr(item, name, value)
        assert items(grid.citerAllValues()) == before


def test_mutable_iterator_items_write_value_and_state_only(mod):
    for cls in grid_classes(mod):
        grid = cls()
        grid.fill((0, 0, 1), (18, 18, 18), cls.oneValue)
        count = grid.activeVoxelCount()
        item = grid.iterOnValues().next()
        for name, value in [("min", (0, 0, 0)), ("max", (0, 0, 0)), ("count", 1), ("depth", 0)]:
            with pytest.raises(AttributeError):
                setattr(item, name, value)
        # Turning every other item off halves the count, as pyopenvdb's own test checks.
        state = True
        for item in grid.iterOnValues():
            item.active = state
            state = not state
        assert grid.activeVoxelCount() == count // 2
        for item in grid.iterOnValues():
            item.value = cls.zeroValue
        assert all(v.value == cls.zeroValue for v in grid.citerOnValues())


def test_next_method_and_protocol(mod):
    grid = nested_fill(mod.FloatGrid())
    expected = items(grid.citerAllValues())
    it = grid.citerAllValues()
    assert iter(it) is it
    seen = []
    while True:
        try:
            v = it.next()
        except StopIteration:
            break
        seen.append((v.value, v.active, v.depth, v.min, v.max, v.count))
    assert seen == expected and len(seen) > 10
    with pytest.raises(StopIteration):
        it.next()
    it = grid.iterOnValues()
    first, second = it.next(), next(it)
    on = [e for e in expected if e[1]]
    assert (first.min, second.min) == (on[0][3], on[1][3])
    assert it.parent is not None


def test_items_read_like_dicts_and_compare_by_content(mod):
    grid = nested_fill(mod.FloatGrid())
    item = grid.citerOnValues().next()
    assert list(item.keys()) == ["value", "active", "depth", "min", "max", "count"]
    assert "value" in item and "missing" not in item
    assert item["min"] == item.min and item["count"] == item.count
    with pytest.raises(KeyError):
        item["missing"]
    assert eval(repr(item)) == {k: getattr(item, k) for k in item.keys()}
    again = grid.citerOnValues().next()
    assert item == again and not (item != again)
    other = list(grid.citerOnValues())[-1]
    assert item != other


# ---- 2. Metadata

# pyopenvdb's own example dictionaries (its test suite's grid metadata and pickled metadata),
# and one value of each type it stores.
META_EXAMPLES = [
    {"name": "test", "xyz": (-1, 0, 1), "xyzw": (1.0, 2.25, 3.5, 4.0), "intval": 42,
     "floatval": 1.25, "mat4val": [[1] * 4] * 4, "saveFloatAsHalf": True},
    {"name": "test", "saveFloatAsHalf": True, "xyz": (-1, 0, 1)},
    {"b": True, "i": 7, "big": 2**40, "neg": -(2**31), "f": 1.25, "s": "text",
     "i2": (1, 2), "f2": (1.5, 2.0), "i3": (1, 2, 3), "f3": (1.0, 2.0, 3.5),
     "i4": (1, 2, 3, 4), "f4": (1.0, 2.0, 3.0, 4.5),
     "m4": [[1.5, 0.0, 0.0, 0.0], [0.0, 2.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0],
            [4.0, 5.0, 6.0, 1.0]]},
]


def canonical(value):
    """The value with each number tagged by its Python type (1 == 1.0 but int is not float)."""
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, tuple(canonical(v) for v in value))
    return (type(value).__name__, value)


@pytest.mark.parametrize("meta", META_EXAMPLES, ids=["pyopenvdb-test", "pickle-test", "types"])
def test_metadata_round_trips(mod, meta):
    for cls in grid_classes(mod):
        grid = cls()
        grid.metadata = meta
        assert grid.metadata == meta
        for name, value in meta.items():
            assert name in grid and grid[name] == value
            assert type(grid[name]) is type(value)
        grid.updateMetadata({"xyz": (-100, 100, 0)})
        assert grid["xyz"] == (-100, 100, 0)
        assert set(grid.iterkeys()) == set(meta) | {"xyz"}
        del grid["xyz"]
        assert "xyz" not in grid


def test_metadata_element_types(mod):
    grid = mod.FloatGrid()
    grid["v"] = (1, 2)
    assert canonical(grid["v"]) == canonical((1, 2))
    grid["v"] = (1.5, 2.0)
    assert canonical(grid["v"]) == canonical((1.5, 2.0))
    grid["v"] = (1, 2.5, 3)
    assert canonical(grid["v"]) == canonical((1.0, 2.5, 3.0))
    grid["v"] = (True, False)
    assert canonical(grid["v"]) == canonical((1, 0))
    grid["v"] = [1, 2, 3, 4]
    assert canonical(grid["v"]) == canonical((1, 2, 3, 4))
    grid["v"] = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    assert canonical(grid["v"]) == canonical([[float(r == c) for c in range(4)] for r in range(4)])
    grid["v"] = np.eye(4)
    assert grid["v"] == [[float(r == c) for c in range(4)] for r in range(4)]
    grid["v"] = np.array([1.5, 2.0, 3.0])
    assert canonical(grid["v"]) == canonical((1.5, 2.0, 3.0))
    grid["v"] = b"abc"
    assert grid["v"] == "abc"
    grid["v"] = np.int64(5)
    assert canonical(grid["v"]) == canonical(5)
    grid["v"] = None  # pyopenvdb stores nothing for None
    assert canonical(grid["v"]) == canonical(5)


def test_metadata_refusals(mod):
    grid = mod.FloatGrid()
    for value in [[1, 2, 3, 4, 5], {}, (), ("a", "b", "c"), [[1, 2], [3, 4]],
                  [[1, 0, 0, 0]] * 3, [[1, 0, 0]] * 3, object()]:
        with pytest.raises(TypeError):
            grid["x"] = value
        assert "x" not in grid
    with pytest.raises(OverflowError):
        grid["x"] = 2**70
    with pytest.raises(OverflowError):
        grid["x"] = (2**40, 1)
    with pytest.raises(TypeError):
        grid[3] = 1
    with pytest.raises(KeyError):
        grid["missing"]
    with pytest.raises(KeyError):
        del grid["missing"]


@pytest.mark.skipif(pyopenvdb is None, reason="pyopenvdb (python3-openvdb) is not installed")
@pytest.mark.parametrize("writer,reader", [("vdb", "pyopenvdb"), ("pyopenvdb", "vdb")])
def test_metadata_types_travel_through_files(writer, reader, tmp_path):
    """Each module reads the other's files with every metadata type intact (vec2, vec4 and
    mat4 values included), grid and file metadata alike."""
    w, r = (vdb if m == "vdb" else pyopenvdb for m in (writer, reader))
    path = str(tmp_path / "meta.vdb")
    meta = dict(META_EXAMPLES[2])
    grid = w.FloatGrid()
    grid.name = "g"
    grid.updateMetadata(meta)
    w.write(path, [grid], metadata={"file_v2": (3, 4), "file_m4": meta["m4"], "file_f": 0.5})
    back = r.read(path, "g")
    for name, value in meta.items():
        assert canonical(back[name]) == canonical(value), name
    file_meta = r.readMetadata(path)
    assert canonical(file_meta["file_v2"]) == canonical((3, 4))
    assert file_meta["file_m4"] == meta["m4"] and file_meta["file_f"] == 0.5


# ---- 3. Meshes in

CUBE_POINTS = np.array([(x, y, z) for x in (0, 100) for y in (0, 100) for z in (0, 100)], float)
CUBE_QUADS = np.array([(0, 1, 3, 2), (0, 2, 6, 4), (4, 6, 7, 5), (5, 7, 3, 1), (2, 3, 7, 6),
                       (0, 4, 5, 1)])
CUBE_TRIANGLES = np.array([t for q in CUBE_QUADS for t in ((q[0], q[1], q[2]),
                                                            (q[0], q[2], q[3]))])


def cube_level_set(mod, points=CUBE_POINTS, **faces):
    xform = mod.createLinearTransform(2.0)
    return mod.FloatGrid.createLevelSetFromPolygons(points, transform=xform, halfWidth=3.0,
                                                    **faces)


def test_meshes_of_the_dtypes_pyopenvdb_accepts(mod):
    reference = cube_level_set(mod, quads=CUBE_QUADS.astype(np.int32))
    assert reference.gridClass == "level set" and reference.background == 6.0
    assert all(50 < d < 58 for d in reference.evalActiveVoxelDim())
    count = reference.activeVoxelCount()
    for dtype in (np.float32, np.float64, np.int32, np.int64):
        assert cube_level_set(mod, CUBE_POINTS.astype(dtype),
                              quads=CUBE_QUADS.astype(np.int32)).activeVoxelCount() == count
    for dtype in (np.int16, np.int32, np.int64, np.uint32, np.uint64, np.float32, np.float64):
        assert cube_level_set(mod, quads=CUBE_QUADS.astype(dtype)).activeVoxelCount() == count
        assert cube_level_set(mod, triangles=CUBE_TRIANGLES.astype(dtype)).activeVoxelCount() == \
            count
    # Positional order: points, triangles, quads, transform, halfWidth.
    grid = mod.FloatGrid.createLevelSetFromPolygons(
        CUBE_POINTS, CUBE_TRIANGLES.astype(np.int32), None, mod.createLinearTransform(2.0), 3.0)
    assert grid.activeVoxelCount() == count
    assert mod.FloatGrid.createLevelSetFromPolygons(CUBE_POINTS).activeVoxelCount() == 0


def test_meshes_refused_as_pyopenvdb_refuses(mod):
    quads = CUBE_QUADS.astype(np.int32)
    for cls in (mod.BoolGrid, mod.Vec3SGrid):
        with pytest.raises(TypeError):
            cls.createLevelSetFromPolygons(CUBE_POINTS, quads=quads)
    with pytest.raises(TypeError):
        cube_level_set(mod, CUBE_POINTS.astype(bool), quads=quads)
    with pytest.raises(TypeError):
        cube_level_set(mod, triangles=quads)  # (N, 4) given as triangles
    with pytest.raises(TypeError):
        cube_level_set(mod, CUBE_POINTS[:, :2], quads=quads)
    with pytest.raises(TypeError):
        cube_level_set(mod, np.zeros((2, 2, 3)), quads=quads)
    with pytest.raises(TypeError):
        cube_level_set(mod, "abc", quads=quads)
    with pytest.raises(TypeError):
        mod.FloatGrid.createLevelSetFromPolygons(CUBE_POINTS, quads=quads, unknown=1)
    with pytest.raises(ValueError):
        mod.FloatGrid.createLevelSetFromPolygons(CUBE_POINTS, quads=quads, halfWidth=-1.0)
    with pytest.raises(TypeError):
        mod.Vec3SGrid().convertToQuads()
    with pytest.raises(TypeError):
        mod.Vec3SGrid().convertToPolygons()


def test_vdb_meshes_from_more_dtypes_and_lists():
    """Beyond pyopenvdb: faces of every integer dtype and lists of tuples, points of every real
    dtype and nested lists; out-of-range and fractional indices are refused."""
    count = cube_level_set(vdb, quads=CUBE_QUADS.astype(np.int32)).activeVoxelCount()
    for dtype in (np.int8, np.uint8, np.uint16):
        assert cube_level_set(vdb, quads=CUBE_QUADS.astype(dtype)).activeVoxelCount() == count
    assert cube_level_set(vdb, quads=[tuple(q) for q in CUBE_QUADS.tolist()]).activeVoxelCount() \
        == count
    assert cube_level_set(vdb, triangles=[tuple(t) for t in CUBE_TRIANGLES.tolist()]) \
        .activeVoxelCount() == count
    assert cube_level_set(vdb, CUBE_POINTS.tolist(), quads=CUBE_QUADS).activeVoxelCount() == count
    assert cube_level_set(vdb, CUBE_POINTS.astype(np.float16),
                          quads=CUBE_QUADS).activeVoxelCount() == count
    with pytest.raises(IndexError):
        cube_level_set(vdb, quads=np.array([[0, 1, 2, 8]]))
    with pytest.raises(IndexError):
        cube_level_set(vdb, triangles=np.array([[0, 1, -1]]))
    with pytest.raises(TypeError):
        cube_level_set(vdb, triangles=np.array([[0, 1, 2.5]]))
    with pytest.raises(TypeError):
        vdb.MaskGrid().convertToPolygons()


def bool_shapes(mod):
    """A BoolGrid with a hollow box, a whole leaf, single voxels and an active false voxel.
    (Inactive true voxels are meshed differently: python/README.md.)"""
    grid = mod.BoolGrid()
    grid.transform = mod.createLinearTransform(0.5)
    grid.fill((0, 0, 0), (9, 9, 9), True)
    grid.fill((3, 3, 3), (5, 5, 5), False)
    grid.fill((16, 0, 0), (23, 7, 7), True)
    grid.fill((43, 0, 0), (47, 3, 3), True)
    acc = grid.getAccessor()
    for ijk in [(30, 30, 30), (31, 30, 30), (-5, 2, 7)]:
        acc.setValueOn(ijk, True)
    acc.setValueOn((31, 31, 30), False)
    return grid


def nearest_distances(a, b):
    """For each point of `a`, the distance to the nearest point of `b` (brute force)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(1)


@pytest.mark.skipif(pyopenvdb is None, reason="pyopenvdb (python3-openvdb) is not installed")
@pytest.mark.parametrize("isovalue", [0.0, 0.5])
@pytest.mark.parametrize("adaptivity", [0.0, 1.0])
def test_bool_grids_mesh_as_in_pyopenvdb(isovalue, adaptivity):
    """The same numbers of points, triangles and quads; at adaptivity 0 the same points to
    0.001 voxel (this library keeps edge crossings that far from voxel centres), while merged
    vertices (adaptivity above 0) are placed by this library's own rule (python/README.md)."""
    voxel = 0.5
    ours = bool_shapes(vdb).convertToPolygons(isovalue=isovalue, adaptivity=adaptivity)
    theirs = bool_shapes(pyopenvdb).convertToPolygons(isovalue=isovalue, adaptivity=adaptivity)
    assert [len(x) for x in ours] == [len(x) for x in theirs]
    if adaptivity == 0.0:
        assert nearest_distances(ours[0], theirs[0]).max() <= 0.0011 * voxel * 3**0.5
        assert nearest_distances(theirs[0], ours[0]).max() <= 0.0011 * voxel * 3**0.5
    qo, qt = bool_shapes(vdb).convertToQuads(isovalue), bool_shapes(pyopenvdb).convertToQuads(isovalue)
    assert [len(x) for x in qo] == [len(x) for x in qt]
    assert nearest_distances(qo[0], qt[0]).max() <= 0.0011 * voxel * 3**0.5


# ---- 4. Transforms and pickling

MATRIX = [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 3, 0], [4, 3, 2, 1]]


def transforms(mod):
    return [
        mod.createLinearTransform(voxelSize=0.1),
        mod.createLinearTransform(matrix=MATRIX),
        mod.createLinearTransform(MATRIX),
        mod.createLinearTransform(np.array(MATRIX, float)),
        mod.createFrustumTransform((0, 0, 0), (10, 10, 10), taper=0.8, depth=10.0),
        mod.createFrustumTransform(taper=0.5, depth=100, xyzMin=(0, 0, 0),
                                   xyzMax=(100, 100, 100), voxelSize=0.25),
    ]


def test_transform_constructors_and_equality(mod):
    a = mod.createLinearTransform([[.5, 0, 0, 0], [0, 1, 0, 0], [0, 0, 2, 0], [1, 2, 3, 1]])
    assert a.indexToWorld((1, 1, 1)) == pytest.approx((1.5, 3, 5))
    assert a == a.deepCopy() and not (a != a.deepCopy())
    frustum = mod.createFrustumTransform(taper=0.5, depth=100, xyzMin=(0, 0, 0),
                                         xyzMax=(100, 100, 100), voxelSize=0.25)
    assert frustum != a
    assert [round(x * 1e6) for x in frustum.indexToWorld((10, 10, 10))] == \
        [-110000, -110000, 2500000]
    assert mod.FloatGrid().transform == mod.createLinearTransform()
    assert (a == 3) is False and (a != 3) is True
    made = transforms(mod)
    assert made[1] == made[2] == made[3]
    for bad in ([[1, 2], [3, 4]], "x", [[1, 0, 0, 0]] * 3):
        with pytest.raises(ValueError):
            mod.createLinearTransform(bad)
    with pytest.raises(ArithmeticError):
        mod.createLinearTransform(matrix=[[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    with pytest.raises(TypeError):
        mod.createLinearTransform(matrix=MATRIX, voxelSize=2.0)


def sheared_points(mod):
    t = mod.createLinearTransform(0.5)
    t.shear(0.25, mod.Axis.X, mod.Axis.Y)
    t.rotate(0.3, mod.Axis.Z)
    return [t.indexToWorld(p) for p in [(1, 0, 0), (0, 1, 0), (0, 0, 1), (3, -2, 5)]]


def test_axis_names_and_values(mod):
    assert mod.Axis.names["Y"] == mod.Axis.Y and mod.Axis.values[2] == mod.Axis.Z
    assert set(mod.Axis.names) == {"X", "Y", "Z"}


@pytest.mark.skipif(pyopenvdb is None, reason="pyopenvdb (python3-openvdb) is not installed")
def test_transform_shear_matches_pyopenvdb():
    for a, b in zip(sheared_points(vdb), sheared_points(pyopenvdb)):
        assert a == pytest.approx(b)
    # A shear is not a no-op: the sheared map differs from the unsheared one.
    plain = vdb.createLinearTransform(0.5)
    plain.rotate(0.3, vdb.Axis.Z)
    assert plain.indexToWorld((0, 1, 0)) != pytest.approx(sheared_points(vdb)[1])


def test_transforms_pickle(mod):
    for xform in transforms(mod):
        for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
            back = pickle.loads(pickle.dumps(xform, protocol))
            assert back == xform
            assert back.indexToWorld((1, 2, 3)) == xform.indexToWorld((1, 2, 3))
        assert copy.deepcopy(xform) == xform


def pickle_grid(mod, cls, half):
    grid = cls()
    grid.metadata = {"name": "test", "saveFloatAsHalf": True, "xyz": (-1, 0, 1)}
    nested_fill(grid)
    grid.fill((100, 0, 0), (103, 2, 2), value_of(cls, 0.3) if cls is not mod.BoolGrid else True)
    grid.transform = mod.createLinearTransform(MATRIX)
    grid.gridClass = "fog volume"
    if half:
        grid.saveFloatAsHalf = True
    return grid


@pytest.mark.parametrize("half", [False, True])
def test_grids_pickle(mod, half):
    for cls in grid_classes(mod):
        grid = pickle_grid(mod, cls, half)
        for protocol in (0, pickle.DEFAULT_PROTOCOL, pickle.HIGHEST_PROTOCOL):
            back = pickle.loads(pickle.dumps(grid, protocol))
            assert type(back) is cls
            assert back.metadata == grid.metadata
            assert back.saveFloatAsHalf == half
            assert back.transform == grid.transform
            assert back.background == grid.background
            if half and mod is not vdb:
                # pyopenvdb pickles with its file writer, which stores halves: values come back
                # rounded (vdb keeps full precision; python/README.md).
                ours, theirs = items(back.citerAllValues()), items(grid.citerAllValues())
                assert [i[1:] for i in ours] == [i[1:] for i in theirs]
                assert np.allclose(np.array([i[0] for i in ours], float),
                                   np.array([i[0] for i in theirs], float), rtol=1e-3)
                continue
            # Every value and state at full precision, even when files would store halves.
            assert items(back.citerAllValues()) == items(grid.citerAllValues())
            for restored, original in zip(back.iterOnValues(), grid.iterOnValues()):
                assert restored == original
        if not (half and mod is not vdb):
            assert items(copy.deepcopy(grid).citerAllValues()) == items(grid.citerAllValues())


@pytest.mark.parametrize("cls", [vdb.DoubleGrid, vdb.Int32Grid, vdb.Int64Grid, vdb.MaskGrid,
                                 vdb.Vec3DGrid, vdb.Vec3IGrid])
def test_every_vdb_grid_type_pickles(cls, rng=np.random.default_rng(3)):
    grid = cls()
    grid.name = cls.__name__
    grid["note"] = (1.5, 2.5)
    nested_fill(grid)
    coords = rng.integers(-300, 300, size=(500, 3)).astype(np.int32)
    acc = grid.getAccessor()
    for c in coords:
        acc.setValueOff(tuple(int(x) for x in c))
    back = pickle.loads(pickle.dumps(grid))
    assert type(back) is cls and back.metadata == grid.metadata
    assert items(back.citerAllValues()) == items(grid.citerAllValues())


def test_unpickling_refuses_bad_state():
    restore, (state,) = vdb.FloatGrid().__reduce__()
    with pytest.raises(ValueError):
        restore("not bytes")
    with pytest.raises(OSError):
        restore(state[: len(state) // 2])
    with pytest.raises(OSError):
        restore(b"")
    assert type(restore(state)) is vdb.FloatGrid


# ---- 5. Accessors


def test_const_accessor_refuses_writes_with_type_error(mod):
    for cls in grid_classes(mod):
        grid = cls()
        zero = cls.zeroValue
        cacc = grid.getConstAccessor()
        with pytest.raises(TypeError):
            cacc.setValueOn((5, 5, 5), zero)
        with pytest.raises(TypeError):
            cacc.setValueOff((5, 5, 5), zero)
        with pytest.raises(TypeError):
            cacc.setActiveState((5, 5, 5), True)
        assert grid.activeVoxelCount() == 0 and grid.empty()


def test_accessor_argument_errors(mod):
    for cls in grid_classes(mod):
        grid = cls()
        acc = grid.getAccessor()
        zero = cls.zeroValue
        for bad in ["", (0, 0), None, (0.5, 0, 0), ("a", 0, 0)]:
            with pytest.raises(TypeError):
                acc.setValueOn(bad, zero)
            with pytest.raises(TypeError):
                acc.getValue(bad)
        with pytest.raises(OverflowError):
            acc.getValue((2**40, 0, 0))
        if cls is not mod.BoolGrid:
            with pytest.raises(TypeError):
                acc.setValueOn((5, 5, 5), object())
            with pytest.raises(TypeError):
                acc.setValueOff((5, 5, 5), object())
            with pytest.raises(TypeError):
                acc.setValueOn((5, 5, 5), "x")
        with pytest.raises(TypeError):
            acc.setActiveState((0, 0, 0), "x")
        acc.setActiveState((0, 0, 0), 5)  # any number is a state
        assert acc.isValueOn((0, 0, 0))
    with pytest.raises(TypeError):
        mod.FloatGrid().getAccessor().setValueOn((0, 0, 0), (1, 2, 3))
    with pytest.raises(TypeError):
        mod.Vec3SGrid().getAccessor().setValueOn((0, 0, 0), 1.0)
    with pytest.raises(TypeError):
        mod.BoolGrid().getAccessor().setValueOn((0, 0, 0), 2.5)
    with pytest.raises(TypeError):
        mod.FloatGrid("x")


def test_accessors_survive_their_grid(mod):
    for cls in grid_classes(mod):
        grid = cls()
        acc, cacc = grid.getAccessor(), grid.getConstAccessor()
        acc.setValueOn((0, 0, 0), cls.oneValue)
        del grid
        assert acc.getValue((0, 0, 0)) == cls.oneValue == cacc.getValue((0, 0, 0))


# ---- 6. The rest of the module: names and keywords


def public(obj):
    return sorted(n for n in dir(obj) if not n.startswith("_"))


# pyopenvdb names this module leaves out on purpose (python/README.md says why).
LEFT_OUT = {"ax"}


def split_top_level(text):
    """`text` split at the commas outside brackets of any kind."""
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch in "([<{":
            depth += 1
        elif ch in ")]>}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def pyopenvdb_signatures(function):
    """pyopenvdb's overloads of `function` as lists of (keyword, default or None), read from
    the C++ signatures Boost.Python lists when a call does not match (the bound object, if
    any, dropped); None for an overload with a parameter that has no keyword name."""
    try:
        function(__no_such_keyword__=1)
    except Exception as e:  # noqa: BLE001 - Boost.Python's ArgumentError
        text = str(e)
    else:
        return []
    if "C++ signature:" not in text:
        return []
    forms = []
    for line in text.split("C++ signature:")[1].strip().splitlines():
        m = re.match(r"\s*\w+\((.*)\)\s*(->.*)?$", line)
        if not m:
            continue
        form = []
        for i, arg in enumerate(split_top_level(m.group(1))):
            if "{lvalue}" in arg or (i == 0 and inspect.ismethod(function)):
                continue
            decl, _, default = arg.partition("=")
            words = re.split(r"[\s*&]+", decl.strip())
            if len(words) < 2 or not re.fullmatch(r"[A-Za-z_]\w*", words[-1]) or ">" in words[-1]:
                form = None
                break
            form.append((words[-1], default.strip() or None))
        if form is not None:
            forms.append(form)
    return forms


def vdb_signatures(function):
    """This module's overloads of `function` as lists of (keyword, default or None), from
    pybind11's signature lines."""
    forms = []
    for line in (function.__doc__ or "").splitlines():
        m = re.match(r"\s*(?:\d+\. )?\w+\((.*)\) -> ", line)
        if not m:
            continue
        form = []
        for arg in split_top_level(m.group(1)):
            name, _, rest = arg.partition(":")
            default = rest.partition(" = ")[2].strip() if " = " in rest else None
            if name.strip() not in ("self", "*args", "**kwargs"):
                form.append((name.strip(), default))
        forms.append(form)
    return forms


def same_default(ours, theirs):
    if theirs is None:
        return True
    enum = re.fullmatch(r"\w+\.(\w+\.\w+)", theirs)  # pyopenvdb.Axis.X against <Axis.X: 0>
    if enum:
        return ours.startswith("<" + enum.group(1) + ":")
    try:
        a, b = eval(ours), eval(theirs)
    except Exception:  # noqa: BLE001 - a default shown by a name, such as an enum value
        return ours == theirs
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return list(a) == list(b)
    return a == b


@pytest.mark.skipif(pyopenvdb is None, reason="pyopenvdb (python3-openvdb) is not installed")
def test_every_pyopenvdb_name_exists():
    assert [n for n in public(pyopenvdb) if not hasattr(vdb, n) and n not in LEFT_OUT] == []
    for name in ["FloatGrid", "BoolGrid", "Vec3SGrid", "Transform", "Metadata", "GridClass",
                 "VectorType"]:
        theirs, ours = getattr(pyopenvdb, name), getattr(vdb, name)
        assert [n for n in public(theirs) if not hasattr(ours, n)] == [], name
    for name in ["names", "values", "X", "Y", "Z"]:
        assert hasattr(vdb.Axis, name)
    for cls in ("FloatGrid", "BoolGrid", "Vec3SGrid"):
        for nested in ("Accessor", "ConstAccessor", "Value"):
            theirs = getattr(getattr(pyopenvdb, cls), nested)
            ours = getattr(getattr(vdb, cls), nested)
            assert [n for n in public(theirs) if not hasattr(ours, n)] == [], (cls, nested)


def keyword_cases():
    if pyopenvdb is None:
        return []
    grid = pyopenvdb.FloatGrid()
    owners = {"": pyopenvdb, "FloatGrid": grid, "Vec3SGrid": pyopenvdb.Vec3SGrid(),
              "BoolGrid": pyopenvdb.BoolGrid(), "Transform": pyopenvdb.createLinearTransform(),
              "Accessor": grid.getAccessor(), "ConstAccessor": grid.getConstAccessor()}
    cases = []
    for owner, obj in owners.items():
        for name in public(obj):
            fn = getattr(obj, name)
            if inspect.isclass(fn) or not callable(fn) or name in LEFT_OUT:
                continue
            for form in pyopenvdb_signatures(fn):
                cases.append((owner, name, form))
    return cases


def our_object(owner):
    grid = vdb.FloatGrid()
    return {"": vdb, "FloatGrid": grid, "Vec3SGrid": vdb.Vec3SGrid(), "BoolGrid": vdb.BoolGrid(),
            "Transform": vdb.createLinearTransform(), "Accessor": grid.getAccessor(),
            "ConstAccessor": grid.getConstAccessor()}[owner]


@pytest.mark.skipif(pyopenvdb is None, reason="pyopenvdb (python3-openvdb) is not installed")
@pytest.mark.parametrize("owner,name,form", keyword_cases(),
                         ids=lambda x: x if isinstance(x, str) else "")
def test_keywords_and_defaults_match(owner, name, form):
    """Every overload of a pyopenvdb function whose parameters have keyword names has an
    overload here with the same keywords in the same order (more may follow with defaults)
    and the same defaults."""
    ours = vdb_signatures(getattr(our_object(owner), name))
    names = [k for k, _ in form]
    matching = [o for o in ours if [k for k, _ in o[: len(names)]] == names and
                all(d is not None for _, d in o[len(names):])]
    assert matching, (names, ours)
    for (key, theirs), (_, mine) in zip(form, matching[0]):
        assert same_default(mine, theirs), (key, mine, theirs)
