# SPDX-License-Identifier: Apache-2.0
"""vdb.tools filtering, operators, measures, level set utilities, fast sweeping, resampling,
sampling, statistics, clipping and compositing, against analytic values, NumPy models and
pyopenvdb where it has the same function."""

import math

import numpy as np
import pytest

import vdb

T = vdb.tools


def dense(grid, lo, shape):
    out = np.zeros(shape + ((3,) if grid.dtype is not None and "Vec3" in type(grid).__name__ else ()),
                   grid.dtype)
    grid.copyToArray(out, lo)
    return out


def active_mask(grid, lo, shape):
    coords, _ = grid.activeVoxels()
    out = np.zeros(shape, bool)
    inside = np.all((coords >= lo) & (coords < np.array(lo) + shape), axis=1)
    c = coords[inside] - lo
    out[c[:, 0], c[:, 1], c[:, 2]] = True
    return out


def index_grid(lo, shape):
    """Index coordinates of a box as three arrays."""
    return np.meshgrid(*(np.arange(l, l + n) for l, n in zip(lo, shape)), indexing="ij")


def field_grid(cls, values, lo=(0, 0, 0), voxel_size=1.0, background=-1000.0):
    grid = cls(background)
    grid.copyFromArray(np.ascontiguousarray(values), lo)
    grid.transform = vdb.createLinearTransform(voxel_size)
    return grid


def sdf_from_array(phi, lo, half_width=3.0, voxel_size=1.0):
    """A level set from a dense array of distances in voxels: the band |phi| < half_width."""
    band = np.clip(phi, -half_width, half_width).astype(np.float32) * voxel_size
    grid = vdb.FloatGrid(half_width * voxel_size)
    grid.copyFromArray(band, lo)
    grid.transform = vdb.createLinearTransform(voxel_size)
    grid.gridClass = vdb.GridClass.LEVEL_SET
    grid.signedFloodFill()
    return grid


def block(cls, lo, hi, v):
    """Voxels (no tiles) of value v over the box lo..hi (inclusive)."""
    coords = np.stack(index_grid(lo, tuple(h - l + 1 for l, h in zip(lo, hi))), -1).reshape(-1, 3)
    values = np.empty((len(coords),) + np.shape(v), cls.dtype)
    values[...] = v
    return cls.fromCoords(coords, values)


def value(grid, ijk):
    return grid.getConstAccessor().getValue(ijk)


# ---- Level set measures


@pytest.mark.parametrize("cls", [vdb.FloatGrid, vdb.DoubleGrid])
def test_sphere_measures_match_the_analytic_values(cls):
    r, dx = 8.0, 0.5  # 16 voxels
    grid = T.createLevelSetSphere(r, (1.0, -2.0, 0.5), dx, 3.0, cls)
    assert T.levelSetArea(grid) == pytest.approx(4 * math.pi * r * r, rel=0.01)
    assert T.levelSetVolume(grid) == pytest.approx(4 / 3 * math.pi * r**3, rel=0.01)
    assert T.levelSetArea(grid, False) == pytest.approx(4 * math.pi * r * r / dx**2, rel=0.01)
    assert T.levelSetVolume(grid, useWorldSpace=False) == pytest.approx(
        4 / 3 * math.pi * r**3 / dx**3, rel=0.01)
    assert T.levelSetEulerCharacteristic(grid) == 2
    assert T.levelSetGenus(grid) == 0
    m = T.LevelSetMeasure(grid)
    assert m.area() == pytest.approx(4 * math.pi * r * r, rel=0.01)
    assert m.avgMeanCurvature() == pytest.approx(1 / r, rel=0.05)
    assert m.avgGaussianCurvature() == pytest.approx(1 / r**2, rel=0.05)
    assert m.totGaussianCurvature() == pytest.approx(4 * math.pi, rel=0.05)
    assert m.genus() == 0 and m.eulerCharacteristic() == 2
    smaller = T.createLevelSetSphere(r / 2, (0, 0, 0), dx, 3.0, cls)
    m.init(smaller)
    assert m.volume() == pytest.approx(4 / 3 * math.pi * (r / 2) ** 3, rel=0.02)


def test_torus_has_genus_one():
    lo, shape = (-24, -24, -10), (48, 48, 20)
    i, j, k = index_grid(lo, shape)
    big, small = 14.0, 5.0
    phi = np.sqrt((np.hypot(i, j) - big) ** 2 + k**2) - small
    torus = sdf_from_array(phi, lo)
    assert T.levelSetGenus(torus) == 1
    assert T.levelSetEulerCharacteristic(torus) == 0
    assert T.levelSetArea(torus) == pytest.approx(4 * math.pi**2 * big * small, rel=0.02)
    assert T.levelSetVolume(torus) == pytest.approx(2 * math.pi**2 * big * small**2, rel=0.02)


