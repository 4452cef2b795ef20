"""`obscura farm slurm` on a real one-node Slurm cluster started on 127.0.0.1 for the test:
a 3-task array job over 6 frames, one task's obscura killed mid-frame, the job resubmitted;
every output ends complete and bit-identical to one process doing all 6 frames (in a directory
whose name holds a blank, a quote and a '%')."""
import json
import os
import shutil
import signal
import subprocess
import time

import pytest

from conftest import CLI, synthetic_scene, write_exr
from farm_engines import EngineUnavailable, SlurmCluster, wait_for
from test_farm import farm

FRAMES = range(1, 7)
# Frames heavy enough (ray-traced AO, about half a second at one thread) to catch a task mid-frame.
ARGS = ["shot.####.exr", "-o", "out/ao.####.exr", "--method", "rtao", "--rtao-rays", "64", "--radius", "0.5",
        "--threads", "1", "--frames", "1-6"]


def task_process(job_id, task):
    """The pid of array task `task`'s obscura process (found through its Slurm environment)."""
    exe = os.path.realpath(CLI)
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            if os.path.realpath(f"/proc/{pid}/exe") != exe:
                continue
            env = dict(v.split("=", 1) for v in open(f"/proc/{pid}/environ").read().split("\0") if "=" in v)
        except OSError:
            continue
        if env.get("SLURM_ARRAY_JOB_ID") == str(job_id) and env.get("SLURM_ARRAY_TASK_ID") == str(task):
            return int(pid)
    return None


def submit(cluster, cwd):
    proc = farm("slurm", *ARGS, "--chunk", "2", env=cluster.env, cwd=cwd)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.split()[2].rstrip(":")  # "submitted job ID: ..."


def test_killed_task_resubmitted(tmp):
    # A show's directory as people name them: a blank, a quote, and a '%' Slurm's log pattern
    # would read as the job's name (%x) unless the script doubles it.
    tmp = tmp / "My Show's 100%x"
    tmp.mkdir()
    for f in FRAMES:
        depth, normal = synthetic_scene(200, 150, f)
        write_exr(tmp / f"shot.{f:04d}.exr", depth, normal, sidecar=True)
    out, ref = tmp / "out", tmp / "ref"
    out.mkdir()
    ref.mkdir()
    # The single-machine run: the same command in one process, into the same paths, moved aside.
    proc = subprocess.run([CLI, *ARGS, "--quiet"], cwd=tmp, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    for f in FRAMES:
        shutil.move(out / f"ao.{f:04d}.exr", ref / f"ao.{f:04d}.exr")

    try:
        cluster = SlurmCluster(cpus=2).__enter__()
    except EngineUnavailable as e:
        pytest.skip(f"Slurm cannot run here: {e}")
    try:
        job = submit(cluster, tmp)
        # Task 1 holds frames 3-4: once frame 3 is written it is computing frame 4; kill it there.
        try:
            wait_for(lambda: (out / "ao.0003.exr").exists(), 120, "task 1's first frame")
        except TimeoutError as e:
            raise AssertionError(f"{e}; slurmd.log ends:\n{cluster.log_tail('slurmd.log')}") from None
        pid = task_process(job, 1)
        assert pid is not None, "task 1's obscura finished before it could be killed (frames too small?)"
        os.kill(pid, signal.SIGKILL)
        cluster.wait(job, timeout=180)
        summary = json.loads(farm("summary", out, "--json").stdout)
        assert summary["missing"] == [4], summary
        assert summary["done"] == [1, 2, 3, 5, 6]

        started = time.monotonic()
        job2 = submit(cluster, tmp)
        assert job2 != job
        cluster.wait(job2, timeout=180)
        resumed = time.monotonic() - started
    finally:
        cluster.__exit__(None, None, None)

    s = farm("summary", out, "--json")
    summary = json.loads(s.stdout)
    assert s.returncode == 0, s.stdout
    assert summary["done"] == list(FRAMES) and summary["temp_files"] == []
    for f in FRAMES:
        assert (out / f"ao.{f:04d}.exr").read_bytes() == (ref / f"ao.{f:04d}.exr").read_bytes(), f"frame {f}"
    # The resubmitted tasks skipped the five finished frames: their logs say so.
    logs = "".join(p.read_text() for p in (out / "obscura_farm_logs").glob(f"{job2}_*.log"))
    assert "(1 skipped)" in logs and "(2 skipped)" in logs, logs
    print(f"resubmitted job {job2}: frame 4 redone in {resumed:.1f} s")
