"""The film-back camera from Python (focal_mm=F, aperture_mm=A, as --focal-mm/--aperture-mm): the
lens whose horizontal field of view is 2 atan(A / 2F), the CLI's AO bit for bit, and the same
refusals in the keywords' words."""
import math

import numpy as np
import pytest

import obscura
from conftest import cli_matrix, pose_matrix, read_channel, run_cli, synthetic_scene, write_exr

FOCAL, APERTURE = 35.0, 24.576


def test_the_film_back_is_the_fov_it_spans_and_the_clis(tmp):
    depth, normal = synthetic_scene()
    src = tmp / "plate.exr"
    write_exr(src, depth, normal)
    fov = math.degrees(2 * math.atan(0.5 * APERTURE / FOCAL))
    pose = pose_matrix()
    lens = obscura.read_passes(src, focal_mm=FOCAL, aperture_mm=APERTURE, camera_to_world=pose)["camera"]
    assert lens.fx == pytest.approx(depth.shape[1] * FOCAL / APERTURE, rel=1e-12)
    assert lens.horizontal_fov_deg(depth.shape[1]) == pytest.approx(fov, rel=1e-12)
    built = obscura.Camera.film_back(FOCAL, APERTURE, depth.shape[1], depth.shape[0], pixel_aspect=2.0)
    assert built.fx == lens.fx and built.fy == 2.0 * lens.fx and built.cx == depth.shape[1] / 2
    with pytest.raises(ValueError, match="aperture_mm must be above 0"):
        obscura.Camera.film_back(FOCAL, 0.0, 64, 48)
    by_film, by_fov, by_cli = tmp / "film.exr", tmp / "fov.exr", tmp / "cli.exr"
    obscura.process(src, by_film, focal_mm=FOCAL, aperture_mm=APERTURE, camera_to_world=pose, out_type="float")
    obscura.process(src, by_fov, fov_deg=fov, camera_to_world=pose, out_type="float")
    run_cli(src, "-o", by_cli, "--focal-mm", FOCAL, "--aperture-mm", APERTURE, "--camera-to-world",
            cli_matrix(pose), "--out-type", "float", "--quiet")
    ao = read_channel(by_film, "obscura.AO.Y")
    assert np.nanmin(ao) < 0.9  # the scene holds occlusion
    np.testing.assert_array_equal(ao, read_channel(by_fov, "obscura.AO.Y"))
    np.testing.assert_array_equal(ao, read_channel(by_cli, "obscura.AO.Y"))


@pytest.mark.parametrize("kw, words", [
    (dict(focal_mm=FOCAL), "focal_mm needs aperture_mm"),
    (dict(aperture_mm=APERTURE), "aperture_mm needs focal_mm"),
    (dict(focal_mm=FOCAL, aperture_mm=APERTURE, fov_deg=40.0), "give either fov_deg or focal_mm and aperture_mm, not both"),
    (dict(focal_mm=0.0, aperture_mm=APERTURE), "focal_mm must be above 0"),
])
def test_lens_keywords_are_refused_apart(tmp, kw, words):
    depth, normal = synthetic_scene()
    src = tmp / "plate.exr"
    write_exr(src, depth, normal)
    with pytest.raises(ValueError, match=words):
        obscura.process(src, tmp / "never.exr", normals="depth", **kw)
    assert not (tmp / "never.exr").exists()