def test_measure_errors():
    with pytest.raises(TypeError, match="Int32Grid"):
        T.levelSetArea(vdb.Int32Grid())
    fog = vdb.FloatGrid()
    fog.fill((0, 0, 0), (7, 7, 7), 1.0)
    with pytest.raises(ValueError):
        T.levelSetArea(fog)  # not a level set
    empty = vdb.FloatGrid(3.0)
    empty.gridClass = vdb.GridClass.LEVEL_SET
    with pytest.raises(ValueError):
        T.LevelSetMeasure(empty)


# ---- Grid operators


def test_gradient_of_a_linear_field():
    lo, shape, dx = (-4, -4, -4), (16, 16, 16), 0.5
    i, j, k = index_grid(lo, shape)
    for cls, out_cls in [(vdb.FloatGrid, vdb.Vec3SGrid), (vdb.DoubleGrid, vdb.Vec3DGrid)]:
        grid = field_grid(cls, (2.0 * i + 3.0 * j - 1.0 * k).astype(cls.dtype), lo, dx)
        grad = T.gradient(grid)
        assert isinstance(grad, out_cls)
        g = dense(grad, (-3, -3, -3), (14, 14, 14))
        np.testing.assert_allclose(g.reshape(-1, 3), np.tile([4.0, 6.0, -2.0], (14**3, 1)),
                                   rtol=1e-5)
        assert grad.activeVoxelCount() == grid.activeVoxelCount()


def test_laplacian_divergence_curl_magnitude_normalize():
    lo, shape = (0, 0, 0), (12, 12, 12)
    i, j, k = index_grid(lo, shape)
    inner = (slice(1, 11),) * 3
    quad = field_grid(vdb.DoubleGrid, (i**2 + 2.0 * j**2 - k**2).astype(np.float64), lo, 2.0)
    lap = dense(T.laplacian(quad), lo, shape)
    np.testing.assert_allclose(lap[inner], (2 + 4 - 2) / 4.0, rtol=1e-9)

    vec = np.stack([i * 1.0, 2.0 * j, 3.0 * k], axis=-1).astype(np.float32)
    vgrid = field_grid(vdb.Vec3SGrid, vec, lo, 1.0, background=(0, 0, -1000))
    div = dense(T.divergence(vgrid), lo, shape)
    np.testing.assert_allclose(div[inner], 6.0, rtol=1e-5)

    rot = np.stack([-1.0 * j, 1.0 * i, np.zeros_like(i, float)], axis=-1).astype(np.float64)
    rgrid = field_grid(vdb.Vec3DGrid, rot, lo, 1.0, background=(0, 0, -1000))
    c = dense(T.curl(rgrid), lo, shape)
    np.testing.assert_allclose(c[inner].reshape(-1, 3), np.tile([0, 0, 2.0], (1000, 1)), atol=1e-9)

    const = vdb.Vec3SGrid()
    const.fill((0, 0, 0), (9, 9, 9), (3.0, 4.0, 0.0))
    mag = T.magnitude(const)
    assert isinstance(mag, vdb.FloatGrid)
    assert value(mag, (5, 5, 5)) == pytest.approx(5.0)
    unit = T.normalize(const)
    assert value(unit, (5, 5, 5)) == pytest.approx((0.6, 0.8, 0.0))


def test_mean_curvature_of_a_sphere_and_masks():
    r = 12.0
    sphere = vdb.createLevelSetSphere(r)
    curv = T.meanCurvature(sphere)
    assert value(curv, (12, 0, 0)) == pytest.approx(1 / r, rel=0.03)
    assert value(curv, (0, -12, 0)) == pytest.approx(1 / r, rel=0.03)
    mask = vdb.BoolGrid()
    mask.fill((0, 0, 0), (20, 20, 20), True)
    masked = T.gradient(sphere, mask)
    coords, _ = masked.activeVoxels()
    assert len(coords) > 0 and coords.min() >= 0
    assert masked.activeVoxelCount() < sphere.activeVoxelCount()
    with pytest.raises(TypeError, match="mask"):
        T.gradient(vdb.DoubleGrid(), vdb.MaskGrid())
    with pytest.raises(TypeError, match="Int32Grid"):
        T.gradient(vdb.Int32Grid())
    with pytest.raises(TypeError, match="FloatGrid"):
        T.divergence(vdb.FloatGrid())


# ---- Filters


def test_filter_mean_gaussian_keep_constant_and_linear_fields():
    lo, shape = (0, 0, 0), (24, 24, 24)
    i, j, k = index_grid(lo, shape)
    linear = (0.5 * i - 2.0 * j + k).astype(np.float32)
    grid = field_grid(vdb.FloatGrid, linear, lo)
    const = block(vdb.DoubleGrid, (0, 0, 0), (23, 23, 23), 7.0)
    T.Filter(grid).mean(2)
    f = T.Filter(const)
    f.gaussian(1, 2)
    assert f.grid is const
    inner = (slice(8, 16),) * 3
    np.testing.assert_allclose(dense(grid, lo, shape)[inner], linear[inner], atol=1e-4)
    np.testing.assert_allclose(dense(const, lo, shape)[inner], 7.0, rtol=1e-5)
    # Next to the background (0) the mean changes the values: the filter did work.
    assert value(const, (0, 0, 0)) < 7.0


