#!/usr/bin/env python3
"""HBAO's time per frame in two builds, on the report's renders: a build before a change (BEFORE)
against the current one (AFTER), each frame's time as the best of --rounds processes taken in turn.

    python3 tests/bench/against_build.py BEFORE/bench_hbao build/tests/bench/bench_hbao [--rounds 3]

Both binaries run their `hbao_8x8/<weighting>/<falloff>/cpu/threads:1` case (so do
7ea9b61, the build before issue 11, and today's) with the sample counts of --preset (as AFTER
names its preset cases, hbao_high_16x12/...) through OBSCURA_BENCH_DIRECTIONS / _STEPS, and each
frame's radius from its .json, so each runs its own default settings. Frames: the report's
cache (build/report/cache, made by `obscura_report`); --size 1080 reads
SCENE_1920x1080_ao1_gi1.exr and .json from --cache, which `build/examples/reference/
reference_render --scene SCENE --width 1920 --height 1080 --ao-rays 1 --gi-rays 1
-o DIR/SCENE_1920x1080_ao1_gi1.exr` writes (the passes; the rays do not matter here).
A build before a change: `git worktree add /tmp/before COMMIT`, then in /tmp/before
`OBSCURA_BUILD_DIR=/tmp/before/build bash scripts/build.sh bench_hbao`.

Output: per frame the two times (ms) and AFTER / BEFORE, then the eight frames summed.
"""
import argparse
import csv
import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path

SCENES = ["corner", "sphere-plane", "cornell", "stairs", "poles", "city", "terrain", "studio"]


def preset_counts(binary, preset):
    """Directions and steps of a quality preset, as the build names its cases (hbao_high_16x12/...)."""
    listed = subprocess.run([binary, "--benchmark_list_tests"], capture_output=True, text=True).stdout
    for name in listed.split():
        match = re.match(rf"hbao_{re.escape(preset)}_(\d+)x(\d+)/", name)
        if match:
            return int(match.group(1)), int(match.group(2))
    sys.exit(f"against_build: {binary} has no preset '{preset}'")


def frame_ms(binary, exr, radius, case, counts, min_time):
    directions, steps = counts
    env = dict(os.environ, OBSCURA_BENCH_EXR=str(exr), OBSCURA_BENCH_RADIUS=str(radius),
               OBSCURA_BENCH_DIRECTIONS=str(directions), OBSCURA_BENCH_STEPS=str(steps))
    run = subprocess.run([binary, f"--benchmark_filter=^hbao_8x8/{case}/cpu/threads:1/",
                          f"--benchmark_min_time={min_time}", "--benchmark_format=csv"],
                         env=env, capture_output=True, text=True)
    if run.returncode != 0:
        last = (run.stderr.strip().splitlines() or ["no message"])[-1]
        sys.exit(f"against_build: {binary} failed on {exr}: {last}")
    out = run.stdout
    rows = [r for r in csv.reader(io.StringIO(out)) if r and r[0].startswith("hbao_8x8/")]
    if len(rows) != 1:
        sys.exit(f"against_build: {binary} ran {len(rows)} cases for {case}, not 1")
    return float(rows[0][3])  # real_time, in ms (the case's unit)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before", help="bench_hbao of the build before the change")
    ap.add_argument("after", help="bench_hbao of the current build")
    ap.add_argument("--case", default="uniform/linear", help="weighting/falloff (uniform/linear)")
    ap.add_argument("--preset", default="high", help="quality preset whose sample counts both run (high)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", default="320", choices=["320", "1080"])
    ap.add_argument("--cache", default="build/report/cache", help="folder of the report's renders")
    ap.add_argument("--min-time", default="0.2", help="seconds per case and process")
    args = ap.parse_args()

    for binary in (args.before, args.after):
        if not os.access(binary, os.X_OK):
            sys.exit(f"against_build: {binary} is not an executable bench_hbao")
    counts = preset_counts(args.after, args.preset)
    name = "{}_320x240_ao1024_gi64" if args.size == "320" else "{}_1920x1080_ao1_gi1"
    best = {}
    for scene in SCENES:
        stem = Path(args.cache) / name.format(scene)
        if not stem.with_suffix(".exr").exists():
            sys.exit(f"against_build: no {stem}.exr (run obscura_report first, or give --cache)")
        radius = json.loads(stem.with_suffix(".json").read_text())["ao_distance"]
        for _ in range(args.rounds):
            for which, binary in (("before", args.before), ("after", args.after)):
                t = frame_ms(binary, stem.with_suffix(".exr"), radius, args.case, counts, args.min_time)
                best[scene, which] = min(best.get((scene, which), t), t)
        b, a = best[scene, "before"], best[scene, "after"]
        print(f"{scene:13s} before {b:9.2f} ms  after {a:9.2f} ms  x{a / b:.3f}", flush=True)
    b = sum(best[s, "before"] for s in SCENES)
    a = sum(best[s, "after"] for s in SCENES)
    print(f"{'summed':13s} before {b:9.2f} ms  after {a:9.2f} ms  x{a / b:.3f}")


if __name__ == "__main__":
    main()
