"""Throwaway farm engines on 127.0.0.1 for the farm tests and tests/bench/bench_farm.py.

SlurmCluster: munged, slurmctld and one slurmd from Debian's munge and slurm-wlm, with a
generated slurm.conf (proctrack/pgid, task/none, no accounting) and every key, socket, state,
log and pid file under one directory. Its slurmctld starts a batch job at its next one-second tick
(batch_sched_delay=0) instead of collecting submissions for up to Slurm's default 3 s, a
throughput setting for sites taking thousands of submissions that only delays a test. DaskCluster: dask-scheduler and worker processes.
Both are context managers that stop every process they started; start() raises
EngineUnavailable with the reason when the engine cannot run here.
"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path


class EngineUnavailable(Exception):
    pass


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(check, timeout, what, period=0.1):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if check():
            return
        time.sleep(period)
    raise TimeoutError(f"timed out after {timeout} s waiting for {what}")


class _Processes:
    """Daemons started in their own process groups, stopped (TERM, then KILL) on exit."""

    def __init__(self, root):
        self.root = Path(root)
        self.procs = []

    def start(self, name, cmd, env=None):
        log = open(self.root / f"{name}.out", "w")
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        log.close()
        self.procs.append((name, proc))
        return proc

    def output(self, name):
        path = self.root / f"{name}.out"
        return path.read_text(errors="replace") if path.exists() else ""

    def stop(self):
        for _, p in reversed(self.procs):
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
        for _, p in reversed(self.procs):
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                p.wait(timeout=10)
        self.procs = []


class _Cluster:
    """A context manager over start() and stop(): a start that fails stops what it started."""

    def __enter__(self):
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()


SLURM_CONF = """\
ClusterName=obscuratest
SlurmctldHost=localhost(127.0.0.1)
SlurmUser={user}
SlurmdUser={user}
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
AuthType=auth/munge
AuthInfo=socket={root}/munge/munge.socket
CredType=cred/munge
StateSaveLocation={root}/state
SlurmdSpoolDir={root}/spool
SlurmctldPidFile={root}/slurmctld.pid
SlurmdPidFile={root}/slurmd.pid
SlurmctldLogFile={root}/slurmctld.log
SlurmdLogFile={root}/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay={batch_sched_delay}
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MailProg=/bin/true
NodeName=obscuranode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN
PartitionName=obscura Nodes=obscuranode Default=YES MaxTime=INFINITE State=UP
"""


class SlurmCluster(_Cluster):
    """A one-node Slurm cluster with `cpus` CPUs; env holds SLURM_CONF for sbatch/squeue.
    Its files live in a fresh directory under /tmp, removed on stop: slurmstepd's Unix sockets
    go in the spool directory, and a socket path may not exceed 108 bytes."""

    def __init__(self, cpus=2, batch_sched_delay=0):
        self.batch_sched_delay = batch_sched_delay
        self.root = Path(tempfile.mkdtemp(prefix="obscura-slurm-", dir="/tmp"))
        self.cpus = cpus
        self.procs = _Processes(self.root)
        self.env = dict(os.environ, SLURM_CONF=str(self.root / "slurm.conf"))

    def start(self):
        for tool in ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"):
            if not shutil.which(tool) and not os.path.exists(f"/usr/sbin/{tool}"):
                raise EngineUnavailable(f"{tool} is not installed (scripts/setup.sh installs munge and slurm-wlm)")
        if os.geteuid() != 0:
            raise EngineUnavailable("slurmd must run as root to start jobs as the submitting user")
        (self.root / "munge").mkdir(mode=0o711)
        for d in ("state", "spool"):
            (self.root / d).mkdir()
        key = self.root / "munge" / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        sbin = lambda tool: shutil.which(tool) or f"/usr/sbin/{tool}"  # noqa: E731
        m = self.root / "munge"
        self.procs.start("munged", [sbin("munged"), "-F", "-f", f"--key-file={key}", f"--socket={m}/munge.socket",
                                    f"--pid-file={m}/munged.pid", f"--log-file={m}/munged.log",
                                    f"--seed-file={m}/munged.seed"])
        wait_for(lambda: (m / "munge.socket").exists(), 15, "munged's socket")
        (self.root / "slurm.conf").write_text(SLURM_CONF.format(
            root=self.root, user="root", cpus=self.cpus, ctld_port=free_port(), slurmd_port=free_port(),
            batch_sched_delay=self.batch_sched_delay))
        conf = str(self.root / "slurm.conf")
        self.procs.start("slurmctld", [sbin("slurmctld"), "-D", "-f", conf], self.env)
        self.procs.start("slurmd", [sbin("slurmd"), "-D", "-f", conf, "-N", "obscuranode"], self.env)
        try:
            wait_for(lambda: self.node_state() == "idle", 60, "the Slurm node to be idle")
        except TimeoutError:
            for name, p in self.procs.procs:
                if p.poll() is not None:
                    tail = self.procs.output(name).strip().splitlines()[-3:]
                    raise EngineUnavailable(f"{name} exited ({p.returncode}): {' | '.join(tail)}") from None
            raise EngineUnavailable(f"the Slurm node did not become idle (state '{self.node_state()}'): "
                                    + self.log_tail("slurmd.log", 3)) from None

    def node_state(self):
        r = subprocess.run(["sinfo", "-h", "-o", "%t"], env=self.env, capture_output=True, text=True, timeout=20)
        return r.stdout.strip()

    def running(self, job_id):
        r = subprocess.run(["squeue", "-h", "-j", str(job_id), "-o", "%i"], env=self.env, capture_output=True,
                           text=True, timeout=20)
        return bool(r.stdout.strip())

    def wait(self, job_id, timeout=300):
        try:
            # squeue costs ~15 ms of CPU (its own, munged's, slurmctld's): at 10 Hz it would take
            # a tenth of a core from the tasks it waits for.
            wait_for(lambda: not self.running(job_id), timeout, f"Slurm job {job_id}", period=0.5)
        except TimeoutError as e:
            raise TimeoutError(f"{e}; slurmd.log ends:\n{self.log_tail('slurmd.log')}") from None

    def log_tail(self, name, lines=5):
        path = self.root / name
        return "".join(path.read_text(errors="replace").splitlines(True)[-lines:]) if path.exists() else ""

    def stop(self):
        self.procs.stop()
        shutil.rmtree(self.root, ignore_errors=True)


class DaskCluster(_Cluster):
    """dask-scheduler and `workers` single-threaded worker processes (no nanny: a killed worker
    stays dead, as a lost node would). address is the scheduler's."""

    def __init__(self, root, workers=2, threads=1, env=None):
        self.root = Path(root).resolve()
        self.workers = workers
        self.threads = threads
        self.env = dict(os.environ, **(env or {}))
        self.procs = _Processes(self.root)
        self.worker_procs = []
        self.address = None

    def start(self):
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise EngineUnavailable("python3-distributed is not installed (scripts/setup.sh installs it)") from None
        self.root.mkdir(parents=True, exist_ok=True)
        port = free_port()
        self.address = f"tcp://127.0.0.1:{port}"
        py = [sys.executable, "-m"]
        self.procs.start("scheduler", [*py, "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                       "--port", str(port), "--no-dashboard", "--no-show"], self.env)
        for i in range(self.workers):
            self.worker_procs.append(self.procs.start(
                f"worker{i}", [*py, "distributed.cli.dask_worker", self.address, "--host", "127.0.0.1",
                               "--nthreads", str(self.threads), "--no-nanny", "--no-dashboard",
                               "--name", f"worker{i}", "--death-timeout", "60",
                               "--local-directory", str(self.root / f"worker{i}")], self.env))
        from distributed import Client
        try:
            with Client(self.address, timeout=60) as client:
                client.wait_for_workers(self.workers, timeout=60)
        except Exception as e:
            raise EngineUnavailable(f"the Dask cluster did not start: {e}; see {self.root}") from None

    def stop(self):
        self.procs.stop()