def test_filter_median_offset_and_mask():
    grid = block(vdb.FloatGrid, (0, 0, 0), (15, 15, 15), 1.0)
    acc = grid.getAccessor()
    acc.setValueOn((8, 8, 8), 100.0)
    T.Filter(grid).median(1)
    assert value(grid, (8, 8, 8)) == 1.0
    T.Filter(grid).offset(2.5)
    assert value(grid, (4, 4, 4)) == 3.5
    vec = block(vdb.Vec3SGrid, (0, 0, 0), (7, 7, 7), (1, 2, 3))
    T.Filter(vec).offset((1, 1, 1))
    assert value(vec, (3, 3, 3)) == (2.0, 3.0, 4.0)
    # A mask of alpha 0 (below minMask) leaves the values; inverted it gives alpha 1.
    grid2 = block(vdb.FloatGrid, (0, 0, 0), (7, 7, 7), 1.0)
    mask = vdb.FloatGrid()
    mask.fill((0, 0, 0), (7, 7, 7), 0.0)
    f = T.Filter(grid2)
    f.offset(1.0, mask)
    assert value(grid2, (2, 2, 2)) == 1.0
    f.invertMask()
    assert f.isMaskInverted()
    f.offset(1.0, mask=mask)
    assert value(grid2, (2, 2, 2)) == 2.0
    f.setMaskRange(-1.0, 2.0)
    assert (f.minMask(), f.maxMask()) == (-1.0, 2.0)


def test_filter_errors():
    grid = vdb.FloatGrid()
    grid.fill((0, 0, 0), (7, 7, 7), 1.0)
    before = dense(grid, (0, 0, 0), (8, 8, 8))
    f = T.Filter(grid)
    for bad in (0, -1, 129, 10**6):
        with pytest.raises(ValueError, match="width"):
            f.mean(bad)
        with pytest.raises(ValueError, match="width"):
            f.gaussian(bad)
    with pytest.raises(ValueError, match="width"):
        f.median(17)
    with pytest.raises(ValueError, match="iterations"):
        f.mean(1, -1)
    with pytest.raises(ValueError):
        f.offset(float("nan"))
    with pytest.raises(ValueError):
        f.setMaskRange(1.0, 0.0)
    np.testing.assert_array_equal(dense(grid, (0, 0, 0), (8, 8, 8)), before)
    with pytest.raises(TypeError, match="vec3s"):
        T.Filter(vdb.Vec3SGrid()).median()
    with pytest.raises(TypeError, match="Int32Grid"):
        T.Filter(vdb.Int32Grid())
    with pytest.raises(TypeError, match="BoolGrid"):
        T.LevelSetFilter(vdb.BoolGrid())


def zero_crossing_x(grid):
    """The zero crossing of a level set along +x from the origin, linearly interpolated."""
    acc = grid.getConstAccessor()
    vs = grid.transform.voxelSize()[0]
    for i in range(0, 200):
        a, b = acc.getValue((i, 0, 0)), acc.getValue((i + 1, 0, 0))
        if a <= 0 < b:
            return (i + a / (a - b)) * vs
    raise AssertionError("no zero crossing")


@pytest.mark.parametrize("cls", [vdb.FloatGrid, vdb.DoubleGrid])
def test_level_set_offset_moves_the_surface(cls):
    grid = T.createLevelSetSphere(12.0, (0, 0, 0), 1.0, 3.0, cls)
    f = T.LevelSetFilter(grid)
    f.offset(2.0)  # erodes
    assert zero_crossing_x(grid) == pytest.approx(10.0, abs=0.1)
    assert T.levelSetVolume(grid) == pytest.approx(4 / 3 * math.pi * 1000, rel=0.02)
    f.offset(-4.0)  # dilates
    assert zero_crossing_x(grid) == pytest.approx(14.0, abs=0.1)
    assert grid.background == pytest.approx(3.0)  # the band keeps its width


def test_level_set_smoothing_keeps_a_sphere_and_curvature_flow_shrinks_it():
    grid = vdb.createLevelSetSphere(10.0)
    f = T.LevelSetFilter(grid)
    f.setSpatialScheme(T.FIRST_BIAS)
    f.setTemporalScheme(T.TVD_RK2)
    f.setNormCount(4)
    assert (f.getSpatialScheme(), f.getTemporalScheme(), f.getNormCount()) == (
        T.FIRST_BIAS, T.TVD_RK2, 4)
    v0 = T.levelSetVolume(grid)
    f.mean()
    f.gaussian()
    f.median()
    # Smoothing moves a convex surface inwards a little (its distance field is convex) and
    # keeps it a sphere.
    r1 = zero_crossing_x(grid)
    assert 9.0 < r1 < 10.0
    assert T.levelSetArea(grid) == pytest.approx(4 * math.pi * r1 * r1, rel=0.02)
    for _ in range(15):
        f.meanCurvature()
    # r^2 = r0^2 - 2 t with dt = 1/3 per step.
    assert zero_crossing_x(grid) == pytest.approx(math.sqrt(r1 * r1 - 10.0), abs=0.1)
    f.laplacian()
    assert T.levelSetVolume(grid) < v0
    with pytest.raises(ValueError):
        f.setSpatialScheme(T.WENO5_BIAS)
    with pytest.raises(ValueError, match="width"):
        f.mean(0)
    with pytest.raises(ValueError, match="width"):
        f.median(17)
    with pytest.raises(ValueError):
        f.offset(float("inf"))


