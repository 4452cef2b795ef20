"""Frames x variants as farm work: one task per (frame, variant), each an obscura.process call.

    from distributed import Client
    import obscura.farm
    result = obscura.farm.run_dask(Client("tcp://10.0.0.5:8786"), ["shot.1001.exr", "shot.1002.exr"],
                                   {"r0.5": {"radius": 0.5}, "r1": {"radius": 1.0}},
                                   out_dir="out", weighting="cosine")

A task writes OUT/<variant>/<input file name> and its report OUT/<variant>/<name>.json, which
records the variant. A task is complete when its output and report exist, are newer than the
input and the report records the same variant (its settings as recorded() gives them: threads
and device aside); with resume those are skipped, on the client
and again on the worker (a task re-run after its worker died may find its work done). Outputs
and reports are written to a temp file and renamed; a task starting a frame first removes the
temp files a killed run left (those whose writer process is gone). examples/batch_ao.py uses
the same rules, so local and Dask runs resume each other's work.

obscura.process releases the GIL while it computes, so a worker's threads run frames in parallel.
"""
import json
import os
import sys
import threading
import time

from . import _obscura

__all__ = ["run_dask", "output_paths", "is_complete", "write_report", "remove_stale_temps", "render"]


def output_paths(out_dir, variant_name, src):
    """(output, report) of one input frame under one variant."""
    out = os.path.join(out_dir, variant_name, os.path.basename(src))
    return out, os.path.splitext(out)[0] + ".json"


def is_complete(src, out, report, record):
    """The output and its report exist, are newer than the input, and the report holds `record`."""
    try:
        src_time = os.path.getmtime(src)
        if os.path.getmtime(out) < src_time or os.path.getmtime(report) < src_time:
            return False
        with open(report) as f:
            recorded = json.load(f).get("batch_variant")
    except (OSError, ValueError):
        return False
    return recorded == record


def write_report(path, report, record):
    """The frame's report with the variant recorded, written atomically (resume reads it)."""
    report = dict(report, batch_variant=record)
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
    result = _obscura.process(src, out, report=report, **settings)
    write_report(report, result, record)
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
    """[(name, settings, record)] from {name: settings} or objects with .name, .settings (.kind)."""
    items = variants.items() if isinstance(variants, dict) else [(v.name, v) for v in variants]
    result = []
    for name, v in items:
        settings = dict(common)
        settings.update(v if isinstance(v, dict) else v.settings)
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
    the keyword settings apply to every variant (obscura.process keywords). Outputs go to
    OUT/<variant>/<file name>, reports next to them. With resume, complete tasks are skipped.
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
    tasks, skipped = [], 0
    for name, merged, record in plan:
        os.makedirs(os.path.join(out_dir, name), exist_ok=True)
        check_settings(name, merged, os.path.join(out_dir, name))
        for src in frames:
            out, report = output_paths(out_dir, name, src)
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
