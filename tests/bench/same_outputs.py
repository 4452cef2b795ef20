#!/usr/bin/env python3
"""Every method's outputs of two builds compared bit for bit: a build before a change (BEFORE)
against the current one (AFTER), on the report's scenes, the test data and deep renders.

    python3 tests/bench/same_outputs.py BEFORE/plugin/obscura build/plugin/obscura \\
        --render build/examples/reference/reference_render --work /tmp/same [--devices cpu,gl-osmesa] \\
        [--methods hbao,ssao,rtao,discs,ssdo]

HBAO:
Each input runs with every combination of --thickness inf / 0.3 R / auto, --falloff linear /
none, --weighting uniform / cosine and --border open / clamp / tangent (36 runs), on each device
of --devices and, for the CPU, each instruction set of --isa (OBSCURA_CPU_ISA; default: the
widest). Inputs: tests/data's two Blender renders, the eight report scenes at 320 x 240 (from
--render, written once into WORK/scenes), three of them as deep input (--flat), one with
overscan, and one read as radial depth and one through an orthographic camera (other camera
specialisations of the kernel). The other methods run on the same inputs (deep ones excepted)
with the settings each reads (OTHER_METHODS below): presets, blur, their own options, and for
ssdo every output (AO, DO, GI, relit) under a sky, a sun and an environment map. Every setting
is given explicitly, so a changed default does not count as a changed output. Outputs are float
EXRs of the new layers alone; two are the same
when their pixel data (everything after the header, which names the output) are the same bytes:
both builds write through the same OpenEXR, so equal pixels compress to equal bytes.

BEFORE's outputs are kept in WORK/before and reused by later runs (the build before does not
change); AFTER's are written again each time. Exit status 1 when any pair differs; each differing
pair is listed with `oiiotool --diff`'s summary.
"""
import argparse
import itertools
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = ["corner", "sphere-plane", "cornell", "stairs", "poles", "city", "terrain", "studio"]
DEEP_SCENES = ["poles", "cornell", "city"]


def render_scenes(render, scenes_dir):
    """The report scenes' passes (the rays do not matter here), deep renders, one with overscan."""
    scenes_dir.mkdir(parents=True, exist_ok=True)
    jobs = [(s, [f"{s}.exr"] + (["--deep", f"{s}_deep.exr"] if s in DEEP_SCENES else [])) for s in SCENES]
    jobs.append(("terrain", ["terrain_overscan.exr", "--overscan", "16"]))
    for scene, (out, *extra) in jobs:
        if (scenes_dir / out).exists():
            continue
        subprocess.run([render, "--scene", scene, "-o", out, "--ao-rays", "1", "--gi-rays", "1", "--quiet"] + extra,
                       cwd=scenes_dir, check=True)


def inputs(scenes_dir):
    """(name, arguments naming the input, radius) of every input."""
    def radius(json_path):
        return json.loads(Path(json_path).read_text())["ao_distance"]

    data = ROOT / "tests" / "data"
    out = [(n, [str(data / f"{n}.exr")], radius(data / f"{n}.json")) for n in ("room", "columns")]
    for s in SCENES:
        out.append((s, [str(scenes_dir / f"{s}.exr")], radius(scenes_dir / f"{s}.json")))
    for s in DEEP_SCENES:
        out.append((f"{s}-deep", [str(scenes_dir / f"{s}_deep.exr"), "--flat", str(scenes_dir / f"{s}.exr")],
                    radius(scenes_dir / f"{s}.json")))
    out.append(("terrain-overscan", [str(scenes_dir / "terrain_overscan.exr")], radius(scenes_dir / "terrain.json")))
    out.append(("cornell-radial", [str(scenes_dir / "cornell.exr"), "--depth", "radial"],
                radius(scenes_dir / "cornell.json")))
    out.append(("stairs-ortho", [str(scenes_dir / "stairs.exr"), "--ortho-width", "8"], radius(scenes_dir / "stairs.json")))
    return out


