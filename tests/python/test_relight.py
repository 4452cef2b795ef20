"""The bounce from Python: process(method='ssdo') keywords, compute_ssdo, compute_gi (hbao), batch_relight.py and relit
contact sheets."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import obscura
from conftest import EXAMPLES, SAMPLES, read_channel

ROOM = SAMPLES / "room.exr"
FAST = dict(samples=16)


def rgb(path, layer):
    return np.stack([read_channel(path, f"{layer}.{c}") for c in "RGB"], axis=-1)


def test_process_ssdo_relit_writes_layers_and_plan(tmp):
    out = tmp / "room_relit.exr"
    report = obscura.process(ROOM, out, method="ssdo", bounce=True, out_layer={"relit": "R"}, out_type="float",
                             report=tmp / "room.json", **FAST)
    written = set(report["written"])
    for layer in ("R", "obscura.DO", "obscura.GI"):
        assert {f"{layer}.{c}" for c in "RGB"} <= written, written
    assert "obscura.AO.Y" in written
    assert any("bounce" in step for step in report["plan"]), report["plan"]
    relit, do, gi = rgb(out, "R"), rgb(out, "obscura.DO"), rgb(out, "obscura.GI")
    assert np.isfinite(relit).all() and relit.max() > 0 and do.max() > 0 and gi.max() > 0
    # relit = albedo (DO + GI) / pi
    albedo = obscura.read_layer(ROOM, "ViewLayer.DiffCol")[..., :3]
    np.testing.assert_allclose(relit, albedo * (do + gi) / np.pi, rtol=1e-5, atol=1e-6)
    assert json.loads((tmp / "room.json").read_text())["plan"] == report["plan"]


@pytest.mark.parametrize("kwargs,message", [
    (dict(samples=0), "samples must be between 1 and 4096"),
    (dict(interleave=9), "interleave must be between 1 and 8"),
    (dict(samples=8, interleave=3), "at least interleave**2 samples"),
    (dict(sky=(1, 2)), "sky must be 3 numbers"),
    (dict(sky=(1, -1, 0)), "sky must be between 0 and 1e9"),
    (dict(lights=[((0, 1, 0),)]), "each light must be"),
    (dict(lights=[((0, 0, 0), (1, 1, 1))]), "must not be (0, 0, 0)"),
    (dict(lights=[((0, 1, 0), (1, 1, 1))] * 5), "at most 4"),
    (dict(up="x"), "up must be one of"),
    (dict(env_intensity=float("nan")), "env_intensity must be finite"),
    (dict(out_layer={"bogus": "X"}), "unknown output 'bogus'"),
    (dict(method="ssao", bounce=True), "bounce is read by method='ssdo' or method='hbao' only, not by method='ssao'"),
    (dict(method="ssao", out_layer={"relit": "R"}), "out_layer 'relit' is written by method='hbao' or method='ssdo' only"),
    (dict(method="hbao", out_layer={"do": "D"}), "out_layer 'do' is written by method='ssdo' only, not by method='hbao'"),
    (dict(method="nope"), "method must be one of"),
])
def test_process_ssdo_bad_values(tmp, kwargs, message):
    kwargs = dict(dict(method="ssdo"), **kwargs)
    with pytest.raises(ValueError) as e:
        obscura.process(ROOM, tmp / "x.exr", **kwargs)
    assert message in str(e.value)
    assert not (tmp / "x.exr").exists()


def test_compute_ssdo_furnace():
    """A white sky over an open plane: DO = pi (the sky's irradiance), GI = 0."""
    h, w = 48, 64
    depth = np.full((h, w), 4.0, np.float32)
    normal = np.zeros((h, w, 3), np.float32)
    normal[..., 2] = 1.0  # facing the camera (OpenGL camera space)
    cam = obscura.Camera.perspective(50.0, w, h)
    radiance = np.ones((h, w, 3), np.float32)
    r = obscura.compute_ssdo(depth, normal, camera=cam, normals="camera", radiance=radiance, bounce=True,
                             sky=(1, 1, 1), radius=0.5, **FAST)
    assert r["do"].shape == (h, w, 3) and r["do"].dtype == np.float32
    assert r["gi"].shape == (h, w, 3) and r["ao"].shape == (h, w)
    np.testing.assert_allclose(r["do"], np.pi, rtol=0.01)
    assert np.all(r["gi"] == 0.0)
    np.testing.assert_allclose(r["ao"], 1.0, atol=0.01)
    # No bounce: no GI; a coloured sky scales DO per channel; arguments are checked.
    r = obscura.compute_ssdo(depth, normal, camera=cam, normals="camera", sky=(0.5, 1, 2), radius=0.5, **FAST)
    assert r["gi"] is None
    np.testing.assert_allclose(r["do"].mean(axis=(0, 1)), np.pi * np.array([0.5, 1, 2]), rtol=0.01)
    with pytest.raises(ValueError, match="bounce=True needs radiance"):
        obscura.compute_ssdo(depth, normal, camera=cam, normals="camera", bounce=True)
    with pytest.raises(ValueError, match="radiance must have shape"):
        obscura.compute_ssdo(depth, normal, camera=cam, normals="camera", radiance=depth, bounce=True)
    with pytest.raises(ValueError, match="environment must have dtype float32"):
        obscura.compute_ssdo(depth, normal, camera=cam, normals="camera", environment=np.ones((8, 16, 3)))


def test_compute_ssdo_matches_process(tmp):
    out = tmp / "room_do.exr"
    report = obscura.process(ROOM, out, method="ssdo", out_type="float", **FAST)
    assert any("no bounce" in step for step in report["plan"])
    p = obscura.read_passes(ROOM)
    r = obscura.compute_ssdo(p["depth"], p["normal"], camera=p["camera"], normals=p["normals"],
                             depth_kind=p["depth_kind"], sky_depth=p["sky_depth"], data_window=p["data_window"],
                             display_window=p["display_window"], up="z", **FAST)
    np.testing.assert_array_equal(r["do"], rgb(out, "obscura.DO"))
    np.testing.assert_array_equal(r["ao"], read_channel(out, "obscura.AO.Y"))
    assert r["gi"] is None

    # With the bounce: the CLI's default source is direct diffuse x albedo. room.exr's colour passes
    # are already in the working space (the plan says so), so the passes read raw are the inputs.
    out = tmp / "room_gi.exr"
    report = obscura.process(ROOM, out, method="ssdo", bounce=True, out_type="float", **FAST)
    colour = [s for s in report["plan"] if s.startswith("colour: ")]
    assert colour and colour[0].split()[1] == colour[0].split()[-1], report["plan"]
    radiance = obscura.read_layer(ROOM, "ViewLayer.DiffDir")[..., :3]  # a strided view: read in place
    albedo = obscura.read_layer(ROOM, "ViewLayer.DiffCol")[..., :3]
    r = obscura.compute_ssdo(p["depth"], p["normal"], camera=p["camera"], normals=p["normals"],
                             depth_kind=p["depth_kind"], sky_depth=p["sky_depth"], data_window=p["data_window"],
                             display_window=p["display_window"], up="z", bounce=True, radiance=radiance,
                             albedo=albedo, **FAST)
    np.testing.assert_array_equal(r["do"], rgb(out, "obscura.DO"))
    np.testing.assert_array_equal(r["gi"], rgb(out, "obscura.GI"))
    assert r["gi"].max() > 0


def test_compute_gi_matches_process_and_an_open_plane_gets_none(tmp):
    """compute_gi is hbao's bounce: the CLI's GI and AO bit for bit; an open plane receives nothing."""
    out = tmp / "room_hbao_gi.exr"
    obscura.process(ROOM, out, method="hbao", bounce=True, out_type="float")
    p = obscura.read_passes(ROOM)
    radiance = obscura.read_layer(ROOM, "ViewLayer.DiffDir")[..., :3]
    albedo = obscura.read_layer(ROOM, "ViewLayer.DiffCol")[..., :3]
    r = obscura.compute_gi(p["depth"], p["normal"], camera=p["camera"], normals=p["normals"],
                           depth_kind=p["depth_kind"], sky_depth=p["sky_depth"], data_window=p["data_window"],
                           display_window=p["display_window"], radiance=radiance, albedo=albedo)
    np.testing.assert_array_equal(r["gi"], rgb(out, "obscura.GI"))
    np.testing.assert_array_equal(r["ao"], read_channel(out, "obscura.AO.Y"))
    assert r["gi"].max() > 0

    h, w = 48, 64
    depth = np.full((h, w), 4.0, np.float32)
    normal = np.zeros((h, w, 3), np.float32)
    normal[..., 2] = 1.0
    cam = obscura.Camera.perspective(50.0, w, h)
    r = obscura.compute_gi(depth, normal, camera=cam, normals="camera", radiance=np.ones((h, w, 3), np.float32),
                           radius=0.5)
    assert r["gi"].shape == (h, w, 3) and r["gi"].dtype == np.float32
    assert np.all(r["gi"] == 0.0)
    np.testing.assert_allclose(r["ao"], 1.0, atol=1e-6)
    with pytest.raises(ValueError, match="compute_gi needs radiance"):
        obscura.compute_gi(depth, normal, camera=cam, normals="camera")
    with pytest.raises(ValueError, match="use compute_ssdo"):
        obscura.compute_gi(depth, normal, camera=cam, normals="camera", radiance=normal, method="ssdo")
    with pytest.raises(ValueError, match="has no bounce"):
        obscura.compute_gi(depth, normal, camera=cam, normals="camera", radiance=normal, method="ssao")


# ------------------------------------------------------------------------------------------
# batch_relight.py


def run(script, *args):
    return subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], capture_output=True, text=True)


