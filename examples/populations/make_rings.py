#!/usr/bin/python3
"""Writes the synthetic ring population of this folder: rings/ring_01.csv ... ring_20.csv,
roundness exports (docs/inputs.md, "Profile CSV files") of 604 mm bores as a roundness
tester would give them, drawn from a known law so that what a population model fitted to
them predicts can be checked against the truth (docs/validation.md).

The law, per harmonic order n of the bore r(theta) = 302 mm + dr + sum C_n cos(n theta + phi_n):
  the Fourier coefficients (C_n cos phi_n, C_n sin phi_n) are two-dimensional normal with
  mean (15 um, 0) at order 3 (a three-jaw chuck's imprint at a fixed phase) and 0 at every
  other order, and standard deviation 12 um / n per coordinate at orders 2 to 8;
  the size dr is normal, mean 5 um, standard deviation 4 um;
  each reading (one per 2 degrees) carries 0.5 um of tester noise; readings are rounded to 10 nm.
Usage: make_rings.py [count] [seed]   (20 rings, seed 2026 as shipped)."""
import math
import pathlib
import random
import sys

COUNT = int(sys.argv[1]) if len(sys.argv) > 1 else 20
SEED = int(sys.argv[2]) if len(sys.argv) > 2 else 2026
ORDERS = range(2, 9)


def draw_ring(rng):
    size = rng.gauss(5.0, 4.0)
    harmonics = []
    for n in ORDERS:
        a = rng.gauss(15.0 if n == 3 else 0.0, 12.0 / n)
        b = rng.gauss(0.0, 12.0 / n)
        harmonics.append((n, math.hypot(a, b), math.atan2(b, a)))
    return size, harmonics


def main():
    rng = random.Random(SEED)
    folder = pathlib.Path(__file__).resolve().parent / "rings"
    folder.mkdir(exist_ok=True)
    for k in range(1, COUNT + 1):
        size, harmonics = draw_ring(rng)
        lines = [
            f"# Ring {k:02d} of the synthetic population of examples/populations (make_rings.py, seed {SEED}):",
            "# not a measurement; its law is in make_rings.py.",
            "angle_deg, radius_mm",
        ]
        for step in range(180):
            theta = math.radians(2.0 * step)
            dr = size + sum(c * math.cos(n * theta + phi) for n, c, phi in harmonics) + rng.gauss(0.0, 0.5)
            lines.append(f"{2.0 * step:.1f}, {302.0 + dr * 1e-3:.5f}")
        (folder / f"ring_{k:02d}.csv").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
