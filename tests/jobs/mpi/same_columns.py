#!/usr/bin/python3
"""Compares two ringtol results files as h5py reads them: every per-sample dataset but the
timing, bit for bit (NaN included), whether a file keeps its samples itself or is an index
of shards; of an allocation's, its design points, every [C, N] dataset but the solve times
and the outcome. Usage: same_columns.py a.h5 b.h5"""
import sys

import h5py
import numpy as np

PER_SAMPLE = ("inputs/u", "inputs/values", "inputs/redraws", "inputs/draw_checksum", "outputs")
ALLOCATION = ("inputs/u", "samples/screen", "samples/confirm", "outcome")


def same(a, b, paths):
    for path in paths:
        x, y = a[path][:], b[path][:]
        assert x.shape == y.shape, (path, x.shape, y.shape)
        assert x.tobytes() == y.tobytes(), f"{path} differs"


with h5py.File(sys.argv[1], "r") as a, h5py.File(sys.argv[2], "r") as b:
    if a.attrs["format"] == "ringtol allocation":
        paths = [name for name in ALLOCATION if isinstance(a[name], h5py.Dataset)]
        for name in ALLOCATION:
            if isinstance(a[name], h5py.Group):
                paths += [f"{name}/{key}" for key in a[name] if key != "solve_time_s"]
        same(a, b, paths)
        print(f"{len(paths)} datasets the same")
        sys.exit(0)
    paths = []
    for name in PER_SAMPLE:
        if isinstance(a[name], h5py.Group):
            paths += [f"{name}/{key}" for key in a[name]]
        else:
            paths.append(name)
    same(a, b, paths)
    failed = {int(s): m for s, m in zip(a["failures/sample"][:], a["failures/message"][:])}
    assert failed == {int(s): m for s, m in zip(b["failures/sample"][:], b["failures/message"][:])}, "failure rows"
    print(f"{len(paths)} datasets the same")
