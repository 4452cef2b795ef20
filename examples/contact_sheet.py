#!/usr/bin/env python3
"""A contact sheet PNG of AO variants or relighting setups: one labelled tile per variant.

From a batch (batch_ao.py's or batch_relight.py's output directory; reads OUT/batch.json):

    python3 examples/contact_sheet.py out --frame 12 -o sheet.png

AO variants show their AO layer (grey); relighting setups (batch_relight.py) show their relit
RGB layer (--exposure stops first, default 0, the same for every tile so setups compare),
each labelled with the setup's name.

or straight from one frame, computing each variant in memory with obscura's arrays
(read_passes once, then ao_from_passes per variant; nothing but the PNG is written):

    python3 examples/contact_sheet.py shot.0012.exr --radii 0.25,0.5,1 \\
        --variant cos:radius=1,weighting=cosine,falloff=none -o sheet.png

Tiles show the display window (overscan cropped) in obscura's one display encoding, the one
obscura --preview writes: clamped to 0..1, the sRGB OETF, 8-bit. An AO tile and the frame's AO
preview agree to the 8-bit step; a relit tile and the relit preview agree when given the same
stops (--exposure EV here, --preview-exposure EV there; the preview's default is automatic).
Tiles are labelled with the variant name. --columns, --scale (nearest-neighbour
downsampling by an integer factor) and --gap shape the sheet. Writes the PNG with Python's
zlib (numpy only; no imaging library needed), atomically.
"""
import argparse
import json
import os
import struct
import sys
import zlib

import numpy as np

import obscura

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import batch_ao  # noqa: E402  (variant parsing and frame patterns are shared)

# ------------------------------------------------------------------------------------------
# A 3x5 pixel font for the labels (upper case, digits, a little punctuation).

_FONT = {
    "A": "010101111101101", "B": "110101110101110", "C": "011100100100011", "D": "110101101101110",
    "E": "111100110100111", "F": "111100110100100", "G": "011100101101011", "H": "101101111101101",
    "I": "111010010010111", "J": "001001001101010", "K": "101101110101101", "L": "100100100100111",
    "M": "101111111101101", "N": "110101101101101", "O": "010101101101010", "P": "110101110100100",
    "Q": "010101101110011", "R": "110101110101101", "S": "011100010001110", "T": "111010010010010",
    "U": "101101101101111", "V": "101101101101010", "W": "101101111111101", "X": "101101010101101",
    "Y": "101101010010010", "Z": "111001010100111", "0": "111101101101111", "1": "010110010010111",
    "2": "110001010100111", "3": "110001010001110", "4": "101101111001001", "5": "111100110001110",
    "6": "011100111101111", "7": "111001010010010", "8": "111101111101111", "9": "111101111001110",
    ".": "000000000000010", "-": "000000111000000", "_": "000000000000111", "=": "000111000111000",
    ":": "000010000010000", "+": "000010111010000", "/": "001001010100100", " ": "000000000000000",
    ",": "000000000010100", "(": "010100100100010", ")": "010001001001010", "#": "101111101111101",
}


