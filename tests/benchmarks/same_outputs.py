#!/usr/bin/python3
"""Holds a campaign computed by a faster build to the same campaign computed by the build it
replaces: every sample's status, rung and steps identical, every length output within
--tolerance-um (default 0.01 um), every force within --force-tolerance-n. The error
estimate (d_trajectory_error_mm) is a bound, not a value: a new build may tighten it, so it
is reported, and only a looser one fails. Prints the largest difference of each output.
Usage: same_outputs.py reference.h5 candidate.h5 [--tolerance-um 0.01]"""
import argparse
import sys

import h5py
import numpy as np

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("reference")
parser.add_argument("candidate")
parser.add_argument("--tolerance-um", type=float, default=0.01)
parser.add_argument("--force-tolerance-n", type=float, default=1e-3)
args = parser.parse_args()

IDENTICAL = ("status", "rung", "steps")
BOUND = "d_trajectory_error_mm"

failed = []
with h5py.File(args.reference, "r") as a, h5py.File(args.candidate, "r") as b:
    names = sorted(a["outputs"].keys())
    missing = [n for n in names if n not in b["outputs"]]
    if missing:
        sys.exit(f"candidate lacks outputs {missing}")
    for name in names:
        x, y = a["outputs"][name][:], b["outputs"][name][:]
        if x.shape != y.shape:
            sys.exit(f"{name}: {x.shape} samples against {y.shape}")
        if name in IDENTICAL:
            differ = int(np.count_nonzero(x != y))
            print(f"{name:36s} {differ} samples differ")
            if differ:
                failed.append(name)
            continue
        nan_x, nan_y = np.isnan(x), np.isnan(y)
        if np.any(nan_x != nan_y):
            failed.append(name)
            print(f"{name:36s} NaN in different samples ({int(np.count_nonzero(nan_x != nan_y))})")
            continue
        both = ~nan_x
        if name.endswith("_N"):
            largest = float(np.max(np.abs(x[both] - y[both]), initial=0.0))
            limit, unit, shown = args.force_tolerance_n, "N", largest
        else:
            largest = float(np.max(np.abs(x[both] - y[both]), initial=0.0)) * 1e3
            limit, unit, shown = args.tolerance_um, "um", largest
        if name == BOUND:
            looser = float(np.max(y[both] - x[both], initial=0.0)) * 1e3
            print(f"{name:36s} largest difference {shown:.3g} {unit}; largest loosening {looser:.3g} um")
            if looser > args.tolerance_um:
                failed.append(name)
            continue
        print(f"{name:36s} largest difference {shown:.3g} {unit} (allowed {limit:g})")
        if largest > limit:
            failed.append(name)
    fa = {int(s): m for s, m in zip(a["failures/sample"][:], a["failures/message"][:])}
    fb = {int(s): m for s, m in zip(b["failures/sample"][:], b["failures/message"][:])}
    if set(fa) != set(fb):
        failed.append("failures")
    print(f"{'failures':36s} {len(fa)} and {len(fb)} samples")
if failed:
    sys.exit("differ: " + ", ".join(failed))
print("same within the tolerances")
