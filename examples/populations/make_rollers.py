#!/usr/bin/python3
"""Writes the synthetic roller batch of this folder: rollers/roller_01.csv ... roller_12.csv,
roundness exports of the running surfaces of 10 mm rollers, drawn from a known law.

The law, per harmonic order n = 2..5 of r(theta) = 5 mm + dr + sum C_n cos(n theta + phi_n):
Fourier coefficients two-dimensional normal about 0 with standard deviation 1.2 um / n per
coordinate; the size dr normal, mean -2 um, standard deviation 1 um (a mean diameter 0 to
-8 um, as ISO 492 Normal allows at 10 mm); 0.05 um of tester noise per reading, one reading
per 2 degrees, rounded to 10 nm.
Usage: make_rollers.py [count] [seed]   (12 rollers, seed 492 as shipped)."""
import math
import pathlib
import random
import sys

count = int(sys.argv[1]) if len(sys.argv) > 1 else 12
seed = int(sys.argv[2]) if len(sys.argv) > 2 else 492
rng = random.Random(seed)
folder = pathlib.Path(__file__).resolve().parent / "rollers"
folder.mkdir(exist_ok=True)
for k in range(1, count + 1):
    size = rng.gauss(-2.0, 1.0)
    form = [(n, rng.gauss(0.0, 1.2 / n), rng.gauss(0.0, 1.2 / n)) for n in range(2, 6)]
    rows = [f"# Roller {k:02d} of the synthetic batch of examples/populations (make_rollers.py, seed {seed}):",
            "# not a measurement; its law is in make_rollers.py.", "angle_deg, radius_mm"]
    for step in range(180):
        theta = math.radians(2 * step)
        dr = size + sum(a * math.cos(n * theta) - b * math.sin(n * theta) for n, a, b in form) + rng.gauss(0.0, 0.05)
        rows.append(f"{2 * step}.0, {5.0 + dr / 1000.0:.5f}")
    (folder / f"roller_{k:02d}.csv").write_text("\n".join(rows) + "\n")