def test_level_set_filter_mask_and_grid_checks():
    grid = vdb.createLevelSetSphere(10.0)
    mask = vdb.FloatGrid()  # alpha 0 everywhere: nothing moves
    f = T.LevelSetFilter(grid)
    f.offset(2.0, mask)
    assert zero_crossing_x(grid) == pytest.approx(10.0, abs=0.05)
    f.invertMask(True)
    f.offset(2.0, mask=mask)
    assert zero_crossing_x(grid) == pytest.approx(8.0, abs=0.1)
    with pytest.raises(ValueError, match="min < max"):
        f.setMaskRange(2.0, 2.0)
    stretched = vdb.createLevelSetSphere(5.0)
    stretched.transform = vdb.createLinearTransform([[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0],
                                                     [0, 0, 0, 1]])
    with pytest.raises(ValueError, match="cubic"):
        T.LevelSetFilter(stretched)
    with pytest.raises(ValueError, match="mask"):
        f.mean(1, grid)  # the mask is the grid itself


# ---- Level set utilities


def test_sdf_to_fog_volume():
    grid = vdb.createLevelSetSphere(10.0)
    T.sdfToFogVolume(grid)
    assert grid.gridClass == vdb.GridClass.FOG_VOLUME
    assert value(grid, (0, 0, 0)) == 1.0
    assert value(grid, (8, 0, 0)) == pytest.approx(2.0 / 3.0, abs=0.02)  # depth 2 of 3
    assert value(grid, (11, 0, 0)) == 0.0
    assert not grid.getConstAccessor().isValueOn((11, 0, 0))
    assert grid.background == 0.0
    d = T.createLevelSetSphere(10.0, (0, 0, 0), 1.0, 3.0, vdb.DoubleGrid)
    T.sdfToFogVolume(d, 1.0)
    assert value(d, (8, 0, 0)) == 1.0


def test_interior_masks_and_enclosed_regions():
    outer = vdb.createLevelSetSphere(12.0)
    inner = vdb.createLevelSetSphere(6.0)
    shell = T.csgDifferenceCopy(outer, inner)
    mask = T.sdfInteriorMask(shell)
    acc = mask.getConstAccessor()
    assert acc.isValueOn((9, 0, 0)) and not acc.isValueOn((0, 0, 0))
    assert not acc.isValueOn((13, 0, 0))
    enclosed = T.extractEnclosedRegion(shell)
    assert enclosed.getConstAccessor().isValueOn((0, 0, 0))
    assert enclosed.getConstAccessor().isValueOn((9, 0, 0))
    assert not enclosed.getConstAccessor().isValueOn((13, 0, 0))
    iface = T.extractIsosurfaceMask(shell, 0.0)
    coords, _ = iface.activeVoxels()
    radii = np.linalg.norm(coords, axis=1)
    assert np.all((np.abs(radii - 12) < 1.8) | (np.abs(radii - 6) < 1.8))
    im = T.interiorMask(shell)
    assert im.activeVoxelCount() == mask.activeVoxelCount()
    fog = vdb.Int32Grid()
    fog.fill((0, 0, 0), (4, 4, 4), 3)
    assert T.interiorMask(fog).activeVoxelCount() == 125


def test_segmentation():
    a = vdb.createLevelSetSphere(8.0, (-15, 0, 0))
    b = vdb.createLevelSetSphere(5.0, (15, 0, 0))
    T.csgUnion(a, b)
    parts = T.segmentSDF(a)
    assert len(parts) == 2
    assert T.levelSetVolume(parts[0]) == pytest.approx(4 / 3 * math.pi * 512, rel=0.03)
    assert T.levelSetVolume(parts[1]) == pytest.approx(4 / 3 * math.pi * 125, rel=0.05)
    boxes = vdb.FloatGrid()
    boxes.fill((0, 0, 0), (9, 9, 9), 1.0)
    boxes.fill((20, 0, 0), (24, 4, 4), 2.0)
    segs = T.segmentActiveVoxels(boxes)
    assert [s.activeVoxelCount() for s in segs] == [1000, 125]
    assert value(segs[1], (22, 2, 2)) == 2.0
    masks = T.extractActiveVoxelSegmentMasks(boxes)
    assert [m.activeVoxelCount() for m in masks] == [1000, 125]
    assert all(isinstance(m, vdb.BoolGrid) for m in masks)


