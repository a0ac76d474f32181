# SPDX-License-Identifier: Apache-2.0
"""vdb.tools and the grid operations without a pyopenvdb counterpart (merge, which pyopenvdb
10 cannot call), against brute-force models over dense arrays."""

import numpy as np
import pytest

import vdb
from conftest import random_values


def dense(grid, lo, shape):
    out = np.zeros(shape, grid.dtype)
    grid.copyToArray(out, lo)
    return out


def active_mask(grid, lo, shape):
    mask = vdb.BoolGrid()
    coords, _ = grid.activeVoxels()
    out = np.zeros(shape, bool)
    inside = np.all((coords >= lo) & (coords < np.array(lo) + shape), axis=1)
    c = coords[inside] - lo
    out[c[:, 0], c[:, 1], c[:, 2]] = True
    del mask
    return out


def test_merge_takes_active_values_where_inactive(rng):
    a_vals = random_values(rng, (20, 20, 20), np.float32, 1, background_fraction=0.6)
    b_vals = random_values(rng, (20, 20, 20), np.float32, 1, background_fraction=0.6)
    a, b = vdb.FloatGrid(), vdb.FloatGrid()
    a.copyFromArray(a_vals, (-5, 0, 0))
    b.copyFromArray(b_vals, (0, 0, 0))
    b.fill((40, 0, 0), (79, 31, 31), 2.0)  # tiles and partial leaves
    a_off = a.getAccessor()
    a_off.setValueOff((0, 0, 0), 9.0)  # inactive, not background
    lo, shape = (-8, -1, -1), (90, 34, 34)
    ea, eb = dense(a, lo, shape), dense(b, lo, shape)
    ma, mb = active_mask(a, lo, shape), active_mask(b, lo, shape)
    a.merge(b)
    take = ~ma & mb
    np.testing.assert_array_equal(dense(a, lo, shape), np.where(take, eb, ea))
    np.testing.assert_array_equal(active_mask(a, lo, shape), ma | mb)
    assert b.empty()


def test_combine_matches_the_model(rng):
    a_vals = random_values(rng, (16, 16, 16), np.float64, 1, background_fraction=0.5)
    b_vals = random_values(rng, (16, 16, 16), np.float64, 1, background_fraction=0.5)
    a, b = vdb.DoubleGrid(1.0), vdb.DoubleGrid(-2.0)
    a.copyFromArray(a_vals, (0, 0, 0))
    b.copyFromArray(b_vals, (8, 0, 0))
    b.fill((64, 0, 0), (191, 127, 127), 4.0, False)
    lo, shape = (-2, -2, -2), (200, 20, 20)
    ea, eb = dense(a, lo, shape), dense(b, lo, shape)
    ma, mb = active_mask(a, lo, shape), active_mask(b, lo, shape)
    a.combine(b, lambda x, y: max(x, y) - 0.5 * y)
    np.testing.assert_array_equal(dense(a, lo, shape), np.maximum(ea, eb) - 0.5 * eb)
    np.testing.assert_array_equal(active_mask(a, lo, shape), ma | mb)
    assert a.background == 1.0 + 1.0


@pytest.mark.parametrize("op,model", [("csgUnion", np.minimum), ("csgIntersection", np.maximum),
                                      ("csgDifference", lambda a, b: np.maximum(a, -b))])
def test_csg(op, model):
    lo, shape = (-40, -40, -40), (80, 80, 80)
    make = [lambda: vdb.createLevelSetSphere(1.0, (0, 0, 0), 0.05),
            lambda: vdb.createLevelSetSphere(1.0, (0.6, 0.2, 0), 0.05)]
    a, b = make[0](), make[1]()
    ea, eb = dense(a, lo, shape), dense(b, lo, shape)
    copy = getattr(vdb.tools, op + "Copy")(a, b)
    getattr(vdb.tools, op)(a, b)
    assert b.empty()
    expected = model(ea, eb)
    for result in (a, copy):
        got = dense(result, lo, shape)
        # Exact where both inputs are inside their narrow bands.
        band = (np.abs(ea) < 0.15) & (np.abs(eb) < 0.15)
        np.testing.assert_array_equal(got[band], expected[band])
        np.testing.assert_array_equal(np.sign(got), np.sign(expected))


def test_morphology_matches_the_model():
    grid = vdb.MaskGrid()
    coords = np.array([[0, 0, 0], [5, 5, 5], [9, 1, 3]])
    grid = vdb.MaskGrid.fromCoords(coords)
    vdb.tools.dilateActiveValues(grid, 2, vdb.tools.NN_FACE)
    lo, shape = (-5, -5, -5), (20, 20, 20)
    got = active_mask(grid, lo, shape)
    idx = np.indices(shape).transpose(1, 2, 3, 0) + lo
    expected = np.zeros(shape, bool)
    for c in coords:
        expected |= np.abs(idx - c).sum(axis=-1) <= 2
    np.testing.assert_array_equal(got, expected)
    vdb.tools.erodeActiveValues(grid, 2, vdb.tools.NN_FACE)
    assert grid.activeVoxelCount() == 3


def test_advection_moves_the_sphere():
    grid = vdb.createLevelSetSphere(1.0, (0, 0, 0), 0.1)
    steps = vdb.tools.advect(grid, (1.0, 0.0, 0.0), 0.0, 0.5)
    assert steps > 0
    acc = grid.getConstAccessor()
    # The surface moved by 0.5 along x: it now crosses x = -0.5 and x = 1.5 (index -5 and 15),
    # the new center (index 5) is deep inside (minus the band's half width, 0.3), the old
    # left pole (index -10) outside.
    assert acc.getValue((5, 0, 0)) == pytest.approx(-0.3, abs=1e-6)
    assert acc.getValue((15, 0, 0)) == pytest.approx(0.0, abs=0.02)
    assert acc.getValue((-5, 0, 0)) == pytest.approx(0.0, abs=0.02)
    assert acc.getValue((-10, 0, 0)) > 0.0


def test_rebuild_and_spheres():
    grid = vdb.createLevelSetSphere(1.0, (0, 0, 0), 0.1, 2.0)
    rebuilt = vdb.tools.levelSetRebuild(grid, 0.0, 3.0)
    assert rebuilt.activeVoxelCount() > grid.activeVoxelCount()
    double = vdb.tools.createLevelSetSphere(1.0, (0, 0, 0), 0.1, 3.0, vdb.DoubleGrid)
    assert isinstance(double, vdb.DoubleGrid)
    enright = vdb.tools.createEnrightSphere(64)
    assert enright.transform.voxelSize()[0] == pytest.approx(1 / 64)
