"""examples/batch_ao.py and examples/contact_sheet.py on a small synthetic sequence."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import obscura
from conftest import EXAMPLES, read_channel, synthetic_scene, write_exr

sys.path.insert(0, str(EXAMPLES))
import batch_ao  # noqa: E402


def run(script, *args):
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], capture_output=True, text=True)
    return proc


@pytest.fixture
def sequence(tmp):
    for frame in (1, 2, 3):
        depth, normal = synthetic_scene(64, 48, frame)
        write_exr(tmp / f"shot.{frame:04d}.exr", depth, normal, sidecar=True)
    return tmp


def test_patterns_and_ranges():
    assert batch_ao.frame_path("a/shot.####.exr", 7) == "a/shot.0007.exr"
    assert batch_ao.frame_path("shot.%04d.exr", 12) == "shot.0012.exr"
    assert batch_ao.frame_path("shot.%d.exr", 12) == "shot.12.exr"
    assert batch_ao.parse_frames("1-5x2,8,10-11") == [1, 3, 5, 8, 10, 11]
    for bad in ("5-1", "a", "1-4x0"):
        with pytest.raises(ValueError):
            batch_ao.parse_frames(bad)
    with pytest.raises(ValueError):
        batch_ao.parse_pattern("shot.exr")
    s = batch_ao.parse_assignments("radius=0.5,weighting=cosine directions=4 layer=normal=N camera_to_world=[1,0,0,0]")
    assert s == {"radius": 0.5, "weighting": "cosine", "directions": 4, "layer": {"normal": "N"},
                 "camera_to_world": [1, 0, 0, 0]}


def test_batch_resume_and_contact_sheet(sequence):
    out = sequence / "out"
    args = ["shot.%04d.exr".join([str(sequence) + "/", ""]), "-o", out, "--frames", "1-3", "--radii", "0.5,1.5",
            "--variant", "cos:radius=1,weighting=cosine,falloff=none", "--set", "out_type=float"]
    proc = run("batch_ao.py", *args)
    assert proc.returncode == 0, proc.stderr
    assert "0 complete, 9 to do" in proc.stderr and "[9/9]" in proc.stderr
    manifest = json.loads((out / "batch.json").read_text())
    assert [v["name"] for v in manifest["variants"]] == ["cos", "r0.5", "r1.5"]
    assert manifest["frames"] == [1, 2, 3]
    for name in ("cos", "r0.5", "r1.5"):
        for f in (1, 2, 3):
            assert (out / name / f"shot.{f:04d}.exr").exists()
            report = json.loads((out / name / f"shot.{f:04d}.json").read_text())
            assert report["batch_variant"]["name"] == name
    # The batch output is what the module computes for that frame and variant.
    passes = obscura.read_passes(sequence / "shot.0002.exr")
    np.testing.assert_array_equal(read_channel(out / "r0.5" / "shot.0002.exr", "obscura.AO.Y"),
                                  obscura.ao_from_passes(passes, radius=0.5))
    r05 = read_channel(out / "r0.5" / "shot.0002.exr", "obscura.AO.Y")
    r15 = read_channel(out / "r1.5" / "shot.0002.exr", "obscura.AO.Y")
    assert r15.mean() < r05.mean()  # a larger radius finds more occlusion

    # --resume: nothing to do; then a stale frame and a changed variant are redone.
    proc = run("batch_ao.py", *args, "--resume")
    assert proc.returncode == 0 and "9 complete, 0 to do" in proc.stderr, proc.stderr
    os.remove(out / "cos" / "shot.0003.exr")
    (out / "r0.5" / "shot.0001.json").write_text("{truncated")
    proc = run("batch_ao.py", *args, "--resume", "--jobs", "2")
    assert proc.returncode == 0 and "7 complete, 2 to do" in proc.stderr, proc.stderr
    changed = [a.replace("falloff=none", "falloff=linear") for a in map(str, args)]
    proc = run("batch_ao.py", *changed, "--resume")
    assert "6 complete, 3 to do" in proc.stderr, proc.stderr
    # A narrower re-run (one variant, one frame) keeps the others in the manifest.
    narrow = run("batch_ao.py", args[0], "-o", out, "--frames", "1", "--radii", "0.5", "--set", "out_type=float",
                 "--resume")
    assert narrow.returncode == 0 and "1 complete, 0 to do" in narrow.stderr, narrow.stderr
    manifest = json.loads((out / "batch.json").read_text())
    assert sorted(v["name"] for v in manifest["variants"]) == ["cos", "r0.5", "r1.5"] and manifest["frames"] == [1, 2, 3]

    # Contact sheet from the batch, and from one frame in memory.
    sheet = sequence / "sheet.png"
    proc = run("contact_sheet.py", out, "--frame", 2, "-o", sheet)
    assert proc.returncode == 0, proc.stderr
    assert sheet.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "3 tile(s)" in proc.stderr
    sheet2 = sequence / "sheet2.png"
    proc = run("contact_sheet.py", sequence / "shot.0001.exr", "--radii", "0.25,1", "--columns", "1", "-o", sheet2)
    assert proc.returncode == 0, proc.stderr
    assert "2 tile(s)" in proc.stderr and sheet2.exists()


def test_batch_reports_failures(sequence):
    out = sequence / "out"
    proc = run("batch_ao.py", str(sequence / "shot.####.exr"), "-o", out, "--frames", "2-4")
    assert proc.returncode == 1
    assert "frame 4: FAILED" in proc.stderr and "shot.0004.exr" in proc.stderr
    assert "2 written" in proc.stderr and (out / "default" / "shot.0003.exr").exists()
    proc = run("batch_ao.py", str(sequence / "shot.####.exr"), "-o", out, "--frames", "9-1")
    assert proc.returncode == 2 and "bad frame range" in proc.stderr
    proc = run("batch_ao.py", str(sequence / "shot.####.exr"), "-o", out, "--variant", "a:weighting=bogus")
    assert proc.returncode == 1 and "weighting must be" in proc.stderr


def test_batch_refuses_two_frames_with_one_output(tmp):
    """The frame number in a directory name: sh010/beauty.exr and sh020/beauty.exr would write one
    output, the second over the first. Refused before anything is written; so is a variant named
    '..' (its directory is OUT's parent)."""
    for shot in (1, 2):
        depth, normal = synthetic_scene(64, 48, shot)
        (tmp / f"sh0{shot}0").mkdir()
        write_exr(tmp / f"sh0{shot}0" / "beauty.exr", depth, normal, sidecar=True)
    out = tmp / "out"
    proc = run("batch_ao.py", tmp / "sh0#0" / "beauty.exr", "-o", out, "--frames", "1-2")
    assert proc.returncode == 2
    assert (f"'{tmp}/sh010/beauty.exr' and '{tmp}/sh020/beauty.exr' are both written to "
            f"'{out}/default/beauty.exr'; nothing written") in proc.stderr, proc.stderr
    proc = run("batch_ao.py", tmp / "sh0#0" / "beauty.exr", "-o", out, "--frames", "1", "--variant", "..:radius=1")
    assert proc.returncode == 2 and "variant name '..' must be" in proc.stderr, proc.stderr
    assert sorted(os.listdir(tmp)) == ["sh010", "sh020"]


def test_batch_prints_each_warning_once(sequence):
    proc = run("batch_ao.py", str(sequence / "shot.####.exr"), "-o", sequence / "w", "--frames", "1-3",
               "--set", "deep_layers=2")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.count("warning: the deep layers setting is read with deep input only") == 1, proc.stderr
