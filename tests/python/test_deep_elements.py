"""Deep elements through process() (docs/deep.md): a list of deep EXRs is merged, one deep EXR
alone is an input of its own, per_element_ao adds an AO per element, and the CLI writes the same."""
import numpy as np
import pytest

import obscura
from conftest import read_channel, run_cli, write_deep_samples

WIDTH, HEIGHT, FOV = 64, 40, 40.0


def rays():
    f = 0.5 * WIDTH / np.tan(np.radians(FOV) / 2)
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    return (xs + 0.5 - WIDTH / 2) / f, -(ys + 0.5 - HEIGHT / 2) / f


def write_deep(path, front, back, rgb):
    """A deep EXR of one sample per pixel where front is finite: R, G, B, A = 1, Z, ZBack."""
    write_deep_samples(path, WIDTH, HEIGHT, lambda p: [(*rgb, 1.0, front.flat[p], back.flat[p])]
                       if np.isfinite(front.flat[p]) else [])


@pytest.fixture
def elements(tmp):
    """The ground y = -1 (points) and a box standing on it beside the frame's centre (spans)."""
    u, v = rays()
    with np.errstate(divide="ignore"):
        ground = np.where(v < 0, -1.0 / v, np.inf)
    # The box's front face z = -4 for x in [0.3, 1.0], y in [-1, 0.5]; 0.6 deep.
    x, y = u * 4.0, v * 4.0
    box = np.where((x >= 0.3) & (x <= 1.0) & (y >= -1) & (y <= 0.5), 4.0, np.inf)
    write_deep(tmp / "ground.exr", ground, ground, (0.5, 0.5, 0.5))
    write_deep(tmp / "box.exr", box, box + 0.6, (0.0, 1.0, 0.0))
    return tmp / "ground.exr", tmp / "box.exr"


def test_a_list_of_elements_is_merged(tmp, elements):
    ground, box = elements
    kw = dict(fov_deg=FOV, radius=1.0, falloff="none", blur=0)
    report = obscura.process([str(ground), str(box)], str(tmp / "comp.exr"), per_element_ao=True, **kw)
    assert report["deep"]["elements"] == [str(ground), str(box)]
    assert set(report["written"]) >= {"obscura.AO.Y", "obscura.AO.ground.Y", "obscura.AO.box.Y"}
    merged = read_channel(tmp / "comp.exr", "obscura.AO.Y")
    own = read_channel(tmp / "comp.exr", "obscura.AO.ground.Y")
    assert np.all(np.isfinite(merged)) and merged.min() >= 0 and merged.max() <= 1
    # The ground alone is a plane: AO 1. Merged, the box darkens the ground at its foot.
    obscura.process(str(ground), str(tmp / "alone.exr"), **kw)
    alone = read_channel(tmp / "alone.exr", "obscura.AO.Y")
    assert alone[HEIGHT // 2 + 2:].min() > 0.999
    assert own.min() < 0.9
    # The CLI writes the same.
    run_cli(ground, box, "-o", tmp / "cli.exr", "--per-element-ao", "--fov-deg", FOV, "--radius", 1.0,
            "--falloff", "none", "--blur", 0, "--quiet")
    for name in ("obscura.AO.Y", "obscura.AO.box.Y", "R", "G", "Z"):
        assert np.array_equal(read_channel(tmp / "cli.exr", name), read_channel(tmp / "comp.exr", name)), name


def test_per_element_ao_needs_the_deep_layers(tmp, elements):
    ground, box = elements
    with pytest.raises(ValueError, match="per_element_ao needs falloff='none'"):
        obscura.process([str(ground), str(box)], str(tmp / "x.exr"), fov_deg=FOV, per_element_ao=True)
    with pytest.raises(ValueError, match="per_element_ao works with method="):
        obscura.process([str(ground), str(box)], str(tmp / "x.exr"), fov_deg=FOV, method="ssao", per_element_ao=True)
    assert not (tmp / "x.exr").exists()
