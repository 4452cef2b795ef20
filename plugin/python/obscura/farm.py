"""Frames x variants as farm work: one task per (frame, variant), each an obscura.process call.

    from distributed import Client
    import obscura.farm
    result = obscura.farm.run_dask(Client("tcp://10.0.0.5:8786"), ["shot.1001.exr", "shot.1002.exr"],
                                   {"r0.5": {"radius": 0.5}, "r1": {"radius": 1.0}},
                                   out_dir="out", weighting="cosine")

A task writes OUT/<variant>/<input file name> and its report OUT/<variant>/<name>.json, which
records the variant and a stamp (absolute path, size, mtime) of each file the task reads: the
input, its camera sidecar and the environment map (files_read). Two frames with one file name
are refused before anything is written: they would write one output. A task is complete when its
output and report exist, are newer than every file it reads, and the report records the same
variant (its settings as recorded() gives them: threads and device aside) and the same stamps as
the files have now, so a file rolled back to an older version counts as changed; with resume those
are skipped, on the client
and again on the worker (a task re-run after its worker died may find its work done). Outputs
and reports are written to a temp file and renamed; a task starting a frame first removes the
temp files a killed run left (those whose writer process is gone). examples/batch_ao.py uses
the same rules, so local and Dask runs resume each other's work.

obscura.process releases the GIL while it computes, so a worker's threads run frames in parallel.
"""
import json
import os
import re
import sys
import threading
import time

from . import _obscura

__all__ = ["run_dask", "output_paths", "plan_outputs", "files_read", "stamps", "is_complete", "write_report",
           "remove_stale_temps", "render"]

# process() keywords naming a file it reads: made absolute on the client (a worker's cwd is its
# own), and compared by resume as the input is.
PATH_SETTINGS = ("camera", "env")


def output_paths(out_dir, variant_name, src):
    """(output, report) of one input frame under one variant."""
    out = os.path.join(out_dir, variant_name, os.path.basename(src))
    return out, os.path.splitext(out)[0] + ".json"


def check_variant_name(name):
    """A variant's name is its output directory: one plain name, never a path out of OUT."""
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.+-]+", name) or name in (".", ".."):
        raise ValueError(f"variant name {name!r} must be letters, digits, '_', '.', '+' or '-' (not '.' or '..')")


def plan_outputs(out_dir, names, frames):
    """{(variant name, input): (output, report)}, or ValueError, before anything is written, for a
    name that is not a plain directory name or two inputs with one output (frames with one file
    name in two directories, or one frame listed twice): the second task would find the first's
    output complete and skip, and the run would report success."""
    paths, written = {}, {}
    for name in names:
        check_variant_name(name)
        for src in frames:
            out, report = output_paths(out_dir, name, src)
            if out in written:
                raise ValueError(f"'{written[out]}' and '{src}' are both written to '{out}'; nothing written"
                                 if written[out] != src else f"'{src}' is listed twice (its output '{out}'); "
                                 "nothing written")
            written[out] = src
            paths[name, src] = out, report
    return paths


def absolute_paths(settings):
    """The settings with their file paths (PATH_SETTINGS) absolute, as a worker elsewhere needs them."""
    return {k: os.path.abspath(v) if k in PATH_SETTINGS and isinstance(v, (str, os.PathLike)) else v
            for k, v in settings.items()}


def _is_sidecar(path):
    """process()'s test for NAME.json beside the input: a file, and not an obscura report."""
    try:
        with open(path) as f:
            j = json.load(f)
    except ValueError:
        return True
    except OSError:
        return False
    return not (isinstance(j, dict) and {"timings_s", "settings", "recipe"} <= j.keys())


def files_read(src, settings):
    """The files a task reads that exist, as the CLI's --resume lists them: the input, the camera
    sidecar (camera=, else NAME.json or NAME.exr.json beside the input, as process() finds it) and
    the environment map (env=)."""
    camera = settings.get("camera")
    if camera is None:
        camera = next((c for c in (os.path.splitext(src)[0] + ".json", src + ".json") if _is_sidecar(c)), None)
    return [os.fspath(f) for f in (src, camera, settings.get("env")) if f is not None and os.path.isfile(f)]


