# SPDX-License-Identifier: Apache-2.0
"""Round trips NumPy -> grid -> NumPy for every grid type, the bulk transfers against the
iterators and a brute-force model, and the copy / no-copy semantics of each transfer."""

import numpy as np
import pytest

import vdb
from conftest import GRID_TYPES, random_values

IDS = [t[0].__name__ for t in GRID_TYPES]


def model_active(values, components):
    """The voxels a dense array makes active: those that differ from the zero background."""
    return np.any(values != 0, axis=-1) if components == 3 else values != 0


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_dense_round_trip_is_exact(cls, dtype, components, _, rng):
    shape = (19, 24, 33)
    values = random_values(rng, shape, dtype, components)
    origin = (-13, 5, -40)
    grid = cls()
    assert grid.dtype == np.dtype(dtype)
    grid.copyFromArray(values, ijk=origin)
    active = model_active(values, components)
    assert grid.activeVoxelCount() == int(active.sum())

    out = np.zeros_like(values)
    grid.copyToArray(out, ijk=origin)
    np.testing.assert_array_equal(out, values)

    # A box larger than the data: background around it.
    big = np.ones((21, 26, 35) + values.shape[3:], dtype)
    grid.copyToArray(big, ijk=(origin[0] - 1, origin[1] - 1, origin[2] - 1))
    np.testing.assert_array_equal(big[1:-1, 1:-1, 1:-1], values)
    assert not big[0].any() and not big[-1].any() and not big[:, :, 0].any()


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_active_voxels_match_the_iterator_and_the_model(cls, dtype, components, _, rng):
    values = random_values(rng, (17, 9, 20), dtype, components)
    grid = cls()
    grid.copyFromArray(values, ijk=(3, -4, 8))
    coords, vals = grid.activeVoxels()
    assert coords.dtype == np.int32 and coords.shape == (grid.activeVoxelCount(), 3)
    assert vals.dtype == np.dtype(dtype)
    assert vals.shape == ((len(coords), 3) if components == 3 else (len(coords),))

    # The same sequence as the value iterator (no tiles: every item is a voxel).
    items = [(item.min, item.value) for item in grid.citerOnValues()]
    assert [tuple(c) for c in coords.tolist()] == [m for m, _ in items]
    expected = np.array([v for _, v in items], dtype=dtype)
    np.testing.assert_array_equal(vals, expected.reshape(vals.shape))

    # Against the dense model.
    local = coords - np.array([3, -4, 8])
    np.testing.assert_array_equal(vals, values[local[:, 0], local[:, 1], local[:, 2]])
    assert model_active(values, components)[local[:, 0], local[:, 1], local[:, 2]].all()


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_active_voxels_expand_tiles(cls, dtype, components, _):
    grid = cls()
    one = cls.oneValue
    grid.fill((0, 0, 0), (15, 15, 15), one)  # whole leaves: tiles
    grid.fill((100, 0, 0), (100, 0, 2), one)  # voxels
    assert grid.leafCount() == 1
    coords, vals = grid.activeVoxels()
    assert len(coords) == 16**3 + 3
    assert len({tuple(c) for c in coords.tolist()}) == len(coords)
    lo, hi = coords.min(axis=0), coords.max(axis=0)
    assert tuple(lo) == (0, 0, 0) and tuple(hi) == (100, 15, 15)
    assert (vals == np.array(one, dtype=dtype)).all()


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_from_coords_rebuilds_the_grid(cls, dtype, components, _, rng):
    values = random_values(rng, (30, 20, 25), dtype, components)
    grid = cls()
    grid.copyFromArray(values, ijk=(-7, 11, 2000))
    coords, vals = grid.activeVoxels()
    if cls is vdb.MaskGrid:
        rebuilt = cls.fromCoords(coords)
    else:
        # Shuffled, as int64 coordinates: the result does not depend on the order.
        order = rng.permutation(len(coords))
        rebuilt = cls.fromCoords(coords[order].astype(np.int64), vals[order])
    c2, v2 = rebuilt.activeVoxels()
    np.testing.assert_array_equal(c2, coords)
    np.testing.assert_array_equal(v2, vals)
    assert rebuilt.leafCount() == grid.leafCount()


