"""Shared fixtures for the obscura Python tests.

Run by ctest (test `python.module`, see plugin/python/CMakeLists.txt), which puts the
build tree's module on PYTHONPATH and names the CLI, the test data (tests/data) and a scratch directory:
OBSCURA_CLI, OBSCURA_TEST_DATA_DIR, OBSCURA_EXAMPLES_DIR, OBSCURA_TEST_TMP.
"""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def _env_path(name, default):
    value = os.environ.get(name)
    return Path(value) if value else Path(default)


CLI = os.environ.get("OBSCURA_CLI", str(ROOT / "build" / "plugin" / "obscura"))
SAMPLES = _env_path("OBSCURA_TEST_DATA_DIR", ROOT / "tests" / "data")
EXAMPLES = _env_path("OBSCURA_EXAMPLES_DIR", ROOT / "examples")
# An AddressSanitizer build (the runtime preloaded, see plugin/python/CMakeLists.txt): its shadow
# memory changes a process's page faults, and valgrind cannot run an instrumented program.
SANITIZED = "libasan" in os.environ.get("LD_PRELOAD", "")


@pytest.fixture
def tmp(tmp_path_factory, request):
    """A fresh scratch directory (under OBSCURA_TEST_TMP when ctest gives one)."""
    base = os.environ.get("OBSCURA_TEST_TMP")
    if not base:
        return tmp_path_factory.mktemp(request.node.name[:40])
    d = Path(base) / request.node.name.replace("[", "_").replace("]", "").replace("/", "_")[:80]
    if d.exists():
        import shutil
        shutil.rmtree(d)
    d.mkdir(parents=True)
    return d


# A posed perspective camera: rotated about Y and X, translated. Row-major, OpenGL convention.
def pose_matrix():
    ay, ax = np.radians(25.0), np.radians(-15.0)
    ry = np.array([[np.cos(ay), 0, np.sin(ay), 0], [0, 1, 0, 0], [-np.sin(ay), 0, np.cos(ay), 0], [0, 0, 0, 1]])
    rx = np.array([[1, 0, 0, 0], [0, np.cos(ax), -np.sin(ax), 0], [0, np.sin(ax), np.cos(ax), 0], [0, 0, 0, 1]])
    m = ry @ rx
    m[:3, 3] = [0.5, 1.25, 3.0]
    return m


FOV_DEG = 50.0


def synthetic_scene(width=96, height=64, frame=0):
    """Depth (planar) and world normals of a bumpy floor in front of a wall, with sky pixels."""
    f = 0.5 * width / np.tan(np.radians(FOV_DEG) / 2)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    u, v = (xs + 0.5 - width / 2) / f, (ys + 0.5 - height / 2) / f
    # Camera-space surface: z = -(4 + bumps), normal from the depth gradient.
    bump = 0.6 * np.exp(-(((xs - width * (0.4 + 0.05 * frame)) ** 2) + (ys - height * 0.55) ** 2) / (0.02 * width * width))
    ridge = 0.3 * np.sin(xs * 0.35) * (ys > height * 0.7)
    depth = 4.0 - bump - ridge
    gy, gx = np.gradient(depth)
    pz = np.stack([u * depth, -v * depth, -depth], axis=-1)
    dx = np.gradient(pz, axis=1)
    dy = np.gradient(pz, axis=0)
    n_cam = np.cross(dy, dx)
    n_cam /= np.linalg.norm(n_cam, axis=-1, keepdims=True)
    n_cam *= np.where(n_cam[..., 2:3] < 0, -1.0, 1.0)  # facing the camera
    rot = pose_matrix()[:3, :3]
    n_world = n_cam @ rot.T
    depth[:6, : width // 3] = np.inf          # a patch of sky
    depth[:6, width // 3 : width // 2] = 1e10
    n_world[:6, : width // 2] = 0.0
    return depth.astype(np.float32), n_world.astype(np.float32)


def write_exr(path, depth, normal, sidecar=False):
    """A generic-preset EXR (Z, N.X, N.Y, N.Z) written with OpenImageIO's Python bindings."""
    import OpenImageIO as oiio
    h, w = depth.shape
    spec = oiio.ImageSpec(w, h, 4, oiio.FLOAT)
    spec.channelnames = ("N.X", "N.Y", "N.Z", "Z")
    spec.attribute("compression", "zip")
    pixels = np.concatenate([normal, depth[..., None]], axis=-1).astype(np.float32)
    out = oiio.ImageOutput.create(str(path))
    assert out is not None, oiio.geterror()
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(pixels), out.geterror()
    out.close()
    if sidecar:
        Path(str(path)[: -len(".exr")] + ".json").write_text(json.dumps({
            "projection": "persp",
            "horizontal_fov_rad": float(np.radians(FOV_DEG)),
            "camera_to_world": pose_matrix().tolist(),
        }))


def write_deep_samples(path, width, height, samples_of):
    """A deep EXR of R, G, B, A, Z, ZBack, written with OpenImageIO's Python bindings:
    samples_of(pixel) gives that pixel's samples, each those six values, nearest first."""
    import OpenImageIO as oiio
    spec = oiio.ImageSpec(width, height, 6, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "A", "Z", "ZBack")
    spec.deep = True
    dd = oiio.DeepData()
    dd.init(spec)
    samples = [samples_of(p) for p in range(width * height)]
    for p, s in enumerate(samples):
        dd.set_samples(p, len(s))
    for p, s in enumerate(samples):
        for i, values in enumerate(s):
            for c, v in enumerate(values):
                dd.set_deep_value(p, c, i, float(v))
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), oiio.geterror()
    assert out.write_deep_image(dd), out.geterror()
    out.close()


def read_channel(path, name):
    """One channel of an EXR as float32 (H, W), read with OpenImageIO (independent of obscura)."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    idx = list(spec.channelnames).index(name)
    data = inp.read_image(idx, idx + 1, oiio.FLOAT)
    inp.close()
    return np.asarray(data, dtype=np.float32).reshape(spec.height, spec.width)


def run_cli(*args):
    proc = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert proc.returncode == 0, f"obscura {' '.join(map(str, args))}: {proc.stderr}"
    return proc


def cli_matrix(m):
    return ",".join(repr(float(x)) for x in np.asarray(m).reshape(-1))


@pytest.fixture
def scene_file(tmp):
    """The synthetic scene as an EXR (depth Z and normals N, no camera in it), in tmp."""
    depth, normal = synthetic_scene()
    src = tmp / "scene.exr"
    write_exr(src, depth, normal)
    return src