def stamps(files):
    """Each file's absolute path, size and mtime: what the report records and resume compares for
    equality, as a newer-than test misses an input rolled back to an older version (a link
    re-pointed to an earlier render, a copy keeping its older mtime). Where links lead is not
    compared: hosts that mount one project under other names resolve them differently."""
    result = []
    for f in files:
        st = os.stat(f)
        result.append({"path": os.path.abspath(f), "size": st.st_size, "mtime_ns": st.st_mtime_ns})
    return result


def is_complete(src, out, report, record):
    """The output and its report exist, are newer than every file the task reads (files_read of
    the record's settings), and the report holds `record` and those files' stamps as they are now.
    A report without stamps (an older obscura's) is not complete."""
    try:
        files = files_read(src, record.get("settings", {}))
        written = min(os.stat(out).st_mtime_ns, os.stat(report).st_mtime_ns)
        if any(os.stat(f).st_mtime_ns > written for f in files):
            return False
        with open(report) as f:
            held = json.load(f)
        return held.get("batch_variant") == record and held.get("batch_inputs") == stamps(files)
    except (OSError, ValueError, AttributeError):
        return False


def write_report(path, report, record, inputs):
    """The frame's report with the variant and the stamps of the files read (`inputs`, taken
    before computing) recorded, written atomically (resume reads it)."""
    report = dict(report, batch_variant=record, batch_inputs=inputs)
    tmp = f"{path}.tmp-{os.getpid()}-{threading.get_ident()}"
    with open(tmp, "w") as f:
        json.dump(report, f, indent=2)
    os.replace(tmp, path)


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_temps(path):
    """Removes '<path>.tmp-<pid>[-<thread>]' files whose writer is no longer running on this host."""
    folder, name = os.path.split(path)
    prefix = name + ".tmp-"
    removed = 0
    try:
        entries = os.listdir(folder or ".")
    except OSError:
        return 0
    for entry in entries:
        pid = entry[len(prefix):].split("-")[0]
        if entry.startswith(prefix) and pid.isdigit() and int(pid) != os.getpid() and not _alive(int(pid)):
            try:
                os.remove(os.path.join(folder, entry))
                removed += 1
            except OSError:
                pass
    return removed


def render(src, out, report, settings, record):
    """Computes one frame under one variant; returns the seconds it took."""
    t0 = time.perf_counter()
    remove_stale_temps(out)
    remove_stale_temps(report)
    inputs = stamps(files_read(src, settings))  # before reading: a file changed meanwhile leaves the task stale
    result = _obscura.process(src, out, report=report, **settings)
    write_report(report, result, record, inputs)
    return time.perf_counter() - t0


def _task(src, out, report, settings, record, resume):
    """What a Dask worker runs: ('skipped', 0) or ('done', seconds)."""
    if resume and is_complete(src, out, report, record):
        return "skipped", 0.0
    os.makedirs(os.path.dirname(out), exist_ok=True)
    return "done", render(src, out, report, settings, record)


def _plain(value):
    """A setting as JSON holds it: arrays (a numpy camera_to_world) as lists, paths as strings."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"a setting of type {type(value).__name__} cannot be recorded in a report")


def recorded(settings):
    """The settings as the report records them (tuples and arrays as lists), less the threads
    and the device, which change no result beyond GL's parity: what resume compares."""
    kept = {k: v for k, v in settings.items() if k not in ("threads", "device")}
    return json.loads(json.dumps(kept, default=_plain))


def _variants(variants, common):
    """[(name, settings, record)] from {name: settings} or objects with .name, .settings (.kind);
    file paths in the settings made absolute."""
    items = variants.items() if isinstance(variants, dict) else [(v.name, v) for v in variants]
    result = []
    for name, v in items:
        check_variant_name(name)
        settings = dict(common)
        settings.update(v if isinstance(v, dict) else v.settings)
        settings = absolute_paths(settings)
        kind = "ao" if isinstance(v, dict) else getattr(v, "kind", "ao")
        result.append((name, settings, {"name": name, "kind": kind, "settings": recorded(settings)}))
    names = [n for n, _, _ in result]
    if len(set(names)) != len(names) or not names:
        raise ValueError(f"variants need distinct names, got {names}")
    return result


