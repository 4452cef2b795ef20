"""obscura.farm.run_dask on a real Dask cluster started on 127.0.0.1 for the test (a scheduler
and 2 single-threaded workers): 6 frames x 2 variants, one worker killed during the run; every
output ends complete and bit-identical to one process computing them in turn. The write mode
(write='append') reaches the workers, and so do relative file settings. Without a cluster: what
run_dask refuses on the client before writing anything, and the resume rule (is_complete)."""
import json
import os
import re
import shutil
import signal
import threading

import numpy as np
import pytest

import obscura
from obscura import farm
from conftest import FOV_DEG, pose_matrix, synthetic_scene, write_exr
from farm_engines import DaskCluster, EngineUnavailable, wait_for

VARIANTS = {"near": {"radius": 0.5}, "far": {"radius": 1.5, "weighting": "cosine"}}
# Ray-traced AO at one thread: about half a second a task, so a worker dies mid-task.
COMMON = {"method": "rtao", "rtao_rays": 64, "threads": 1}


def test_run_dask_survives_a_killed_worker(tmp):
    frames = []
    for f in range(1, 7):
        depth, normal = synthetic_scene(200, 150, f)
        write_exr(tmp / f"shot.{f:04d}.exr", depth, normal, sidecar=True)
        frames.append(str(tmp / f"shot.{f:04d}.exr"))
    out, ref = tmp / "out", tmp / "ref"
    # One process, in turn, into the same paths (the file records them), then moved aside.
    for name, settings in VARIANTS.items():
        (out / name).mkdir(parents=True)
        (ref / name).mkdir(parents=True)
        for src in frames:
            dst, report = farm.output_paths(str(out), name, src)
            obscura.process(src, dst, report=report, **COMMON, **settings)
            shutil.move(dst, ref / name / os.path.basename(dst))
            os.remove(report)

    try:
        cluster = DaskCluster(tmp / "dask", workers=2).__enter__()
    except EngineUnavailable as e:
        pytest.skip(f"Dask cannot run here: {e}")
    from distributed import Client
    result = {}
    try:
        with Client(cluster.address, timeout=60) as client:
            run = threading.Thread(target=lambda: result.update(
                farm.run_dask(client, frames, VARIANTS, out_dir=str(out), **COMMON)), daemon=True)
            run.start()
            # Once the first outputs are in, both workers are busy with the next ones: kill one.
            written = lambda: sum(1 for n in VARIANTS for p in (out / n).glob("*.json"))  # noqa: E731
            wait_for(lambda: written() >= 2 or not run.is_alive(), 120, "the first frames")
            victim = cluster.worker_procs[1]
            address = next(a for a, w in client.scheduler_info()["workers"].items() if w["name"] == "worker1")
            wait_for(lambda: client.processing().get(address) or not run.is_alive(), 30, "a task on worker1")
            held = client.processing().get(address)
            assert victim.poll() is None and held, "the run ended before a worker could be killed"
            os.kill(victim.pid, signal.SIGKILL)
            victim.wait(timeout=30)  # reaped, as a dead node's process is gone (a zombie looks alive)
            run.join(timeout=300)
            assert not run.is_alive(), "run_dask did not finish"
            # Run again: everything is complete, nothing is recomputed.
            again = farm.run_dask(client, frames, VARIANTS, out_dir=str(out), progress=False, **COMMON)
    finally:
        cluster.__exit__(None, None, None)

    assert result["failed"] == [], result["failed"]
    print(f"killed worker1 holding {len(held)} task(s)")
    assert result["done"] + result["skipped"] == 12, result
    assert again["done"] == 0 and again["skipped"] == 12 and again["failed"] == []
    for name in VARIANTS:
        assert not [p for p in os.listdir(out / name) if ".tmp-" in p]
        for src in frames:
            base = os.path.basename(src)
            assert (out / name / base).read_bytes() == (ref / name / base).read_bytes(), (name, base)