# Each method's settings: a few combinations that reach every branch of its kernel.
OTHER_METHODS = {
    "ssao": [["--ssao-samples", "8", "--blur", "0"], ["--ssao-samples", "32", "--blur", "2"],
             ["--ssao-samples", "16", "--ssao-hemisphere", "--blur", "0"]],
    "rtao": [["--rtao-rays", "4", "--thickness", "auto", "--blur", "0"],
             ["--rtao-rays", "4", "--thickness", "inf", "--rtao-grid", "2", "--blur", "1"]],
    "discs": [["--disc-window", "1", "--blur", "0"], ["--disc-window", "3", "--border", "open", "--blur", "1"],
              ["--disc-window", "2", "--disc-passes", "2", "--disc-sum", "--blur", "0"],
              ["--disc-window", "1", "--disc-blend-levels", "--disc-no-polygon", "--blur", "0"]],
    "ssdo": [["--samples", "16", "--interleave", "1", "--blur", "0", "--bounce"],
             ["--samples", "64", "--interleave", "2", "--blur", "2", "--bounce", "--light", "0.3,0.5,0.8,3,2.8,2.5"],
             ["--samples", "32", "--interleave", "2", "--blur", "2", "--bounce", "--env", "ENV", "--env-rotate", "30"],
             ["--samples", "32", "--interleave", "1", "--blur", "0", "--bounce", "--times-albedo", "--relit-direct",
              "--sky", "0.4,0.5,0.9"]],
}


def environment_map(work):
    """A small lat-long map, warm above and cool below, for ssdo's --env."""
    env = work / "scenes" / "env.exr"
    if not env.exists():
        subprocess.run(["oiiotool", "--pattern", "fill:top=2,1.6,1.2:bottom=0.1,0.2,0.4", "64x32", "3",
                        "-d", "float", "-o", str(env)], check=True)
    return str(env)


def other_configs(all_inputs, devices, isas, methods, env):
    for (name, args, r), device, method in itertools.product(all_inputs, devices, methods):
        if "--flat" in args or (method == "rtao" and device != "cpu"):
            continue
        for isa, (i, flags) in itertools.product(isas if device == "cpu" else [""], enumerate(OTHER_METHODS[method])):
            flags = [env if f == "ENV" else f for f in flags]
            ao_definition = [] if method == "ssdo" else ["--weighting", "cosine", "--falloff", "none"]
            yield (f"{name}.{device}{('-' + isa) if isa else ''}.{method}{i}",
                   args + ["--method", method, "--radius", f"{r:.6g}", "--device", device] + ao_definition + flags, isa)


def configs(all_inputs, devices, isas):
    for (name, args, r), device in itertools.product(all_inputs, devices):
        for isa in (isas if device == "cpu" else [""]):
            for t, falloff, weighting, border in itertools.product(
                    ["inf", "fixed", "auto"], ["linear", "none"], ["uniform", "cosine"], ["open", "clamp", "tangent"]):
                thickness = f"{0.3 * r:.6g}" if t == "fixed" else t
                key = f"{name}.{device}{('-' + isa) if isa else ''}.t{t}.{falloff}.{weighting}.{border}"
                flags = args + ["--radius", f"{r:.6g}", "--thickness", thickness, "--falloff", falloff,
                                "--weighting", weighting, "--border", border, "--device", device,
                                "--directions", "8", "--steps", "8", "--blur", "0"]
                yield key, flags, isa


def run_one(binary, out_dir, key, flags, isa):
    out = out_dir / f"{key}.exr"
    env = dict(os.environ)
    if isa:
        env["OBSCURA_CPU_ISA"] = isa
    cmd = [binary] + flags + ["-o", str(out), "--write", "new", "--out-type", "float", "--threads", "1", "--quiet"]
    run = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        return f"{key}: {Path(binary).name} failed: {run.stderr.strip()}"
    return None


