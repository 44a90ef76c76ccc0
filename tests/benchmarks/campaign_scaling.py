#!/usr/bin/python3
"""Campaign pool benchmark: the default campaign alone and under `mpirun -n 2`, repeated
and interleaved, reporting medians and their ratio (parallel efficiency) from one run.

    tests/benchmarks/campaign_scaling.py build/release/ringtol [--samples N] [--repeats R]
                                         [--campaign FILE] [--ranks 1 2]

Each run writes a fresh results file in a temporary folder and reads ringtol's JSON
summary: wall time, samples per second, the share of the computing ranks' time spent in
samples (solve times summed over ranks / (wall time x computing ranks)) and the time rank
0 spent writing HDF5. "command s" is the whole command (MPI start, calibration, summary);
"pool s" the sampling itself."""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

MPI_ENVIRONMENT = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMPI_MCA_pml": "ob1", "OMPI_MCA_btl": "self,vader",
    "OMPI_MCA_btl_vader_single_copy_mechanism": "none",
}


def run(ringtol, campaign, samples, ranks, folder, index):
    out = os.path.join(folder, f"r{ranks}_{index}.h5")
    # One computing thread per rank, so that ranks are the only parallelism compared.
    command = [ringtol, "campaign", campaign, "--out", out, "--samples", str(samples), "--json", "--quiet",
               "--threads", "1"]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + command
    start = time.perf_counter()
    result = subprocess.run(command, check=True, capture_output=True, text=True,
                            env={**os.environ, **MPI_ENVIRONMENT})
    end_to_end = time.perf_counter() - start
    os.remove(out)
    summary = json.loads(result.stdout)["run"]
    busy = summary["wall_time_s"] * summary["computing_ranks"]
    return {"end_to_end_s": end_to_end, "wall_s": summary["wall_time_s"], "rate": summary["samples_per_s"],
            "in_samples": summary["solver_time_s"] / busy, "writing_s": summary["commit_time_s"]}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ringtol")
    parser.add_argument("--campaign", default=os.path.join(os.path.dirname(__file__), "../../examples/campaigns/default.toml"))
    parser.add_argument("--samples", type=int, default=2048)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    results = {ranks: [] for ranks in args.ranks}
    with tempfile.TemporaryDirectory() as folder:
        for index in range(args.repeats):
            for ranks in args.ranks:
                results[ranks].append(run(args.ringtol, args.campaign, args.samples, ranks, folder, index))
    print(f"{args.samples} samples of {os.path.basename(args.campaign)}, median of {args.repeats} interleaved runs")
    print(f"{'ranks':>5} {'command s':>10} {'pool s':>8} {'samples/s':>10} {'in samples':>11} {'writing s':>10} {'efficiency':>11}")
    base = statistics.median(r["rate"] for r in results[args.ranks[0]])
    for ranks in args.ranks:
        rate = statistics.median(r["rate"] for r in results[ranks])
        efficiency = rate / (base * ranks / args.ranks[0])
        print(f"{ranks:>5} {statistics.median(r['end_to_end_s'] for r in results[ranks]):>10.2f} "
              f"{statistics.median(r['wall_s'] for r in results[ranks]):>8.2f} {rate:>10.1f} "
              f"{100 * statistics.median(r['in_samples'] for r in results[ranks]):>10.1f}% "
              f"{statistics.median(r['writing_s'] for r in results[ranks]):>10.3f} {100 * efficiency:>10.1f}%")


if __name__ == "__main__":
    main()
