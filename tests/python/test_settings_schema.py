"""One settings schema for every host (issue 29): Python refuses each shared numeric setting of
obscura.NUMBER_SETTINGS (core/settings_schema.h) just outside its range with the same words as
the CLI, so no host keeps a range of its own. Generated from the table."""
import pytest

import obscura
from conftest import FOV_DEG, pose_matrix


def call(src, out, key, value):
    kw = {key: value}
    if key in ("env_rotate", "env_intensity"):
        kw["method"] = "ssdo"
    if key == "preview_exposure":
        kw["preview"] = str(out.with_suffix(".png"))
    if key not in ("fov_deg", "ortho_width"):
        kw["fov_deg"] = FOV_DEG
    if key == "depth_range":
        kw["depth"] = "normalized"
    return obscura.process(str(src), str(out), camera_to_world=pose_matrix().reshape(-1), preset="generic", **kw)


def test_every_setting_is_refused_outside_its_range(tmp, scene_file):
    assert len(obscura.NUMBER_SETTINGS) >= 10
    for key, n in obscura.NUMBER_SETTINGS.items():
        below = n["min"] if n["min_excluded"] else n["min"] - 1
        above = n["max"] * 2 + 1
        for bad in (below, above):
            value = int(bad) if n["integer"] else float(bad)
            if n["count"] == 2:  # a pair (depth_range): the bad end first, the other end in range
                value = (value, float(n["max"]))
            with pytest.raises(ValueError, match=rf"^{key} must be .*at most .*, got "):
                call(scene_file, tmp / "never.exr", key, value)
        assert not (tmp / "never.exr").exists()


def test_the_cli_says_the_same(tmp, scene_file):
    """The CLI's refusal of radius 0 names the flag where Python names the keyword, nothing else."""
    import subprocess
    from conftest import CLI
    proc = subprocess.run([CLI, str(scene_file), "-o", str(tmp / "o.exr"), "--radius", "0"], capture_output=True, text=True)
    with pytest.raises(ValueError) as e:
        call(scene_file, tmp / "o.exr", "radius", 0.0)
    assert proc.returncode == 2
    assert proc.stderr.strip() == "obscura: " + str(e.value).replace("radius", "--radius", 1)
