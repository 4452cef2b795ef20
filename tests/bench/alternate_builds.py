#!/usr/bin/env python3
"""One Google Benchmark binary of two builds timed in turn: the build before a change (BEFORE)
against the current one (AFTER), case by case, each case's time the best of --rounds runs.

    python3 tests/bench/alternate_builds.py BEFORE/tests/bench/bench_ssdo build/tests/bench/bench_ssdo \\
        --filter 'threads:1' [--rounds 5]

Rounds alternate BEFORE, AFTER, BEFORE, ... so that a load that comes and goes on the machine
falls on both. Only the cases both builds have are compared. Output: per case the two times
(ms) and AFTER / BEFORE, then the geometric mean of the ratios. A build before a change:
`git worktree add /tmp/before COMMIT`, then in /tmp/before
`OBSCURA_BUILD_DIR=/tmp/before/build bash scripts/build.sh bench_ssdo`.
"""
import argparse
import json
import math
import subprocess


def run(binary, pattern):
    """Each case's real time (ms) in one run of the binary."""
    out = subprocess.run([binary, f"--benchmark_filter={pattern}", "--benchmark_format=json"],
                         capture_output=True, text=True, check=True).stdout
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    return {b["name"]: b["real_time"] * scale[b["time_unit"]] for b in json.loads(out)["benchmarks"]
            if b.get("run_type", "iteration") == "iteration"}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--filter", default=".", help="--benchmark_filter for both binaries")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    best = {"before": {}, "after": {}}
    for _ in range(args.rounds):
        for label, binary in (("before", args.before), ("after", args.after)):
            for case, ms in run(binary, args.filter).items():
                best[label][case] = min(ms, best[label].get(case, math.inf))
    cases = [c for c in best["after"] if c in best["before"]]
    logs = []
    print(f"{'case':64s} {'before ms':>10s} {'after ms':>10s} {'after/before':>12s}")
    for c in cases:
        ratio = best["after"][c] / best["before"][c]
        logs.append(math.log(ratio))
        print(f"{c:64s} {best['before'][c]:10.2f} {best['after'][c]:10.2f} {ratio:12.3f}")
    if logs:
        print(f"geometric mean of after/before over {len(logs)} cases: {math.exp(sum(logs) / len(logs)):.3f}")


if __name__ == "__main__":
    main()
