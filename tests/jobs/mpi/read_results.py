#!/usr/bin/python3
"""Reads a ringtol results file as a user's script would (Debian's h5py), checking the
schema docs/results.md documents. Usage: read_results.py results.h5"""
import sys

import h5py
import numpy as np

with h5py.File(sys.argv[1], "r") as f:
    assert f.attrs["format"] == "ringtol campaign", f.attrs["format"]
    # Written under mpirun: an index whose per-sample datasets are virtual, over shards.
    index = f.attrs["layout"] == "shard index"
    assert int(f.attrs["schema_version"]) == 6 and (not index or int(f.attrs["rows_schema"]) == 6)
    if index:
        assert all(f[path].is_virtual for path in ("inputs/u", "outputs/status", "failures/sample"))
        assert len(f["shards/file"]) >= 2 and int(f.attrs["shard_chunk_rows"]) >= 1
    for key in ("ringtol_version", "catalogue_version", "campaign_file", "base_scene", "design", "solver"):
        assert isinstance(f.attrs[key], str) and f.attrs[key], key
    n = int(f.attrs["samples"])
    d = f["inputs/name"].shape[0]
    kept = min(n, int(f.attrs["inputs_stored_below"]))  # the first samples' inputs; ringtol replays the rest
    assert f["inputs/u"].shape == (kept, d) and f["inputs/values"].shape == (kept, d)
    assert index or f["inputs/u"].maxshape[0] is None, "extendable along samples"
    assert f["inputs/draw_checksum"].shape == (n,) and f["inputs/draw_checksum"].dtype == np.uint32
    assert (index or f["outputs/status"].compression == "gzip") and "message" not in f["outputs"]
    names = [x.decode() for x in f["inputs/name"][:]]
    assert all(name.endswith(("_um", "_deg", "_percent")) for name in names), names
    status = f["outputs/status"]
    mapping = h5py.check_enum_dtype(status.dtype)
    assert mapping["pending"] == -1 and mapping["ok"] == 0, mapping
    ok = status[:] == mapping["ok"]
    failed = f["failures/sample"][:]
    messages = f["failures/message"][:]
    assert failed.shape == messages.shape and failed.dtype == np.int64
    done = status[:] != mapping["pending"]
    assert set(failed.tolist()) == set(np.flatnonzero(done & ~ok).tolist()), "one message row per failed sample"
    d_trajectory = f["outputs/d_trajectory_mm"][:]
    assert np.all(np.isfinite(d_trajectory[ok])) and np.all(np.isnan(d_trajectory[~ok]))
    assert f["outputs/d_trajectory_mm"].attrs["upper_spec_limit"] == 0.2
    assert f["timing/solve_time_s"].shape == (n,)
    assert f["outputs/runout_mm"].attrs["definition"].startswith("total indicator reading")
    swing = f["outputs/swing_mm"]
    assert abs(swing.attrs["resolution_um"] - 0.1) < 1e-12 and swing.attrs["cutoff_upr"] == 0.0
    runout = f["outputs/runout_mm"][:]
    assert np.all(swing[:][ok] <= runout[ok]), "a swing never exceeds max - min"
    rung = f["outputs/rung"][:]
    error = f["outputs/d_trajectory_error_mm"][:]
    assert rung.dtype == np.int8 and np.all((rung[ok] >= 0) & (rung[ok] <= 2)), "the rung a sample settled on"
    assert h5py.check_enum_dtype(f["outputs/rung"].dtype) == {"none": -1, "linear": 0, "quasistatic": 1, "dynamic": 2}
    assert np.all(error[ok] >= 0.0) and np.all(np.isnan(error[~ok]))
    life = f["outputs/life_d_trajectory_mm"][:]
    assert np.all(life[ok] >= d_trajectory[ok] - 1e-6), "the life's union holds the drawn revolution"
    assert np.all(f["outputs/life_runout_mm"][:][ok] >= runout[ok] - 1e-6)
    total, synchronous, asynchronous = (f["outputs/error_motion_" + part + "_mm"][:][ok]
                                        for part in ("total", "synchronous", "asynchronous"))
    assert np.all(asynchronous >= 0.0) and np.all(total <= synchronous + asynchronous + 1e-9)
    assert np.all(total >= synchronous - 1e-9) and np.all(np.isnan(life[~ok]))
    for part in ("total", "synchronous", "asynchronous"):
        attrs = f["outputs/error_motion_" + part + "_mm"].attrs
        assert attrs["filter"] == "ISO 16610-21 Gaussian" and attrs["cutoff_upr"] == 50.0, dict(attrs)
        assert attrs["revolutions"] == "every revolution of the life", dict(attrs)
    rollers = [x.decode() for x in f["rollers/name"][:]]
    off_bore = f["outputs/off_bore_percent"][:]
    assert off_bore.shape == (n, len(rollers)) and off_bore.dtype == np.float32, off_bore.shape
    assert np.all((off_bore[ok] >= 0.0) & (off_bore[ok] <= 100.0)) and np.all(np.isnan(off_bore[~ok]))
    print(f"{int(ok.sum())} samples ok of {n}, {d} inputs, {len(rollers)} rollers")