# ---- Fast sweeping


def fog_sphere(r, lo=(-24, -24, -24), shape=(48, 48, 48), cls=vdb.FloatGrid):
    i, j, k = index_grid(lo, shape)
    density = np.clip(0.5 - (np.sqrt(i**2 + j**2 + k**2) - r) / 4.0, 0.0, 1.0)
    grid = cls(-1.0)  # background never met: every voxel of the box is active
    grid.copyFromArray(density.astype(cls.dtype), lo)
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    return grid


def check_distances(sdf, r, points, tol):
    for p in points:
        assert value(sdf, p) == pytest.approx(np.linalg.norm(p) - r, abs=tol), p


@pytest.mark.parametrize("cls", [vdb.FloatGrid, vdb.DoubleGrid])
def test_fog_to_sdf_gives_distances(cls):
    fog = fog_sphere(12.0, cls=cls)
    sdf = T.fogToSdf(fog, 0.5)
    assert isinstance(sdf, cls)
    assert sdf.gridClass == vdb.GridClass.LEVEL_SET
    pts = [(12, 0, 0), (18, 0, 0), (0, 20, 0), (0, 0, -4), (10, 10, 0), (15, 10, 5), (3, 2, 1)]
    check_distances(sdf, 12.0, pts, 0.6)
    sdf2 = T.sdfToSdf(sdf, 0.0, 2)
    check_distances(sdf2, 12.0, pts, 0.6)


def test_sdf_to_sdf_restores_unit_gradient():
    lo, shape = (-20, -20, -20), (40, 40, 40)
    i, j, k = index_grid(lo, shape)
    phi = 2.0 * (np.sqrt(i**2 + j**2 + k**2) - 10.0)  # gradient 2
    grid = vdb.FloatGrid(100.0)
    grid.copyFromArray(phi.astype(np.float32), lo)
    fixed = T.sdfToSdf(grid)
    check_distances(fixed, 10.0, [(10, 0, 0), (15, 0, 0), (0, 5, 0), (0, 0, -17), (8, 8, 8)], 0.6)


def test_dilate_and_mask_sdf():
    sphere = vdb.createLevelSetSphere(10.0)
    wide = T.dilateSdf(sphere, 5)
    assert wide.activeVoxelCount() > 2 * sphere.activeVoxelCount()
    check_distances(wide, 10.0, [(17, 0, 0), (0, 0, -17), (0, 4, 0), (10, 0, 0)], 0.6)
    outside = T.dilateSdf(sphere, 4, T.NN_FACE_EDGE_VERTEX, 1, T.SWEEP_GREATER_THAN_ISOVALUE)
    assert outside.getConstAccessor().isValueOn((16, 0, 0))
    assert not outside.getConstAccessor().isValueOn((5, 0, 0))
    assert wide.getConstAccessor().isValueOn((5, 0, 0))
    assert value(outside, (16, 0, 0)) == pytest.approx(6.0, abs=0.6)
    with pytest.raises(ValueError):
        T.dilateSdf(sphere, -1)
    with pytest.raises(ValueError):
        T.fogToSdf(fog_sphere(4.0, (-8, -8, -8), (16, 16, 16)), 0.5, -1)
    mask = vdb.MaskGrid()
    mask.fill((0, 0, 0), (24, 3, 3), True)
    extended = T.maskSdf(sphere, mask)
    assert extended.getConstAccessor().isValueOn((22, 1, 1))
    assert value(extended, (22, 0, 0)) == pytest.approx(12.0, abs=0.6)
    moved = vdb.MaskGrid()
    moved.transform = vdb.createLinearTransform(2.0)
    with pytest.raises(ValueError):
        T.maskSdf(sphere, moved)


def test_extension_of_a_field_grid():
    r = 10.0
    sphere = vdb.createLevelSetSphere(r)
    wide = T.dilateSdf(sphere, 6)
    lo, shape = (-20, -20, -20), (40, 40, 40)
    i, j, k = index_grid(lo, shape)
    field = field_grid(vdb.FloatGrid, i.astype(np.float32), lo, 1.0, background=0.0)
    ext = T.sdfToExt(wide, field)
    assert isinstance(ext, vdb.FloatGrid)
    # Constant along the normals: the x of the nearest surface point.
    for p in [(15, 0, 0), (-14, 0, 0), (11, 11, 0), (0, 15, 0)]:
        n = np.linalg.norm(p)
        assert value(ext, p) == pytest.approx(r * p[0] / n, abs=0.5), p
    vel = vdb.Vec3SGrid()
    vel.fill((-20, -20, -20), (19, 19, 19), (1.0, 2.0, 3.0))
    sdf, vext = T.sdfToSdfAndExt(wide, vel)
    assert value(vext, (15, 0, 0)) == pytest.approx((1.0, 2.0, 3.0))
    assert value(sdf, (15, 0, 0)) == pytest.approx(5.0, abs=0.6)
    fog = fog_sphere(8.0, (-16, -16, -16), (32, 32, 32))
    fext = T.fogToExt(fog, field, 0.5)
    assert value(fext, (12, 0, 0)) == pytest.approx(8.0, abs=0.6)
    fsdf, _ = T.fogToSdfAndExt(fog, field, 0.5)
    assert value(fsdf, (12, 0, 0)) == pytest.approx(4.0, abs=0.6)


