#!/usr/bin/env python3
"""Farm throughput: N frames on a local 2-CPU Slurm cluster and on 2 Dask workers, against one
process doing the same frames one after another, in frames per minute and as a time ratio.

    PYTHONPATH=build/plugin/python /usr/bin/python3 tests/bench/bench_farm.py [--repeat 3]

Frames: the tests' synthetic scene at --size, one thread per frame, so a frame's cost dominates
a task's start-up: HBAO at --quality ultra (default), or ray-traced AO with --rays per pixel
(--method rtao; on this machine two rtao processes reach only about 1.5x one process's
throughput where two HBAO processes reach 2x, so rtao ratios show the cores, not the farm). Slurm splits the frames into one
chunk per CPU (--chunk); Dask runs one task per frame, on single-threaded workers and on one
worker with as many threads (obscura releases the GIL while it computes). Each figure is the best of --repeat
runs (the machine may be shared); the clusters are started once, on 127.0.0.1, and stopped.
Under each figure: where that run's time went (farm_timeline.py): task start and end times after
submission, CPU time of the tasks, workers and daemons, Slurm's submission and queue exit. The
local slurmctld starts a batch job at its next one-second pass (--batch-sched-delay 3: Slurm's default
of collecting submissions for 3 s).
"""
import argparse
import contextlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(ROOT / "tests" / "python"))
sys.path.insert(0, os.environ.get("OBSCURA_MODULE_DIR", str(ROOT / "build" / "plugin" / "python")))