def test_batch_relight_on_a_scheduler_resumes_like_a_local_run(tmp):
    import subprocess
    import sys

    from conftest import EXAMPLES, SAMPLES, read_channel
    for f in (1, 2):
        shutil.copy(SAMPLES / "room.exr", tmp / f"shot.{f:04d}.exr")
        shutil.copy(SAMPLES / "room.json", tmp / f"shot.{f:04d}.json")
    out = tmp / "out"
    args = [sys.executable, str(EXAMPLES / "batch_relight.py"), tmp / "shot.####.exr", "-o", out,
            "--sky", "1,1,1", "--sky", "0.5,0.5,1", "--set", "samples=8"]
    try:
        cluster = DaskCluster(tmp / "dask", workers=2).__enter__()
    except EngineUnavailable as e:
        pytest.skip(f"Dask cannot run here: {e}")
    try:
        proc = subprocess.run([*map(str, args), "--scheduler", cluster.address], capture_output=True, text=True,
                              timeout=300)
    finally:
        cluster.__exit__(None, None, None)
    assert proc.returncode == 0, proc.stderr
    assert "2 frame(s) x 2 variant(s); 0 complete, 4 to do" in proc.stderr and "4 written" in proc.stderr
    # A local run finds the cluster's work complete: one resume rule.
    local = subprocess.run([*map(str, args), "--resume"], capture_output=True, text=True, timeout=300)
    assert local.returncode == 0 and "4 complete, 0 to do" in local.stderr, local.stderr
    # And the cluster computed what the module computes here.
    mine = tmp / "mine.exr"
    obscura.process(tmp / "shot.0002.exr", mine, method="ssdo", bounce=True, out_layer={"relit": "Relit"},
                    sky=[0.5, 0.5, 1.0], samples=8)
    for c in "RGB":
        np.testing.assert_array_equal(read_channel(out / "sky_0.5_0.5_1" / "shot.0002.exr", f"Relit.{c}"),
                                      read_channel(mine, f"Relit.{c}"))


def test_run_dask_passes_the_write_mode(tmp):
    import OpenImageIO as oiio
    frames = []
    for f in (1, 2):
        depth, normal = synthetic_scene(64, 48, f)
        write_exr(tmp / f"shot.{f:04d}.exr", depth, normal, sidecar=True)
        frames.append(str(tmp / f"shot.{f:04d}.exr"))
    try:
        cluster = DaskCluster(tmp / "dask", workers=1).__enter__()
    except EngineUnavailable as e:
        pytest.skip(f"Dask cannot run here: {e}")
    from distributed import Client
    try:
        with Client(cluster.address, timeout=60) as client:
            result = farm.run_dask(client, frames, {"v": {}}, out_dir=str(tmp / "out"), progress=False,
                                   write="append", threads=1)
    finally:
        cluster.__exit__(None, None, None)
    assert result["done"] == 2 and result["failed"] == [], result
    for src in frames:
        out, report = farm.output_paths(str(tmp / "out"), "v", src)
        inp = oiio.ImageInput.open(out)
        assert inp.seek_subimage(1, 0) and list(inp.spec().channelnames) == ["obscura.AO.Y"], out
        inp.close()
        with open(report) as f:
            assert json.load(f)["write"]["mode"] == "append"


def test_resume_records_settings_as_a_report_holds_them():
    """Tuples and arrays as lists, threads and device aside, so a resumed run compares like with like."""
    import pathlib
    settings = {"radius": 0.5, "threads": 2, "device": "cpu", "sky": (1, 1, 1), "camera_to_world": np.eye(4),
                "camera": pathlib.Path("cam.json")}
    record = obscura.farm.recorded(settings)
    assert record == {"radius": 0.5, "sky": [1, 1, 1], "camera_to_world": np.eye(4).tolist(), "camera": "cam.json"}
    assert record == json.loads(json.dumps(record))
    assert obscura.farm.recorded(dict(settings, threads=1)) == record
    with pytest.raises(TypeError, match="a list of input files"):
        obscura.farm.run_dask(None, "shot.####.exr", {"a": {}}, out_dir="out")


