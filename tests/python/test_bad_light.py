"""Light inputs with values no light has (a renderer's NaN or infinite pixels, a map with broken
texels, a light too strong for half float): the bad values stay where they are (black), the run
says so, and every output stays finite."""
import subprocess

import numpy as np
import OpenImageIO as oiio
import pytest

import obscura
from conftest import CLI, SAMPLES, read_channel

ROOM = SAMPLES / "room.exr"
FAST = ["--samples", "16"]


def rgb(path, layer):
    return np.stack([read_channel(path, f"{layer}.{c}") for c in "RGB"], axis=-1)


def room_with(tmp, channel, value, name="room_bad.exr"):
    """room.exr with a 20 x 10 patch of `channel` set to `value` (every other channel as it is)."""
    inp = oiio.ImageInput.open(str(ROOM))
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    pixels[40:50, 60:80, list(spec.channelnames).index(channel)] = value
    out = tmp / name
    spec.set_format(oiio.FLOAT)
    o = oiio.ImageOutput.create(str(out))
    assert o.open(str(out), spec) and o.write_image(pixels), o.geterror()
    o.close()
    (tmp / name.replace(".exr", ".json")).write_text((SAMPLES / "room.json").read_text())
    return out


def run(*args):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)


@pytest.mark.parametrize("value", [np.nan, np.inf])
@pytest.mark.parametrize("method", ["ssdo", "hbao"])
def test_a_broken_bounce_source_stays_black_where_it_is(tmp, value, method):
    src, out = room_with(tmp, "ViewLayer.DiffDir.R", value), tmp / "out.exr"
    r = run(src, "-o", out, "--method", method, "--bounce", "--out-type", "float", *(FAST if method == "ssdo" else []))
    assert r.returncode == 0, r.stderr
    assert "the bounce source: 200 pixel(s) hold NaN, infinite or huge (above 1e9) values; they count as 0 (black)" in r.stderr
    for layer in (["obscura.DO"] if method == "ssdo" else []) + ["obscura.GI", "obscura.relit"]:
        assert np.isfinite(rgb(out, layer)).all(), layer


def test_a_map_with_broken_texels_lights_as_the_rest_of_it(tmp):
    env = np.full((8, 16, 3), 0.5, np.float32)
    good, bad = tmp / "env.exr", tmp / "env_bad.exr"
    for path, texels in ((good, env), (bad, env.copy())):
        if path == bad:
            texels[2, 3] = np.nan
            texels[5, 9] = np.inf
        o = oiio.ImageOutput.create(str(path))
        assert o.open(str(path), oiio.ImageSpec(16, 8, 3, oiio.FLOAT)) and o.write_image(texels)
        o.close()
    dos = []
    for path in (good, bad):
        out = tmp / f"do_{path.stem}.exr"
        r = run(ROOM, "-o", out, "--method", "ssdo", "--env", path, "--out-type", "float", *FAST)
        assert r.returncode == 0, r.stderr
        dos.append(rgb(out, "obscura.DO"))
    assert "the environment map: 2 pixel(s) hold NaN, infinite or huge (above 1e9) values" in r.stderr
    assert np.isfinite(dos[1]).all()
    assert 0.5 * dos[0].mean() < dos[1].mean() <= dos[0].mean()  # two black texels of 128


def test_light_past_half_float_is_clipped_and_said(tmp):
    out = tmp / "sun.exr"
    r = run(ROOM, "-o", out, "--method", "ssdo", "--light", "0,0,1,1e5,1e5,1e5", *FAST)
    assert r.returncode == 0, r.stderr
    assert "obscura.DO: " in r.stderr and "written as 65504; --out-type float keeps them" in r.stderr
    do = rgb(out, "obscura.DO")
    assert np.isfinite(do).all() and do.max() == 65504
    # Light that would overflow float itself is refused.
    r = run(ROOM, "-o", tmp / "x.exr", "--method", "ssdo", "--sky", "1e38,1e38,1e38")
    assert r.returncode == 2 and "--sky radiance must be between 0 and 1e9" in r.stderr
    with pytest.raises(ValueError, match="sky must be between 0 and 1e9"):
        obscura.process(ROOM, tmp / "x.exr", method="ssdo", sky=(1e38, 1, 1))


def test_compute_ssdo_warns_of_a_broken_source_and_stays_finite():
    p = obscura.read_passes(ROOM)
    radiance = np.ascontiguousarray(obscura.read_layer(ROOM, "ViewLayer.DiffDir")[..., :3])
    radiance[40:50, 60:80] = np.nan
    with pytest.warns(RuntimeWarning, match="the bounce source: 200 pixel"):
        r = obscura.compute_ssdo(p["depth"], p["normal"], camera=p["camera"], normals=p["normals"],
                                 depth_kind=p["depth_kind"], sky_depth=p["sky_depth"], data_window=p["data_window"],
                                 display_window=p["display_window"], up="z", bounce=True, radiance=radiance,
                                 samples=16)
    assert np.isfinite(r["do"]).all() and np.isfinite(r["gi"]).all()


@pytest.mark.parametrize("value", [np.nan, 3e38])
def test_compute_gi_warns_of_a_broken_or_huge_source_and_stays_finite(value):
    """hbao's bounce from arrays: the same warning as SSDO's, and no value beyond float in its sums."""
    p = obscura.read_passes(ROOM)
    radiance = np.ascontiguousarray(obscura.read_layer(ROOM, "ViewLayer.DiffDir")[..., :3])
    radiance[40:50, 60:80] = value
    with pytest.warns(RuntimeWarning, match="the bounce source: 200 pixel"):
        r = obscura.compute_gi(p["depth"], p["normal"], camera=p["camera"], normals=p["normals"],
                               depth_kind=p["depth_kind"], sky_depth=p["sky_depth"], data_window=p["data_window"],
                               display_window=p["display_window"], radiance=radiance)
    assert np.isfinite(r["gi"]).all() and np.isfinite(r["ao"]).all()
