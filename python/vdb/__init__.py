# SPDX-License-Identifier: Apache-2.0
"""Sparse volumes after Museth's VDB, with pyopenvdb's names and bulk NumPy transfers.

A script written for pyopenvdb ports by changing its import::

    import vdb as openvdb

Beyond pyopenvdb: every standard grid type (FloatGrid, DoubleGrid, Int32Grid, Int64Grid,
BoolGrid, MaskGrid, Vec3SGrid, Vec3DGrid, Vec3IGrid), bulk transfers without per-voxel Python
calls (``activeVoxels``, ``fromCoords``, ``leafValues``, ``leafBuffers``), and the C++ tools under
``vdb.tools``.

Long operations release the GIL, so other Python threads run meanwhile. As in C++, reading one
grid from several threads is safe, but a grid must not be changed by one thread while another
reads or changes it.
"""

from . import _vdb
from ._vdb import *  # noqa: F401,F403
from ._vdb import tools  # noqa: F401

__all__ = [name for name in dir(_vdb) if not name.startswith("_")]

for _cls in [*GridTypes, GridBase, Transform, Metadata, Axis, GridClass, VectorType]:  # noqa: F405
    _cls.__module__ = "vdb"
del _cls


def _restore_grid(state):
    """Unpickles a grid: the callable that a grid's __reduce__ names (a Python function, so
    that pickle stores it by name)."""
    return _vdb._restoreGrid(state)


def _restore_transform(state):
    """Unpickles a transform, as _restore_grid a grid."""
    return _vdb._restoreTransform(state)
