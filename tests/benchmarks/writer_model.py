#!/usr/bin/python3
"""The results writer's costs on 1 to 3 ranks, measured, and a model of 100 and 1,000 ranks
built from them.

    tests/benchmarks/writer_model.py build/ringtol [--samples N] [--campaign FILE]
                                     [--fs-bandwidth GB/s ...] [--sample-us T ...]

Runs the campaign alone (one computing thread), under `mpirun -n 2` (rank 0 computes and
coordinates) and under `mpirun -n 3 --coordinator-computes 0` (rank 0 only coordinates, as
it does from 16 ranks on; on a 2-core machine 3 ranks oversubscribe the cores, which the
MPI environment below allows). From ringtol's JSON summaries it reads, per sample: the
coordinator's messages and bytes, its handling time, the time spent writing a shard, the
stored bytes, and the time rank 0 takes to write the index of the shards at the end.

The model (rank 0 coordinates only; R - 1 workers each compute and write their shard;
the results file is an index of the shards, nothing is copied), for a campaign of N samples:
    a worker's time per sample        t + w           t: sample, w: writing its shard
    throughput [samples/s]            X = min((R - 1) / (t + w), 1 / c, F / B)
        c = 2 h / n: rank 0's handling per sample, h its CPU time per message (measured),
        n = max(block, chunk_seconds / t) samples per chunk; F: the file system's
        aggregate bandwidth, B: stored bytes per sample beyond the first 16,384 (--row-bytes);
        w measured alone, or given (--write-us)
    the end of the run                T = s R: rank 0 writing the index of R shards, s per
        shard (--index-seconds-per-shard, from build/ringtol_shard_index_benchmark)
    efficiency                        E = N t / (R (N / X + T))
"""
import argparse
import json
import os
import subprocess
import tempfile

MPI_ENVIRONMENT = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMPI_MCA_pml": "ob1", "OMPI_MCA_btl": "self,vader",
    "OMPI_MCA_btl_vader_single_copy_mechanism": "none",
}


def run(ringtol, campaign, samples, ranks, folder, extra=()):
    out = os.path.join(folder, f"r{ranks}.h5")
    command = [ringtol, "campaign", campaign, "--out", out, "--samples", str(samples), "--json", "--quiet",
               "--threads", "1", *extra]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks)] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + command
    result = subprocess.run(command, check=True, capture_output=True, text=True, env={**os.environ, **MPI_ENVIRONMENT})
    for name in os.listdir(folder):
        if name.startswith(f"r{ranks}.h5"):
            os.remove(os.path.join(folder, name))
    return json.loads(result.stdout)["run"]


CHUNK_SECONDS = 0.5  # PoolOptions::chunk_seconds
BLOCK = 1024  # samples per stored chunk of a campaign (8 KiB of a float64 column)


def efficiency(ranks, samples, t, w, per_message, row_bytes, fs_bandwidth, index_per_shard):
    c = 2 * per_message / max(BLOCK, CHUNK_SECONDS / t)
    throughput = min((ranks - 1) / (t + w), 1 / c, fs_bandwidth / row_bytes)
    return samples * t / (ranks * (samples / throughput + index_per_shard * ranks))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ringtol")
    parser.add_argument("--campaign", default=os.path.join(os.path.dirname(__file__), "../../examples/campaigns/default.toml"))
    parser.add_argument("--samples", type=int, default=2048)
    parser.add_argument("--fs-bandwidth", type=float, nargs="+", default=[1.0, 10.0, 100.0], help="GB/s, aggregate")
    parser.add_argument("--sample-us", type=float, nargs="+", default=[], help="model these sample times too")
    parser.add_argument("--model-samples", type=float, nargs="+", default=[1e7, 1e8], help="campaign sizes modelled")
    parser.add_argument("--write-us", type=float, nargs="+", default=[],
                        help="model these worker overheads a sample too (default: w measured alone, every sample "
                             "keeping its inputs)")
    parser.add_argument("--row-bytes", type=float, default=133.0,
                        help="stored bytes a sample beyond the first 16,384 (CampaignStore test, docs/results.md)")
    parser.add_argument("--index-seconds-per-shard", type=float, default=2.1e-4,
                        help="writing the index, per shard (build/ringtol_shard_index_benchmark at 1,000 shards)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        runs = {1: run(args.ringtol, args.campaign, args.samples, 1, folder),
                2: run(args.ringtol, args.campaign, args.samples, 2, folder),
                3: run(args.ringtol, args.campaign, args.samples, 3, folder, ["--coordinator-computes", "0"])}
    print(f"{args.samples} samples of {os.path.basename(args.campaign)}; 3 ranks oversubscribe a 2-core machine")
    print(f"{'ranks':>5} {'wall s':>7} {'index s':>8} {'samples/s':>10} {'msgs/sample':>12} {'bytes/sample':>13} "
          f"{'rank 0 us/sample':>17} {'of it CPU':>10} {'writing us/sample':>18}")
    for ranks, r in runs.items():
        n = r["computed"]
        wall = r["wall_time_s"] + r.get("index_time_s", 0.0)
        print(f"{ranks:>5} {r['wall_time_s']:>7.2f} {r.get('index_time_s', 0.0):>8.3f} {n / wall:>10.1f} "
              f"{r.get('coordinator_messages', 0) / n:>12.4f} {r.get('coordinator_bytes', 0) / n:>13.1f} "
              f"{1e6 * r['coordinator_time_s'] / n:>17.2f} {1e6 * r['coordinator_cpu_time_s'] / n:>10.2f} "
              f"{1e6 * r['commit_time_s'] / n:>18.2f}")
    one, two, three = runs[1], runs[2], runs[3]
    rate = lambda r: r["computed"] / (r["wall_time_s"] + r.get("index_time_s", 0.0))
    print(f"2-rank efficiency against 1 rank (index included): {100 * rate(two) / (2 * rate(one)):.1f} %")

    # CPU times, not wall times: on a busy machine the wall times mostly measure waits for a core.
    t = one["solver_time_s"] / one["computed"]
    w = one["coordinator_cpu_time_s"] / one["computed"]  # rank 0 alone: collecting and writing every sample
    per_message = three["coordinator_cpu_time_s"] / three["coordinator_messages"]  # rank 0 coordinating only
    print(f"\nmodel inputs: t = {1e6 * t:.0f} us, w = {1e6 * w:.2f} us, h = {1e6 * per_message:.1f} us a message, "
          f"B = {args.row_bytes:.0f} bytes, s = {1e3 * args.index_seconds_per_shard:.2f} ms a shard")
    print(f"{'sample us':>9} {'w us':>5} {'F GB/s':>7} {'N':>8} {'E(100)':>7} {'E(1000)':>8}")
    for sample in [t] + [us * 1e-6 for us in args.sample_us]:
        for write in [w] + [us * 1e-6 for us in args.write_us]:
            for bandwidth in args.fs_bandwidth:
                for n in args.model_samples:
                    row = [efficiency(r, n, sample, write, per_message, args.row_bytes, bandwidth * 1e9,
                                      args.index_seconds_per_shard) for r in (100, 1000)]
                    print(f"{1e6 * sample:>9.0f} {1e6 * write:>5.1f} {bandwidth:>7.0f} {n:>8.0e} {100 * row[0]:>6.1f}% "
                          f"{100 * row[1]:>7.1f}%")


if __name__ == "__main__":
    main()
