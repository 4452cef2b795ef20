"""hbao's bounce with deep layers from Python (docs/deep.md): read_deep gives the arrays that
compute_gi(deep=, deep_colour=) takes, and their light is the CLI's --flat deep run's, bit for bit."""
import json

import numpy as np
import pytest

import obscura
from conftest import FOV_DEG, pose_matrix, read_channel, run_cli, synthetic_scene, write_deep_samples

HIDDEN_RED = (1.0, 0.0, 0.0)


def write_flat(path, depth, normal, rgb):
    """A generic-preset EXR with a beauty (R, G, B, A), world normals and Z, and its camera sidecar."""
    import OpenImageIO as oiio
    h, w = depth.shape
    spec = oiio.ImageSpec(w, h, 8, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "A", "N.X", "N.Y", "N.Z", "Z")
    pixels = np.concatenate([rgb, np.ones((h, w, 1)), normal, depth[..., None]], axis=-1).astype(np.float32)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(pixels), out.geterror()
    out.close()
    path.with_suffix(".json").write_text(json.dumps({
        "projection": "persp", "horizontal_fov_rad": float(np.radians(FOV_DEG)),
        "camera_to_world": pose_matrix().tolist()}))


def write_deep(path, depth, rgb):
    """Each surface pixel: its visible surface (a point, the beauty's colour) and, 0.3 behind it, a
    red solid 0.5 deep; sky pixels hold no sample."""
    h, w = depth.shape
    colours = rgb.reshape(-1, 3)

    def samples(p):
        z = float(depth.flat[p])
        if not (np.isfinite(z) and z < 1e9):
            return []
        return [(*colours[p], 1.0, z, z), (*HIDDEN_RED, 1.0, z + 0.3, z + 0.8)]
    write_deep_samples(path, w, h, samples)


@pytest.fixture
def pair(tmp):
    depth, normal = synthetic_scene()
    rgb = np.full(depth.shape + (3,), 0.25, np.float32)
    rgb[..., 1] = np.linspace(0.0, 0.5, depth.shape[1], dtype=np.float32)  # a ramp, so colours are told apart
    write_flat(tmp / "flat.exr", depth, normal, rgb)
    write_deep(tmp / "deep.exr", depth, rgb)
    return tmp / "flat.exr", tmp / "deep.exr", rgb


def test_read_deep_gives_the_layers_and_their_colour(pair):
    flat, deep, rgb = pair
    d = obscura.read_deep(deep, colour=True)
    h, w = rgb.shape[:2]
    assert d["layers"] == 2 and d["deep"].shape == (h, w, 4) and d["colour"].shape == (h, w, 6)
    assert d["data_window"] == (0, 0, w, h) and d["empty_pixels"] > 0
    depth = obscura.read_passes(flat)["depth"]
    hit = np.isfinite(d["deep"][..., 0])
    np.testing.assert_array_equal(d["deep"][..., 0][hit], depth[hit])
    np.testing.assert_allclose(d["deep"][..., 3][hit] - d["deep"][..., 2][hit], 0.5, rtol=1e-5)
    np.testing.assert_array_equal(d["colour"][..., 3:][hit], np.broadcast_to(HIDDEN_RED, (hit.sum(), 3)))
    np.testing.assert_array_equal(d["colour"][..., :3][hit], rgb[hit])
    assert obscura.read_deep(deep)["colour"] is None
    one = obscura.read_deep(deep, deep_layers=1)
    assert one["layers"] == 1 and one["truncated_pixels"] == hit.sum()
    # Over a wider window: the pixels the file does not cover hold no surface and no colour.
    wide = obscura.read_deep(deep, colour=True, data_window=(-2, -1, w + 3, h))
    assert wide["deep"].shape == (h + 1, w + 5, 4)
    assert np.all(np.isinf(wide["deep"][0, :, 0])) and np.all(wide["colour"][:, :2] == 0)
    np.testing.assert_array_equal(wide["deep"][1:, 2:w + 2], d["deep"])


def test_compute_gi_with_deep_layers_is_the_clis_light(tmp, pair):
    flat, deep, rgb = pair
    out = tmp / "lit.exr"
    run_cli(deep, "--flat", flat, "-o", out, "--method", "hbao", "--bounce-source", "beauty", "--out-layer", "gi=GI",
            "--out-type", "float", "--radius", "1", "--falloff", "none", "--thickness", "0.05", "--quiet")
    p = obscura.read_passes(flat)
    d = obscura.read_deep(deep, colour=True, data_window=p["data_window"])
    kw = dict(camera=p["camera"], normals=p["normals"], depth_kind=p["depth_kind"], sky_depth=p["sky_depth"],
              radiance=rgb, radius=1.0, falloff="none", thickness=0.05)
    lit = obscura.compute_gi(p["depth"], p["normal"], deep=d["deep"], deep_colour=d["colour"], **kw)
    for c, name in enumerate("RGB"):
        np.testing.assert_array_equal(lit["gi"][..., c], read_channel(out, f"GI.{name}"))
    np.testing.assert_array_equal(lit["ao"], read_channel(out, "obscura.AO.Y"))
    # The hidden red solids light what sees them: without their colour they hide and send nothing.
    dark = obscura.compute_gi(p["depth"], p["normal"], deep=d["deep"], **kw)
    assert lit["gi"][..., 0].mean() > 1.05 * dark["gi"][..., 0].mean()
    np.testing.assert_array_equal(lit["gi"][..., 1:], dark["gi"][..., 1:])
    np.testing.assert_array_equal(lit["ao"], dark["ao"])


def test_deep_arguments_are_checked(pair):
    flat, deep, rgb = pair
    p = obscura.read_passes(flat)
    d = obscura.read_deep(deep, colour=True)
    kw = dict(camera=p["camera"], radiance=rgb)
    with pytest.raises(ValueError, match="deep_colour needs deep="):
        obscura.compute_gi(p["depth"], p["normal"], deep_colour=d["colour"], **kw)
    with pytest.raises(ValueError, match=r"deep_colour must have shape \(H, W, 3K\).*at most deep's 1"):
        obscura.compute_gi(p["depth"], p["normal"], deep=d["deep"][..., :2], deep_colour=d["colour"], **kw)
    with pytest.raises(ValueError, match="deep_colour must cover the same pixels as depth"):
        obscura.compute_gi(p["depth"], p["normal"], deep=d["deep"], deep_colour=d["colour"][1:], **kw)
    with pytest.raises(ValueError, match="deep_layers"):
        obscura.read_deep(deep, deep_layers=0)
    with pytest.raises(TypeError, match="colour must be True or False"):
        obscura.read_deep(deep, colour="yes")
    with pytest.raises(obscura.Error, match="flat.exr"):
        obscura.read_deep(flat)