# ---- Resampling and sampling


def test_resample_sphere_to_twice_the_voxel_size():
    r = 16.0
    sphere = vdb.createLevelSetSphere(r)
    coarse = vdb.FloatGrid()
    coarse.transform = vdb.createLinearTransform(2.0)
    coarse.gridClass = vdb.GridClass.LEVEL_SET
    T.resampleToMatch(sphere, coarse)
    assert coarse.transform.voxelSize()[0] == 2.0
    s = T.GridSampler(coarse, "box")
    for p in [(16, 0, 0), (17.5, 0, 0), (0, -15, 0), (9.2, 9.2, 9.2), (0, 0, 18)]:
        assert s.wsSample(p) == pytest.approx(np.linalg.norm(p) - r, abs=0.3), p
    same = vdb.FloatGrid()
    T.resampleToMatch(sphere, same, "point")
    np.testing.assert_array_equal(dense(same, (-20, -20, -20), (40, 40, 40)),
                                  dense(sphere, (-20, -20, -20), (40, 40, 40)))
    with pytest.raises(ValueError, match="sampler"):
        T.resampleToMatch(sphere, same, "cubic")
    with pytest.raises(TypeError):
        T.resampleToMatch(sphere, vdb.DoubleGrid())


@pytest.mark.parametrize("sampler", ["box", "quadratic"])
def test_transform_grid_scales_a_linear_field(sampler):
    lo, shape = (0, 0, 0), (16, 16, 16)
    i, j, k = index_grid(lo, shape)
    grid = field_grid(vdb.DoubleGrid, (i + 2.0 * j - k).astype(np.float64), lo, 1.0)
    out = vdb.DoubleGrid()
    T.transformGrid(grid, out, np.diag([2.0, 2.0, 2.0, 1.0]), sampler)
    for ijk in [(4, 6, 8), (10, 10, 10), (20, 8, 14), (9, 7, 5)]:
        assert value(out, ijk) == pytest.approx((ijk[0] + 2 * ijk[1] - ijk[2]) / 2.0, abs=1e-9)
    x = T.GridTransformer((0, 0, 0), (2, 2, 2), (0, 0, 0), (0, 0, 0))
    np.testing.assert_allclose(x.getTransform(), np.diag([2.0, 2.0, 2.0, 1.0]))
    out2 = vdb.DoubleGrid()
    x.transformGrid(grid, out2, sampler)
    assert value(out2, (10, 10, 10)) == value(out, (10, 10, 10))
    with pytest.raises(ValueError):
        T.GridTransformer(np.zeros((4, 4)))
    with pytest.raises(TypeError):
        T.transformGrid(grid, out, [[1, 2], [3, 4]])


def test_grid_sampler_reconstructs_linear_and_nearest_values():
    lo, shape = (-4, -4, -4), (12, 12, 12)
    i, j, k = index_grid(lo, shape)
    grid = field_grid(vdb.FloatGrid, (i + 2.0 * j + 3.0 * k).astype(np.float32), lo, 0.5)
    box = T.GridSampler(grid)
    assert box.isSample((1.5, 2.25, 3.75)) == pytest.approx(1.5 + 4.5 + 11.25)
    assert box.wsSample((0.75, 1.125, 1.875)) == pytest.approx(1.5 + 4.5 + 11.25)
    assert T.GridSampler(grid, "point").isSample((1.4, 2.6, -0.2)) == 1 + 6 + 0
    assert T.GridSampler(grid, "quadratic").isSample((1.5, 2.5, 3.5)) == pytest.approx(17.0)
    pts = np.array([[0.25, 0.5, 1.0], [2.0, 3.0, 1.5], [-1.5, 0.0, 0.5]])
    np.testing.assert_allclose(box.isSample(pts), pts @ [1.0, 2.0, 3.0], rtol=1e-6)
    vec = vdb.Vec3DGrid()
    vec.fill((0, 0, 0), (3, 3, 3), (1.0, 2.0, 3.0))
    out = T.GridSampler(vec).isSample(np.array([[1.5, 1.5, 1.5], [1.0, 1.0, 1.0]]))
    assert out.shape == (2, 3)
    np.testing.assert_allclose(out, [[1, 2, 3], [1, 2, 3]])
    with pytest.raises(ValueError):
        T.GridSampler(grid, "linear")
    with pytest.raises(TypeError):
        box.isSample("text")


# ---- Statistics and backgrounds


