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
    proc = subprocess.Popen([CLI, str(src), "-o", str(out), *HEAVY_FLAGS], stderr=subprocess.PIPE, text=True)
    time.sleep(0.3)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    assert err.strip().splitlines()[-1] == f"obscura: stopped by {signal.Signals(sig).name}; nothing written", err
    assert sorted(p.name for p in tmp.iterdir()) == ["long.exr", "long.json"]


def test_a_sequence_stops_at_the_frame_it_is_on_and_resume_goes_on(tmp):
    for f in (1, 2):
        long_frame(tmp, f"shot.{f:04d}")
    pattern, out = str(tmp / "shot.####.exr"), str(tmp / "ao.####.exr")
    proc = subprocess.Popen([CLI, pattern, "-o", out, *HEAVY_FLAGS], stderr=subprocess.PIPE, text=True)
    time.sleep(0.3)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert "stopped by SIGTERM at frame 1, which is not written" in err, err
    assert not any(p.name.startswith("ao.") for p in tmp.iterdir())
    # What is left is a clean start: --resume runs both frames (at a light setting).
    done = subprocess.run([CLI, pattern, "-o", out, "--resume", "--directions", "2", "--steps", "2"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp.iterdir() if p.name.startswith("ao.")) == ["ao.0001.exr", "ao.0002.exr"]
