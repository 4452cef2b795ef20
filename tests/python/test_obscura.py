"""The obscura Python module: parity with the CLI, argument checking, zero-copy views, files."""
import json
import os
import threading
import time
import tracemalloc

import numpy as np
import pytest

import obscura
from conftest import (CLI, FOV_DEG, SAMPLES, cli_matrix, pose_matrix, read_channel, run_cli, synthetic_scene,
                      write_exr)

ROOM = SAMPLES / "room.exr"


def camera(width=96, height=64):
    return obscura.Camera.perspective(FOV_DEG, width, height, camera_to_world=pose_matrix())


# Each case: keyword arguments of compute_ao, and the same as CLI flags (in the CLI's order).
CASES = {
    "defaults": ({}, []),
    "cosine-none-blur": (dict(radius=0.7, directions=6, steps=5, weighting="cosine", falloff="none", blur=2),
                         ["--radius", 0.7, "--directions", 6, "--steps", 5, "--weighting", "cosine",
                          "--falloff", "none", "--blur", 2]),
    "quality-low-steps": (dict(quality="low", steps=6, radius=1.5), ["--quality", "low", "--steps", 6, "--radius", 1.5]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_compute_ao_matches_cli_exactly(tmp, case):
    kwargs, flags = CASES[case]
    depth, normal = synthetic_scene()
    src, out = tmp / "scene.exr", tmp / "scene_ao.exr"
    write_exr(src, depth, normal)
    run_cli(src, "-o", out, "--preset", "generic", "--fov-deg", FOV_DEG, "--camera-to-world",
            cli_matrix(pose_matrix()), "--out-type", "float", "--quiet", *flags)
    expected = read_channel(out, "obscura.AO.Y")

    ao = obscura.compute_ao(depth, normal, camera=camera(), **kwargs)
    assert ao.shape == depth.shape and ao.dtype == np.float32
    assert ao.flags.c_contiguous
    np.testing.assert_array_equal(ao, expected)
    assert 0.0 <= ao.min() < 0.999 and ao.max() <= 1.0  # the scene does occlude something
    assert np.all(ao[:6, :48] == 1.0)                    # sky pixels


def test_process_matches_cli_and_returns_report(tmp):
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal, sidecar=True)        # camera from scene.json, as the CLI finds it
    cli_out, py_out, report_path = tmp / "cli.exr", tmp / "py.exr", tmp / "py.json"
    run_cli(src, "-o", cli_out, "--radius", 0.8, "--weighting", "cosine", "--out-type", "float", "--quiet")
    report = obscura.process(src, py_out, radius=0.8, weighting="cosine", out_type="float", report=report_path)
    assert py_out.exists()
    np.testing.assert_array_equal(read_channel(py_out, "obscura.AO.Y"), read_channel(cli_out, "obscura.AO.Y"))
    assert report["settings"]["radius"] == pytest.approx(0.8)
    assert report["settings"]["weighting"] == "cosine"
    assert report["output_channels"] == {"ao": "obscura.AO.Y"}
    assert report["camera"]["source"].startswith("sidecar:")
    assert report["stats"]["pixels"] == depth.size
    assert report["stats"]["sky_pixels"] == 6 * 48
    assert {"read", "camera", "compute", "write"} <= set(report["timings_s"])
    assert json.loads(report_path.read_text()) == report
    # The passes of the same file through the arrays path give the same AO.
    passes = obscura.read_passes(src)
    np.testing.assert_array_equal(obscura.ao_from_passes(passes, radius=0.8, weighting="cosine"),
                                  read_channel(py_out, "obscura.AO.Y"))


def test_process_options(tmp):
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal)
    out, preview = tmp / "out.exr", tmp / "out.png"
    report = obscura.process(str(src), str(out), fov_deg=FOV_DEG, camera_to_world=pose_matrix().reshape(-1),
                             preset="generic", out_layer={"ao": "occ"}, preview=preview, quality="low", threads=1)
    assert report["output_channels"] == {"ao": "occ.Y"}
    assert report["settings"]["directions"] == 4 and report["settings"]["threads"] == 1
    assert preview.exists() and preview.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert obscura.read_layer(out, "occ").shape == depth.shape
    with pytest.raises(ValueError, match="is the same file as the input"):
        obscura.process(src, src)


def test_quality_sets_what_the_keywords_do_not(tmp):
    """ssdo's levels are its sample counts, its blur stays the interleaving block's; a keyword wins."""
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal)
    common = dict(fov_deg=FOV_DEG, camera_to_world=pose_matrix().reshape(-1), preset="generic", threads=1)
    for level, samples in (("low", 16), ("high", 256)):
        report = obscura.process(str(src), str(tmp / f"{level}.exr"), method="ssdo", quality=level, **common)
        assert report["settings"]["ssdo"]["samples"] == samples and report["settings"]["blur"] == 2
    report = obscura.process(str(src), str(tmp / "own.exr"), method="ssdo", quality="low", samples=32, **common)
    assert report["settings"]["ssdo"]["samples"] == 32
    report = obscura.process(str(src), str(tmp / "blur.exr"), quality="low", blur=3, **common)
    assert report["settings"]["blur"] == 3 and report["settings"]["directions"] == 4