def write_env(path):
    """A tiny lat-long map: dim blue sky with a bright warm patch on one side."""
    import OpenImageIO as oiio
    h, w = 16, 32
    env = np.zeros((h, w, 3), np.float32)
    env[...] = (0.2, 0.3, 0.5)
    env[2:8, 4:10] = (8.0, 6.0, 3.0)
    spec = oiio.ImageSpec(w, h, 3, oiio.FLOAT)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(env), out.geterror()
    out.close()


def test_batch_relight_resume_and_contact_sheet(tmp):
    for f in (1, 2):
        shutil.copy(ROOM, tmp / f"shot.{f:04d}.exr")
        shutil.copy(SAMPLES / "room.json", tmp / f"shot.{f:04d}.json")
    env = tmp / "studio.exr"
    write_env(env)
    out = tmp / "out"
    args = [tmp / "shot.####.exr", "-o", out, "--env", env, "--rotations", "0,180", "--set", "samples=16"]
    proc = run("batch_relight.py", *args)
    assert proc.returncode == 0, proc.stderr
    assert "0 complete, 4 to do" in proc.stderr and "[4/4]" in proc.stderr and "eta" in proc.stderr
    manifest = json.loads((out / "batch.json").read_text())
    assert [v["name"] for v in manifest["variants"]] == ["studio.r0", "studio.r180"]
    for name in ("studio.r0", "studio.r180"):
        for f in (1, 2):
            path = out / name / f"shot.{f:04d}.exr"
            report = json.loads(path.with_suffix(".json").read_text())
            assert {"Relit.R", "obscura.DO.G", "obscura.GI.B"} <= set(report["written"])
            assert any("environment" in step for step in report["plan"])
    r0 = rgb(out / "studio.r0" / "shot.0001.exr", "Relit")
    r180 = rgb(out / "studio.r180" / "shot.0001.exr", "Relit")
    assert np.isfinite(r0).all() and r0.max() > 0
    assert np.abs(r0 - r180).mean() > 1e-3 * r0.mean()  # turning the map changes the light

    # --resume: nothing to do; a removed frame is redone; missing frames fail, are listed, exit 1.
    proc = run("batch_relight.py", *args, "--resume")
    assert proc.returncode == 0 and "4 complete, 0 to do" in proc.stderr, proc.stderr
    os.remove(out / "studio.r180" / "shot.0002.exr")
    proc = run("batch_relight.py", *args, "--resume", "--frames", "1-3")
    assert proc.returncode == 1
    assert "3 complete, 3 to do" in proc.stderr, proc.stderr
    assert "1 written" in proc.stderr and "2 failed" in proc.stderr
    assert "failed:" in proc.stderr and "studio.r0 frame 3" in proc.stderr and "studio.r180 frame 3" in proc.stderr
    proc = run("batch_relight.py", tmp / "shot.####.exr", "-o", out, "--rotations", "0,90")
    assert proc.returncode == 2 and "give --env FILE" in proc.stderr

    sheet = tmp / "sheet.png"
    proc = run("contact_sheet.py", out, "--frame", 1, "-o", sheet)
    assert proc.returncode == 0, proc.stderr
    assert "2 tile(s)" in proc.stderr
    data = sheet.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[25] == 2  # IHDR colour type 2: RGB


