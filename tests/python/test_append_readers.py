"""Other programs read a --write append file and see every layer: OpenImageIO (the module and
oiiotool), OpenEXR's exrheader and exrinfo, and Blender's compositor, which composites the AO
pass from the appended part. The input is tests/data/columns.exr, a Blender render; a program
that is not installed is skipped (Debian: openimageio-tools, openexr, blender)."""
import shutil
import subprocess

import numpy as np
import pytest

from conftest import SAMPLES, read_channel, run_cli

BLENDER_SCRIPT = """
import bpy, sys
path, out, w, h = sys.argv[sys.argv.index("--") + 1:]
scene = bpy.context.scene
scene.render.engine = "CYCLES"          # renders nothing here; only the compositor runs
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = int(w), int(h), 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out
scene.use_nodes = True
tree = scene.node_tree
node = tree.nodes.new("CompositorNodeImage")
node.image = bpy.data.images.load(path)
for layer in ("ViewLayer", "obscura"):
    node.layer = layer
    print("PASSES", layer, ",".join(o.name for o in node.outputs if o.enabled))
composite = next(n for n in tree.nodes if n.type == "COMPOSITE")
tree.links.new(node.outputs["AO"], composite.inputs[0])
bpy.ops.render.render(write_still=True)
"""


@pytest.fixture(scope="module")
def appended(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("append-readers")
    shutil.copy(SAMPLES / "columns.exr", tmp / "columns.exr")
    shutil.copy(SAMPLES / "columns.json", tmp / "columns.json")
    run_cli(tmp / "columns.exr", "-o", tmp / "ao.exr", "--write", "append", "--radius", "1", "--quiet")
    return tmp


def tool(name):
    path = shutil.which(name)
    if not path:
        pytest.skip(f"{name} is not installed")
    return path


def test_openimageio_sees_both_parts_and_every_channel(appended):
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(appended / "ao.exr"))
    channels = list(inp.spec().channelnames)
    assert inp.seek_subimage(1, 0) and list(inp.spec().channelnames) == ["obscura.AO.Y"]
    inp.close()
    source = oiio.ImageInput.open(str(appended / "columns.exr"))
    assert channels == list(source.spec().channelnames) and len(channels) == 23
    source.close()
    for name in channels:
        np.testing.assert_array_equal(read_channel(appended / "ao.exr", name), read_channel(appended / "columns.exr", name))
    info = subprocess.run([tool("oiiotool"), "--info", "-v", "-a", appended / "ao.exr"], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr
    assert "2 subimages" in info.stdout and "channel list: obscura.AO.Y" in info.stdout
    assert "ViewLayer.Depth.Z" in info.stdout and 'name: "obscura"' in info.stdout


def test_openexr_tools_list_both_parts(appended):
    header = subprocess.run([tool("exrheader"), appended / "ao.exr"], capture_output=True, text=True)
    assert header.returncode == 0, header.stderr
    assert 'name (type string): "render"' in header.stdout and 'name (type string): "obscura"' in header.stdout
    assert "obscura.AO.Y, 16-bit floating-point" in header.stdout and "ViewLayer.Normal.X" in header.stdout
    info = subprocess.run([tool("exrinfo"), "-v", appended / "ao.exr"], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr
    assert "part 2: obscura" in info.stdout and "'obscura.AO.Y'" in info.stdout


def test_blender_compositor_offers_and_composites_the_ao_pass(appended):
    script = appended / "compositor.py"
    script.write_text(BLENDER_SCRIPT)
    out = appended / "composited.exr"
    proc = subprocess.run([tool("blender"), "-b", "--factory-startup", "--python", script, "--",
                           appended / "ao.exr", out, "320", "240"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and out.exists(), proc.stdout + proc.stderr
    passes = dict(line.split(" ")[1:] for line in proc.stdout.splitlines() if line.startswith("PASSES "))
    assert passes["obscura"] == "AO"
    assert {"Combined", "Depth", "Normal", "Position", "AO"} <= set(passes["ViewLayer"].split(","))
    import OpenImageIO as oiio
    ao = oiio.ImageBuf(str(appended / "ao.exr"), 1, 0).get_pixels(oiio.FLOAT)[..., 0]  # part 2: the AO
    np.testing.assert_array_equal(read_channel(out, "R"), ao)
