"""What a new user meets first: inspect() is the CLI's --inspect --json, a missing or wrong
argument is one line naming it, and process(bounce=True) writes the layers its docstring lists."""
import json
import subprocess

import numpy as np
import pytest

import obscura
from conftest import CLI, SAMPLES, read_channel, synthetic_scene, write_exr

ROOM = SAMPLES / "room.exr"
FAST = dict(samples=16)


def cli_inspect_json(path):
    proc = subprocess.run([CLI, str(path), "--inspect", "--json"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


# ------------------------------------------------------------------------------------------
# inspect


def test_inspect_equals_cli_json_with_a_camera():
    info = obscura.inspect(ROOM)
    assert info == cli_inspect_json(ROOM)
    assert info["preset"] == "blender"
    assert info["roles"]["depth"] == ["ViewLayer.Depth.Z"]
    assert info["display_window"] == [0, 0, 320, 320]
    assert {"name": "ViewLayer.AO", "part": 0, "part_name": "", "channels": ["R", "G", "B"],
            "type": "float"} in info["layers"]
    cam = info["camera"]
    assert cam["source"].startswith("sidecar:") and info["camera_error"] is None
    # The same camera as read_passes finds, in the same row-major convention.
    passes = obscura.read_passes(ROOM)
    np.testing.assert_allclose(cam["camera_to_world"], passes["camera"].camera_to_world)
    assert cam["fx"] == pytest.approx(passes["camera"].fx)


def test_inspect_equals_cli_json_without_a_camera(tmp):
    depth, normal = synthetic_scene(32, 24)
    path = tmp / "nocam.exr"
    write_exr(path, depth, normal)  # no sidecar, no position pass: nothing gives a camera
    info = obscura.inspect(path)
    assert info == cli_inspect_json(path)
    assert info["camera"] is None and info["camera_error"]
    assert info["roles"]["albedo"] is None  # a role the file lacks is listed, as null
    # The CLI's text is printed from the same structure.
    text = subprocess.run([CLI, str(path), "--inspect"], capture_output=True, text=True).stdout
    assert f"camera:  none ({info['camera_error']})" in text
    assert "albedo: (not found)" in text


def test_json_without_inspect_is_refused(tmp):
    proc = subprocess.run([CLI, str(ROOM), "-o", str(tmp / "o.exr"), "--json"], capture_output=True, text=True)
    assert proc.returncode == 2 and "--json" in proc.stderr
    assert not (tmp / "o.exr").exists()


# ------------------------------------------------------------------------------------------
# One line naming the argument

DEPTH = np.ones((40, 40), np.float32)
NORMAL = np.zeros((40, 40, 3), np.float32)
CAM = obscura.Camera.perspective(40, 40, 40)

CALLS = [
    ("compute_ao", lambda: obscura.compute_ao(DEPTH, NORMAL), TypeError, "camera"),
    ("compute_ao", lambda: obscura.compute_ao(DEPTH, NORMAL, CAM), TypeError, "by keyword"),
    ("compute_ao", lambda: obscura.compute_ao(DEPTH, camera=CAM), TypeError, "normal"),
    ("compute_ao", lambda: obscura.compute_ao([[1.0]], NORMAL, camera=CAM), TypeError, "depth"),
    ("compute_ao", lambda: obscura.compute_ao(DEPTH, NORMAL, camera="cam.json"), TypeError, "camera"),
    ("compute_ao", lambda: obscura.compute_ao(DEPTH, NORMAL.astype(np.float64), camera=CAM), ValueError, "normal"),
    ("compute_ssdo", lambda: obscura.compute_ssdo(DEPTH, NORMAL), TypeError, "camera"),
    ("compute_ssdo", lambda: obscura.compute_ssdo(DEPTH, NORMAL, camera=CAM, radiance_=NORMAL), TypeError,
     "radiance_"),
    ("compute_ssdo", lambda: obscura.compute_ssdo(DEPTH, NORMAL, camera=CAM, normals="camera", radiance=DEPTH), ValueError,
     "radiance"),
    ("compute_gi", lambda: obscura.compute_gi(DEPTH, NORMAL), TypeError, "camera"),
    ("compute_gi", lambda: obscura.compute_gi(DEPTH, NORMAL, camera=CAM, radiance_=NORMAL), TypeError, "radiance_"),
    ("compute_gi", lambda: obscura.compute_gi(DEPTH, NORMAL, camera=CAM, normals="camera", radiance=DEPTH), ValueError,
     "radiance"),
    ("ao_from_passes", lambda: obscura.ao_from_passes(), TypeError, "passes"),
    ("ao_from_passes", lambda: obscura.ao_from_passes(DEPTH), TypeError, "passes"),
    ("ao_from_passes", lambda: obscura.ao_from_passes({"depth": DEPTH}), ValueError, "normal"),
    ("process", lambda: obscura.process(ROOM), TypeError, "out"),
    ("process", lambda: obscura.process(ROOM, "o.exr", "ssdo"), TypeError, "by keyword"),
    ("process", lambda: obscura.process(ROOM, "o.exr", radius="big"), TypeError, "radius"),
    ("inspect", lambda: obscura.inspect(), TypeError, "path"),
    ("inspect", lambda: obscura.inspect(ROOM, presett="blender"), TypeError, "presett"),
    ("read_layer", lambda: obscura.read_layer(ROOM), TypeError, "name"),
    ("read_layer", lambda: obscura.read_layer(ROOM, 3), TypeError, "name"),
    ("read_passes", lambda: obscura.read_passes(), TypeError, "path"),
    ("read_passes", lambda: obscura.read_passes(ROOM, "blender"), TypeError, "by keyword"),
    ("read_passes", lambda: obscura.read_passes(ROOM, layer=["normal"]), TypeError, "layer"),
]


@pytest.mark.parametrize("name,call,error,names", CALLS, ids=[f"{c[0]}-{i}" for i, c in enumerate(CALLS)])
def test_bad_argument_is_one_line_naming_it(name, call, error, names):
    with pytest.raises(error) as e:
        call()
    message = str(e.value)
    assert "\n" not in message, message
    assert "incompatible function arguments" not in message
    assert names in message, message
    assert len(message) < 300, message


def test_missing_arguments_name_the_function():
    with pytest.raises(TypeError, match=r"^compute_ao\(\) needs camera=: an obscura\.Camera"):
        obscura.compute_ao(DEPTH, NORMAL)
    with pytest.raises(TypeError, match=r"^process\(\) needs path"):
        obscura.process(out="o.exr")


def test_errors_name_keywords_not_flags(tmp):
    """The file pipeline's messages are the CLI's; Python's say what to pass as a keyword."""
    cases = [
        (dict(method="rtao", device="gl"), "method='rtao' runs on the CPU only; use device='cpu'"),
        (dict(layer={"normal": "Nope"}), "layer={'normal': 'Nope'}: no layer or channel 'Nope'"),
        (dict(layer={"depth": "View Layer.Depth"}), "layer={'depth': 'View Layer.Depth'}: no layer or channel"),
        (dict(layer={"depth": "BG-plate.Z"}), "layer={'depth': 'BG-plate.Z'}: no layer or channel"),
    ]
    for kwargs, said in cases:
        with pytest.raises(obscura.Error) as e:
            obscura.process(ROOM, tmp / "o.exr", **kwargs)
        assert said in str(e.value) and "--" not in str(e.value), str(e.value)
    # A path is quoted as it is, dashes and all.
    odd = tmp / "--takes" / "shot--v2.exr"
    with pytest.raises(obscura.Error, match="shot--v2.exr': cannot open"):
        obscura.process(odd, tmp / "o.exr")
    spaced = tmp / "shots --radius 2" / "x.exr"
    with pytest.raises(obscura.Error) as e:
        obscura.process(spaced, tmp / "o.exr")
    assert str(e.value).startswith(f"'{spaced}': cannot open"), str(e.value)
    depth, normal = synthetic_scene(32, 24)
    nocam = tmp / "nocam.exr"
    write_exr(nocam, depth, normal)
    error = obscura.read_passes(nocam)["camera_error"]
    assert "give fov_deg, focal_mm with aperture_mm, or ortho_width" in error and "--" not in error, error


# ------------------------------------------------------------------------------------------
# process(bounce=True) writes what it asks for


def rgb(path, layer):
    return np.stack([read_channel(path, f"{layer}.{c}") for c in "RGB"], axis=-1)


def channels(layers):
    return {f"{layer}.{c}" for layer in layers for c in "RGB"}


def test_bounce_writes_gi_and_relit(tmp):
    out = tmp / "relit.exr"
    report = obscura.process(ROOM, out, method="ssdo", bounce=True, out_type="float", **FAST)
    written = set(report["written"])
    assert written == channels(["obscura.DO", "obscura.GI", "obscura.relit"]) | {"obscura.AO.Y"}
    assert report["output_channels"]["relit"] == "obscura.relit"
    # relit is albedo x (DO + GI) / pi, from the layers in the same file.
    albedo = rgb(ROOM, "ViewLayer.DiffCol")
    expected = albedo * (rgb(out, "obscura.DO") + rgb(out, "obscura.GI")) / np.pi
    np.testing.assert_allclose(rgb(out, "obscura.relit"), expected, rtol=1e-5, atol=1e-6)
    assert rgb(out, "obscura.relit").max() > 0


def test_cli_bounce_writes_the_same_layers(tmp):
    out, rep = tmp / "cli.exr", tmp / "cli.json"
    proc = subprocess.run([CLI, str(ROOM), "-o", str(out), "--method", "ssdo", "--bounce", "--samples", "16",
                           "--report", str(rep), "--quiet"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    py = obscura.process(ROOM, tmp / "py.exr", method="ssdo", bounce=True, **FAST)
    assert json.loads(rep.read_text())["written"] == py["written"]


def test_naming_gi_alone_writes_no_relit(tmp):
    report = obscura.process(ROOM, tmp / "gi.exr", method="ssdo", out_layer={"gi": "obscura.GI"}, **FAST)
    written = set(report["written"])
    assert channels(["obscura.GI"]) <= written
    assert not any(c.startswith("obscura.relit") for c in written), written
    report = obscura.process(ROOM, tmp / "do.exr", method="ssdo", **FAST)
    assert set(report["written"]) == channels(["obscura.DO"]) | {"obscura.AO.Y"}


def write_beauty_without_albedo(path):
    """A generic-preset EXR with depth, normals and a beauty (R, G, B), but no albedo pass."""
    import OpenImageIO as oiio
    write_exr(path, *synthetic_scene(32, 24), sidecar=True)
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = inp.spec(), inp.read_image(oiio.FLOAT)
    inp.close()
    beauty = np.full(pixels.shape[:2] + (3,), 0.5, np.float32)
    spec = oiio.ImageSpec(spec.width, spec.height, 7, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "N.X", "N.Y", "N.Z", "Z")
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(np.concatenate([beauty, pixels], axis=-1)), out.geterror()
    out.close()


def test_bounce_without_albedo_says_how_to_get_gi_alone(tmp):
    src, out = tmp / "beauty.exr", tmp / "o.exr"
    write_beauty_without_albedo(src)
    with pytest.raises(obscura.Error, match=r"no albedo layer.*out_layer=\{'gi': NAME\} in place of bounce=True"):
        obscura.process(src, out, method="ssdo", bounce=True, bounce_source="beauty", **FAST)
    assert not out.exists()
    report = obscura.process(src, out, method="ssdo", bounce_source="beauty", out_layer={"gi": "obscura.GI"}, **FAST)
    assert channels(["obscura.GI"]) <= set(report["written"])