def test_read_passes_up_lights_arrays_as_process_does(tmp):
    """room.exr is Blender's (Z up): read_passes says so, and compute_ssdo given that up lights the
    arrays with an environment map exactly as process() lights the file."""
    import OpenImageIO as oiio
    h, w = 16, 32
    env = np.zeros((h, w, 3), np.float32)
    env[..., 0] = np.linspace(0.0, 2.0, w)[None, :]
    env[..., 2] = np.linspace(0.0, 1.0, h)[:, None] ** 2
    path = tmp / "env.exr"
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(w, h, 3, oiio.FLOAT)) and out.write_image(env)
    out.close()
    p = obscura.read_passes(ROOM)
    assert p["up"] == "z"
    arrays = obscura.compute_ssdo(p["depth"], p["normal"], camera=p["camera"], environment=env, up=p["up"], **FAST)
    obscura.process(ROOM, tmp / "o.exr", method="ssdo", env=str(path), out_type="float", **FAST)
    written = rgb(tmp / "o.exr", "obscura.DO")
    assert np.abs(arrays["do"] - written).max() < 1e-5
    other = obscura.compute_ssdo(p["depth"], p["normal"], camera=p["camera"], environment=env, up="y", **FAST)
    assert np.abs(other["do"] - written).max() > 0.01  # the axis matters on this map
