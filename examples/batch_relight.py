#!/usr/bin/env python3
"""Relight a frame sequence under several lighting setups, one output sequence per setup.

    python3 examples/batch_relight.py 'shot.####.exr' --frames 1-24 -o out \\
        --env studio.exr --env sunset.hdr --rotations 0,90,180,270 --set samples=32 --resume

Inputs: a pattern and a frame list, as batch_ao.py ('shot.####.exr' or 'shot.%04d.exr';
'1-24', '1-24x2', '1,5,10-12'; default: every matching frame on disk). The frames need the
passes SSDO relighting reads: depth, normals, albedo and direct diffuse (Blender's DiffCol and
DiffDir, or --set bounce_source=beauty / layer=albedo=NAME).

Lighting setups, each one output sequence:
  --env FILE        a lat-long environment map (repeatable); setup '<map name>'
  --rotations LIST  degrees about the up axis, applied to every --env; setups '<map>.r<deg>'
  --sky R,G,B       a constant sky (repeatable); setup 'sky_<r>_<g>_<b>'
--set key=value applies to every setup: the keyword arguments of obscura.process(), i.e. the
CLI's flags with underscores (samples, interleave, radius, env_intensity, up, lights,
relit_direct, times_albedo, bounce_source, out_type, ...).

Each setup writes OUT/<setup>/<input file name> with Relit.R/G/B (albedo x (DO + GI) / pi;
--relit-layer renames it) plus obscura.DO and obscura.GI, via obscura.process(method='ssdo',
bounce=True, out_layer={'relit': ...}), and the frame's report next to it. OUT/batch.json lists
the setups (contact_sheet.py OUT --frame N shows them side by side). Progress with an ETA goes
to stderr; --resume skips frames already complete for that setup (batch_ao.py's rule: output
and report newer than the files the frame reads, the input, its camera sidecar and the map, made
with the same settings and from those files as they are now); failed frames are listed at the
end and the exit status is 1.

--scheduler ADDRESS runs the same tasks on a Dask cluster (obscura.farm.run_dask; Debian's
python3-distributed): one task per frame and setup, the same outputs and resume rule, and a
task lost with its worker is run again elsewhere. --jobs is then the cluster's business.

Sequence handling, resume and progress are batch_ao.py's (imported, not copied).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import batch_ao  # noqa: E402
from batch_ao import Variant  # noqa: E402

import obscura  # noqa: E402


def render_relight(src, out, settings, report_path):
    return obscura.process(src, out, report=report_path, **settings)


batch_ao.RENDERERS["relight"] = render_relight


def _number_name(x):
    return f"{x:g}".replace("-", "m")


def _numbers(text, what, count=None):
    try:
        values = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        raise ValueError(f"{what} expects comma-separated numbers, got '{text}'") from None
    if not values or (count and len(values) != count):
        raise ValueError(f"{what} expects {count or 'some'} comma-separated numbers, got '{text}'")
    return values


def build_setups(envs, rotations, skies, common, relit_layer="Relit"):
    """The lighting setups as batch_ao Variants of kind 'relight'."""
    base = dict(common)
    base.update(method="ssdo", bounce=True)
    out_layer = dict(base.get("out_layer") or {}) if isinstance(base.get("out_layer"), dict) else {}
    out_layer["relit"] = relit_layer
    base["out_layer"] = out_layer
    setups = []
    angles = _numbers(rotations, "--rotations") if rotations else [None]
    if rotations and not envs:
        raise ValueError("--rotations turns an environment map: give --env FILE")
    for env in envs or []:
        if not os.path.isfile(env):
            raise ValueError(f"environment map '{env}' does not exist")
        stem = os.path.splitext(os.path.basename(env))[0]
        for angle in angles:
            settings = dict(base, env=os.path.abspath(env))
            name = stem
            if angle is not None:
                settings["env_rotate"] = angle
                name = f"{stem}.r{_number_name(angle)}"
            setups.append(Variant(name, settings, "relight"))
    for sky in skies or []:
        rgb = _numbers(sky, "--sky", 3)
        if min(rgb) < 0:
            raise ValueError(f"--sky must not be negative, got '{sky}'")
        settings = dict(base, sky=rgb)
        settings.pop("env", None)
        setups.append(Variant("sky_" + "_".join(_number_name(c) for c in rgb), settings, "relight"))
    if not setups:
        raise ValueError("no lighting setup: give --env FILE, --sky R,G,B (and --rotations with --env)")
    for s in setups:
        if not all(ch.isalnum() or ch in "_.+-" for ch in s.name):
            s.name = "".join(ch if ch.isalnum() or ch in "_.+-" else "_" for ch in s.name)
    names = [s.name for s in setups]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise ValueError(f"duplicate setup names: {', '.join(sorted(dupes))} (maps with the same file name?)")
    return setups


def run_on_dask(address, pattern, frames, setups, out_dir, resume, quiet):
    """The setups over the frames on the Dask scheduler at `address`; exit status 1 if any failed."""
    import obscura.farm
    from distributed import Client

    paths = [batch_ao.frame_path(pattern, f) for f in frames]
    obscura.farm.plan_outputs(out_dir, [s.name for s in setups], paths)  # refused before the manifest is written
    os.makedirs(out_dir, exist_ok=True)
    batch_ao.write_manifest(out_dir, pattern, frames, setups)
    with Client(address, timeout=60) as client:
        result = obscura.farm.run_dask(client, paths, setups, out_dir=out_dir, resume=resume, progress=not quiet)
    for name, src, err in result["failed"]:
        print(f"  {name} {src}: {err}", file=sys.stderr)
    return 1 if result["failed"] else 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("pattern", help="input frames: shot.####.exr or shot.%%04d.exr")
    ap.add_argument("-o", "--out-dir", required=True, help="output directory (one subdirectory per setup)")
    ap.add_argument("--frames", help="frame list: 1-24, 1-24x2, 1,5,10-12 (default: every matching file)")
    ap.add_argument("--env", action="append", default=[], metavar="FILE", help="a lat-long environment map")
    ap.add_argument("--rotations", metavar="DEG,...", help="rotations of each --env about the up axis")
    ap.add_argument("--sky", action="append", default=[], metavar="R,G,B", help="a constant sky setup")
    ap.add_argument("--relit-layer", default="Relit", help="name of the relit layer (default Relit)")
    ap.add_argument("--set", action="append", default=[], metavar="key=value", help="setting for every setup")
    ap.add_argument("--resume", action="store_true", help="skip frames whose output is complete")
    ap.add_argument("--jobs", type=int, default=1, help="frames computed at once (threads; default 1)")
    ap.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask cluster (e.g. tcp://farm:8786)")
    ap.add_argument("--dry-run", action="store_true", help="list what would be done")
    ap.add_argument("--quiet", action="store_true", help="print only errors and the summary")
    args = ap.parse_args(argv)

    try:
        batch_ao.parse_pattern(args.pattern)
        frames = batch_ao.parse_frames(args.frames) if args.frames else batch_ao.frames_on_disk(args.pattern)
        common = {}
        for s in args.set:
            common.update(batch_ao.parse_assignments(s))
        setups = build_setups(args.env, args.rotations, args.sky, common, args.relit_layer)
    except ValueError as e:
        ap.error(str(e))
    if not frames:
        ap.error(f"no frames match '{args.pattern}' (give --frames)")
    if args.jobs < 1:
        ap.error("--jobs must be at least 1")
    try:
        if args.scheduler and not args.dry_run:
            return run_on_dask(args.scheduler, args.pattern, frames, setups, args.out_dir, args.resume, args.quiet)
        return batch_ao.run_batch("batch_relight", args.pattern, frames, setups, args.out_dir, resume=args.resume,
                                  jobs=args.jobs, dry_run=args.dry_run, quiet=args.quiet)
    except ValueError as e:  # frames that would write one output, a setting run_dask refuses: nothing written
        ap.error(str(e))


if __name__ == "__main__":
    sys.exit(main())
