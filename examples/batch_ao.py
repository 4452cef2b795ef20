#!/usr/bin/env python3
"""Batch AO over a frame sequence, one output sequence per settings variant.

    python3 examples/batch_ao.py 'shot.####.exr' --frames 1-24 -o out \\
        --radii 0.25,0.5,1 --set weighting=cosine --jobs 2 --resume

Inputs: a pattern with '#' padding ('shot.####.exr') or printf style ('shot.%04d.exr'), and
a frame list ('1-24', '1-24x2', '1,5,10-12'; default: every frame on disk that matches).
Variants: --variant NAME:key=value,key=value (repeatable) and/or --radii R1,R2,... (one
variant 'r<R>' per radius); --set key=value applies to every variant. Keys are the keyword
arguments of obscura.process(), i.e. the CLI's flags with underscores (radius, directions,
steps, weighting, falloff, blur, quality, fov_deg, camera_to_world, preset, out_type, ...).

Outputs: OUT/<variant>/<input file name>, a copy of each frame with the AO layer, and next
to it <name>.json, the frame's report. OUT/batch.json records the variants and the frames
(contact_sheet.py reads it). --resume skips a frame whose output and report exist, are newer
than every file it was computed from (the input, its camera sidecar, an env= map), were made
with the same settings, and whose report's stamps of those files (path, size, mtime) are equal to
theirs now, so an input rolled back to an older version is computed again (outputs are written
atomically, so an existing file is a complete one). Two frames that would write one output (the
frame number in a directory name: 'sh###/beauty.exr') are refused before anything is written.
Progress goes to stderr; the exit status is 1 if any frame failed (the others are still done).

Each variant has a `kind` ("ao"): a renderer registered in RENDERERS turns (input frame,
output frame, settings) into a report. Relighting variants (environment maps, rotations)
will register another kind here; the sequence, resume and progress logic stays the same.

Needs the obscura module (build/plugin/python on PYTHONPATH, or installed) and Debian's
python3-numpy; run it with Debian's interpreter (/usr/bin/python3).
"""
import argparse
import glob
import json
import os
import re
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field

import obscura
from obscura import farm

# ------------------------------------------------------------------------------------------
# Frame patterns


def parse_pattern(pattern):
    """'shot.####.exr' / 'shot.%04d.exr' -> (prefix, padding, suffix)."""
    m = re.search(r"%0?(\d*)d", pattern)
    if m:
        return pattern[: m.start()], int(m.group(1) or 1), pattern[m.end():]
    m = re.search(r"#+", pattern)
    if m:
        return pattern[: m.start()], len(m.group(0)), pattern[m.end():]
    raise ValueError(f"pattern '{pattern}' has no frame number ('####' or '%04d')")


def frame_path(pattern, frame):
    prefix, pad, suffix = parse_pattern(pattern)
    sign = "-" if frame < 0 else ""
    return f"{prefix}{sign}{abs(frame):0{pad}d}{suffix}"


def parse_frames(spec):
    """'1-24', '1-24x2', '1,5,10-12' -> sorted unique frame numbers."""
    frames = set()
    for part in spec.split(","):
        part = part.strip()
        m = re.fullmatch(r"(-?\d+)(?:-(-?\d+)(?:x(\d+))?)?", part)
        if not m:
            raise ValueError(f"bad frame range '{part}' (expected e.g. 1-24, 1-24x2 or 1,5,10-12)")
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        step = int(m.group(3) or 1)
        if last < first or step < 1:
            raise ValueError(f"bad frame range '{part}'")
        frames.update(range(first, last + 1, step))
    return sorted(frames)


def frames_on_disk(pattern):
    prefix, pad, suffix = parse_pattern(pattern)
    rx = re.compile(re.escape(os.path.basename(prefix)) + r"(-?\d+)" + re.escape(suffix) + "$")
    found = []
    for p in glob.glob(glob.escape(prefix) + "*" + glob.escape(suffix)):
        m = rx.match(os.path.basename(p))
        if m and len(m.group(1).lstrip("-")) >= pad:
            found.append(int(m.group(1)))
    return sorted(set(found))


# ------------------------------------------------------------------------------------------
# Variants


def parse_value(text):
    """'0.5' -> 0.5, '8' -> 8, 'true' -> True, '1,0,0,...' -> list, 'a=b;c=d' -> dict, else str."""
    low = text.lower()
    if low in ("true", "false"):
        return low == "true"
    if low == "none":
        return None
    if "=" in text:
        return dict(item.split("=", 1) for item in text.split(";"))
    if "," in text:
        return [parse_value(t) for t in text.split(",")]
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return text


