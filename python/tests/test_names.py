# SPDX-License-Identifier: Apache-2.0
"""pyopenvdb's remaining names: LIBRARY_VERSION, the logging settings, VectorType and the
grids' vectorType, the statistics metadata, the tree structure queries (nodeLog2Dims,
getIndexRange, evalLeafBoundingBox, evalLeafDim), and the grids read/readAll cannot return.
Where pyopenvdb 10 is installed, the same body runs on both modules and the results must be
equal; the brute-force models below check the module alone on every grid type."""

import ast
import inspect
import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

import vdb
from conftest import GRID_TYPES, SAMPLES, random_values

ORACLE_TYPES = [t for t in GRID_TYPES if t[3]]
ORACLE_IDS = [t[0].__name__ for t in ORACLE_TYPES]
ALL_IDS = [t[0].__name__ for t in GRID_TYPES]
STATS_NAMES = {"file_bbox_min", "file_bbox_max", "file_mem_bytes", "file_voxel_count"}
EMPTY_BOX = ((2**31 - 1,) * 3, (-(2**31),) * 3)
SAMPLE_FILES = ["smoke.vdb", "sphere.vdb", "torus01.vdb", "fluid_data_0001.vdb", "sphereCd.vdb",
                "wdas_cloud_sixteenth.vdb", "vel_VDB_bound_v02.vdb"]


def outcome(fn, *args, **kwargs):
    """('ok', result) or ('raise', exception class, message), to compare two modules' calls.
    Boost.Python's ArgumentError is reported as the TypeError it derives from."""
    try:
        return ("ok", fn(*args, **kwargs))
    except Exception as e:  # noqa: BLE001 - every exception is compared
        cls = TypeError if type(e).__name__ == "ArgumentError" else type(e)
        return ("raise", cls, str(e))


def same_outcome(a, b, message=True):
    """Asserts that two outcome() results agree (messages too when `message`)."""
    assert a[:2] == b[:2], (a, b)
    if message and a[0] == "raise":
        assert a[2] == b[2]


# ---- Module-level names


def test_library_version(oracle, tmp_path):
    version = vdb.LIBRARY_VERSION
    assert type(version) is type(oracle.LIBRARY_VERSION) is tuple
    assert len(version) == 3 and all(type(v) is int for v in version)
    assert version[:2] == oracle.LIBRARY_VERSION[:2]  # the OpenVDB API the module follows
    # The version the module's files record in their header (after the magic and the file
    # format version: library major and minor, 32-bit little-endian).
    vdb.write(tmp_path / "v.vdb", [vdb.FloatGrid()])
    header = (tmp_path / "v.vdb").read_bytes()[:20]
    assert struct.unpack("<III", header[8:20]) == (vdb.FILE_FORMAT_VERSION, *version[:2])


@pytest.fixture
def restore_logging(oracle):
    yield
    for m in (vdb, oracle):
        m.setLoggingLevel("warn")


def test_logging_level(oracle, restore_logging):
    assert vdb.getLoggingLevel() == oracle.getLoggingLevel() == "warn"
    for level in ["debug", "info", "warn", "error", "fatal", "DEBUG", "Warn", "ERROR"]:
        for m in (vdb, oracle):
            assert m.setLoggingLevel(level) is None
        assert vdb.getLoggingLevel() == oracle.getLoggingLevel() == level.lower()
        assert type(vdb.getLoggingLevel()) is str
    for m in (vdb, oracle):
        m.setLoggingLevel(level="info")
    assert vdb.getLoggingLevel() == oracle.getLoggingLevel() == "info"
    for bad in ["warning", "", " info", "inf", 3, None, 2.5]:
        same_outcome(outcome(vdb.setLoggingLevel, bad), outcome(oracle.setLoggingLevel, bad))
        assert outcome(vdb.setLoggingLevel, bad)[1] is ValueError
        assert vdb.getLoggingLevel() == oracle.getLoggingLevel() == "info"  # unchanged
    for args in [(), ("info", "extra")]:
        same_outcome(outcome(vdb.setLoggingLevel, *args), outcome(oracle.setLoggingLevel, *args),
                     message=False)
    same_outcome(outcome(vdb.getLoggingLevel, 1), outcome(oracle.getLoggingLevel, 1),
                 message=False)