def header(data):
    """The header's attributes (name: value bytes) and the offset just past it."""
    i = 8  # magic and version
    attributes = {}
    while data[i] != 0:
        name_end = data.index(b"\0", i)
        type_end = data.index(b"\0", name_end + 1)
        size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
        attributes[data[i:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        i = type_end + 5 + size
    return attributes, i


def channels(path):
    """The channel names of a single-part file, in its order."""
    chlist, names, i = header(Path(path).read_bytes())[0]["channels"], [], 0
    while chlist[i] != 0:  # name, then pixel type, pLinear, 3 reserved, x and y sampling: 16 bytes
        end = chlist.index(b"\0", i)
        names.append(chlist[i:end].decode())
        i = end + 1 + 16
    return names


# Scanlines per chunk of each OpenEXR compression (NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A,
# DWAA, DWAB).
LINES_PER_CHUNK = [1, 1, 1, 16, 32, 16, 32, 32, 32, 256]


def pixel_bytes(path):
    """The file's chunks (scanline y, size, pixel data) after its header and offset table: the
    header names the output, so its length, and with it the table's file offsets, differ."""
    data = Path(path).read_bytes()
    attributes, i = header(data)
    window = attributes["dataWindow"]
    y_min, y_max = (int.from_bytes(window[k:k + 4], "little", signed=True) for k in (4, 12))
    per_chunk = LINES_PER_CHUNK[attributes["compression"][0]]
    chunks = (y_max - y_min + per_chunk) // per_chunk
    return data[i + 1 + 8 * chunks:]


def same_pixels(a, b):
    """Equal pixel bytes; where one build writes more layers (a new output), the layers both
    write compared exactly (oiiotool --diff failing on any difference)."""
    ca, cb = channels(a), channels(b)
    if ca == cb:
        return pixel_bytes(a) == pixel_bytes(b)
    common = ",".join(c for c in ca if c in cb)
    print(f"note {a.name}: layers compared {common}; only before: {set(ca) - set(cb) or '-'}, "
          f"only after: {set(cb) - set(ca) or '-'}")
    run = subprocess.run(["oiiotool", str(a), "--ch", common, str(b), "--ch", common, "--fail", "0",
                          "--failpercent", "0", "--warn", "0", "--diff"], capture_output=True, text=True)
    return run.returncode == 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before", help="obscura of the build before the change")
    ap.add_argument("after", help="obscura of the current build")
    ap.add_argument("--render", default=str(ROOT / "build/examples/reference/reference_render"))
    ap.add_argument("--work", default="/tmp/obscura_same_outputs")
    ap.add_argument("--devices", default="cpu,gl-osmesa")
    ap.add_argument("--isa", default="", help="comma-separated OBSCURA_CPU_ISA values for the CPU ('' the widest)")
    ap.add_argument("--methods", default="hbao,ssao,rtao,discs,ssdo")
    ap.add_argument("--only", default="", help="run only the configurations whose name contains this")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--compare-only", action="store_true", help="compare the outputs WORK holds; run nothing")
    args = ap.parse_args()

    work = Path(args.work)
    render_scenes(str(Path(args.render).resolve()), work / "scenes")
    methods = args.methods.split(",")
    devices = args.devices.split(",")
    todo = list(configs(inputs(work / "scenes"), devices, args.isa.split(","))) if "hbao" in methods else []
    todo += other_configs(inputs(work / "scenes"), devices, args.isa.split(","), [m for m in methods if m != "hbao"],
                          environment_map(work))
    todo = [c for c in todo if args.only in c[0]]
    errors = []
    for label, binary, reuse in (("before", args.before, True), ("after", args.after, False)):
        out_dir = work / label
        out_dir.mkdir(parents=True, exist_ok=True)
        pending = [c for c in todo if not ((reuse or args.compare_only) and (out_dir / f"{c[0]}.exr").exists())]
        with ThreadPoolExecutor(args.jobs) as pool:
            errors += [e for e in pool.map(lambda c: run_one(binary, out_dir, *c), pending) if e]
    for e in errors:
        print(e)
    differ = []
    for key, _, _ in todo:
        a, b = work / "before" / f"{key}.exr", work / "after" / f"{key}.exr"
        if a.exists() and b.exists() and not same_pixels(a, b):
            diff = subprocess.run(["oiiotool", str(a), str(b), "--diff"], capture_output=True, text=True).stdout
            differ.append(key)
            print(f"DIFFERS {key}\n  " + "\n  ".join(l for l in diff.splitlines() if "error" in l or "pixel" in l))
    same = len(todo) - len(differ) - len(errors)
    print(f"same_outputs: {same} of {len(todo)} configurations bit-identical, {len(differ)} differ, "
          f"{len(errors)} failed")
    return 1 if differ or errors else 0


if __name__ == "__main__":
    sys.exit(main())