def parse_assignments(text):
    """'radius=0.5 weighting=cosine' or 'radius=0.5,weighting=cosine' -> dict.
    Lists use spaces between items only inside [] (camera_to_world=[1,0,...])."""
    settings = {}
    for item in re.findall(r"[^,\s\[]+=(?:\[[^\]]*\]|[^,\s]+)", text):
        key, value = item.split("=", 1)
        if value.startswith("["):
            value = [parse_value(v) for v in value[1:-1].split(",") if v]
        else:
            value = parse_value(value)
        settings[key.replace("-", "_")] = value
    return settings


@dataclass
class Variant:
    name: str
    settings: dict = field(default_factory=dict)
    kind: str = "ao"

    def __post_init__(self):
        # As run_dask makes them, so a local run and a Dask run record the same settings.
        self.settings = farm.absolute_paths(self.settings)

    def to_json(self):
        return {"name": self.name, "kind": self.kind, "settings": farm.recorded(self.settings)}


def radius_name(r):
    return "r" + (f"{r:g}")


def build_variants(variant_specs, radii, common):
    variants = []
    for spec in variant_specs or []:
        name, _, rest = spec.partition(":")
        farm.check_variant_name(name)
        settings = dict(common)
        settings.update(parse_assignments(rest))
        kind = settings.pop("kind", "ao")
        variants.append(Variant(name, settings, kind))
    for r in radii or []:
        settings = dict(common)
        settings["radius"] = r
        variants.append(Variant(radius_name(r), settings))
    if not variants:
        variants.append(Variant("default", dict(common)))
    names = [v.name for v in variants]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise ValueError(f"duplicate variant names: {', '.join(sorted(dupes))}")
    for v in variants:
        if v.kind not in RENDERERS:
            raise ValueError(f"variant '{v.name}': unknown kind '{v.kind}' (available: {', '.join(RENDERERS)})")
    return variants


# ------------------------------------------------------------------------------------------
# Renderers: one per variant kind. Each writes `out` (and the report) atomically, returns the report.


def render_ao(src, out, settings, report_path):
    return obscura.process(src, out, report=report_path, **settings)


RENDERERS = {"ao": render_ao}


# ------------------------------------------------------------------------------------------
# The batch


@dataclass
class Task:
    variant: Variant
    frame: int
    src: str
    out: str
    report: str


def is_complete(task):
    """obscura.farm's rule (so local and Dask runs resume each other's work): the output and its
    report exist, are newer than the files the frame reads, match the settings, and the report's
    stamps of those files equal theirs now."""
    return farm.is_complete(task.src, task.out, task.report, task.variant.to_json())


def run_task(task):
    """Renders one output; returns its seconds and its report's warnings."""
    t0 = time.perf_counter()
    farm.remove_stale_temps(task.out)
    farm.remove_stale_temps(task.report)
    inputs = farm.stamps(farm.files_read(task.src, task.variant.settings))  # as they are before reading
    report = RENDERERS[task.variant.kind](task.src, task.out, task.variant.settings, task.report)
    # Record the variant and the inputs' stamps, so --resume can tell a stale output from a complete one.
    farm.write_report(task.report, report, task.variant.to_json(), inputs)
    return time.perf_counter() - t0, report.get("warnings", [])


