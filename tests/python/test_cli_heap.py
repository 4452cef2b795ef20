"""The CLI's heap (plugin/cli/heap_tuning.h): it runs itself once more with glibc's huge-page and
top-pad tunables, which cuts the page faults a frame takes, and gives the environment back as the
user had it, so that what it starts (sbatch) sees the user's GLIBC_TUNABLES and nothing else."""
import os
import resource
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import CLI, SANITIZED, synthetic_scene, write_exr


def faults_of(args, env):
    """Minor page faults of one CLI run, from the children's rusage before and after it."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_minflt
    proc = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_minflt - before


def thp_available():
    mode = Path("/sys/kernel/mm/transparent_hugepage/enabled")
    return mode.exists() and "[never]" not in mode.read_text()


@pytest.mark.skipif(not thp_available(), reason="transparent huge pages are off on this machine")
@pytest.mark.skipif(SANITIZED, reason="ASan's shadow memory takes page faults of its own")
def test_huge_pages_cut_a_frames_page_faults(tmp):
    depth, normal = synthetic_scene(1024, 576)
    write_exr(tmp / "frame.exr", depth, normal, sidecar=True)
    args = [tmp / "frame.exr", "-o", tmp / "ao.exr", "--quiet"]
    base = {k: v for k, v in os.environ.items() if k not in ("GLIBC_TUNABLES", "OBSCURA_HEAP_TUNING")}
    tuned = faults_of(args, base)
    plain = faults_of(args, dict(base, OBSCURA_HEAP_TUNING="0"))
    print(f"1024x576 frame: {tuned} page faults with the tunables, {plain} without")
    assert tuned < 0.5 * plain


@pytest.mark.parametrize("user", [None, "glibc.malloc.check=0"])
def test_what_the_cli_starts_sees_the_users_environment(tmp, user):
    """farm slurm runs sbatch: a stand-in on PATH records the environment it was given."""
    depth, normal = synthetic_scene(48, 32)
    write_exr(tmp / "shot.0001.exr", depth, normal, sidecar=True)
    bin_dir = tmp / "bin"
    bin_dir.mkdir()
    (bin_dir / "sbatch").write_text(f"#!/bin/sh\nenv > {tmp}/sbatch.env\necho 4242\n")
    (bin_dir / "sbatch").chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"}
    env["PATH"] = f"{bin_dir}:{env['PATH']}"
    if user:
        env["GLIBC_TUNABLES"] = user
    (tmp / "out").mkdir()
    proc = subprocess.run([CLI, "farm", "slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1"],
                          capture_output=True, text=True, env=env, cwd=tmp, timeout=300)
    assert proc.returncode == 0, proc.stderr
    seen = dict(line.split("=", 1) for line in (tmp / "sbatch.env").read_text().splitlines() if "=" in line)
    assert seen.get("GLIBC_TUNABLES") == user
    assert not any(k.startswith("OBSCURA_HEAP") for k in seen)


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind is not installed")
@pytest.mark.skipif(SANITIZED, reason="valgrind cannot run a program built with AddressSanitizer")
def test_valgrind_checks_obscura_itself(tmp):
    """Under valgrind the CLI does not start itself again (that would run valgrind's own program,
    or leave obscura unchecked): the run is valgrind's, and it works."""
    env = {k: v for k, v in os.environ.items() if k not in ("GLIBC_TUNABLES", "OBSCURA_HEAP_TUNING")}
    proc = subprocess.run(["valgrind", "-q", "--error-exitcode=9", CLI, "--version"], capture_output=True, text=True,
                          env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("obscura ")