def copy_and(tmp, mode):
    """The synthetic scene (with its sidecar) written with write='copy' and with `mode`:
    (input, depth, the copy, the other output, its report)."""
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal, sidecar=True)
    copy, out = tmp / "copy.exr", tmp / f"{mode}.exr"
    obscura.process(src, copy, radius=0.8)
    report = obscura.process(src, out, radius=0.8, write=mode)
    assert report["write"]["mode"] == mode
    return src, depth, copy, out, report


def test_process_write_new_holds_only_the_new_layers(tmp):
    src, depth, copy, new, report = copy_and(tmp, "new")
    import OpenImageIO as oiio
    spec = oiio.ImageInput.open(str(new)).spec()
    assert list(spec.channelnames) == ["obscura.AO.Y"]
    assert (spec.full_width, spec.full_height) == (depth.shape[1], depth.shape[0])
    np.testing.assert_array_equal(read_channel(new, "obscura.AO.Y"), read_channel(copy, "obscura.AO.Y"))
    with pytest.raises(ValueError, match="write must be one of"):
        obscura.process(src, tmp / "o.exr", write="layers")
    with pytest.raises(ValueError, match="in_place"):
        obscura.process(src, src, write="new", in_place=True)
    assert not (tmp / "o.exr").exists()


def test_process_write_append_copies_the_input_and_adds_a_part(tmp):
    import OpenImageIO as oiio
    src, depth, copy, appended, report = copy_and(tmp, "append")
    assert {"read", "compute", "copy", "append"} <= set(report["timings_s"]) and "write" not in report["timings_s"]
    inp = oiio.ImageInput.open(str(appended))
    first = list(inp.spec().channelnames)
    assert inp.seek_subimage(1, 0) and list(inp.spec().channelnames) == ["obscura.AO.Y"]
    assert inp.spec().getattribute("name") == "obscura" and not inp.seek_subimage(2, 0)
    inp.close()
    assert sorted(first) == ["N.X", "N.Y", "N.Z", "Z"]  # OpenImageIO lists Z first
    for name in first:
        np.testing.assert_array_equal(read_channel(appended, name), read_channel(src, name))
    ao = oiio.ImageBuf(str(appended), 1, 0)
    np.testing.assert_array_equal(ao.get_pixels(oiio.FLOAT)[..., 0], read_channel(copy, "obscura.AO.Y"))
    # In place: the file becomes itself plus the AO part.
    obscura.process(src, src, radius=0.8, write="append", in_place=True)
    assert oiio.ImageInput.open(str(src)).seek_subimage(1, 0)


def test_huge_window_in_a_header_is_refused_before_allocating(tmp):
    import struct
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal, sidecar=True)
    data = bytearray(src.read_bytes())
    at = data.index(b"dataWindow\0box2i\0") + len(b"dataWindow\0box2i\0") + 4  # past the attribute size
    data[at:at + 16] = struct.pack("<4i", 0, 0, 99999, 99999)
    src.write_bytes(bytes(data))
    for call in (lambda: obscura.read_passes(src), lambda: obscura.process(src, tmp / "o.exr")):
        with pytest.raises(obscura.Error, match=r"data window \[0,0 - 99999,99999\] holds .*max_pixels"):
            call()
    assert not (tmp / "o.exr").exists()


def test_read_passes_room_sample():
    p = obscura.read_passes(ROOM)
    assert p["depth"].shape == (320, 320) and p["depth"].dtype == np.float32
    assert p["normal"].shape == (320, 320, 3) and p["normal"].dtype == np.float32
    assert p["position"].shape == (320, 320, 3)
    assert p["preset"] == "blender"
    assert p["layers"]["depth"] == ["ViewLayer.Depth.Z"]
    assert p["data_window"] == (0, 0, 320, 320) and p["display_window"] == (0, 0, 320, 320)
    assert p["normals"] == "world" and p["depth_kind"] == "planar"
    cam = p["camera"]
    assert isinstance(cam, obscura.Camera) and cam.has_pose and cam.source.startswith("sidecar:")
    side = obscura.Camera.from_sidecar(SAMPLES / "room.json", 320, 320)
    assert side.fx == cam.fx and np.array_equal(side.camera_to_world, cam.camera_to_world)
    n = np.linalg.norm(p["normal"], axis=-1)
    surface = (p["depth"] > 0) & (p["depth"] < p["sky_depth"])
    assert surface.any() and abs(np.median(n[surface]) - 1.0) < 0.02  # unit, but averaged at edges
    # The planes match an independent reader.
    np.testing.assert_array_equal(p["depth"], read_channel(ROOM, "ViewLayer.Depth.Z"))