def test_statistics_histogram_and_min_max_match_numpy(rng, oracle):
    values = rng.standard_normal((20, 20, 20)).astype(np.float32)
    grid = field_grid(vdb.FloatGrid, values, (3, -5, 0), 1.0, background=1000.0)
    s = T.statistics(grid)
    v = values.astype(np.float64).ravel()
    assert s["count"] == v.size
    assert s["min"] == v.min() and s["max"] == v.max()
    assert s["mean"] == pytest.approx(v.mean(), rel=1e-9, abs=1e-12)
    assert s["variance"] == pytest.approx(v.var(), rel=1e-9)
    assert s["stdDev"] == pytest.approx(v.std(), rel=1e-9)
    e = T.extrema(grid)
    assert (e["count"], e["min"], e["max"]) == (v.size, v.min(), v.max())
    counts = T.histogram(grid, -2.0, 2.0, 8)
    np.testing.assert_array_equal(counts, np.histogram(v, bins=8, range=(-2.0, 2.0))[0])
    assert T.minMax(grid) == (v.min(), v.max())
    pg = oracle.FloatGrid(1000.0)
    pg.copyFromArray(values, (3, -5, 0))
    lo, hi = pg.evalMinMax()
    assert T.minMax(grid) == pytest.approx((lo, hi))
    off = T.statistics(grid, "off")
    assert off["count"] > 0 and off["min"] == off["max"] == 1000.0
    with pytest.raises(ValueError):
        T.histogram(grid, 1.0, 1.0)
    with pytest.raises(ValueError):
        T.histogram(grid, 0.0, 1.0, 0)
    with pytest.raises(ValueError):
        T.statistics(grid, "some")
    ints = vdb.Int32Grid()
    ints.fill((0, 0, 0), (1, 1, 1), 5)
    ints.getAccessor().setValueOn((9, 9, 9), -2)
    assert T.minMax(ints) == (-2, 5)
    assert T.statistics(ints)["mean"] == pytest.approx((8 * 5 - 2) / 9)
    vec = vdb.Vec3SGrid()
    vec.fill((0, 0, 0), (1, 1, 1), (3.0, 4.0, 0.0))
    assert T.statistics(vec)["max"] == pytest.approx(5.0)


def test_change_background_matches_pyopenvdb(rng, oracle):
    values = rng.standard_normal((16, 16, 16)).astype(np.float32)
    values[rng.random(values.shape) < 0.4] = 0.0
    grid = vdb.FloatGrid(0.0)
    grid.copyFromArray(values)
    acc = grid.getAccessor()
    acc.setValueOff((1, 1, 1), 0.0)
    acc.setValueOff((2, 2, 2), -0.0)
    pg = oracle.FloatGrid(0.0)
    pg.copyFromArray(values)
    pacc = pg.getAccessor()
    pacc.setValueOff((1, 1, 1), 0.0)
    pacc.setValueOff((2, 2, 2), -0.0)
    T.changeBackground(grid, 2.5)
    pg.background = 2.5  # pyopenvdb sets it with tools::changeBackground
    lo, shape = (-8, -8, -8), (32, 32, 32)
    expected = np.zeros(shape, np.float32)
    pg.copyToArray(expected, lo)
    np.testing.assert_array_equal(dense(grid, lo, shape), expected)
    assert grid.background == 2.5


def test_change_level_set_background():
    sphere = vdb.createLevelSetSphere(10.0)
    inside = sphere.getConstAccessor().getValue((0, 0, 0))
    assert inside == -3.0
    T.changeLevelSetBackground(sphere, 5.0)
    assert sphere.background == 5.0
    assert value(sphere, (0, 0, 0)) == -5.0 and value(sphere, (30, 0, 0)) == 5.0
    T.changeAsymmetricLevelSetBackground(sphere, 4.0, -6.0)
    assert value(sphere, (0, 0, 0)) == -6.0 and value(sphere, (30, 0, 0)) == 4.0
    with pytest.raises(ValueError):
        T.changeLevelSetBackground(sphere, 0.0)
    with pytest.raises(ValueError):
        T.changeAsymmetricLevelSetBackground(sphere, 1.0, 1.0)


# ---- Clip, activation, compositing