def test_program_name(oracle):
    calls = [(("prog",), {}), (("prog", False), {}), ((), {"name": "prog", "color": False}),
             (("prog",), {"color": True}), (("x", 0), {}), (("x", None), {}), ((3,), {}),
             ((None,), {}), (("x", "y"), {}), ((), {}), (("x",), {"colour": True})]
    for args, kwargs in calls:
        ours = outcome(vdb.setProgramName, *args, **kwargs)
        theirs = outcome(oracle.setProgramName, *args, **kwargs)
        # pyopenvdb's own type errors have its messages; the argument errors Boost's.
        same_outcome(ours, theirs, message=args in [(3,), (None,)])
        assert ours[0] == "raise" or ours[1] is None


VECTOR_TYPE_PROBE = """
import os, pyopenvdb
print(repr(vector_type_facts(pyopenvdb)), flush=True)
os._exit(0)  # pyopenvdb aborts at interpreter exit once these dict-like calls ran
"""


def vector_type_facts(m):
    """What VectorType of module `m` holds: the keys, the attribute values, and an instance's
    len(), iteration and lookups (by name, and of keys that are not names)."""
    v = m.VectorType()

    def lookup(key):
        try:
            return ("ok", v[key])
        except Exception as e:  # noqa: BLE001 - the exception is the fact
            return ("raise", type(e).__name__, str(e))

    return (list(m.VectorType.keys()), type(m.VectorType.keys()).__name__,
            [getattr(m.VectorType, k) for k in m.VectorType.keys()], len(v), list(v),
            [lookup(k) for k in ["INVARIANT", "CONTRAVARIANT_ABSOLUTE", "nope", "invariant", 0]])


def test_vector_type_class(oracle):
    # pyopenvdb's VectorType.keys(), len(), iteration and lookup make the interpreter abort at
    # exit, so its facts come from a child process that leaves without finalizing.
    code = inspect.getsource(vector_type_facts) + VECTOR_TYPE_PROBE
    probe = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           timeout=120)
    theirs = ast.literal_eval(probe.stdout.strip())
    ours = vector_type_facts(vdb)
    assert ours == theirs
    assert ours[0] == ["INVARIANT", "COVARIANT", "COVARIANT_NORMALIZE", "CONTRAVARIANT_RELATIVE",
                       "CONTRAVARIANT_ABSOLUTE"]
    assert ours[1] == "dict_keys" and ours[3] == 5 and ours[4] == ours[0]
    assert vdb.VectorType.COVARIANT_NORMALIZE == "covariant normalize"
    assert ours[5][2][:2] == ("raise", "KeyError")
    for key in ours[0]:  # the attributes that need no instance, on both modules
        assert getattr(vdb.VectorType, key) == getattr(oracle.VectorType, key)


# ---- vectorType


def vector_type_body(m, cls_name):
    """The vectorType operations of one grid class of module `m`, with what they read back."""
    g = getattr(m, cls_name)()
    seen = [g.vectorType, "vector_type" in g.metadata]
    for key in ["INVARIANT", "COVARIANT", "COVARIANT_NORMALIZE", "CONTRAVARIANT_RELATIVE",
                "CONTRAVARIANT_ABSOLUTE"]:  # (pyopenvdb's keys() would abort the exit)
        g.vectorType = getattr(m.VectorType, key)
        seen += [g.vectorType, g.metadata.get("vector_type"), type(g.vectorType)]
    g.vectorType = None  # removes the metadata
    seen += [g.vectorType, "vector_type" in g.metadata]
    g["vector_type"] = "contravariant absolute"  # the metadata is the property's storage
    seen.append(g.vectorType)
    g["vector_type"] = "unheard of"  # an unknown stored name reads as invariant
    seen.append(g.vectorType)
    seen.append(outcome(setattr, g, "vectorType", 3)[:2])
    seen.append(g.vectorType)
    return seen


@pytest.mark.parametrize("cls,dtype,components,name", ORACLE_TYPES, ids=ORACLE_IDS)
def test_vector_type_property(oracle, cls, dtype, components, name):
    assert vector_type_body(vdb, name) == vector_type_body(oracle, name)


@pytest.mark.parametrize("cls,dtype,components,name", GRID_TYPES, ids=ALL_IDS)
def test_vector_type_every_grid(cls, dtype, components, name):
    g = cls()
    assert g.vectorType == vdb.VectorType.INVARIANT
    g.vectorType = vdb.VectorType.COVARIANT
    assert g.vectorType == "covariant" and g["vector_type"] == "covariant"
    # Deliberately stricter than pyopenvdb (which stores "invariant" for any unknown name), as
    # gridClass is: a misspelt name raises instead of silently meaning something else.
    with pytest.raises(ValueError, match="covariant normalize"):
        g.vectorType = "covariant normalised"
    with pytest.raises(TypeError):
        g.vectorType = 1
    assert g.vectorType == "covariant"
    g.vectorType = None
    assert g.vectorType == "invariant" and "vector_type" not in g