def test_room_arrays_match_process_and_cli(tmp):
    settings = dict(radius=1.0, weighting="cosine", falloff="none")
    p = obscura.read_passes(ROOM)
    ao = obscura.ao_from_passes(p, **settings)
    report = obscura.process(ROOM, tmp / "room_ao.exr", out_type="float", reference="ViewLayer.AO", **settings)
    np.testing.assert_array_equal(ao, obscura.read_layer(tmp / "room_ao.exr", "obscura.AO.Y"))
    run_cli(ROOM, "-o", tmp / "room_cli.exr", "--radius", 1, "--weighting", "cosine", "--falloff", "none",
            "--out-type", "float", "--quiet")
    np.testing.assert_array_equal(ao, read_channel(tmp / "room_cli.exr", "obscura.AO.Y"))
    ref = report["reference"]
    assert ref["layer"] == "ViewLayer.AO" and 18.0 < ref["psnr_db"] < 40.0


def test_read_layer(tmp):
    n = obscura.read_layer(ROOM, "ViewLayer.Normal")
    assert n.shape == (320, 320, 3)
    np.testing.assert_array_equal(n, obscura.read_passes(ROOM)["normal"])
    assert obscura.read_layer(ROOM, "ViewLayer.Depth.Z").shape == (320, 320)
    with pytest.raises(obscura.Error, match="no channel or layer 'nope'"):
        obscura.read_layer(ROOM, "nope")


# ---------------------------------------------------------------------------------------------
# Argument checking

@pytest.fixture
def scene():
    depth, normal = synthetic_scene()
    return depth, normal, camera()


@pytest.mark.parametrize("bad", [
    lambda d, n: (d, n[..., 0]),                         # 2-D normal
    lambda d, n: (d, n[..., :2]),                        # 2 components
    lambda d, n: (d[..., None], n),                      # 3-D depth
    lambda d, n: (d[:-1], n),                            # mismatched sizes
    lambda d, n: (d, n[:, :-1]),
    lambda d, n: (d[:0], n[:0]),                         # empty
    lambda d, n: (d.astype(np.float64), n),              # dtypes
    lambda d, n: (d, n.astype(np.float64)),
    lambda d, n: (np.ones(d.shape, np.int32), n),
    lambda d, n: (d, n.astype(np.float16)),
    lambda d, n: (d.astype(">f4"), n),                   # byte-swapped float32
    lambda d, n: (d, np.ascontiguousarray(np.moveaxis(n, -1, 0)).transpose(1, 2, 0)),  # planar components
], ids=["normal-2d", "normal-2ch", "depth-3d", "rows", "cols", "empty", "depth-f64", "normal-f64",
        "depth-int", "normal-f16", "depth-bigendian", "normal-planar"])
def test_bad_arrays_raise_value_error(scene, bad):
    depth, normal, cam = scene
    d, n = bad(depth, normal)
    with pytest.raises(ValueError) as e:
        obscura.compute_ao(d, n, camera=cam)
    assert "\n" not in str(e.value)


def test_messages_say_what_is_expected(scene):
    depth, normal, cam = scene
    with pytest.raises(ValueError, match=r"normal must have shape \(H, W, 3\), got \(64, 96\)"):
        obscura.compute_ao(depth, normal[..., 0], camera=cam)
    with pytest.raises(ValueError, match=r"depth must have dtype float32.*got float64.*astype"):
        obscura.compute_ao(depth.astype(np.float64), normal, camera=cam)
    with pytest.raises(ValueError, match="same size"):
        obscura.compute_ao(depth[1:], normal, camera=cam)
    with pytest.raises(TypeError, match="numpy.ndarray"):
        obscura.compute_ao(depth.tolist(), normal, camera=cam)


