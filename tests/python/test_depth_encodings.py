"""Depth encodings from Python (depth='inverse'|'normalized', depth_range=(A, B)): the file's
depth decoded to planar before the operator, as the CLI decodes it, and the same refusals."""
import numpy as np
import pytest

import obscura
from conftest import FOV_DEG, cli_matrix, pose_matrix, read_channel, run_cli, synthetic_scene, write_exr

NEAR, FAR = 0.5, 50.0


def encoded_files(tmp):
    """The synthetic scene stored planar, as 1/z (sky 0) and normalised over (NEAR, FAR) (sky 1)."""
    depth, normal = synthetic_scene()
    sky = ~np.isfinite(depth) | (depth >= 1e9)
    inverse = np.where(sky, 0.0, 1.0 / np.where(sky, 1.0, depth)).astype(np.float32)
    normalised = np.where(sky, 1.0, (depth - NEAR) / (FAR - NEAR)).astype(np.float32)
    files = {}
    for name, z in (("planar", depth), ("inverse", inverse), ("normalized", normalised)):
        files[name] = tmp / f"{name}.exr"
        write_exr(files[name], z, normal)
    return depth, sky, files


def test_each_encoding_reads_as_the_planar_depth_and_writes_the_clis_ao(tmp):
    depth, sky, files = encoded_files(tmp)
    cam = dict(fov_deg=FOV_DEG, camera_to_world=pose_matrix())
    planar = obscura.read_passes(files["planar"], **cam)["depth"]
    for name, kw in (("inverse", dict(depth="inverse")), ("normalized", dict(depth="normalized", depth_range=(NEAR, FAR)))):
        p = obscura.read_passes(files[name], **cam, **kw)
        assert p["depth_encoding"] == name and p["depth_kind"] == "planar"
        assert np.all(np.isinf(p["depth"][sky]))
        np.testing.assert_allclose(p["depth"][~sky], planar[~sky], rtol=2e-6)
        out, cli_out = tmp / f"{name}_py.exr", tmp / f"{name}_cli.exr"
        obscura.process(files[name], out, out_type="float", **cam, **kw)
        flags = ["--depth", name] + (["--depth-range", f"{NEAR},{FAR}"] if name == "normalized" else [])
        run_cli(files[name], "-o", cli_out, "--fov-deg", FOV_DEG, "--camera-to-world", cli_matrix(pose_matrix()),
                "--out-type", "float", "--quiet", *flags)
        np.testing.assert_array_equal(read_channel(out, "obscura.AO.Y"), read_channel(cli_out, "obscura.AO.Y"))


def test_what_cannot_be_decoded_is_refused(tmp):
    _, _, files = encoded_files(tmp)
    with pytest.raises(obscura.Error, match=r"depth='normalized' needs depth_range=\(NEAR, FAR\)"):
        obscura.process(files["normalized"], tmp / "never.exr", fov_deg=FOV_DEG, depth="normalized")
    with pytest.raises(ValueError, match="depth_range needs two different ends"):
        obscura.read_passes(files["normalized"], depth="normalized", depth_range=(3, 3))
    with pytest.raises(ValueError, match="depth_range must be 2 numbers"):
        obscura.read_passes(files["normalized"], depth="normalized", depth_range=3)
    assert not (tmp / "never.exr").exists()
    info = obscura.inspect(files["inverse"])
    assert "inverse" in info["depth_statistics"]["hint"]
    assert info["depth_statistics"]["type"] == "float"