def draw_text(img, text, x, y, scale, value):
    """Draws `text` into the 2-D float image at (x, y) (top-left), clipped to the image."""
    for ch in text.upper():
        glyph = _FONT.get(ch, _FONT["#"])
        for i, bit in enumerate(glyph):
            if bit == "1":
                gy, gx = y + (i // 3) * scale, x + (i % 3) * scale
                img[max(gy, 0):max(gy + scale, 0), max(gx, 0):max(gx + scale, 0)] = value
        x += 4 * scale


# ------------------------------------------------------------------------------------------
# PNG (8-bit grey or RGB), written with zlib


def write_png(path, pixels8):
    """pixels8: uint8 (H, W) grey or (H, W, 3) RGB."""
    h, w = pixels8.shape[:2]
    colour_type = 2 if pixels8.ndim == 3 else 0
    raw = b"".join(b"\x00" + pixels8[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, colour_type, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


def to_display(ao, exposure=0.0):
    """Linear AO (or RGB) -> sRGB-encoded 0..1, obscura's display encoding (plugin/io/preview.h)."""
    v = np.nan_to_num(np.asarray(ao, dtype=np.float64), nan=0.0) * (2.0 ** exposure)
    v = np.clip(v, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)


# ------------------------------------------------------------------------------------------
# Tiles


def crop_to_display(ao, data_window, display_window):
    dx0, dy0, dx1, dy1 = data_window
    x0, y0 = max(display_window[0], dx0), max(display_window[1], dy0)
    x1, y1 = min(display_window[2], dx1), min(display_window[3], dy1)
    if x1 <= x0 or y1 <= y0:
        return ao
    return ao[y0 - dy0:y1 - dy0, x0 - dx0:x1 - dx0]


def relit_layer(variant):
    """The RGB layer a batch variant shows: its relit layer (batch_relight.py), else None (AO)."""
    out_layer = variant.get("settings", {}).get("out_layer")
    if isinstance(out_layer, dict) and "relit" in out_layer:
        return out_layer["relit"]
    return "obscura.relit" if variant.get("kind") == "relight" else None


def tiles_from_batch(out_dir, frame, only):
    with open(os.path.join(out_dir, "batch.json")) as f:
        manifest = json.load(f)
    if frame is None:
        frame = manifest["frames"][len(manifest["frames"]) // 2]
    tiles = []
    for v in manifest["variants"]:
        if only and v["name"] not in only:
            continue
        path = batch_ao.frame_path(os.path.join(out_dir, v["output"]), frame)
        report_path = os.path.splitext(path)[0] + ".json"
        channel = "obscura.AO.Y"
        if os.path.exists(report_path):
            with open(report_path) as f:
                channel = json.load(f).get("output_channels", {}).get("ao", channel)
        layer = relit_layer(v)
        try:
            ao = obscura.read_layer(path, layer) if layer else obscura.read_layer(path, channel)
            if layer and (ao.ndim != 3 or ao.shape[2] < 3):
                raise obscura.Error(f"'{path}': layer '{layer}' is not RGB")
            if layer:
                ao = ao[..., :3]
            # The display window: read_passes knows it (the AO shares the depth's part).
            p = obscura.read_passes(path)
            ao = crop_to_display(ao, p["data_window"], p["display_window"])
        except obscura.Error as e:
            print(f"contact_sheet: {v['name']}: {e}", file=sys.stderr)
            ao = None
        tiles.append((v["name"], ao))
    return tiles, f"frame {frame}"


def tiles_from_frame(path, variants):
    passes = obscura.read_passes(path)
    if passes["camera"] is None:
        raise obscura.Error(passes["camera_error"])
    tiles = []
    for v in variants:
        if v.kind != "ao":
            raise ValueError(f"variant '{v.name}' is of kind '{v.kind}': show it from its batch directory")
        # Only operator settings apply in memory; file-level keys (preset, out_type...) are ignored.
        settings = {k: val for k, val in v.settings.items() if k in SETTING_KEYS}
        ao = obscura.ao_from_passes(passes, **settings)
        tiles.append((v.name, crop_to_display(ao, passes["data_window"], passes["display_window"])))
    return tiles, os.path.basename(path)


SETTING_KEYS = {"quality", "method", "radius", "directions", "steps", "weighting", "falloff", "blur", "device",
                "threads"}


def compose(tiles, columns, scale, gap, title, exposure=0.0):
    shapes = [t.shape for _, t in tiles if t is not None]
    if not shapes:
        raise SystemExit("contact_sheet: no tile could be read")
    th = max(s[0] for s in shapes) // scale
    tw = max(s[1] for s in shapes) // scale
    text = 2 if tw >= 160 else 1
    label_h = 5 * text + gap + 3  # gap, the text, 3 px, then the tile
    columns = columns or min(len(tiles), 4)
    rows = (len(tiles) + columns - 1) // columns
    title_h = label_h
    sheet = np.full((title_h + rows * (th + label_h + gap), columns * (tw + gap) + gap), 0.15)
    rgb = any(t is not None and t.ndim == 3 for _, t in tiles)
    if rgb:  # grey tiles (AO) and labels go to all three channels
        sheet = np.repeat(sheet[..., None], 3, axis=2)
    draw_text(sheet, title, gap, gap, text, 1.0)
    for i, (name, ao) in enumerate(tiles):
        r, c = divmod(i, columns)
        x = gap + c * (tw + gap)
        y = title_h + r * (th + label_h + gap)
        draw_text(sheet, name, x, y + gap, text, 0.9)
        y += label_h
        if ao is None:
            draw_text(sheet, "missing", x + gap, y + gap, text, 0.6)
            continue
        tile = to_display(ao[::scale, ::scale], exposure if ao.ndim == 3 else 0.0)[:th, :tw]
        if rgb and tile.ndim == 2:
            tile = tile[..., None]
        sheet[y:y + tile.shape[0], x:x + tile.shape[1]] = tile
    return np.round(np.clip(sheet, 0, 1) * 255).astype(np.uint8)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("source", help="a batch_ao.py output directory, or one EXR frame")
    ap.add_argument("-o", "--output", required=True, help="the PNG to write")
    ap.add_argument("--frame", type=int, help="batch: which frame (default: the middle one)")
    ap.add_argument("--only", help="batch: comma-separated variant names to include")
    ap.add_argument("--variant", action="append", metavar="NAME:key=value,...", help="frame: a settings variant")
    ap.add_argument("--radii", help="frame: comma-separated radii, one variant each")
    ap.add_argument("--set", action="append", default=[], metavar="key=value", help="frame: setting for every variant")
    ap.add_argument("--columns", type=int, default=0, help="tiles per row (default: up to 4)")
    ap.add_argument("--scale", type=int, default=1, help="integer downsampling of each tile (default 1)")
    ap.add_argument("--gap", type=int, default=6, help="pixels between tiles (default 6)")
    ap.add_argument("--exposure", type=float, default=0.0, help="stops applied to relit (RGB) tiles (default 0)")
    args = ap.parse_args(argv)
    if args.scale < 1 or args.gap < 0 or args.columns < 0:
        ap.error("--scale must be >= 1, --gap and --columns >= 0")

    try:
        if os.path.isdir(args.source):
            only = set(args.only.split(",")) if args.only else None
            tiles, title = tiles_from_batch(args.source, args.frame, only)
        else:
            common = {}
            for s in args.set:
                common.update(batch_ao.parse_assignments(s))
            radii = [float(r) for r in args.radii.split(",")] if args.radii else []
            variants = batch_ao.build_variants(args.variant, radii, common)
            tiles, title = tiles_from_frame(args.source, variants)
        sheet = compose(tiles, args.columns, args.scale, args.gap, title, args.exposure)
        write_png(args.output, sheet)
    except (obscura.Error, ValueError, OSError) as e:
        print(f"contact_sheet: {e}", file=sys.stderr)
        return 1
    print(f"contact_sheet: {len(tiles)} tile(s), {sheet.shape[1]}x{sheet.shape[0]} -> {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