def write_manifest(out_dir, pattern, frames, variants):
    """OUT/batch.json: the pattern, frames and variants, merged with what an earlier run into the
    same directory recorded for the same pattern, so that a narrower re-run (one variant, a few
    frames) does not drop the others from the contact sheet."""
    prefix, pad, suffix = parse_pattern(pattern)
    name = os.path.basename(prefix) + "#" * pad + suffix
    entries = [dict(v.to_json(), output=os.path.join(v.name, name)) for v in variants]
    try:
        with open(os.path.join(out_dir, "batch.json")) as f:
            earlier = json.load(f)
    except (OSError, ValueError):
        earlier = {}
    if isinstance(earlier, dict) and earlier.get("pattern") == os.path.abspath(pattern):
        names = {e["name"] for e in entries}
        entries = [e for e in earlier.get("variants", []) if e.get("name") not in names] + entries
        frames = sorted(set(earlier.get("frames", [])) | set(frames))
    manifest = {
        "pattern": os.path.abspath(pattern),
        "frames": frames,
        "variants": entries,
        "obscura": obscura.__version__,
    }
    tmp = os.path.join(out_dir, f".batch.json.tmp-{os.getpid()}")
    with open(tmp, "w") as f:
        json.dump(manifest, f, indent=2)
    os.replace(tmp, os.path.join(out_dir, "batch.json"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("pattern", help="input frames: shot.####.exr or shot.%%04d.exr")
    ap.add_argument("-o", "--out-dir", required=True, help="output directory (one subdirectory per variant)")
    ap.add_argument("--frames", help="frame list: 1-24, 1-24x2, 1,5,10-12 (default: every matching file)")
    ap.add_argument("--variant", action="append", metavar="NAME:key=value,...", help="a settings variant")
    ap.add_argument("--radii", help="comma-separated radii: one variant r<R> per radius")
    ap.add_argument("--set", action="append", default=[], metavar="key=value", help="setting for every variant")
    ap.add_argument("--resume", action="store_true", help="skip frames whose output is complete")
    ap.add_argument("--jobs", type=int, default=1, help="frames computed at once (threads; default 1)")
    ap.add_argument("--dry-run", action="store_true", help="list what would be done")
    ap.add_argument("--quiet", action="store_true", help="print only errors and the summary")
    args = ap.parse_args(argv)

    try:
        parse_pattern(args.pattern)
        frames = parse_frames(args.frames) if args.frames else frames_on_disk(args.pattern)
        common = {}
        for s in args.set:
            common.update(parse_assignments(s))
        radii = [float(r) for r in args.radii.split(",")] if args.radii else []
        variants = build_variants(args.variant, radii, common)
    except ValueError as e:
        ap.error(str(e))
    if not frames:
        ap.error(f"no frames match '{args.pattern}' (give --frames)")
    if args.jobs < 1:
        ap.error("--jobs must be at least 1")

    try:
        return run_batch("batch_ao", args.pattern, frames, variants, args.out_dir, resume=args.resume,
                         jobs=args.jobs, dry_run=args.dry_run, quiet=args.quiet)
    except ValueError as e:  # frames that would write one output: refused before writing
        ap.error(str(e))


def run_batch(tool, pattern, frames, variants, out_dir, resume=False, jobs=1, dry_run=False, quiet=False):
    """Every (variant, frame): skips complete outputs with `resume`, prints progress with an ETA
    to stderr, writes OUT/batch.json. Returns the exit status: 1 if any frame failed, else 0; raises
    ValueError, writing nothing, where two frames would write one output.
    Shared by batch_relight.py (and any other batch over registered RENDERERS)."""
    srcs = {frame: frame_path(pattern, frame) for frame in frames}
    paths = farm.plan_outputs(out_dir, [v.name for v in variants], list(srcs.values()))
    tasks = [Task(v, frame, src, *paths[v.name, src]) for v in variants for frame, src in srcs.items()]
    todo = [t for t in tasks if not (resume and is_complete(t))]
    skipped = len(tasks) - len(todo)
    log = (lambda *a: None) if quiet else (lambda msg: print(msg, file=sys.stderr, flush=True))
    log(f"{tool}: {len(frames)} frame(s) x {len(variants)} variant(s) = {len(tasks)} output(s); "
        f"{skipped} complete, {len(todo)} to do")
    if dry_run:
        for t in todo:
            print(f"{t.variant.name}: {t.src} -> {t.out}")
        return 0

    os.makedirs(out_dir, exist_ok=True)
    for v in variants:
        os.makedirs(os.path.join(out_dir, v.name), exist_ok=True)
    write_manifest(out_dir, pattern, frames, variants)

    failures = []
    t_start = time.perf_counter()
    width = len(str(len(todo)))
    warned = set()  # each distinct warning printed once, not once a frame
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_task, t): t for t in todo}
        for i, fut in enumerate(as_completed(futures), 1):
            t = futures[fut]
            elapsed = time.perf_counter() - t_start
            eta = elapsed / i * (len(todo) - i)
            try:
                seconds, warnings = fut.result()
                log(f"[{i:{width}}/{len(todo)}] {t.variant.name} frame {t.frame}: {seconds:.2f} s  "
                    f"(elapsed {elapsed:.1f} s, eta {eta:.1f} s)")
                for w in warnings:
                    if w not in warned:
                        warned.add(w)
                        log(f"{tool}: warning: {w} (first at {t.variant.name} frame {t.frame})")
            except (obscura.Error, ValueError, TypeError, OSError) as e:
                failures.append((t, str(e)))
                print(f"[{i:{width}}/{len(todo)}] {t.variant.name} frame {t.frame}: FAILED: {e}",
                      file=sys.stderr, flush=True)
    done = len(todo) - len(failures)
    print(f"{tool}: {done} written, {skipped} skipped (complete), {len(failures)} failed "
          f"in {time.perf_counter() - t_start:.1f} s -> {out_dir}", file=sys.stderr)
    if failures:
        print(f"{tool}: failed:", file=sys.stderr)
        for t, err in failures:
            print(f"  {t.variant.name} frame {t.frame} ({t.src}): {err}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