def test_bad_settings_are_refused_before_any_task(tmp):
    """A typo or a value out of range fails once, on the client, naming the variant; no task runs."""
    for variants, error, words in (({"bad": {"raduis": 0.5}}, TypeError, "variant bad: .*raduis"),
                                   ({"cos": {"weighting": "cos"}}, ValueError, "variant cos: weighting must be")):
        with pytest.raises(error, match=words):
            obscura.farm.run_dask(None, [str(tmp / "shot.1001.exr")], variants, out_dir=str(tmp / "out"))


def write_frame(path, frame=1, sidecar=True):
    depth, normal = synthetic_scene(48, 32, frame)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_exr(path, depth, normal, sidecar=sidecar)
    return str(path)


def write_env(path):
    """A tiny lat-long map, for method='ssdo' with env=."""
    import OpenImageIO as oiio
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(16, 8, 3, oiio.FLOAT)), oiio.geterror()
    assert out.write_image(np.full((8, 16, 3), 0.5, np.float32)), out.geterror()
    out.close()


def test_relative_file_settings_reach_the_workers(tmp, monkeypatch):
    """camera= and env= relative to the client's directory: a worker, elsewhere, opens them there."""
    shots = tmp / "shots"
    for f in (1, 2):
        write_frame(shots / f"shot.{f:04d}.exr", f, sidecar=False)
    (shots / "cam.json").write_text(json.dumps({"projection": "persp", "horizontal_fov_rad": float(np.radians(FOV_DEG)),
                                                "camera_to_world": pose_matrix().tolist()}))
    write_env(shots / "env.exr")
    try:
        cluster = DaskCluster(tmp / "dask", workers=1).__enter__()  # its worker's directory is this one
    except EngineUnavailable as e:
        pytest.skip(f"Dask cannot run here: {e}")
    from distributed import Client
    monkeypatch.chdir(shots)
    variants = {"v": {"camera": "cam.json", "method": "ssdo", "env": "env.exr"}}
    try:
        with Client(cluster.address, timeout=60) as client:
            result = farm.run_dask(client, ["shot.0001.exr", "shot.0002.exr"], variants, out_dir="out",
                                   progress=False, threads=1)
            again = farm.run_dask(client, ["shot.0001.exr", "shot.0002.exr"], variants, out_dir="out",
                                  progress=False, threads=1)
    finally:
        cluster.__exit__(None, None, None)
    assert result["failed"] == [] and result["done"] == 2, result
    assert again["skipped"] == 2 and again["done"] == 0, again
    report = json.loads((shots / "out" / "v" / "shot.0001.json").read_text())
    assert report["batch_variant"]["settings"]["env"] == str(shots / "env.exr")
    assert [i["path"] for i in report["batch_inputs"]] == [str(shots / n) for n in ("shot.0001.exr", "cam.json",
                                                                                      "env.exr")]


def test_two_frames_with_one_output_are_refused(tmp):
    """sh010/beauty.0001.exr and sh020/beauty.0001.exr would both write OUT/v/beauty.0001.exr, the
    second finding the first's output complete; so would one frame listed twice. Refused on the
    client, before any directory is made."""
    a, b = write_frame(tmp / "sh010" / "beauty.0001.exr"), write_frame(tmp / "sh020" / "beauty.0001.exr")
    out = tmp / "out"
    with pytest.raises(ValueError) as e:
        farm.run_dask(None, [a, b], {"v": {}}, out_dir=str(out))
    assert str(e.value) == f"'{a}' and '{b}' are both written to '{out / 'v' / 'beauty.0001.exr'}'; nothing written"
    with pytest.raises(ValueError, match=f"'{re.escape(a)}' is listed twice .*; nothing written"):
        farm.run_dask(None, [a, a], {"v": {}}, out_dir=str(out))
    assert not out.exists()