@pytest.mark.parametrize("kwargs, match", [
    (dict(radius=0), "radius must be above 0 and at most"),
    (dict(radius=-1.0), "radius must be above 0 and at most"),
    (dict(radius=float("nan")), "radius must be finite"),
    (dict(directions=0), "directions must be between 1 and 256"),
    (dict(steps=1000), "steps must be between 1 and 256"),
    (dict(blur=-1), "blur must be a whole number at least 0 and at most 64"),
    (dict(threads=-2), "threads must be a whole number at least 0 and at most"),
    (dict(weighting="cos"), "weighting must be 'uniform' or 'cosine'"),
    (dict(falloff="exp"), "falloff must be 'linear' or 'none'"),
    (dict(quality="max"), "quality must be"),
    (dict(method="nope"), "method must be one of .hbao."),
    (dict(device="cuda"), "device must be"),
    (dict(normals="object"), "normals must be 'world', 'camera' or 'depth'"),
    (dict(depth_kind="z"), "depth_kind must be 'planar' or 'radial'"),
    (dict(sky_depth=0.0), "sky_depth must be above 0"),
    (dict(data_window=(0, 0, 10, 10)), "data_window is 10x10"),
    (dict(data_window=(0, 0, 1)), "data_window must be"),
    (dict(method="rtao", thickness=-1.0), r"thickness must be between 0 and 1e\+30"),
    (dict(method="rtao", rtao_grid=0), "rtao_grid must be between 1 and 64"),
    (dict(method="ssao", ssao_samples=0), "ssao_samples must be between 1 and 1024"),
])
def test_bad_settings_raise_value_error(scene, kwargs, match):
    depth, normal, cam = scene
    with pytest.raises(ValueError, match=match):
        obscura.compute_ao(depth, normal, camera=cam, **kwargs)


def test_method_keywords_come_from_the_method_table(scene, tmp):
    """Every method of obscura.METHODS runs through compute_ao / process with its own keywords."""
    depth, normal, cam = scene
    assert {"hbao", "ssdo", "ssao", "rtao"} <= set(obscura.METHODS)
    assert obscura.METHODS["rtao"]["devices"] == ["cpu"]
    assert obscura.METHODS["ssao"]["params"]["ssao_samples"] == (1.0, 1024.0)
    for method, own in [("ssao", dict(ssao_samples=8, ssao_hemisphere=True)),
                        ("rtao", dict(rtao_rays=8, thickness=0.2, rtao_grid=2))]:
        ao = obscura.compute_ao(depth, normal, camera=cam, method=method, radius=0.5, **own)
        assert np.all(np.isfinite(ao)) and ao.min() >= 0 and ao.max() <= 1 and ao.min() < 0.9
    report = obscura.process(ROOM, tmp / "rtao.exr", method="rtao", rtao_rays=4, thickness=0.1, out_type="float")
    assert report["settings"]["thickness"] == pytest.approx(0.1) and report["settings"]["rtao_rays"] == 4
    # hbao and rtao share one thickness, a number of world units or a word.
    assert obscura.METHODS["hbao"]["params"]["thickness"] == obscura.METHODS["rtao"]["params"]["thickness"]
    for word in ["auto", "inf"]:
        report = obscura.process(ROOM, tmp / "hbao.exr", thickness=word, quality="low", out_type="float")
        assert report["settings"]["thickness"] == word
    with pytest.raises(ValueError, match=r"thickness must be between 0 and 1e\+30, or auto, or inf"):
        obscura.compute_ao(depth, normal, camera=cam, thickness="thick")
    with pytest.raises(TypeError, match="unexpected keyword argument 'thicknes'"):
        obscura.compute_ao(depth, normal, camera=cam, method="rtao", thicknes=0.1)
    with pytest.raises(TypeError, match="ssao_hemisphere must be True or False, got int"):
        obscura.compute_ao(depth, normal, camera=cam, method="ssao", ssao_hemisphere=1)


def test_wrong_types_raise_type_error(scene):
    depth, normal, cam = scene
    with pytest.raises(TypeError):
        obscura.compute_ao(depth, normal, camera=cam, directions=2.5)
    with pytest.raises(TypeError):
        obscura.compute_ao(depth, normal, camera="room.json")
    with pytest.raises(TypeError):
        obscura.compute_ao(depth, normal)                       # camera is required
    with pytest.raises(TypeError):
        obscura.compute_ao(depth, normal, camera=cam, radiuss=1)  # unknown keyword


