# SPDX-License-Identifier: Apache-2.0
"""Shared fixtures of the Python module's tests: the module, the oracle and sample files."""

import os
import pathlib

import numpy as np
import pytest

import vdb

try:
    import pyopenvdb
except ImportError:  # the oracle is optional: its tests are skipped without it
    pyopenvdb = None

SAMPLES = pathlib.Path(os.environ.get("VDB_SAMPLES_DIR") or "/work/shared/vdb-samples")
TEST_DATA = pathlib.Path(
    os.environ.get("VDB_TEST_DATA_DIR") or pathlib.Path(__file__).resolve().parents[2] / "tests/data"
)

# (vdb class, NumPy dtype, components, pyopenvdb class name or None)
GRID_TYPES = [
    (vdb.FloatGrid, np.float32, 1, "FloatGrid"),
    (vdb.DoubleGrid, np.float64, 1, None),
    (vdb.Int32Grid, np.int32, 1, None),
    (vdb.Int64Grid, np.int64, 1, None),
    (vdb.BoolGrid, np.bool_, 1, "BoolGrid"),
    (vdb.MaskGrid, np.bool_, 1, None),
    (vdb.Vec3SGrid, np.float32, 3, "Vec3SGrid"),
    (vdb.Vec3DGrid, np.float64, 3, None),
    (vdb.Vec3IGrid, np.int32, 3, None),
]


def random_values(rng, shape, dtype, components, background_fraction=0.3, background=0):
    """Random values of `dtype` with about `background_fraction` of them equal to background."""
    full = shape + ((components,) if components == 3 else ())
    if dtype == np.bool_:
        values = rng.random(full) < 0.5
    elif np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        values = rng.integers(info.min, info.max, size=full, dtype=dtype, endpoint=True)
    else:
        values = (rng.standard_normal(full) * 100).astype(dtype)
    mask = rng.random(shape) < background_fraction
    values[mask] = background
    return values


@pytest.fixture
def rng():
    return np.random.default_rng(20)


@pytest.fixture
def oracle():
    if pyopenvdb is None:
        pytest.skip("pyopenvdb (python3-openvdb) is not installed")
    return pyopenvdb