def test_vector_type_files_each_way(oracle, tmp_path):
    ours = vdb.Vec3SGrid()
    ours.name = "v"
    ours.vectorType = vdb.VectorType.CONTRAVARIANT_RELATIVE
    vdb.write(tmp_path / "ours.vdb", [ours])
    assert oracle.read(str(tmp_path / "ours.vdb"), "v").vectorType == "contravariant relative"
    theirs = oracle.Vec3SGrid()
    theirs.name = "n"
    theirs.vectorType = oracle.VectorType.COVARIANT_NORMALIZE
    oracle.write(str(tmp_path / "theirs.vdb"), [theirs])
    assert vdb.read(tmp_path / "theirs.vdb", "n").vectorType == "covariant normalize"


# ---- Statistics metadata


def stats_body(m, cls_name, values, one):
    """Statistics metadata through the life of a grid of module `m`; file_mem_bytes, which
    counts each library's own node sizes, is checked against memUsage() and left out."""
    g = getattr(m, cls_name)()
    seen = [g.getStatsMetadata(), g.addStatsMetadata()]
    stats = g.getStatsMetadata()
    assert stats["file_mem_bytes"] == g.memUsage() and type(stats["file_mem_bytes"]) is int
    del stats["file_mem_bytes"]
    seen.append(stats)
    g.copyFromArray(values, (-5, 3, 9))
    g.fill((64, 0, -128), (191, 127, -1), one)  # tiles of two levels
    seen.append(g.getStatsMetadata()["file_voxel_count"])  # not kept up to date
    g.addStatsMetadata()
    stats = g.getStatsMetadata()
    assert stats["file_mem_bytes"] == g.memUsage()
    assert (stats["file_bbox_min"], stats["file_bbox_max"]) == g.evalActiveVoxelBoundingBox()
    assert stats["file_voxel_count"] == g.activeVoxelCount()
    del stats["file_mem_bytes"]
    seen.append(stats)
    seen.append({k: type(v) for k, v in g.getStatsMetadata().items()})
    seen.append(sorted(g.metadata))  # the four names join the metadata
    g["other"] = 1
    seen.append(sorted(g.getStatsMetadata()))  # other metadata is not statistics
    for name in ["file_bbox_min", "file_mem_bytes"]:
        del g[name]
    g["file_voxel_count"] = "any type"
    seen.append(g.getStatsMetadata())
    seen.append(outcome(g.addStatsMetadata, 1)[:2])
    return seen


@pytest.mark.parametrize("cls,dtype,components,name", ORACLE_TYPES, ids=ORACLE_IDS)
def test_stats_metadata(oracle, cls, dtype, components, name, rng):
    values = random_values(rng, (14, 9, 11), dtype, components)
    one = cls.oneValue
    ours = stats_body(vdb, name, values, one)
    assert ours == stats_body(oracle, name, values, one)
    assert ours[0] == {} and ours[1] is None
    assert ours[2] == {"file_bbox_min": EMPTY_BOX[0], "file_bbox_max": EMPTY_BOX[1],
                       "file_voxel_count": 0}


@pytest.mark.parametrize("cls,dtype,components,name", GRID_TYPES, ids=ALL_IDS)
def test_stats_metadata_every_grid(cls, dtype, components, name, rng, tmp_path):
    coords = np.unique(rng.integers(-300, 300, size=(500, 3)), axis=0)
    g = from_coords(cls, dtype, components, coords)
    g.name = "g"
    assert g.getStatsMetadata() == {}
    g.addStatsMetadata()
    assert g.getStatsMetadata() == {
        "file_bbox_min": tuple(int(x) for x in coords.min(axis=0)),
        "file_bbox_max": tuple(int(x) for x in coords.max(axis=0)),
        "file_mem_bytes": g.memUsage(), "file_voxel_count": len(coords)}
    # A file stores the same statistics (recomputed at writing) and reading keeps them.
    vdb.write(tmp_path / "g.vdb", [g])
    assert vdb.read(tmp_path / "g.vdb", "g").getStatsMetadata() == g.getStatsMetadata()


# ---- Tree structure


def from_coords(cls, dtype, components, coords):
    """A grid of `cls` whose active voxels are `coords`, with values one."""
    if cls is vdb.MaskGrid:
        return cls.fromCoords(coords)
    shape = (len(coords),) + ((3,) if components == 3 else ())
    return cls.fromCoords(coords, np.ones(shape, dtype))


def structure(g):
    return (g.nodeLog2Dims(), g.getIndexRange(), g.evalLeafBoundingBox(), g.evalLeafDim())