def test_from_coords_last_repeated_coordinate_wins():
    coords = np.array([[1, 2, 3], [1, 2, 3], [-9, 0, 0], [1, 2, 3]], np.int32)
    grid = vdb.FloatGrid.fromCoords(coords, np.array([1, 2, 3, 4], np.float32), -1.0)
    acc = grid.getConstAccessor()
    assert acc.getValue((1, 2, 3)) == 4.0 and acc.getValue((-9, 0, 0)) == 3.0
    assert acc.getValue((0, 0, 0)) == -1.0 and grid.background == -1.0
    assert grid.activeVoxelCount() == 2


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_leaf_values_and_origins(cls, dtype, components, _, rng):
    values = random_values(rng, (20, 12, 17), dtype, components)
    grid = cls()
    grid.copyFromArray(values, ijk=(-4, 0, 3))
    origins = grid.leafOrigins()
    leaves = grid.leafValues()
    assert origins.shape == (grid.leafCount(), 3) and (origins % 8 == 0).all()
    assert leaves.shape == (grid.leafCount(), 8, 8, 8) + ((3,) if components == 3 else ())
    for origin, leaf in zip(origins, leaves):
        dense = np.zeros_like(leaf)
        grid.copyToArray(dense, ijk=tuple(int(x) for x in origin))
        np.testing.assert_array_equal(leaf, dense)
    # leafValues() is a copy: writing it leaves the grid alone ...
    before = grid.activeVoxels()[1].copy()
    leaves[...] = cls.oneValue
    np.testing.assert_array_equal(grid.activeVoxels()[1], before)
    # ... until written back with setLeafValues().
    grid.setLeafValues(leaves)
    assert (grid.activeVoxels()[1] == np.array(cls.oneValue, dtype)).all()


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES[:4] + GRID_TYPES[6:], ids=IDS[:4] + IDS[6:])
def test_leaf_buffers_are_views_both_ways(cls, dtype, components, _, rng):
    values = random_values(rng, (16, 16, 8), dtype, components, background_fraction=0)
    grid = cls()
    grid.copyFromArray(values)
    views = grid.leafBuffers()
    origins = grid.leafOrigins()
    assert len(views) == 4 and all(v.flags.writeable and not v.flags.owndata for v in views)
    acc = grid.getAccessor()
    ijk = tuple(int(x) for x in origins[2] + [1, 2, 3])
    one = np.array(cls.oneValue, dtype)
    # A write through the view is seen by the grid ...
    views[2][1, 2, 3] = one
    assert np.array_equal(np.array(acc.getValue(ijk), dtype), one)
    # ... and a write through the grid is seen by the view.
    acc.setValueOn(ijk, cls.zeroValue)
    assert not np.any(views[2][1, 2, 3])
    # A view keeps the grid alive, and blocks operations that could free its leaves.
    with pytest.raises(RuntimeError, match="leafBuffers"):
        grid.prune()
    with pytest.raises(RuntimeError):
        grid.copyFromArray(values)
    view = views[0]
    del views, grid, acc
    view[0, 0, 0] = one  # the leaf is still alive
    assert np.array_equal(view[0, 0, 0], one)


def test_leaf_buffers_release_the_grid():
    grid = vdb.FloatGrid()
    grid.fill((0, 0, 0), (7, 7, 7), 1.0)
    grid.getAccessor().setValueOn((0, 0, 0), 2.0)
    views = grid.leafBuffers()
    del views
    grid.prune()  # allowed again
    with pytest.raises(TypeError):
        vdb.BoolGrid().leafBuffers()


@pytest.mark.parametrize("cls,dtype,components,_", GRID_TYPES, ids=IDS)
def test_strided_views_are_read_and_written_in_place(cls, dtype, components, _, rng):
    base = random_values(rng, (24, 18, 30), dtype, components)
    view = base[::2, 3:15, ::-3]  # non-contiguous, negative step
    assert not view.flags.c_contiguous
    a, b = cls(), cls()
    a.copyFromArray(view, ijk=(1, 2, 3))
    b.copyFromArray(np.ascontiguousarray(view), ijk=(1, 2, 3))
    np.testing.assert_array_equal(a.activeVoxels()[1], b.activeVoxels()[1])

    target = np.zeros_like(base)
    window = target[1::2, ::2, 5:25]
    a.copyToArray(window, ijk=(1, 2, 3))
    expected = np.zeros_like(base[: window.shape[0], : window.shape[1], : window.shape[2]])
    a.copyToArray(expected, ijk=(1, 2, 3))
    np.testing.assert_array_equal(window, expected)
    untouched = np.ones(target.shape[:3], bool)
    untouched[1::2, ::2, 5:25] = False
    assert not target[untouched].any()


def test_other_dtypes_are_converted():
    grid = vdb.FloatGrid()
    values = np.arange(2 * 3 * 4, dtype=np.float64).reshape(2, 3, 4) / 3
    grid.copyFromArray(values)
    out = np.zeros((2, 3, 4), np.float64)
    grid.copyToArray(out)
    np.testing.assert_array_equal(out, values.astype(np.float32).astype(np.float64))
    ints = np.zeros((2, 3, 4), np.int16)
    grid.copyToArray(ints)
    np.testing.assert_array_equal(ints, values.astype(np.float32).astype(np.int16))


def test_tolerance_deactivates_near_background():
    grid = vdb.FloatGrid(1.0)
    values = np.array([[[1.0, 1.05, 1.2, 0.95]]], np.float32)
    grid.copyFromArray(values, tolerance=0.1)
    acc = grid.getConstAccessor()
    assert [acc.isValueOn((0, 0, k)) for k in range(4)] == [False, False, True, False]
    assert acc.getValue((0, 0, 1)) == 1.0  # inactive background
    vec = vdb.Vec3SGrid((1, 1, 1))
    vec.copyFromArray(np.array([[[[1.05, 1, 1], [2, 1, 1]]]], np.float32), tolerance=0.1)
    assert vec.activeVoxelCount() == 1
