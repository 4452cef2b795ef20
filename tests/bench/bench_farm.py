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
from farm_engines import DaskCluster, EngineUnavailable, SlurmCluster, wait_for  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--method", default="hbao", choices=["hbao", "rtao"], help="per-frame work")
    ap.add_argument("--size", default="", help="frame size (hbao: 1280x960, rtao: 320x240)")
    ap.add_argument("--quality", default="ultra", help="hbao's preset")
    ap.add_argument("--rays", type=int, default=64, help="rtao's rays per pixel")
    ap.add_argument("--cpus", type=int, default=2, help="Slurm CPUs and Dask workers")
    ap.add_argument("--chunk", type=int, default=0, help="frames per Slurm task (default: frames / cpus)")
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

        def one_process_cli():
            clean()
            t0 = time.perf_counter()
            subprocess.run([args.cli, *run_args, "--quiet"], cwd=work, check=True, timeout=3600)
            return time.perf_counter() - t0

        print(f"bench_farm: {args.frames} frames {width}x{height}, {work_label}, 1 thread per frame; "
              f"best of {args.repeat}; {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}", flush=True)

        def row(label, seconds, base=None):
            fpm = 60.0 * args.frames / seconds
            ratio = f"  ratio {seconds / base:.2f} of one process" if base else ""
            print(f"  {label:<44} {seconds:7.2f} s  {fpm:6.1f} frames/min{ratio}", flush=True)

        import obscura
        from obscura import farm
        frames = [str(work / f"shot.{f:04d}.exr") for f in range(1, args.frames + 1)]
        settings = {"method": args.method, **work_settings, "radius": 0.5, "threads": 1}

        def one_process_python():
            clean()
            (work / "out" / "v").mkdir()
            t0 = time.perf_counter()
            for src in frames:
                out, report = farm.output_paths(str(work / "out"), "v", src)
                obscura.process(src, out, report=report, **settings)
            return time.perf_counter() - t0

        def slurm_run(cluster):
            clean()
            t0 = time.perf_counter()
            proc = subprocess.run([args.cli, "farm", "slurm", *run_args, "--chunk", str(chunk)], cwd=work,
                                  env=cluster.env, capture_output=True, text=True, timeout=300)
            if proc.returncode != 0:
                raise RuntimeError(proc.stderr)
            job = proc.stdout.split()[2].rstrip(":")
            wait_for(lambda: not cluster.running(job), 3600, f"job {job}")
            seconds = time.perf_counter() - t0
            done = subprocess.run([args.cli, "farm", "summary", "out"], cwd=work, capture_output=True)
            if done.returncode != 0:
                raise RuntimeError(f"job {job} left frames undone: {done.stdout.decode()}")
            return seconds

        def dask_run(client):
            clean()
            t0 = time.perf_counter()
            result = farm.run_dask(client, frames, {"v": {}}, out_dir=str(work / "out"), progress=False, **settings)
            if result["failed"] or result["done"] != args.frames:
                raise RuntimeError(f"dask run incomplete: {result}")
            return time.perf_counter() - t0

        # The clusters start once; each round runs every case, so a busy spell hits all of them.
        times = {k: [] for k in ("cli", "slurm", "python", "dask", "threads")}
        skipped = {}
        with contextlib.ExitStack() as stack:
            try:
                slurm = stack.enter_context(SlurmCluster(cpus=args.cpus))
            except EngineUnavailable as e:
                slurm, skipped["slurm"] = None, str(e)
            try:
                dask = stack.enter_context(DaskCluster(work / "dask", workers=args.cpus))
                from distributed import Client
                client = stack.enter_context(Client(dask.address, timeout=60))
                # One worker with as many threads: the GIL is released while a frame computes.
                threaded = stack.enter_context(DaskCluster(work / "dask-threads", workers=1, threads=args.cpus))
                threaded_client = stack.enter_context(Client(threaded.address, timeout=60))
            except EngineUnavailable as e:
                client, skipped["dask"] = None, str(e)
            for _ in range(args.repeat):
                times["cli"].append(one_process_cli())
                if slurm:
                    times["slurm"].append(slurm_run(slurm))
                times["python"].append(one_process_python())
                if client:
                    times["dask"].append(dask_run(client))
                    times["threads"].append(dask_run(threaded_client))
        tasks = -(-args.frames // chunk)
        row("one process, frames in turn (CLI)", min(times["cli"]))
        if times["slurm"]:
            row(f"slurm, {args.cpus} CPUs, {tasks} tasks of {chunk} frames", min(times["slurm"]), min(times["cli"]))
        row("one process, frames in turn (Python)", min(times["python"]))
        if times["dask"]:
            row(f"dask, {args.cpus} workers x 1 thread", min(times["dask"]), min(times["python"]))
            row(f"dask, 1 worker x {args.cpus} threads", min(times["threads"]), min(times["python"]))
        print(f"  load average after: {os.getloadavg()[0]:.1f} (ratios mean little when other work holds the cores)")
        for engine, why in skipped.items():
            print(f"  {engine}: skipped ({why})")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
