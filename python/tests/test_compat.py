# SPDX-License-Identifier: Apache-2.0
"""The same operations on vdb and on pyopenvdb 10 (Debian's python3-openvdb), in one process,
give the same results: dense arrays, level sets, meshes, files, metadata, transforms,
iterators and the grid operations. Skipped when pyopenvdb is not installed."""

import numpy as np
import pytest

import vdb
from conftest import GRID_TYPES, SAMPLES, random_values

ORACLE_TYPES = [t for t in GRID_TYPES if t[3]]
ORACLE_IDS = [t[0].__name__ for t in ORACLE_TYPES]


def active_items(grid):
    """(min, max, depth, count, value, active) of every active item, in iterator order."""
    out = []
    for item in grid.citerOnValues():
        value = item.value
        out.append((tuple(item.min), tuple(item.max), item.depth, item.count,
                    tuple(value) if isinstance(value, tuple) else value, item.active))
    return out


def same_grid(a, b, tol=0.0):
    """Asserts that a vdb grid and a pyopenvdb grid hold the same active values."""
    assert a.activeVoxelCount() == b.activeVoxelCount()
    assert a.evalActiveVoxelBoundingBox() == b.evalActiveVoxelBoundingBox()
    coords, values = a.activeVoxels()
    acc = b.getConstAccessor()
    sample = coords[:: max(1, len(coords) // 20000)]
    theirs = np.array([acc.getValue(tuple(int(x) for x in c)) for c in sample])
    ours = values[:: max(1, len(coords) // 20000)]
    assert all(acc.isValueOn(tuple(int(x) for x in c)) for c in sample[:2000])
    if tol:
        np.testing.assert_allclose(ours, theirs.reshape(ours.shape), atol=tol)
    else:
        np.testing.assert_array_equal(ours, theirs.reshape(ours.shape))


@pytest.mark.parametrize("cls,dtype,components,name", ORACLE_TYPES, ids=ORACLE_IDS)
@pytest.mark.parametrize("tolerance", [0, 0.5])
def test_copy_from_and_to_array(oracle, cls, dtype, components, name, tolerance, rng):
    values = random_values(rng, (21, 17, 30), dtype, components)
    if dtype != np.bool_:
        values = (values / 50).astype(dtype)  # many values within the tolerance of 0
    ours, theirs = cls(), getattr(oracle, name)()
    if components == 3:  # pyopenvdb takes a vector tolerance for vector grids
        tolerance = (tolerance,) * 3
    elif dtype == np.bool_:
        tolerance = False  # a bool tolerance means nothing (OpenVDB treats True as "all equal")
    ours.copyFromArray(values, (5, -6, 7), tolerance)
    theirs.copyFromArray(values, (5, -6, 7), tolerance)
    same_grid(ours, theirs)
    a = np.zeros((25, 20, 33) + values.shape[3:], dtype)
    b = np.zeros_like(a)
    ours.copyToArray(a, (3, -8, 6))
    theirs.copyToArray(b, (3, -8, 6))
    np.testing.assert_array_equal(a, b)


def test_level_set_spheres(oracle):
    for radius, center, voxel, width in [(10.0, (0.5, 1.2, -3.1), 0.5, 3.0), (1.0, (0, 0, 0), 0.05, 2.5)]:
        ours = vdb.createLevelSetSphere(radius, center, voxel, width)
        theirs = oracle.createLevelSetSphere(radius, center, voxel, width)
        assert ours.gridClass == theirs.gridClass == "level set"
        assert ours.background == pytest.approx(theirs.background)
        assert ours.transform.voxelSize() == pytest.approx(theirs.transform.voxelSize())
        same_grid(ours, theirs, tol=1e-5)


def test_polygons_to_level_set_and_back(oracle):
    sphere = oracle.createLevelSetSphere(5.0, (0.3, 0.1, 0.2), 0.2)
    points, triangles, quads = sphere.convertToPolygons()
    ours_mesh = vdb.createLevelSetSphere(5.0, (0.3, 0.1, 0.2), 0.2).convertToPolygons()
    assert abs(len(ours_mesh[0]) - len(points)) <= 0.01 * len(points)
    xform = oracle.createLinearTransform(0.2)
    theirs = oracle.FloatGrid.createLevelSetFromPolygons(points, triangles, quads, xform, 3.0)
    ours = vdb.FloatGrid.createLevelSetFromPolygons(points, triangles, quads,
                                                    vdb.createLinearTransform(0.2), 3.0)
    assert ours.gridClass == "level set"
    # The same band (to a voxel at its edge) and the same distances near the surface.
    assert abs(ours.activeVoxelCount() - theirs.activeVoxelCount()) <= 0.02 * theirs.activeVoxelCount()
    coords, values = ours.activeVoxels()
    near = np.abs(values) < 0.2  # within a voxel of the surface
    acc = theirs.getConstAccessor()
    theirs_near = np.array([acc.getValue(tuple(int(x) for x in c)) for c in coords[near]])
    np.testing.assert_allclose(values[near], theirs_near, atol=0.02)


def test_files_each_way(oracle, tmp_path):
    ours = vdb.createLevelSetSphere(3.0, (1, 2, 3), 0.25)
    ours.name = "sphere"
    ours["note"] = "from vdb"
    vec = vdb.Vec3SGrid((0, 0, 0))
    vec.name = "vel"
    vec.copyFromArray(np.ones((9, 9, 9, 3), np.float32) * [1, 2, 3])
    vdb.write(tmp_path / "ours.vdb", [ours, vec], metadata={"author": "vdb", "n": 7})
    grids, meta = oracle.readAll(str(tmp_path / "ours.vdb"))
    assert meta["author"] == "vdb" and meta["n"] == 7
    by_name = {g.name: g for g in grids}
    same_grid(ours, by_name["sphere"])
    same_grid(vec, by_name["vel"])
    assert by_name["sphere"]["note"] == "from vdb"

    theirs = oracle.createLevelSetSphere(2.0, (0, 0, 0), 0.1)
    theirs.name = "ls"
    theirs["count"] = 2**40
    oracle.write(str(tmp_path / "theirs.vdb"), [theirs], {"tool": "pyopenvdb"})
    back = vdb.read(tmp_path / "theirs.vdb", "ls")
    same_grid(back, theirs)
    assert back["count"] == 2**40
    assert vdb.readMetadata(tmp_path / "theirs.vdb")["tool"] == "pyopenvdb"
    meta_only = vdb.readAllGridMetadata(tmp_path / "theirs.vdb")
    assert [g.name for g in meta_only] == ["ls"] and meta_only[0].activeVoxelCount() == 0
    assert meta_only[0]["file_voxel_count"] == theirs.activeVoxelCount()


@pytest.mark.parametrize("sample", ["smoke.vdb", "sphere.vdb", "torus01.vdb"])
def test_sample_files(oracle, sample):
    path = SAMPLES / sample
    if not path.exists():
        pytest.skip(f"{path} is not present")
    ours, ours_meta = vdb.readAll(path)
    theirs, theirs_meta = oracle.readAll(str(path))
    assert ours_meta == theirs_meta
    assert sorted(g.name for g in ours) == sorted(g.name for g in theirs)
    for a in ours:
        b = next(g for g in theirs if g.name == a.name)
        assert a.metadata == b.metadata
        assert a.transform.voxelSize() == pytest.approx(b.transform.voxelSize())
        same_grid(a, b)


def test_metadata_types(oracle):
    items = {"i": 1, "big": 2**40, "neg": -(2**31), "f": 1.5, "s": "text", "b": True,
             "vi": (1, 2, 3), "vd": (1.0, 2.5, 3.0)}
    ours, theirs = vdb.FloatGrid(), oracle.FloatGrid()
    for k, v in items.items():
        ours[k] = v
        theirs[k] = v
    assert ours.metadata == theirs.metadata
    for k, v in items.items():
        assert type(ours[k]) is type(theirs[k]) and ours[k] == theirs[k]
    ours.updateMetadata({"i": 5})
    theirs.updateMetadata({"i": 5})
    assert ours.metadata == theirs.metadata
    del ours["i"]
    assert "i" not in ours and "s" in ours and sorted(ours) == sorted(k for k in items if k != "i")


def test_transforms(oracle):
    for voxel in [0.5, 0.1]:
        ours = vdb.createLinearTransform(voxel)
        theirs = oracle.createLinearTransform(voxel)
        ours.translate((1, 2, 3))
        theirs.translate((1, 2, 3))
        ours.rotate(0.3, vdb.Axis.Y)
        theirs.rotate(0.3, oracle.Axis.Y)
        ours.scale((1.0, 2.0, 0.5))
        theirs.scale((1.0, 2.0, 0.5))
        for p in [(0, 0, 0), (1.5, -2, 7), (100, 3, -9)]:
            assert ours.indexToWorld(p) == pytest.approx(theirs.indexToWorld(p))
            assert ours.worldToIndex(p) == pytest.approx(theirs.worldToIndex(p))
            assert ours.worldToIndexCellCentered(p) == theirs.worldToIndexCellCentered(p)
        assert ours.voxelSize() == pytest.approx(theirs.voxelSize())
    m = [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0], [1, 2, 3, 1]]
    assert vdb.createLinearTransform(m).indexToWorld((1, 1, 1)) == pytest.approx(
        oracle.createLinearTransform(m).indexToWorld((1, 1, 1)))
    grid = vdb.FloatGrid()
    grid.transform = vdb.createLinearTransform(0.25)
    assert grid.transform.voxelSize() == (0.25, 0.25, 0.25)


@pytest.mark.parametrize("cls,dtype,components,name", ORACLE_TYPES, ids=ORACLE_IDS)
def test_iterators_and_grid_operations(oracle, cls, dtype, components, name, rng):
    values = random_values(rng, (10, 12, 9), dtype, components)
    one = cls.oneValue
    ours, theirs = cls(), getattr(oracle, name)()
    for g in (ours, theirs):
        g.copyFromArray(values, (-3, 0, 2))
        g.fill((64, 0, 0), (127, 127, 127), one)  # tiles of two levels
        g.fill((200, 0, 0), (203, 1, 1), one, False)
    assert active_items(ours) == active_items(theirs)
    assert ours.evalMinMax() == theirs.evalMinMax()
    assert ours.evalActiveVoxelBoundingBox() == theirs.evalActiveVoxelBoundingBox()
    assert ours.activeVoxelCount() == theirs.activeVoxelCount()
    assert ours.leafCount() == theirs.leafCount()
    for g in (ours, theirs):
        for item in g.iterOnValues():
            if item.depth == 3 and item.min[0] % 2 == 0:
                item.active = False
        g.pruneInactive()
    assert active_items(ours) == active_items(theirs)
    assert ours.leafCount() == theirs.leafCount()
    if dtype != np.bool_:
        for g in (ours, theirs):
            g.mapOn(lambda v: tuple(x * 2 for x in v) if isinstance(v, tuple) else v * 2)
        assert active_items(ours) == active_items(theirs)


def test_signed_flood_fill_prune_background_combine(oracle, rng):
    ours = vdb.createLevelSetSphere(4.0, (0, 0, 0), 0.2)
    theirs = oracle.createLevelSetSphere(4.0, (0, 0, 0), 0.2)
    acc = (ours.getConstAccessor(), theirs.getConstAccessor())
    for p in [(0, 0, 0), (5, 3, 1), (30, 0, 0), (-100, 0, 0)]:
        assert acc[0].getValue(p) == pytest.approx(acc[1].getValue(p))
    for g in (ours, theirs):
        g.background = 1.0
    assert ours.getConstAccessor().getValue((100, 0, 0)) == theirs.getConstAccessor().getValue((100, 0, 0))
    assert ours.getConstAccessor().getValue((0, 0, 0)) == pytest.approx(
        theirs.getConstAccessor().getValue((0, 0, 0)))

    a, b = vdb.FloatGrid(1.0), vdb.FloatGrid(2.0)
    oa, ob = oracle.FloatGrid(1.0), oracle.FloatGrid(2.0)
    vals = random_values(rng, (12, 12, 12), np.float32, 1)
    for x, y in ((a, b), (oa, ob)):
        x.copyFromArray(vals, (0, 0, 0))
        y.copyFromArray(vals[::-1].copy(), (4, 0, 0))
        y.fill((64, 64, 64), (95, 95, 95), 3.0)
        x.combine(y, lambda p, q: p * 2 + q)
    assert a.background == oa.background
    assert active_items(a) == active_items(oa)
    assert b.activeVoxelCount() == ob.activeVoxelCount() == 0
    dense = [np.zeros((100, 100, 100), np.float32) for _ in range(2)]
    a.copyToArray(dense[0])
    oa.copyToArray(dense[1])
    np.testing.assert_array_equal(dense[0], dense[1])


def test_value_depth_and_is_voxel(oracle):
    # A leaf voxel, tiles filled at the lower internal, upper internal and root levels, and
    # coordinates with no root entry (the background), as pyopenvdb reports them.
    probes = [(1, 2, 3), (200, 0, 0), (130, 0, 0), (9000, 0, 0), (5000, 5000, 5000),
              (-70000, 12, 3), (4095, 4095, 4095)]
    results = []
    for module in (vdb, oracle):
        grid = module.FloatGrid()
        acc = grid.getAccessor()
        acc.setValueOn((1, 2, 3), 1.0)
        grid.fill((128, 0, 0), (255, 127, 127), 2.0)  # a lower internal node's tile
        grid.fill((8192, 0, 0), (12287, 4095, 4095), 3.0)  # a root tile
        grid.fill((4096, 4096, 4096), (8191, 8191, 8191), 4.0, active=False)
        acc = grid.getAccessor()
        results.append([(acc.getValueDepth(p), acc.isVoxel(p)) for p in probes])
    assert results[0] == results[1]
