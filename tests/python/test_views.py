"""Multi-view (stereo) files from Python: view= (as --view), process() writing each view's AO in
that view's naming, and inspect() describing the plate and giving a command that runs. The
plate: RGBA + Z in half float, no normals, no camera, a cropped data window, written with
OpenImageIO as one part with the views in the channel names, and as a part per view."""
import json
import subprocess

import numpy as np
import pytest

import obscura
from conftest import CLI

W, H = 64, 48
CROP = (4, 3, 60, 44)  # x0, y0, x1, y1 half-open, inside the 64 x 48 display window
VIEWS = ("left", "right")


def plate(view):
    """RGBA and Z of one eye over the crop: a ground plane and a box; nothing left of x = 8."""
    x0, y0, x1, y1 = CROP
    ys, xs = np.mgrid[y0:y1, x0:x1]
    xs = xs + 3 * view
    covered = xs >= 8
    box = (xs >= 24) & (xs < 36) & (ys >= 14) & (ys < 30)
    z = np.where(covered, 6.0 - 0.06 * ys - 1.5 * box, 0.0)
    rgba = np.stack([(xs + 2 * ys + c) % 8 / 8.0 for c in range(3)] + [covered * 1.0], axis=-1)
    return np.concatenate([rgba, z[..., None]], axis=-1).astype(np.float32)


def spec_for(names):
    import OpenImageIO as oiio
    x0, y0, x1, y1 = CROP
    spec = oiio.ImageSpec(x1 - x0, y1 - y0, len(names), oiio.HALF)
    spec.x, spec.y = x0, y0
    spec.full_x, spec.full_y, spec.full_width, spec.full_height = 0, 0, W, H
    spec.channelnames = tuple(names)
    spec.attribute("compression", "zip")
    return spec


def write_plate(path, by_part):
    import OpenImageIO as oiio
    out = oiio.ImageOutput.create(str(path))
    names = ["R", "G", "B", "A", "Z"]
    if by_part:
        specs = [spec_for(names) for _ in VIEWS]
        for spec, view in zip(specs, VIEWS):
            spec.attribute("view", view)
            spec.attribute("oiio:subimagename", view)
        assert out.open(str(path), specs), oiio.geterror()
        assert out.write_image(plate(0))
        assert out.open(str(path), specs[1], "AppendSubimage")
        assert out.write_image(plate(1))
    else:
        spec = spec_for(names + [f"right.{n}" for n in names])
        spec.attribute("multiView", oiio.TypeDesc("string[2]"), VIEWS)
        assert out.open(str(path), spec), oiio.geterror()
        assert out.write_image(np.concatenate([plate(0), plate(1)], axis=-1))
    out.close()


def read_in_view(path, view, name):
    """Channel `name` of the part whose view attribute is `view` (None: a part without one)."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    try:
        sub = 0
        while inp.seek_subimage(sub, 0):
            spec = inp.spec()
            if spec.getattribute("view") == view and name in spec.channelnames:
                i = list(spec.channelnames).index(name)
                return np.asarray(inp.read_image(sub, 0, i, i + 1, oiio.FLOAT)).reshape(spec.height, spec.width)
            sub += 1
        return None
    finally:
        inp.close()


def ao_places(by_part):
    return [(v, "obscura.AO.Y") for v in VIEWS] if by_part else [(None, f"obscura.AO.{v}.Y") for v in VIEWS]


@pytest.mark.parametrize("by_part", [False, True])
def test_each_view_gets_its_ao_and_view_restricts(tmp, by_part):
    src = tmp / "plate.exr"
    write_plate(src, by_part)
    out = tmp / "plate_ao.exr"
    report = obscura.process(src, out, fov_deg=40, device="cpu")
    assert report["views"] == list(VIEWS)
    aos = [read_in_view(out, view, name) for view, name in ao_places(by_part)]
    for ao in aos:
        assert ao is not None and ao.shape == (CROP[3] - CROP[1], CROP[2] - CROP[0])
        assert np.all(np.isfinite(ao)) and ao.min() >= 0 and ao.max() <= 1 and ao.min() < 0.99
    assert not np.array_equal(aos[0], aos[1]), "the eyes see the box in different places"
    for view, name in (("left", "Z"), ("right", "Z")) if by_part else ((None, "Z"), (None, "right.Z")):
        i = 0 if name == "Z" and view != "right" else 1
        np.testing.assert_array_equal(read_in_view(out, view, name), read_in_view(src, view, name))
        np.testing.assert_array_equal(read_in_view(src, view, name), plate(i)[..., 4].astype(np.float16).astype(np.float32))

    right = tmp / "right_ao.exr"
    obscura.process(src, right, fov_deg=40, device="cpu", view="right")
    np.testing.assert_array_equal(read_in_view(right, *ao_places(by_part)[1]), aos[1])
    assert read_in_view(right, *ao_places(by_part)[0]) is None
    assert obscura.read_passes(src, fov_deg=40, view=["right"])["depth"].shape == aos[1].shape


def test_a_view_not_in_the_file_is_refused(tmp):
    src = tmp / "plate.exr"
    write_plate(src, False)
    with pytest.raises(obscura.Error, match=r"plate.exr': no view 'middle'; the file's views: left, right$"):
        obscura.process(src, tmp / "never.exr", fov_deg=40, view="middle")
    with pytest.raises(ValueError, match="view names 'left' twice"):
        obscura.process(src, tmp / "never.exr", fov_deg=40, view=["left", "left"])
    assert not (tmp / "never.exr").exists()


@pytest.mark.parametrize("by_part", [False, True])
def test_inspect_answers_with_a_command_that_runs(tmp, by_part):
    src = tmp / "plate.exr"
    write_plate(src, by_part)
    info = obscura.inspect(src)
    assert info["views"] == list(VIEWS) and info["views_processed"] == list(VIEWS)
    assert info["roles"]["normal"] is None and "reconstructed from depth" in info["fills"]["normal"]
    assert info["camera"] is None and any("--fov-deg" in n for n in info["command_notes"])
    cli = subprocess.run([CLI, str(src), "--inspect", "--json"], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    assert json.loads(cli.stdout) == info, "--inspect --json and obscura.inspect() say the same"
    proc = subprocess.run([CLI, *info["command_args"][1:]], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    out = info["command_args"][info["command_args"].index("-o") + 1]
    for view, name in ao_places(by_part):
        assert read_in_view(out, view, name) is not None


@pytest.mark.parametrize("by_part", [False, True])
def test_light_clipped_to_half_float_is_said_per_view(tmp, by_part):
    """A light past half float's largest value is written as 65504, and the warning names each
    view's layer: in a part per view the layers' names repeat, so the view is said beside them."""
    src = tmp / "plate.exr"
    write_plate(src, by_part)
    out = tmp / "lit.exr"
    r = subprocess.run([CLI, str(src), "-o", str(out), "--fov-deg", "40", "--method", "ssdo", "--samples", "16",
                        "--device", "cpu", "--light", "0,0,1,1e5,1e5,1e5"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    layers = ["obscura.DO (view left)", "obscura.DO (view right)"] if by_part else \
        ["obscura.DO.left", "obscura.DO.right"]
    for layer in layers:
        assert f"{layer}: " in r.stderr and "written as 65504" in r.stderr, r.stderr
