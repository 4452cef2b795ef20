"""Normals reconstructed from the depth (normals='depth', the CLI's --normals depth): what the
module does for a file without a normal layer, equal to the CLI's, and without a normal array."""
import numpy as np
import pytest

import obscura
from conftest import FOV_DEG, read_channel, run_cli, synthetic_scene


def write_depth_only(path, depth):
    """A generic-preset EXR holding the depth alone (Z), written with OpenImageIO's Python bindings."""
    import OpenImageIO as oiio
    h, w = depth.shape
    spec = oiio.ImageSpec(w, h, 1, oiio.FLOAT)
    spec.channelnames = ("Z",)
    out = oiio.ImageOutput.create(str(path))
    assert out is not None, oiio.geterror()
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(depth[..., None].astype(np.float32)), out.geterror()
    out.close()


def test_depth_only_file_reads_writes_and_computes_alike(tmp):
    depth, _ = synthetic_scene()
    src, cli_out, py_out = tmp / "plate.exr", tmp / "cli.exr", tmp / "py.exr"
    write_depth_only(src, depth)
    run_cli(src, "-o", cli_out, "--fov-deg", FOV_DEG, "--out-type", "float", "--quiet")
    expected = read_channel(cli_out, "obscura.AO.Y")

    p = obscura.read_passes(src, fov_deg=FOV_DEG)
    assert p["normal"] is None and p["normals"] == "depth"
    np.testing.assert_array_equal(obscura.ao_from_passes(p), expected)
    report = obscura.process(src, py_out, fov_deg=FOV_DEG, out_type="float")
    assert report["conventions"]["normals"] == "depth"
    assert "normals: reconstructed from depth (no normal layer)" in report["plan"]
    np.testing.assert_array_equal(read_channel(py_out, "obscura.AO.Y"), expected)

    h, w = depth.shape
    ao = obscura.compute_ao(depth, camera=obscura.Camera.perspective(FOV_DEG, w, h), normals="depth")
    np.testing.assert_array_equal(ao, expected)
    assert 0.0 <= ao.min() < 0.999  # the scene occludes something
    assert obscura.inspect(src)["conventions"]["normals"] == "depth"


def test_normals_depth_ignores_a_normal_array_and_needs_none():
    depth, normal = synthetic_scene()
    h, w = depth.shape
    cam = obscura.Camera.perspective(FOV_DEG, w, h)
    without = obscura.compute_ao(depth, camera=cam, normals="depth")
    np.testing.assert_array_equal(obscura.compute_ao(depth, normal, camera=cam, normals="depth"), without)
    ssdo = obscura.compute_ssdo(depth, camera=cam, normals="depth", samples=16)
    assert ssdo["ao"].shape == depth.shape
    with pytest.raises(TypeError, match="normals='depth'"):
        obscura.compute_ao(depth, camera=cam)
    with pytest.raises(ValueError, match="'world', 'camera' or 'depth'"):
        obscura.compute_ao(depth, normal, camera=cam, normals="sideways")