def test_camera_checks(scene):
    depth, normal, _ = scene
    unposed = obscura.Camera.perspective(FOV_DEG, 96, 64)
    with pytest.raises(ValueError, match="needs the camera's pose"):
        obscura.compute_ao(depth, normal, camera=unposed)
    # Camera-space normals need no pose.
    n_cam = (normal.reshape(-1, 3) @ pose_matrix()[:3, :3]).reshape(normal.shape).astype(np.float32)
    a = obscura.compute_ao(depth, n_cam, camera=unposed, normals="camera")
    b = obscura.compute_ao(depth, normal, camera=camera())
    assert np.abs(a - b).max() < 1e-3
    with pytest.raises(ValueError, match="fov_deg must be between 0 and 180"):
        obscura.Camera.perspective(180, 96, 64)
    with pytest.raises(ValueError, match="camera_to_world must be a 4x4"):
        obscura.Camera.perspective(40, 96, 64, camera_to_world=np.eye(3))
    with pytest.raises(ValueError, match="camera_to_world"):
        obscura.Camera.perspective(40, 96, 64, camera_to_world=np.zeros((4, 4)))
    with pytest.raises(ValueError, match="width must be between 1 and"):
        obscura.Camera.orthographic(2.0, 0, 64)
    # A camera made for another frame (its principal point elsewhere) is refused, on every array
    # function; one made for the display window given beside an overscan is taken.
    other = obscura.Camera.perspective(FOV_DEG, 960, 640)
    for f in (obscura.compute_ao, obscura.compute_ssdo):
        with pytest.raises(ValueError, match="camera was made for a 960x640 display window but the display "
                                             "window is 96x64"):
            f(depth, n_cam, camera=other, normals="camera")
    inner = obscura.Camera.perspective(FOV_DEG, 90, 60)
    c = obscura.compute_ao(depth, n_cam, camera=inner, normals="camera", data_window=(-3, -2, 93, 62),
                           display_window=(0, 0, 90, 60))
    assert c.shape == depth.shape and np.isfinite(c).all()


def test_windows_may_be_an_exr_headers(scene):
    """display_window and data_window in a header's absolute pixels: the camera counts from the
    display window's corner, so moving both by one offset is the same frame, and moving the display
    window alone moves the image against the camera."""
    depth, normal, _ = scene
    cam = camera()
    at_zero = obscura.compute_ao(depth, normal, camera=cam)
    moved = obscura.compute_ao(depth, normal, camera=cam, display_window=(10, 20, 106, 84), data_window=(10, 20, 106, 84))
    assert np.array_equal(at_zero, moved)
    defaulted = obscura.compute_ao(depth, normal, camera=cam, display_window=(10, 20, 106, 84))
    assert np.array_equal(at_zero, defaulted)  # the arrays cover the display window by default
    shifted = obscura.compute_ao(depth, normal, camera=cam, display_window=(10, 20, 106, 84), data_window=(0, 0, 96, 64))
    assert not np.array_equal(at_zero, shifted)


def test_camera_pickles_copies_and_compares(tmp):
    """Dask and multiprocessing send read_passes() dicts, camera included, by pickle."""
    import copy
    import pickle
    posed = camera()
    for cam in (posed, obscura.Camera.orthographic(3.0, 96, 64), obscura.read_passes(ROOM)["camera"],
                obscura.Camera(100.0, cx=48.0, cy=32.0, orthographic=True)):
        back = pickle.loads(pickle.dumps(cam))
        assert back == cam and copy.deepcopy(cam) == cam
        assert (back.projection, back.fx, back.fy, back.cx, back.cy, back.source, back.display_size) == \
            (cam.projection, cam.fx, cam.fy, cam.cx, cam.cy, cam.source, cam.display_size)
        assert (back.camera_to_world is None) == (cam.camera_to_world is None)
    assert obscura.Camera.perspective(FOV_DEG, 96, 64) != posed
    assert posed != "a camera"
    assert "display=96x64" in repr(posed) and "camera_to_world=[" in repr(posed)
    passes = pickle.loads(pickle.dumps(obscura.read_passes(ROOM)))
    assert passes["camera"] == obscura.read_passes(ROOM)["camera"]


def test_arguments_are_taken_as_they_are_meant(scene, tmp):
    """A truthy word is not True, True is not 1.0, an int past 64 bits is a ValueError, and a
    camera's bad argument is one line naming it; a path that is not UTF-8 is said, not cast."""
    depth, normal, _ = scene
    cam = camera()
    with pytest.raises(TypeError, match="bounce must be True or False, got str"):
        obscura.compute_ssdo(depth, normal, camera=cam, bounce="no")
    obscura.compute_ssdo(depth, normal, camera=cam, bounce=np.bool_(False), samples=16)
    with pytest.raises(TypeError, match="radius must be a number, got bool"):
        obscura.compute_ao(depth, normal, camera=cam, radius=True)
    with pytest.raises(ValueError, match="directions is out of range"):
        obscura.compute_ao(depth, normal, camera=cam, directions=2**70)
    for call, match in [(lambda: obscura.Camera.perspective(50, 64.0, 64), "width must be an int, got float"),
                        (lambda: obscura.Camera.film_back("35", 36, 64, 64), "focal_mm must be a number, got str"),
                        (lambda: obscura.Camera(10.0, cx=1, cy=1, orthographic="yes"), "orthographic must be True or False"),
                        (lambda: cam.horizontal_fov_deg(0), "width must be between 1 and")]:
        with pytest.raises((TypeError, ValueError), match=match) as e:
            call()
        assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match="is not UTF-8"):
        obscura.read_passes(bytes(tmp) + b"/caf\xe9.exr")


