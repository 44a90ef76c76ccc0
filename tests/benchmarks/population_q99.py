#!/usr/bin/python3
"""How well 20 measured rings predict the q99 of D_trajectory of the rings not measured
(docs/validation.md, "Populations of measured parts"). The truth is known: rings are drawn
from the law of examples/populations/make_rings.py. A campaign over 1,000 rings of that
law (4,096 assemblies) stands for the truth; then, for each of `batches` independent
batches of 20 rings, examples/populations' two campaigns (resample.toml, model.toml) run
on that batch with 2,048 assemblies each. Prints each batch's q99 and, per draw, the mean,
spread and rms error of the prediction against the truth.
Usage: population_q99.py RINGTOL [batches] [work folder]   (10 batches in /tmp as shipped)"""
import json
import math
import pathlib
import statistics
import subprocess
import sys

RINGTOL = sys.argv[1]
BATCHES = int(sys.argv[2]) if len(sys.argv) > 2 else 10
WORK = pathlib.Path(sys.argv[3] if len(sys.argv) > 3 else "/tmp/ringtol_population_q99")
EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def rings(count, seed):
    folder = WORK / f"rings_{count}_{seed}"
    if not folder.exists():
        folder.mkdir(parents=True)
        script = folder / "make_rings.py"
        script.write_text((EXAMPLES / "populations/make_rings.py").read_text())
        subprocess.run(["/usr/bin/python3", str(script), str(count), str(seed)], check=True)
    return folder / "rings"


def q99(draw, folder, samples, name):
    text = (EXAMPLES / f"populations/{draw}.toml").read_text()
    text = text.replace('scene = "../paper/scene.toml"', f'scene = "{EXAMPLES / "paper/scene.toml"}"')
    text = text.replace('folder = "rings"', f'folder = "{folder}"').replace("samples = 1024", f"samples = {samples}")
    campaign = WORK / f"{name}.toml"
    campaign.write_text(text)
    results = WORK / f"{name}.h5"
    results.unlink(missing_ok=True)
    run = subprocess.run([RINGTOL, "campaign", str(campaign), "--out", str(results), "--json", "--quiet"],
                         check=True, capture_output=True, text=True)
    quantile = json.loads(run.stdout)["outputs"]["d_trajectory_mm"]["quantiles"][2]
    return quantile["value"], quantile["lower"], quantile["upper"]


def main():
    WORK.mkdir(parents=True, exist_ok=True)
    truth, lower, upper = q99("resample", rings(1000, 7), 4096, "truth")
    print(f"truth (1,000 rings, 4,096 assemblies): q99 {truth:.4f} mm [{lower:.4f}, {upper:.4f}]")
    predicted = {"resample": [], "model": []}
    for batch in range(BATCHES):
        seed = 101 + batch
        folder = rings(20, seed)
        row = []
        for draw in predicted:
            value = q99(draw, folder, 2048, f"batch{seed}_{draw}")[0]
            predicted[draw].append(value)
            row.append(f"{draw} {value:.4f}")
        print(f"batch {seed}: " + ", ".join(row))
    for draw, values in predicted.items():
        errors = [v / truth - 1.0 for v in values]
        rms = math.sqrt(sum(e * e for e in errors) / len(errors))
        print(f"{draw}: mean {statistics.mean(values):.4f} mm ({100 * statistics.mean(errors):+.1f} %), "
              f"spread {statistics.stdev(values):.4f} mm, rms error {100 * rms:.1f} %, "
              f"range {min(values):.4f} to {max(values):.4f} mm")


if __name__ == "__main__":
    main()
