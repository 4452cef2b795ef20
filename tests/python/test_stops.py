"""A run stopped part way (Ctrl-C, a farm's SIGTERM): it stops between the operator's tiles, not
when the frame ends, and leaves no output and no temporary file behind."""
import os
import signal
import subprocess
import threading
import time

import pytest

import obscura
from conftest import CLI, synthetic_scene, write_exr

# A frame of seconds on one thread (more on a loaded machine): a stop 0.3 s in comes while its
# tiles run, whatever the machine.
W, H = 1024, 768
HEAVY = dict(directions=32, steps=48, radius=2.0, threads=1)
HEAVY_FLAGS = ["--directions", "32", "--steps", "48", "--radius", "2", "--threads", "1"]


def handles(pid, sig):
    """Whether process `pid` has a handler installed for `sig` (its SigCgt mask in /proc)."""
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("SigCgt:"):
            return bool(int(line.split()[1], 16) >> (sig - 1) & 1)
    return False


def start_and_signal(args, sig):
    """Starts the CLI, waits until it handles `sig` (a loaded machine may take a while to get
    there), then gives it a moment's work and the signal. Returns (return code, stderr)."""
    proc = subprocess.Popen([CLI, *args], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not handles(proc.pid, sig) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    time.sleep(0.2)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err


def long_frame(tmp, name="long"):
    depth, normal = synthetic_scene(W, H)
    src = tmp / f"{name}.exr"
    write_exr(src, depth, normal, sidecar=True)
    return src


def test_ctrl_c_in_python_stops_process_and_writes_nothing(tmp):
    src, out = long_frame(tmp), tmp / "long_ao.exr"
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            obscura.process(src, out, **HEAVY)
    finally:
        timer.cancel()
    assert sorted(p.name for p in tmp.iterdir()) == ["long.exr", "long.json"]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_stops_the_command_line_cleanly(tmp, sig):
    src, out = long_frame(tmp), tmp / "long_ao.exr"
    code, err = start_and_signal([str(src), "-o", str(out), *HEAVY_FLAGS], sig)
    # It ends by the signal (a shell loop around it stops too), after one line.
    assert code == -sig, err
    assert err.strip().splitlines()[-1] == f"obscura: stopped by {signal.Signals(sig).name}; nothing written", err
    assert sorted(p.name for p in tmp.iterdir()) == ["long.exr", "long.json"]


def test_a_sequence_stops_at_the_frame_it_is_on_and_resume_goes_on(tmp):
    for f in (1, 2):
        long_frame(tmp, f"shot.{f:04d}")
    pattern, out = str(tmp / "shot.####.exr"), str(tmp / "ao.####.exr")
    code, err = start_and_signal([pattern, "-o", out, *HEAVY_FLAGS], signal.SIGTERM)
    assert code == -signal.SIGTERM, err
    assert "stopped by SIGTERM; frame 1 is not written (--resume goes on from there)" in err, err
    assert not any(p.name.startswith("ao.") for p in tmp.iterdir())
    # What is left is a clean start: --resume runs both frames (at a light setting).
    done = subprocess.run([CLI, pattern, "-o", out, "--resume", "--directions", "2", "--steps", "2"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp.iterdir() if p.name.startswith("ao.")) == ["ao.0001.exr", "ao.0002.exr"]


def test_an_ignored_sigint_stays_ignored(tmp):
    """A parent that ignores SIGINT (a job started with & by a script) keeps it ignored."""
    src, out = long_frame(tmp), tmp / "long_ao.exr"
    light = ["--directions", "8", "--steps", "8", "--threads", "1"]
    proc = subprocess.Popen([CLI, str(src), "-o", str(out), *light], stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    assert out.exists()


def test_a_signal_during_the_write_ends_by_it_after_a_whole_file(tmp):
    """SIGTERM while the output's temp file is there (the frame's files are being written): the
    write finishes, the files are whole, then the process ends by the signal, so a wrapper running
    one frame at a time sees it, not success."""
    import OpenImageIO as oiio
    src, out = long_frame(tmp), tmp / "long_ao.exr"
    light = ["--directions", "2", "--steps", "2", "--threads", "1", "--out-type", "float"]
    proc = subprocess.Popen([CLI, str(src), "-o", str(out), "--report", str(tmp / "r.json"), *light],
                            stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while proc.poll() is None and time.monotonic() < deadline:
        if any(p.name.startswith("long_ao.exr.tmp-") for p in tmp.iterdir()):
            proc.send_signal(signal.SIGTERM)
            break
        time.sleep(0.0002)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == -signal.SIGTERM, err
    assert err.strip().splitlines()[-1] == "obscura: stopped by SIGTERM; the frame was written whole first", err
    written = oiio.ImageBuf(str(out))
    assert written.read() and written.spec().width == W, written.geterror()
    assert (tmp / "r.json").exists() and not any(".tmp-" in p.name for p in tmp.iterdir())
