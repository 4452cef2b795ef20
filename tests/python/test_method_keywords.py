"""Every keyword does what it says or is refused (issue 31), generated from the method table
(obscura.METHODS, core/methods.h): for each method, process() refuses every keyword that only
other methods read, naming one that reads it, and every output the method cannot write, as the
CLI refuses the flags (tests/test_method_flags.cpp). A refused call writes nothing."""
import pytest

import obscura
from conftest import FOV_DEG, pose_matrix

# A value each keyword accepts; a keyword added to the table without one fails the test.
VALUES = {
    "directions": 4, "steps": 4, "thickness": "inf", "border": "open", "deep_layers": 2,
    "samples": 16, "interleave": 1, "ssao_samples": 8, "ssao_hemisphere": True, "rtao_rays": 4, "rtao_grid": 2,
    "disc_window": 2, "disc_passes": 2, "disc_blend_levels": True, "disc_no_polygon": True, "disc_sum": True,
    "weighting": "cosine", "falloff": "none", "bounce": True, "bounce_source": "beauty", "env": "env.exr",
    "env_rotate": 10, "env_intensity": 2, "env_colorspace": "ACEScg", "sky": (1, 1, 1),
    "lights": [((0, 1, 0), (1, 1, 1))], "up": "z", "colorspace": "ACEScg", "times_albedo": True,
    "relit_direct": True,
}


def readers():
    """keyword -> the methods that read it."""
    who = {}
    for name, m in obscura.METHODS.items():
        for key in list(m["params"]) + list(m["options"]):
            who.setdefault(key, set()).add(name)
    return who


def test_every_keyword_has_a_sample_value():
    assert set(readers()) <= set(VALUES), set(readers()) - set(VALUES)


def process(src, out, **kw):
    return obscura.process(str(src), str(out), fov_deg=FOV_DEG, camera_to_world=pose_matrix().reshape(-1),
                           preset="generic", **kw)


def test_keywords_of_other_methods_are_refused(tmp, scene_file):
    refused = 0
    for method in obscura.METHODS:
        for key, methods in readers().items():
            if method in methods:
                continue
            out = tmp / f"{method}_{key}.exr"
            with pytest.raises(ValueError, match=rf"^{key} is read by method='\w+'.* only, not by method='{method}'$"):
                process(scene_file, out, method=method, **{key: VALUES[key]})
            assert not out.exists()
            refused += 1
    assert refused > 30


def test_outputs_the_method_cannot_write_are_refused(tmp, scene_file):
    for method, m in obscura.METHODS.items():
        for output in ("do", "gi", "relit"):
            if output in m["outputs"]:
                continue
            out = tmp / "never.exr"
            with pytest.raises(ValueError, match=rf"out_layer '{output}' is written by method='\w+'.* only, not by method='{method}'"):
                process(scene_file, out, method=method, out_layer={output: "X"})
            assert not out.exists()


def test_defaults_ask_for_nothing(tmp, scene_file):
    """False and None are what the keywords default to: passing them is not a request."""
    process(scene_file, tmp / "a.exr", method="hbao", bounce=False, times_albedo=False, env=None, quality="low")
    assert (tmp / "a.exr").exists()


def test_collisions_are_refused_like_the_cli(tmp, scene_file):
    sidecar = tmp / "scene.json"
    sidecar.write_text("{}")
    before = sidecar.read_bytes()
    with pytest.raises(ValueError, match="report '.*scene.json' is the same file as the camera sidecar"):
        process(scene_file, tmp / "o.exr", report=str(sidecar))
    with pytest.raises(ValueError, match="preview '.*scene.exr' is the same file as the input"):
        process(scene_file, tmp / "o.exr", preview=str(scene_file))
    with pytest.raises(ValueError, match="out '.*o.png': the output is an OpenEXR file"):
        process(scene_file, tmp / "o.png")
    assert sidecar.read_bytes() == before and not (tmp / "o.exr").exists()