def check_settings(name, settings, out_dir):
    """Raises the TypeError or ValueError obscura.process would raise for these settings (an
    unknown keyword, a value out of range), before any task is sent: a worker would fail every
    frame alike, and retry each. Runs process's own checks on an input that does not exist."""
    probe = os.path.join(out_dir, f".obscura-settings-check-{os.getpid()}")
    try:
        _obscura.process(probe + "-in.exr", probe + "-out.exr", **settings)
    except (TypeError, ValueError) as e:
        raise type(e)(f"variant {name}: {e}") from None
    except _obscura.Error:
        pass  # the probe's input does not exist: every setting was read


def run_dask(client, frames, variants, *, out_dir, resume=True, progress=True, retries=1, **settings):
    """Maps frames x variants onto a distributed.Client; each task is one obscura.process call.

    frames: input file paths. variants: {name: settings} (or objects with .name and .settings);
    the keyword settings apply to every variant (obscura.process keywords; relative file paths
    are taken from the client's directory). Outputs go to OUT/<variant>/<file name>, reports next
    to them: variant names and frames that would write outside OUT or one output twice are
    refused before anything is written. With resume, complete tasks are skipped.
    A task lost with its worker is run again elsewhere by the scheduler; a failing one is
    retried `retries` times. Progress lines go to stderr. Returns a dict: 'done', 'skipped'
    (counts), 'failed' (a list of (variant, input, error)) and 'seconds' (wall time).
    """
    from distributed import as_completed

    if isinstance(frames, (str, os.PathLike)):
        raise TypeError("frames: a list of input files (a pattern such as 'shot.####.exr' is not expanded; "
                        "use sorted(glob.glob('shot.*.exr')))")
    frames = [os.path.abspath(f) for f in frames]
    out_dir = os.path.abspath(out_dir)
    plan = _variants(variants, settings)
    paths = plan_outputs(out_dir, [name for name, _, _ in plan], frames)
    for name, merged, _ in plan:  # every variant checked before any directory is made
        check_settings(name, merged, os.path.join(out_dir, name))
    tasks, skipped = [], 0
    for name, merged, record in plan:
        os.makedirs(os.path.join(out_dir, name), exist_ok=True)
        for src in frames:
            out, report = paths[name, src]
            if resume and is_complete(src, out, report, record):
                skipped += 1
                continue
            tasks.append((name, src, out, report, merged, record))
    log = (lambda msg: print(msg, file=sys.stderr, flush=True)) if progress else (lambda msg: None)
    log(f"obscura.farm: {len(frames)} frame(s) x {len(plan)} variant(s); {skipped} complete, {len(tasks)} to do")
    start = time.perf_counter()
    futures = {}
    for name, src, out, report, merged, record in tasks:
        key = f"obscura-{name}-{os.path.basename(src)}-{time.time_ns()}"
        fut = client.submit(_task, src, out, report, merged, record, resume, key=key, pure=False, retries=retries)
        futures[fut] = (name, src)
    done, failed = 0, []
    width = len(str(len(tasks)))
    for i, fut in enumerate(as_completed(futures), 1):
        name, src = futures[fut]
        elapsed = time.perf_counter() - start
        try:
            state, seconds = fut.result()
        except Exception as e:  # the worker's exception (obscura.Error, ...) or a lost task
            failed.append((name, src, str(e)))
            log(f"[{i:{width}}/{len(tasks)}] {name} {os.path.basename(src)}: FAILED: {e}")
            continue
        skipped += state == "skipped"
        done += state == "done"
        eta = elapsed / i * (len(tasks) - i)
        log(f"[{i:{width}}/{len(tasks)}] {name} {os.path.basename(src)}: {state} {seconds:.2f} s  "
            f"(elapsed {elapsed:.1f} s, eta {eta:.1f} s)")
    result = {"done": done, "skipped": skipped, "failed": failed, "seconds": time.perf_counter() - start}
    log(f"obscura.farm: {done} written, {skipped} skipped (complete), {len(failed)} failed "
        f"in {result['seconds']:.1f} s -> {out_dir}")
    return result