def leaf_box_model(g):
    """The leaf bounding box from the leaves and tiles themselves: the union of the boxes of
    the leaves that hold an active voxel and of the active tiles."""
    boxes = []
    on_leaves = {tuple(int(c) - int(c) % 8 for c in v.min)
                 for v in g.citerOnValues() if v.depth == g.treeDepth - 1}
    boxes += [(o, tuple(c + 7 for c in o)) for o in on_leaves]
    boxes += [(v.min, v.max) for v in g.citerOnValues() if v.depth < g.treeDepth - 1]
    if not boxes:
        return EMPTY_BOX
    lo = tuple(min(b[0][i] for b in boxes) for i in range(3))
    hi = tuple(max(b[1][i] for b in boxes) for i in range(3))
    return lo, hi


def index_range_model(regions):
    """getIndexRange from the 4096^3 regions (by origin) that hold values: the first and the
    last in (x, y, z) order."""
    if not regions:
        return ((0, 0, 0), (0, 0, 0))
    return min(regions), tuple(c + 4095 for c in max(regions))


def regions_of_box(lo, hi):
    """The origins of the 4096^3 regions that the box [lo, hi] touches."""
    axes = [range(int(a) // 4096, int(b) // 4096 + 1) for a, b in zip(lo, hi)]
    return {(x * 4096, y * 4096, z * 4096) for x in axes[0] for y in axes[1] for z in axes[2]}


def structure_steps(m, cls_name, values, one, zero):
    """Structure queries after each of a series of edits of a grid of module `m`."""
    g = getattr(m, cls_name)()
    out = [structure(g)]
    acc = g.getAccessor()
    for ijk in [(1, 2, 3), (-20, 30, 100), (-5000, 5000, 0), (5000, -5000, 0)]:
        acc.setValueOn(ijk, one)
        out.append(structure(g))
    acc.setValueOff((9000, 9000, 9000), one)  # a leaf without an active voxel
    out.append(structure(g))
    g.copyFromArray(values, (-77, 14, -3))
    out.append(structure(g))
    g.fill((1024, 1024, 1024), (1159, 1151, 1151), one)  # tiles of two levels
    g.fill((-4096 * 3, 0, 0), (-4096 * 2 - 1, 4095, 4095), one)  # a root tile
    out.append(structure(g))
    g.fill((1024, 1024, 1024), (1151, 1151, 1151), zero, False)
    out.append(structure(g))
    for v in g.iterOnValues():
        v.active = False
    out.append(structure(g))
    g.pruneInactive()
    out.append(structure(g))
    g.clear()
    out.append(structure(g))
    return out


@pytest.mark.parametrize("cls,dtype,components,name", ORACLE_TYPES, ids=ORACLE_IDS)
def test_structure_queries(oracle, cls, dtype, components, name, rng):
    values = random_values(rng, (20, 30, 17), dtype, components)
    args = (values, cls.oneValue, cls.zeroValue)
    ours = structure_steps(vdb, name, *args)
    assert ours == structure_steps(oracle, name, *args)
    for step in ours:  # the types too: tuples of ints
        assert type(step[0]) is tuple and all(type(x) is int for x in step[0])
        for box in step[1:3]:
            assert type(box) is tuple and all(type(c) is tuple for c in box)
        assert type(step[3]) is tuple
    assert ours[0] == ((0, 5, 4, 3), ((0, 0, 0), (0, 0, 0)), EMPTY_BOX, (0, 0, 0))
    # A root's keys in (x, y, z) order: the corners are not the componentwise extremes.
    assert ours[4][1] == ((-8192, 4096, 0), (8191, -4097, 4095))


@pytest.mark.parametrize("cls,dtype,components,name", GRID_TYPES, ids=ALL_IDS)
def test_structure_models(cls, dtype, components, name, rng):
    for trial in range(6):
        coords = rng.integers(-9000, 9000, size=(int(rng.integers(1, 40)), 3))
        g = from_coords(cls, dtype, components, coords)
        regions = {tuple(int(c) for c in ijk - ijk % 4096) for ijk in coords}
        if trial % 2:  # tiles of two levels and partly filled leaves
            corner = rng.integers(-40, 40, size=3) * 128
            boxes = [(corner, corner + 127), (corner + 128, corner + 135)]
            lo = rng.integers(-300, 300, size=3)
            boxes.append((lo, lo + rng.integers(0, 40, size=3)))
            for a, b in boxes:
                g.fill(tuple(int(x) for x in a), tuple(int(x) for x in b), cls.oneValue)
                regions |= regions_of_box(a, b)
        for v in g.iterOnValues():  # deactivate some voxels and tiles
            if rng.random() < 0.3:
                v.active = False
        assert g.nodeLog2Dims() == (0, 5, 4, 3)
        assert g.evalLeafBoundingBox() == leaf_box_model(g)
        lo, hi = leaf_box_model(g)
        expected_dim = (0, 0, 0) if lo == EMPTY_BOX[0] else tuple(b - a + 1 for a, b in zip(lo, hi))
        assert g.evalLeafDim() == expected_dim
        assert g.getIndexRange() == index_range_model(regions)


@pytest.mark.parametrize("sample", SAMPLE_FILES)
def test_sample_files(oracle, sample):
    path = SAMPLES / sample
    if not path.exists():
        pytest.skip(f"{path} is not present")
    ours = {g.name: g for g in vdb.readAll(path)[0]}
    theirs = {g.name: g for g in oracle.readAll(str(path))[0]}
    assert sorted(ours) == sorted(theirs)
    for name, g in ours.items():
        t = theirs[name]
        assert structure(g) == structure(t)
        assert g.getStatsMetadata() == t.getStatsMetadata()
        assert g.vectorType == t.vectorType


# ---- Grids that read and readAll cannot return


def file_with_foreign_grid(path):
    """A file of three grids whose "flags" grid has a type no library knows (its type name
    changed in place from Tree_int32_5_4_3), with the other two grids' contents."""
    density = vdb.FloatGrid()
    density.fill((0, 0, 0), (9, 9, 9), 2.5)
    density.name = "density"
    vel = vdb.Vec3SGrid()
    vel.getAccessor().setValueOn((3, -4, 5), (1, 2, 3))
    vel.name = "vel"
    flags = vdb.Int32Grid()
    flags.getAccessor().setValueOn((1, 1, 1), 7)
    flags.name = "flags"
    vdb.write(path, [density, vel, flags])
    data = path.read_bytes()
    assert data.count(b"Tree_int32_5_4_3") == 1
    path.write_bytes(data.replace(b"Tree_int32_5_4_3", b"Tree_xnt32_5_4_3"))
    return density, vel


def test_read_all_warns_about_grids_it_leaves_out(tmp_path):
    path = tmp_path / "mixed.vdb"
    density, vel = file_with_foreign_grid(path)
    with pytest.warns(UserWarning) as caught:
        grids, meta = vdb.readAll(path)
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1
    assert '"flags"' in messages[0] and "Tree_xnt32_5_4_3" in messages[0]
    assert str(path) in messages[0]
    assert sorted(g.name for g in grids) == ["density", "vel"]
    by_name = {g.name: g for g in grids}
    assert by_name["density"].activeVoxelCount() == density.activeVoxelCount() == 1000
    assert by_name["vel"].getConstAccessor().getValue((3, -4, 5)) == (1, 2, 3)

    with pytest.warns(UserWarning, match='"flags"'):
        names = [g.name for g in vdb.readAllGridMetadata(path)]
    assert sorted(names) == ["density", "vel"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning turned into an error propagates
        with pytest.raises(UserWarning, match='"flags"'):
            vdb.readAll(path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning for grids the module returns
        assert vdb.read(path, "vel").name == "vel"
        assert vdb.readGridMetadata(path, "density").name == "density"
        assert vdb.readMetadata(path) == {}
    with pytest.raises(TypeError, match='"flags".*Tree_xnt32_5_4_3'):
        vdb.read(path, "flags")
    with pytest.raises(TypeError, match='"flags"'):
        vdb.readGridMetadata(path, "flags")
    with pytest.raises(OSError):
        vdb.read(path, "nothing")


def test_read_all_warns_about_points_grids():
    path = SAMPLES / "pointgrid.vdb"
    if not path.exists():
        pytest.skip(f"{path} is not present")
    with pytest.warns(UserWarning, match='"points".*Tree_ptdataidx32_5_4_3'):
        grids, _ = vdb.readAll(path)
    assert grids == []
    with pytest.raises(TypeError, match="Tree_ptdataidx32_5_4_3"):
        vdb.read(path, "points")


def test_oracle_refuses_the_same_grids(oracle, tmp_path):
    """pyopenvdb raises for the whole file instead; the module returns what it can."""
    path = tmp_path / "mixed.vdb"
    file_with_foreign_grid(path)
    with pytest.raises(LookupError, match="Tree_xnt32_5_4_3"):
        oracle.readAll(str(path))
    points = SAMPLES / "pointgrid.vdb"
    if points.exists():
        with pytest.raises(TypeError):
            oracle.readAll(str(points))
