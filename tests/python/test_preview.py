"""--preview and examples/contact_sheet.py use one display encoding: a frame's AO preview and its
contact sheet tile agree to the 8-bit step; preview_exposure is checked like the CLI's flag."""
import subprocess
import sys

import numpy as np
import pytest

import obscura
from conftest import EXAMPLES, SAMPLES


def read_png(path):
    """8-bit pixels (H, W, C), read with OpenImageIO (independent of both writers)."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    data = np.asarray(inp.read_image(0, spec.nchannels, oiio.UINT8), dtype=np.int32)
    inp.close()
    return data.reshape(spec.height, spec.width, spec.nchannels)


def test_ao_preview_matches_the_contact_sheet_tile(tmp):
    room = SAMPLES / "room.exr"
    preview = tmp / "ao.png"
    obscura.process(room, tmp / "ao.exr", preview=preview)  # every setting at its default
    sheet = tmp / "sheet.png"
    # One tile of the same frame at the default radius, no gap: the tile is the sheet's bottom rows.
    proc = subprocess.run([sys.executable, str(EXAMPLES / "contact_sheet.py"), str(room), "--radii", "1",
                           "--columns", "1", "--gap", "0", "-o", str(sheet)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    ao, tiles = read_png(preview), read_png(sheet)
    h, w, _ = ao.shape
    assert tiles.shape[1] == w and ao.shape[2] == tiles.shape[2] == 1
    tile = tiles[-h:, :w]
    assert np.abs(tile - ao).max() <= 1
    assert ao.min() < 200, "the frame must hold occlusion to compare"


@pytest.mark.parametrize("kwargs, message", [
    (dict(preview_exposure=1.0), "preview_exposure needs preview"),
    (dict(preview="p.png", preview_exposure=99), "preview_exposure must be at least -24 and at most 24"),
])
def test_preview_exposure_is_checked(tmp, kwargs, message):
    if "preview" in kwargs:
        kwargs["preview"] = tmp / kwargs["preview"]
    with pytest.raises(ValueError, match=message):
        obscura.process(SAMPLES / "room.exr", tmp / "out.exr", **kwargs)
    assert not (tmp / "out.exr").exists()