def test_ssdo_says_the_sample_count_it_runs(scene):
    """SSDO's N samples are N / 4 directions, one at least per pixel of the interleave block: a
    count that runs as another is said, and runs exactly as that one."""
    import warnings
    depth, normal, _ = scene
    cam = camera()
    with pytest.warns(RuntimeWarning, match=r"samples=8 runs as 16 \(4 samples a direction"):
        eight = obscura.compute_ssdo(depth, normal, camera=cam, samples=8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sixteen = obscura.compute_ssdo(depth, normal, camera=cam, samples=16)
    assert np.array_equal(eight["do"], sixteen["do"])
    with pytest.warns(RuntimeWarning, match="samples=18 runs as 16"):
        obscura.compute_ssdo(depth, normal, camera=cam, samples=18, interleave=1)


def test_camera_properties():
    m = pose_matrix()
    c = obscura.Camera.perspective(60.0, 200, 100, camera_to_world=m)
    assert c.projection == "perspective" and c.has_pose
    assert c.fx == pytest.approx(100 / np.tan(np.radians(30))) and c.fy == c.fx
    assert (c.cx, c.cy) == (100.0, 50.0)
    assert c.horizontal_fov_deg(200) == pytest.approx(60.0)
    np.testing.assert_allclose(c.camera_to_world, m)
    c.camera_to_world = None
    assert not c.has_pose and c.camera_to_world is None
    o = obscura.Camera.orthographic(4.0, 200, 100)
    assert o.projection == "orthographic" and o.fx == 50.0 and o.horizontal_fov_deg(200) == 0.0
    k = obscura.Camera(300.0, cx=50, cy=40, camera_to_world=m.tolist())
    assert k.fy == 300.0 and k.has_pose and "perspective" in repr(k)


# ---------------------------------------------------------------------------------------------
# Zero-copy views

def test_strided_views_give_the_same_result(scene):
    depth, normal, cam = scene
    expected = obscura.compute_ao(depth, normal, camera=cam)
    # Every other pixel of a 2x larger buffer: strides (2 rows, 2 pixels).
    big_d = np.zeros((128, 192), np.float32)
    big_n = np.zeros((128, 192, 4), np.float32)   # RGBA-like interleave, normal in the first 3
    big_d[::2, ::2] = depth
    big_n[::2, ::2, :3] = normal
    d_view, n_view = big_d[::2, ::2], big_n[::2, ::2, :3]
    assert not d_view.flags.c_contiguous and not n_view.flags.c_contiguous
    np.testing.assert_array_equal(obscura.compute_ao(d_view, n_view, camera=cam), expected)
    # Column-major depth, reversed-row (negative stride) views.
    np.testing.assert_array_equal(obscura.compute_ao(np.asfortranarray(depth), normal, camera=cam), expected)
    flipped = obscura.compute_ao(np.ascontiguousarray(depth[::-1])[::-1], np.ascontiguousarray(normal[::-1])[::-1],
                                 camera=cam)
    np.testing.assert_array_equal(flipped, expected)
    # Read-only arrays are fine: nothing is written to the inputs.
    d_ro = depth.copy()
    d_ro.flags.writeable = False
    np.testing.assert_array_equal(obscura.compute_ao(d_ro, normal, camera=cam), expected)


def test_inputs_are_not_copied():
    # A broadcast normal (stride 0) is 12 bytes of memory; a copy would allocate H*W*3 floats.
    h, w = 512, 768
    depth = np.full((h, w), 6.0, np.float32)
    normal = np.broadcast_to(np.array([0.0, 0.0, 1.0], np.float32), (h, w, 3))
    cam = obscura.Camera.perspective(40.0, w, h, camera_to_world=np.eye(4))
    tracemalloc.start()
    try:
        ao = obscura.compute_ao(depth, normal, camera=cam, directions=2, steps=2)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < h * w * 4 // 4, f"{peak} bytes traced: the inputs were copied"
    assert np.allclose(ao, 1.0, atol=1e-5)   # an infinite plane facing the camera is unoccluded


def test_result_owns_its_memory(scene):
    depth, normal, cam = scene
    ao = obscura.compute_ao(depth, normal, camera=cam)
    del depth, normal
    ao2 = ao.copy()
    ao[:] = 0.5
    assert ao.base is not None and ao2.min() < 1.0


def test_gil_is_released_while_computing():
    h, w = 384, 512
    depth, normal = synthetic_scene(w, h)
    cam = obscura.Camera.perspective(FOV_DEG, w, h, camera_to_world=pose_matrix())
    done = {}

    def work():
        t0 = time.perf_counter()
        obscura.compute_ao(depth, normal, camera=cam, directions=24, steps=16, threads=1)
        done["t"] = time.perf_counter() - t0

    ticks = []
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    duration = done["t"]
    gaps = np.diff(ticks) if len(ticks) > 1 else np.array([duration])
    if duration < 0.2:
        pytest.skip(f"compute too fast ({duration:.3f} s) to observe")
    assert gaps.max() < 0.5 * duration, f"main thread stalled {gaps.max():.3f} s of {duration:.3f} s"


# ---------------------------------------------------------------------------------------------
# File errors

def test_missing_file_raises_obscura_error(tmp):
    missing = tmp / "nope.exr"
    for call in (lambda: obscura.read_passes(missing), lambda: obscura.process(missing, tmp / "o.exr"),
                 lambda: obscura.inspect(missing), lambda: obscura.read_layer(missing, "Z")):
        with pytest.raises(obscura.Error) as e:
            call()
        msg = str(e.value)
        assert isinstance(e.value, RuntimeError)
        assert "\n" not in msg and str(missing) in msg and "no such file" in msg
    assert not (tmp / "o.exr").exists()


def test_file_errors_leave_nothing_behind(tmp):
    not_exr = tmp / "text.exr"
    not_exr.write_text("hello")
    with pytest.raises(obscura.Error, match="not an OpenEXR file"):
        obscura.process(not_exr, tmp / "o.exr")
    with pytest.raises(obscura.Error, match="does not exist"):
        obscura.process(ROOM, tmp / "missing-dir" / "o.exr")
    with pytest.raises(obscura.Error, match="no reference layer"):
        obscura.process(ROOM, tmp / "o.exr", reference="NoSuchLayer")
    assert sorted(p.name for p in tmp.iterdir()) == ["text.exr"]


def test_threads_writing_one_output_each_write_it_whole(tmp):
    """Every call writes through a temp file of its own, so threads writing one path (the GIL is
    released) never rename or remove each other's: each call succeeds and the last one's file is
    whole."""
    calls = [dict(radius=r, directions=4, steps=4) for r in (0.25, 0.5, 1.0, 2.0)]
    errors = []

    def run(kw):
        try:
            obscura.process(ROOM, tmp / "out.exr", **kw)
        except Exception as e:  # noqa: BLE001 - every failure is the finding
            errors.append(e)

    threads = [threading.Thread(target=run, args=(kw,)) for kw in calls]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert obscura.read_layer(tmp / "out.exr", "obscura.AO.Y").shape == (320, 320)
    assert sorted(p.name for p in tmp.iterdir()) == ["out.exr"]


def test_file_errors_are_the_clis_line(tmp):
    """obscura.Error carries the CLI's line without its 'obscura: ' prefix: 'FILE': what, with the
    flags it names spelled as keywords."""
    import subprocess
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal, sidecar=True)
    not_exr, cut, broken = tmp / "text.exr", tmp / "cut.exr", tmp / "broken.json"
    not_exr.write_text("hello")
    cut.write_bytes(src.read_bytes()[:len(src.read_bytes()) // 2])
    broken.write_text('{"camera_to_world": 3}')
    out = tmp / "o.exr"
    cases = [((tmp / "nope.exr", out), {}, [], tmp / "nope.exr"), ((not_exr, out), {}, [], not_exr),
             ((cut, out), {}, [], cut), ((src, tmp / "no-dir" / "o.exr"), {}, [], tmp / "no-dir" / "o.exr"),
             ((src, out), dict(camera=broken), ["--camera", broken], broken),
             ((src, out), dict(reference="Nope"), ["--reference", "Nope"], src),
             ((src, out), dict(layer={"normal": "nope"}), ["--layer", "normal=nope"], src)]
    for (path, dest), kwargs, flags, at_fault in cases:
        proc = subprocess.run([CLI, str(path), "-o", str(dest), *map(str, flags)], capture_output=True, text=True)
        assert proc.returncode == 1, proc.stderr
        with pytest.raises(obscura.Error) as e:
            obscura.process(path, dest, **kwargs)
        cli_line = proc.stderr.replace("--layer normal=nope", "layer={'normal': 'nope'}")
        assert cli_line == f"obscura: {e.value}\n"
        assert str(e.value).startswith(f"'{at_fault}': ")
    assert not out.exists()


def test_max_pixels_keyword_is_the_clis_limit(tmp):
    depth, normal = synthetic_scene()  # 96 x 64 = 6144 pixels
    src = tmp / "scene.exr"
    write_exr(src, depth, normal, sidecar=True)
    for call in (lambda **k: obscura.read_passes(src, **k), lambda **k: obscura.process(src, tmp / "o.exr", **k),
                 lambda **k: obscura.inspect(src, **k), lambda **k: obscura.read_layer(src, "Z", **k)):
        with pytest.raises(obscura.Error, match=r"96 x 64 pixels, more than the limit of 6143 \(max_pixels\)"):
            call(max_pixels=6143)
        call(max_pixels=6144)
    for bad, error in ((0, ValueError), (-5, ValueError), (2.5, TypeError), ("many", TypeError)):
        with pytest.raises(error, match="max_pixels"):
            obscura.read_passes(src, max_pixels=bad)


def test_process_bad_keywords_raise_value_error(tmp):
    for kwargs, match in [(dict(preset="maya"), "preset must be one of"), (dict(layer={"colour": "X"}), "unknown role"),
                          (dict(out_type="double"), "out_type must be one of"), (dict(fov_deg=0), "fov_deg"),
                          (dict(fov_deg=40, ortho_width=2), "not both"), (dict(bad_pixels="ignore"), "bad_pixels"),
                          (dict(out_layer={"bogus": "x"}), "unknown output"),
                          (dict(out_layer={"do": "x"}), "written by method='ssdo' only"), (dict(camera_to_world=[1, 2]), "4x4"),
                          (dict(out_layer="a" * 300), "300 characters long"), (dict(out_layer="a..b"), "empty part"),
                          (dict(out_layer={"ao": ".x"}), "empty part"), (dict(out_layer=""), "is empty")]:
        with pytest.raises(ValueError, match=match):
            obscura.process(ROOM, tmp / "o.exr", **kwargs)
    assert not (tmp / "o.exr").exists()


def test_inspect_and_metadata():
    info = obscura.inspect(ROOM)
    assert info["preset"] == "blender" and info["roles"]["depth"] == ["ViewLayer.Depth.Z"]
    assert obscura.__version__.count(".") == 2
    assert obscura.QUALITY_PRESETS["low"] == {"directions": 4, "steps": 4, "blur": 2}
    assert "blender" in obscura.PRESETS
    assert issubclass(obscura.Error, RuntimeError)
    for f in (obscura.compute_ao, obscura.read_passes, obscura.process, obscura.ao_from_passes):
        assert f.__doc__ and len(f.__doc__) > 200


def roof_over_block(width=320, height=96, pixels_per_unit=32.0):
    """Top-down orthographic floor at depth 10; over the right half a roof 3 units up hides a
    block 1.5 units high: the block is only in the deep layers (tests/test_deep.cpp's scene)."""
    depth = np.full((height, width), 10.0, np.float32)
    depth[:, width // 2:] = 7.0
    normal = np.zeros((height, width, 3), np.float32)
    normal[..., 2] = 1.0
    deep = np.full((height, width, 4), np.inf, np.float32)
    deep[..., 0] = deep[..., 1] = depth
    deep[:, width // 2:, 2] = 8.5
    deep[:, width // 2:, 3] = 10.0
    cam = obscura.Camera.orthographic(width / pixels_per_unit, width, height)
    return depth, normal, deep, cam


def test_compute_ao_deep_layers_show_a_hidden_occluder():
    depth, normal, deep, cam = roof_over_block()
    kw = dict(camera=cam, normals="camera", radius=1.0, weighting="cosine", falloff="none", directions=16, steps=32)
    flat = obscura.compute_ao(depth, normal, **kw)
    with_deep = obscura.compute_ao(depth, normal, deep=deep, **kw)
    column = 160 - 1 - 8  # 8.5 pixels (0.27 R) left of the hidden block's face
    assert flat[40:56, column].min() > 0.999  # the roof is out of reach
    # The corner's closed form at c = 0.2656: 1 - (2/pi)(pi/4 - (c sqrt(1-c^2) + asin c)/2)
    c = 8.5 / 32
    expected = 1 - (2 / np.pi) * (np.pi / 4 - 0.5 * (c * np.sqrt(1 - c * c) + np.arcsin(c)))
    assert abs(with_deep[40:56, column].mean() - expected) < 0.02
    # deep_layers=1 keeps the visible layer only: the block is gone again.
    only_visible = obscura.compute_ao(depth, normal, deep=deep, deep_layers=1, **kw)
    assert only_visible[40:56, column].min() > 0.999


def test_compute_ao_deep_argument_checks():
    depth, normal, deep, cam = roof_over_block(64, 32)
    with pytest.raises(ValueError, match=r"\(H, W, 2K\)"):
        obscura.compute_ao(depth, normal, camera=cam, normals="camera", deep=deep[..., :3])
    with pytest.raises(ValueError, match="same pixels"):
        obscura.compute_ao(depth, normal, camera=cam, normals="camera", deep=deep[:16])
    with pytest.raises(ValueError, match="method='hbao' only"):
        obscura.compute_ao(depth, normal, camera=cam, normals="camera", deep=deep, method="ssao")
    with pytest.raises(ValueError, match="deep_layers"):
        obscura.compute_ao(depth, normal, camera=cam, normals="camera", deep=deep, deep_layers=0)
