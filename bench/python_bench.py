#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The Python module against pyopenvdb 10 on the same data in one process: dense transfers
(copyFromArray / copyToArray of N^3 float32 arrays), the active voxels of the Enright sphere
as NumPy arrays (one call here; pyopenvdb's way is its value iterator), and reading sample
files. Prints a table of medians and ratios (ours / pyopenvdb); --markdown FILE also writes
the table for docs/BENCHMARKS.md and FILE.status, the overview line.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_bench.py --dense 256,512
"""

import argparse
import os
import pathlib
import platform
import statistics
import sys
import time

import numpy as np

import vdb

try:
    import pyopenvdb
except ImportError:
    sys.exit("pyopenvdb (Debian's python3-openvdb) is needed: it is the reference")

TARGET_BULK = 0.5  # ours / pyopenvdb for the bulk transfers


def load() -> str:
    return pathlib.Path("/proc/loadavg").read_text().split()[0]


def median_time(fn, reps, setup=None):
    times = []
    for _ in range(reps):
        state = setup() if setup else None
        t0 = time.perf_counter()
        fn(state)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


class Report:
    def __init__(self):
        self.rows = []

    def add(self, case, ours, theirs, bulk, note=""):
        ratio = ours / theirs
        self.rows.append((case, ours, theirs, ratio, bulk, note))
        mark = f" (target <= {TARGET_BULK})" if bulk else ""
        print(f"{case:48s} ours {ours * 1e3:10.2f} ms  pyopenvdb {theirs * 1e3:10.2f} ms  "
              f"ratio {ratio:6.3f}{mark} {note}", flush=True)

    def markdown(self):
        lines = ["| case | ours (ms) | pyopenvdb (ms) | ratio | note |",
                 "|---|---:|---:|---:|---|"]
        for case, ours, theirs, ratio, bulk, note in self.rows:
            target = f" (target <= {TARGET_BULK})" if bulk else ""
            lines.append(f"| {case} | {ours * 1e3:.1f} | {theirs * 1e3:.1f} | "
                         f"{ratio:.3f}{target} | {note} |")
        return "\n".join(lines) + "\n"

    def status(self):
        bulk = [r[3] for r in self.rows if r[4]]
        other = [r[3] for r in self.rows if not r[4]]
        parts = []
        if bulk:
            met = "met" if max(bulk) <= TARGET_BULK else "not met"
            parts.append(f"bulk transfers {min(bulk):.3f}-{max(bulk):.3f} "
                         f"(target <= {TARGET_BULK}: {met})")
        if other:
            parts.append(f"other {min(other):.3f}-{max(other):.3f}")
        return "; ".join(parts)


def dense_cases(report, n, reps):
    rng = np.random.default_rng(n)
    # A fog-like field: values in (0, 1], a third of them background (0) in slabs, so that
    # both libraries build leaves and tiles.
    data = rng.random((n, n, n), dtype=np.float32) + np.float32(1e-3)
    data[:, : n // 3] = 0.0
    ours_grid = vdb.FloatGrid()
    theirs_grid = pyopenvdb.FloatGrid()
    t_ours = median_time(lambda _: vdb.FloatGrid().copyFromArray(data), reps)
    t_theirs = median_time(lambda _: pyopenvdb.FloatGrid().copyFromArray(data), reps)
    ours_grid.copyFromArray(data)
    theirs_grid.copyFromArray(data)
    assert ours_grid.activeVoxelCount() == theirs_grid.activeVoxelCount()
    # The floor of each transfer on this machine: NumPy copying the same bytes, into new memory
    # (page faults included, as for the new leaves) and into an existing array.
    floor_new = median_time(lambda _: np.copy(data), reps)
    report.add(f"copyFromArray {n}^3 float32", t_ours, t_theirs, True,
               f"{ours_grid.activeVoxelCount()} active voxels; floor (np.copy into new "
               f"memory) {floor_new * 1e3:.1f} ms")
    out = np.empty_like(data)
    t_ours = median_time(lambda _: ours_grid.copyToArray(out), reps)
    check = out.copy()
    t_theirs = median_time(lambda _: theirs_grid.copyToArray(out), reps)
    assert np.array_equal(check, out)
    floor_into = median_time(lambda _: np.copyto(out, data), reps)
    report.add(f"copyToArray {n}^3 float32", t_ours, t_theirs, True,
               f"into an existing array; floor (np.copyto) {floor_into * 1e3:.1f} ms")


def enright_case(report, res, reps):
    args = (0.15, (0.35, 0.35, 0.35), 1.0 / res, 5.0)
    ours = vdb.createLevelSetSphere(*args)
    theirs = pyopenvdb.createLevelSetSphere(*args)
    assert ours.activeVoxelCount() == theirs.activeVoxelCount()

    def theirs_active(_):
        coords, values = [], []
        for item in theirs.citerOnValues():
            coords.append(item.min)
            values.append(item.value)
        return np.array(coords, np.int32), np.array(values, np.float32)

    t_ours = median_time(lambda _: ours.activeVoxels(), reps)
    t_theirs = median_time(theirs_active, max(1, reps // 3))
    report.add(f"activeVoxels, Enright sphere {res}^3", t_ours, t_theirs, True,
               f"{ours.activeVoxelCount()} voxels; pyopenvdb: citerOnValues into arrays")


def read_cases(report, samples, reps):
    for name in samples:
        path = pathlib.Path(name)
        if not path.exists():
            print(f"skipped {path}: not present", flush=True)
            continue

        def ours_read(_):
            grids, _meta = vdb.readAll(path)
            return [g.activeVoxelCount() for g in grids]

        def theirs_read(_):
            grids, _meta = pyopenvdb.readAll(str(path))
            return [g.activeVoxelCount() for g in grids]

        def load_all(module):
            def fn(_):
                grids, _meta = module.readAll(str(path))
                for g in grids:
                    if g.valueTypeName not in ("float",) or g.empty():
                        continue
                    lo, hi = g.evalActiveVoxelBoundingBox()
                    out = np.empty(tuple(h - l + 1 for l, h in zip(lo, hi)), np.float32)
                    g.copyToArray(out, lo)
            return fn

        assert ours_read(None) == theirs_read(None)
        report.add(f"readAll {path.name}", median_time(ours_read, reps),
                   median_time(theirs_read, reps), False, "delayed loading: topology only")
        report.add(f"readAll + copyToArray of every float grid, {path.name}",
                   median_time(load_all(vdb), reps), median_time(load_all(pyopenvdb), reps),
                   False, "all values loaded")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dense", default="256,512", help="edge lengths of the dense arrays")
    parser.add_argument("--enright", default="1024", help="resolutions of the Enright sphere")
    parser.add_argument("--reps", type=int, default=5)
    samples_dir = os.environ.get("VDB_SAMPLES_DIR") or "/work/shared/vdb-samples"
    parser.add_argument("--samples", default=",".join(
        f"{samples_dir}/{n}" for n in ("smoke.vdb", "wdas_cloud_sixteenth.vdb", "sphere.vdb")))
    parser.add_argument("--markdown", help="write the table to this file, the status to FILE.status")
    args = parser.parse_args()

    print(f"{platform.node()}: {os.cpu_count()} CPUs, Python {platform.python_version()}, "
          f"NumPy {np.__version__}, pyopenvdb {'.'.join(map(str, pyopenvdb.LIBRARY_VERSION))}; "
          f"load average {load()} at the start", flush=True)
    report = Report()
    for n in [int(x) for x in args.dense.split(",") if x]:
        dense_cases(report, n, args.reps)
    for res in [int(x) for x in args.enright.split(",") if x]:
        enright_case(report, res, args.reps)
    read_cases(report, [s for s in args.samples.split(",") if s], args.reps)
    print(f"load average {load()} at the end; {report.status()}", flush=True)
    if args.markdown:
        pathlib.Path(args.markdown).write_text(report.markdown())
        pathlib.Path(args.markdown + ".status").write_text(report.status() + "\n")


if __name__ == "__main__":
    main()