from conftest import synthetic_scene, write_exr  # noqa: E402
from farm_engines import DaskCluster, EngineUnavailable, SlurmCluster  # noqa: E402
from farm_timeline import SlurmWatch, boot_clock, cpu_delta, cpu_seconds, run_measured  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--method", default="hbao", choices=["hbao", "rtao"], help="per-frame work")
    ap.add_argument("--size", default="", help="frame size (hbao: 1280x960, rtao: 320x240)")
    ap.add_argument("--quality", default="ultra", help="hbao's preset")
    ap.add_argument("--rays", type=int, default=64, help="rtao's rays per pixel")
    ap.add_argument("--cpus", type=int, default=2, help="Slurm CPUs and Dask workers")
    ap.add_argument("--chunk", type=int, default=0, help="frames per Slurm task (default: frames / cpus)")
    ap.add_argument("--batch-sched-delay", type=int, default=0,
                    help="slurmctld's batch_sched_delay (Slurm's default: 3 s, when tasks wait for a 3-second tick)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cli", default=os.environ.get("OBSCURA_CLI", str(ROOT / "build" / "plugin" / "obscura")))
    args = ap.parse_args()
    width, height = map(int, (args.size or ("1280x960" if args.method == "hbao" else "320x240")).split("x"))
    chunk = args.chunk or -(-args.frames // args.cpus)

    work = Path(tempfile.mkdtemp(prefix="obscura-bench-farm-"))
    try:
        for f in range(1, args.frames + 1):
            depth, normal = synthetic_scene(width, height, f)
            write_exr(work / f"shot.{f:04d}.exr", depth, normal, sidecar=True)
        if args.method == "hbao":
            work_flags, work_settings, work_label = ["--quality", args.quality], {"quality": args.quality}, f"hbao {args.quality}"
        else:
            work_flags, work_settings = ["--rtao-rays", str(args.rays)], {"rtao_rays": args.rays}
            work_label = f"rtao {args.rays} rays"
        flags = ["--method", args.method, *work_flags, "--radius", "0.5", "--threads", "1"]
        run_args = ["shot.####.exr", "-o", "out/ao.####.exr", *flags, "--frames", f"1-{args.frames}"]

        def clean():
            shutil.rmtree(work / "out", ignore_errors=True)
            (work / "out").mkdir()

        print(f"bench_farm: {args.frames} frames {width}x{height}, {work_label}, 1 thread per frame; "
              f"best of {args.repeat}; {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}", flush=True)

        # What every obscura process pays before its first frame (the baseline once, the farm
        # in `farm slurm` and again in each task): mostly loading the shared libraries.
        startup = min((run_measured([args.cli, "--version"], capture_output=True)[1:] for _ in range(3)),
                      key=lambda r: r[0])
        print(f"  obscura start-up (--version, best of 3): {startup[0]:.2f} s, CPU {startup[1]:.2f} s", flush=True)

        def one_process_cli():
            clean()
            _, wall, cpu = run_measured([args.cli, *run_args, "--quiet"], cwd=work, check=True, timeout=3600)
            return wall, [f"CPU {cpu:.2f} s ({cpu / wall:.2f} of a core: --threads 1 holds it to one)"]

        import obscura
        from obscura import farm
        frames = [str(work / f"shot.{f:04d}.exr") for f in range(1, args.frames + 1)]
        settings = {"method": args.method, **work_settings, "radius": 0.5, "threads": 1}

        def one_process_python():
            clean()
            (work / "out" / "v").mkdir()
            t0, c0 = time.perf_counter(), time.process_time()
            for src in frames:
                out, report = farm.output_paths(str(work / "out"), "v", src)
                obscura.process(src, out, report=report, **settings)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            return wall, [f"CPU {cpu:.2f} s ({cpu / wall:.2f} of a core)"]

        def slurm_run(cluster):
            clean()
            daemons = {name: p.pid for name, p in cluster.procs.procs}
            before = cpu_seconds(daemons)
            origin, t0, own = boot_clock(), time.perf_counter(), time.process_time()
            proc, submit_wall, submit_cpu = run_measured(
                [args.cli, "farm", "slurm", *run_args, "--chunk", str(chunk)], cwd=work, env=cluster.env,
                capture_output=True, text=True, timeout=300)
            if proc.returncode != 0:
                raise RuntimeError(proc.stderr)
            job = proc.stdout.split()[2].rstrip(":")
            reports = [str(work / "out" / f"ao.{f:04d}.json") for f in range(1, args.frames + 1)]
            watch = SlurmWatch(cluster, job, tasks, args.cli, reports, origin).run()
            seconds, own = time.perf_counter() - t0, time.process_time() - own
            used = cpu_delta(before, cpu_seconds(daemons))
            done = subprocess.run([args.cli, "farm", "summary", "out"], cwd=work, capture_output=True)
            if done.returncode != 0:
                raise RuntimeError(f"job {job} left frames undone: {done.stdout.decode()}")
            return seconds, [f"submit (obscura farm slurm + sbatch) {submit_wall:.2f} s, CPU {submit_cpu:.2f} s",
                             *watch.lines(),
                             "daemon CPU: " + ", ".join(f"{k} {v:.2f} s" for k, v in used.items())
                             + f"; this bench's watching {own:.2f} s"]

        def dask_run(client, cluster):
            from distributed import get_task_stream
            clean()
            pids = {name: p.pid for name, p in cluster.procs.procs}
            before = cpu_seconds(pids)
            t0, epoch0 = time.perf_counter(), time.time()
            with get_task_stream(client) as stream:
                result = farm.run_dask(client, frames, {"v": {}}, out_dir=str(work / "out"), progress=False,
                                       **settings)
            seconds = time.perf_counter() - t0
            used = cpu_delta(before, cpu_seconds(pids))
            if result["failed"] or result["done"] != args.frames:
                raise RuntimeError(f"dask run incomplete: {result}")
            spans = {}
            for t in stream.data:
                for ss in t.get("startstops", ()):
                    if ss["action"] == "compute":
                        spans.setdefault(t["worker"], []).append((ss["start"] - epoch0, ss["stop"] - epoch0))
            lines = []
            for w, s in sorted(spans.items()):
                s.sort()
                busy = sum(b - a for a, b in s)
                gaps = sum(max(0.0, s[i + 1][0] - s[i][1]) for i in range(len(s) - 1))
                lines.append(f"{w.rsplit(':', 1)[-1]:>6}: {len(s)} task(s), first start {s[0][0]:5.2f} s, last end "
                             f"{s[-1][1]:6.2f} s, computing {busy:6.2f} s, idle between tasks {gaps:.2f} s")
            lines.append("process CPU: " + ", ".join(f"{k} {v:.2f} s" for k, v in used.items()))
            lines.insert(0, f"run_dask {result['seconds']:.2f} s (the rest: the task stream's set-up and fetch)")
            return seconds, lines

        def row(label, runs, base=None):
            seconds, details = min(runs, key=lambda r: r[0])
            fpm = 60.0 * args.frames / seconds
            ratio = f"  ratio {seconds / base:.2f} of one process" if base else ""
            print(f"  {label:<44} {seconds:7.2f} s  {fpm:6.1f} frames/min{ratio}", flush=True)
            for d in details:
                print(f"      {d}")
            return seconds

        # The clusters start once; each round runs every case, so a busy spell hits all of them.
        tasks = -(-args.frames // chunk)
        times = {k: [] for k in ("cli", "slurm", "python", "dask", "threads")}
        skipped = {}
        with contextlib.ExitStack() as stack:
            try:
                slurm = stack.enter_context(SlurmCluster(cpus=args.cpus, batch_sched_delay=args.batch_sched_delay))
            except EngineUnavailable as e:
                slurm, skipped["slurm"] = None, str(e)
            try:
                dask = stack.enter_context(DaskCluster(work / "dask", workers=args.cpus))
                from distributed import Client
                client = stack.enter_context(Client(dask.address, timeout=60))
                # One worker with as many threads: the GIL is released while a frame computes.
                threaded = stack.enter_context(DaskCluster(work / "dask-threads", workers=1, threads=args.cpus))
                threaded_client = stack.enter_context(Client(threaded.address, timeout=60))
                # Each worker imports obscura once (a few tenths of a second): not part of a run.
                for c in (client, threaded_client):
                    c.run(__import__, "obscura.farm")
            except EngineUnavailable as e:
                client, skipped["dask"] = None, str(e)
            for _ in range(args.repeat):
                times["cli"].append(one_process_cli())
                if slurm:
                    times["slurm"].append(slurm_run(slurm))
                times["python"].append(one_process_python())
                if client:
                    times["dask"].append(dask_run(client, dask))
                    times["threads"].append(dask_run(threaded_client, threaded))
        print("  (times in the details are seconds after submission; CPU is user + system)")
        cli = row("one process, frames in turn (CLI)", times["cli"])
        if times["slurm"]:
            row(f"slurm, {args.cpus} CPUs, {tasks} tasks of {chunk} frames", times["slurm"], cli)
            print(f"      (batch_sched_delay={args.batch_sched_delay}: tasks start at slurmctld's next "
                  f"{max(1, args.batch_sched_delay)}-second tick after submission)")
        py = row("one process, frames in turn (Python)", times["python"])
        if times["dask"]:
            row(f"dask, {args.cpus} workers x 1 thread", times["dask"], py)
            row(f"dask, 1 worker x {args.cpus} threads", times["threads"], py)
        print(f"  load average after: {os.getloadavg()[0]:.1f} (ratios mean little when other work holds the cores)")
        for engine, why in skipped.items():
            print(f"  {engine}: skipped ({why})")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