def test_clip_keeps_only_the_voxels_in_the_box(rng):
    lo, shape = (-10, -10, -10), (20, 20, 20)
    values = rng.random(shape).astype(np.float32) + 1.0
    grid = field_grid(vdb.FloatGrid, values, lo, 0.5, background=0.0)
    box = ((-1.2, 0.0, 0.3), (2.0, 1.6, 4.9))  # world; index box floor(lo / 0.5)..floor(hi / 0.5)
    inside = T.clip(grid, box)
    outside = T.clip(grid, box, keepInterior=False)
    i, j, k = index_grid(lo, shape)
    in_box = (i >= -3) & (i <= 4) & (j >= 0) & (j <= 3) & (k >= 0) & (k <= 9)
    np.testing.assert_array_equal(active_mask(inside, lo, shape), in_box)
    np.testing.assert_array_equal(active_mask(outside, lo, shape), ~in_box)
    np.testing.assert_array_equal(dense(inside, lo, shape), np.where(in_box, values, 0.0))
    assert grid.activeVoxelCount() == 8000  # the input is not changed
    mask = vdb.BoolGrid()
    mask.fill((0, 0, 0), (30, 30, 30), True)
    mask.transform = vdb.createLinearTransform(0.5)
    by_mask = T.clip(grid, mask)
    np.testing.assert_array_equal(active_mask(by_mask, lo, shape), (i >= 0) & (j >= 0) & (k >= 0))
    ints = vdb.Int64Grid()
    ints.fill((0, 0, 0), (9, 9, 9), 3)
    assert T.clip(ints, ((0, 0, 0), (4, 4, 4))).activeVoxelCount() == 125
    with pytest.raises(ValueError):
        T.clip(grid, ((0, 0, 0), (float("inf"), 1, 1)))
    with pytest.raises(TypeError):
        T.clip(grid, "box")


def test_activate_and_deactivate():
    grid = vdb.FloatGrid()
    grid.fill((0, 0, 0), (7, 7, 7), 1.0)
    acc = grid.getAccessor()
    acc.setValueOff((1, 1, 1), 7.0)
    acc.setValueOff((2, 2, 2), 7.05)
    acc.setValueOff((3, 3, 3), 8.0)
    T.activate(grid, 7.0)
    assert grid.activeVoxelCount() == 512 - 2
    T.activate(grid, 7.0, 0.1)
    assert grid.activeVoxelCount() == 512 - 1
    T.deactivate(grid, 1.0)
    assert grid.activeVoxelCount() == 2
    assert acc.isValueOn((1, 1, 1)) and acc.isValueOn((2, 2, 2))
    vec = vdb.Vec3IGrid()
    vec.fill((0, 0, 0), (3, 3, 3), (1, 2, 3))
    T.deactivate(vec, (1, 2, 3))
    assert vec.activeVoxelCount() == 0


@pytest.mark.parametrize("op,model", [
    ("compMax", np.maximum), ("compMin", np.minimum), ("compSum", np.add),
    ("compMul", np.multiply), ("compDiv", np.divide)])
def test_compositing_matches_the_model(op, model, rng):
    lo, shape = (-2, -2, -2), (20, 20, 20)
    a_vals = rng.random((12, 12, 12)) + 0.5
    b_vals = rng.random((12, 12, 12)) + 0.5
    a = vdb.DoubleGrid(1.0)
    b = vdb.DoubleGrid(2.0)
    a.copyFromArray(a_vals, (0, 0, 0))
    b.copyFromArray(b_vals, (4, 2, 0))
    ea, eb = dense(a, lo, shape), dense(b, lo, shape)
    ma, mb = active_mask(a, lo, shape), active_mask(b, lo, shape)
    getattr(T, op)(a, b)
    assert b.empty()
    np.testing.assert_allclose(dense(a, lo, shape), model(ea, eb), rtol=1e-12)
    np.testing.assert_array_equal(active_mask(a, lo, shape), ma | mb)
    assert a.background == pytest.approx(float(model(1.0, 2.0)))


def test_comp_replace_and_errors():
    a = vdb.Int32Grid()
    a.fill((0, 0, 0), (9, 9, 9), 1)
    b = vdb.Int32Grid()
    b.fill((5, 5, 5), (14, 14, 14), 2)
    T.compReplace(a, b)
    assert value(a, (7, 7, 7)) == 2 and value(a, (2, 2, 2)) == 1 and value(a, (12, 12, 12)) == 2
    assert b.activeVoxelCount() == 1000  # b is kept
    other = vdb.Int32Grid()
    other.transform = vdb.createLinearTransform(2.0)
    with pytest.raises(ValueError):
        T.compSum(a, other)
    with pytest.raises(ValueError):
        T.compMax(a, a)
    with pytest.raises(TypeError, match="Int32Grid"):
        T.compSum(a, vdb.FloatGrid())
    vec_a, vec_b = vdb.Vec3SGrid(), vdb.Vec3SGrid()
    vec_a.fill((0, 0, 0), (1, 1, 1), (1.0, 0.0, 0.0))
    vec_b.fill((0, 0, 0), (1, 1, 1), (0.0, 2.0, 0.0))
    T.compMax(vec_a, vec_b)  # the longer vector
    assert value(vec_a, (0, 0, 0)) == (0.0, 2.0, 0.0)


def test_tools_refuse_grids_with_viewed_leaves():
    grid = vdb.createLevelSetSphere(5.0)
    views = grid.leafBuffers()
    with pytest.raises(RuntimeError, match="leafBuffers"):
        T.LevelSetFilter(grid).mean()
    with pytest.raises(RuntimeError, match="leafBuffers"):
        T.changeLevelSetBackground(grid, 4.0)
    del views
    T.LevelSetFilter(grid).mean()