def test_variant_names_and_settings_are_checked_before_any_directory(tmp):
    """A variant's name is its directory under OUT: a path in it is refused, and so is '.' or '..'.
    Every variant is checked before any directory is made."""
    src = str(tmp / "shot.1001.exr")
    out = tmp / "a" / "out"
    for name in ("../../escape", "", ".", "..", "a/b"):
        with pytest.raises(ValueError, match=f"variant name {re.escape(repr(name))} must be"):
            farm.run_dask(None, [src], {name: {}}, out_dir=str(out))
    with pytest.raises(TypeError, match="variant bad: .*raduis"):
        farm.run_dask(None, [src], {"good": {}, "bad": {"raduis": 0.5}}, out_dir=str(out))
    assert os.listdir(tmp) == []


def test_resume_compares_every_file_a_task_reads(tmp):
    """A task is stale once a file it reads is newer than its output: the input's camera sidecar
    re-exported, a camera= file, an env= map repainted (the CLI's --resume rule)."""
    cases = {"sidecar": ({}, "shot.0001.json"), "camera": ({"camera": "cam.json"}, "cam.json"),
             "env": ({"method": "ssdo", "env": "env.exr"}, "env.exr")}
    for name, (settings, changed) in cases.items():
        src = write_frame(tmp / name / "shot.0001.exr")
        shutil.copy(tmp / name / "shot.0001.json", tmp / name / "cam.json")
        write_env(tmp / name / "env.exr")
        settings = {k: str(tmp / name / v) if k in ("camera", "env") else v for k, v in settings.items()}
        out, report = farm.output_paths(str(tmp / name / "out"), "v", src)
        os.makedirs(os.path.dirname(out))
        record = {"name": "v", "kind": "ao", "settings": farm.recorded(settings)}
        farm.render(src, out, report, settings, record)
        assert farm.is_complete(src, out, report, record), name
        later = os.stat(out).st_mtime + 10
        os.utime(tmp / name / changed, (later, later))
        assert not farm.is_complete(src, out, report, record), name


def test_resume_sees_an_input_rolled_back(tmp):
    """An input rolled back to an older render (a link re-pointed, a copy keeping its mtime) is not
    newer than the output, but it is not what the output was computed from: the report's stamps
    (path, size, mtime) tell. A report without stamps is not complete."""
    earlier, later = write_frame(tmp / "v1" / "shot.0001.exr", 1), write_frame(tmp / "v2" / "shot.0001.exr", 2)
    old = os.stat(later).st_mtime - 100
    os.utime(earlier, (old, old))
    shutil.copy(tmp / "v2" / "shot.0001.json", tmp / "shot.0001.json")
    src = tmp / "shot.0001.exr"
    out, report = farm.output_paths(str(tmp / "out"), "v", str(src))
    os.makedirs(os.path.dirname(out))
    record = {"name": "v", "kind": "ao", "settings": {}}

    def rolled_back(now, then):
        """Computed from the input as now() makes it, then then() replaces it: complete?"""
        now()
        farm.render(str(src), out, report, {}, record)
        assert farm.is_complete(str(src), out, report, record)
        src.unlink()
        then()
        complete = farm.is_complete(str(src), out, report, record)
        src.unlink()
        return complete

    assert not rolled_back(lambda: src.symlink_to(later), lambda: src.symlink_to(earlier))
    assert not rolled_back(lambda: shutil.copy2(later, src), lambda: shutil.copy2(earlier, src))  # cp -p
    shutil.copy2(later, src)
    with open(report) as f:
        older = {k: v for k, v in json.load(f).items() if k != "batch_inputs"}
    farm.render(str(src), out, report, {}, record)
    with open(report, "w") as f:
        json.dump(older, f)
    assert not farm.is_complete(str(src), out, report, record)
