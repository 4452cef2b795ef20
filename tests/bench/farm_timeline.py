"""Where a farm run's time goes, for tests/bench/bench_farm.py: when each task ran (relative to
submission) and the CPU time of every process involved, read from /proc, so that a busy machine
(whose wall times mean little) still shows what the farm itself costs.

SlurmWatch follows one array job without asking slurmctld: it finds each task's obscura process
in /proc (by its SLURM_ARRAY_* environment), samples its CPU time until it exits, and calls
squeue only once the outputs are all there (squeue costs about 12 ms of CPU, plus munged's and
slurmctld's share, per call; polling it at 10 Hz takes a tenth of a core from the tasks).
"""
import os
import subprocess
import time

TICK = os.sysconf("SC_CLK_TCK")


def boot_clock():
    """Seconds since boot: the clock /proc/PID/stat start times count on."""
    return time.clock_gettime(time.CLOCK_BOOTTIME)


def proc_stat(pid):
    """(user+system CPU seconds, start time in seconds since boot) of a live process, else None."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / TICK, int(fields[19]) / TICK


def cpu_seconds(pids):
    """{name: CPU seconds so far} of named live processes."""
    return {name: (proc_stat(pid) or (0.0, 0.0))[0] for name, pid in pids.items()}


def cpu_delta(before, after):
    return {name: after[name] - before.get(name, 0.0) for name in after}


class Task:
    def __init__(self, pid, start):
        self.pid, self.start, self.end, self.cpu = pid, start, None, 0.0


class SlurmWatch:
    """Follows array job `job` of `ntasks` tasks running executable `exe`, until every path in
    `outputs` exists and the job has left the queue. Times are seconds after `origin` (a
    boot_clock() value taken just before submission)."""

    def __init__(self, cluster, job, ntasks, exe, outputs, origin):
        self.cluster, self.job, self.ntasks = cluster, str(job), ntasks
        self.exe, self.outputs, self.origin = os.path.realpath(exe), outputs, origin
        self.tasks = {}      # array index -> Task
        self.steps = {}      # slurmstepd pid -> CPU seconds last seen
        self.outputs_done = self.job_gone = None
        self.squeue_calls = 0

    def _scan(self):
        """New task processes and slurmstepd processes in /proc."""
        for entry in os.listdir("/proc"):
            if not entry.isdigit():
                continue
            pid = int(entry)
            if any(t.pid == pid for t in self.tasks.values()):
                continue
            try:
                # A task's process is slurmstepd until it execs the script (and obscura), so a
                # slurmstepd pid is looked at again on the next scan.
                exe = os.readlink(f"/proc/{pid}/exe")
                if os.path.basename(exe).startswith("slurmstepd"):  # Debian: slurmstepd-wlm
                    self.steps.setdefault(pid, 0.0)
                    continue
                if exe != self.exe:
                    continue
                with open(f"/proc/{pid}/environ") as f:
                    env = dict(v.split("=", 1) for v in f.read().split("\0") if "=" in v)
            except OSError:
                continue
            if env.get("SLURM_ARRAY_JOB_ID") == self.job and "SLURM_ARRAY_TASK_ID" in env:
                st = proc_stat(pid)
                if st:
                    self.tasks[int(env["SLURM_ARRAY_TASK_ID"])] = Task(pid, st[1] - self.origin)
                    self.steps.pop(pid, None)

    def _sample(self, now):
        for task in self.tasks.values():
            if task.end is None:
                st = proc_stat(task.pid)
                if st:
                    task.cpu = st[0]
                else:
                    task.end = now
        for pid in self.steps:
            st = proc_stat(pid)
            if st:
                self.steps[pid] = st[0]

    def _in_queue(self):
        self.squeue_calls += 1
        return self.cluster.running(self.job)

    def run(self, timeout=3600, period=0.05):
        deadline = time.monotonic() + timeout
        last_squeue = time.monotonic()
        while time.monotonic() < deadline:
            now = boot_clock() - self.origin
            if len(self.tasks) < self.ntasks:
                self._scan()
            self._sample(now)
            if self.outputs_done is None and all(os.path.exists(p) for p in self.outputs):
                self.outputs_done = now
            running = any(t.end is None for t in self.tasks.values())
            # squeue only when the work looks finished, or once a second as a safeguard (a
            # task that failed before its process could be seen).
            if (self.outputs_done is not None and not running) or time.monotonic() - last_squeue > 1.0:
                last_squeue = time.monotonic()
                if not self._in_queue():
                    self.job_gone = boot_clock() - self.origin
                    return self
            time.sleep(period)
        raise TimeoutError(f"Slurm job {self.job} still queued after {timeout} s")

    def lines(self):
        out = []
        for i, t in sorted(self.tasks.items()):
            end = f"{t.end:6.2f}" if t.end is not None else "  ?   "
            run = t.end - t.start if t.end is not None else float("nan")
            out.append(f"task {i}: start {t.start:5.2f} s, end {end} s (ran {run:5.2f} s), CPU {t.cpu:5.2f} s")
        if self.tasks:
            out.append(f"tasks' CPU in all {sum(t.cpu for t in self.tasks.values()):.2f} s (against one process's: "
                       "each task's start-up, and what sharing the caches and memory costs)")
        if len(self.tasks) < self.ntasks:
            out.append(f"{self.ntasks - len(self.tasks)} task(s) never seen running")
        out.append(f"outputs complete at {self.outputs_done:.2f} s, job gone from squeue at {self.job_gone:.2f} s "
                   f"({self.squeue_calls} squeue calls); slurmstepd CPU {sum(self.steps.values()):.2f} s "
                   f"in {len(self.steps)} process(es)")
        return out


def run_measured(cmd, **kwargs):
    """subprocess.run with (result, wall seconds, CPU seconds of the child and its waited-for descendants)."""
    import resource
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    result = subprocess.run(cmd, **kwargs)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return result, wall, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
