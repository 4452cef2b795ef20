"""`obscura farm slurm` (the generated array job, its chunks, submission) and `obscura farm
summary`, without a Slurm cluster: the script's tasks run under bash as Slurm would run them,
and submission goes through a stand-in sbatch. test_farm_slurm.py runs them on real Slurm."""
import json
import os
import subprocess

import pytest

from conftest import CLI, SAMPLES, synthetic_scene, write_exr


def farm(*args, env=None, cwd=None):
    return subprocess.run([CLI, "farm", *map(str, args)], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=300)


@pytest.fixture
def sequence(tmp):
    for frame in range(1, 8):
        depth, normal = synthetic_scene(48, 32, frame)
        write_exr(tmp / f"shot.{frame:04d}.exr", depth, normal, sidecar=True)
    (tmp / "out").mkdir()
    return tmp


def run_tasks(script, count, cwd, only=None):
    """Runs the array job's tasks as Slurm would: the script under bash with SLURM_ARRAY_TASK_ID."""
    for task in range(count) if only is None else only:
        env = dict(os.environ, SLURM_ARRAY_TASK_ID=str(task))
        proc = subprocess.run(["bash", "-c", script], env=env, cwd=cwd, capture_output=True, text=True, timeout=300)
        yield task, proc


def test_dry_run_script_chunks_and_writes_nothing(sequence):
    proc = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--radius", "0.5", "--threads", "1",
                "--frames", "1-7", "--chunk", "3", "--dry-run", "--sbatch-arg=--partition=render", cwd=sequence)
    assert proc.returncode == 0, proc.stderr
    script = proc.stdout
    assert script.startswith("#!/bin/bash\n")
    lines = script.splitlines()
    assert "#SBATCH --array=0-2" in lines  # 7 frames, 3 per task
    assert "chunks=(1-3 4-6 7)" in lines
    assert "#SBATCH --cpus-per-task=1" in lines and "#SBATCH --partition=render" in lines
    assert f'#SBATCH --chdir="{sequence}"' in lines
    assert f'#SBATCH --output="{sequence}/out/obscura_farm_logs/%A_%a.log"' in lines
    assert "#SBATCH --open-mode=append" in lines  # a requeued task's log keeps its first attempt's
    command = lines[-1]
    assert command.startswith(f"exec '{os.path.realpath(CLI)}' 'shot.####.exr' '-o' 'out/ao.####.exr'")
    assert command.endswith(f"--frames \"${{chunks[$SLURM_ARRAY_TASK_ID]}}\" --resume --keep-going --report "
                            f"'{sequence}/out/ao.####.json'")
    assert sorted(os.listdir(sequence / "out")) == []
    # The same command line gives the same chunks: a resubmission redoes the same split.
    again = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--radius", "0.5", "--threads", "1",
                 "--frames", "1-7", "--chunk", "3", "--dry-run", "--sbatch-arg=--partition=render", cwd=sequence)
    assert again.stdout == script
    # Without --frames, the frames found on disk; a chunk larger than the job is one task.
    whole = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--chunk", "100", "--dry-run", cwd=sequence)
    assert "chunks=(1-7)" in whole.stdout.splitlines() and "#SBATCH --array=0-0" in whole.stdout
    assert proc.stderr == "" and whole.stderr == ""


def test_submission_warns_of_what_tasks_would_miss(sequence):
    """Frames with no input and a missing --env are said before submitting (a job may run after
    the renders it reads, so they are warnings); a missing output directory is refused, dry or not."""
    proc = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1-10", "--method", "ssdo",
                "--env", "nope.hdr", "--dry-run", cwd=sequence)
    assert proc.returncode == 0, proc.stderr
    assert "warning: frame(s) 8-10 of 10 have no input (shot.####.exr) yet" in proc.stderr
    assert "warning: 'nope.hdr' does not exist; every task reads it" in proc.stderr
    nodir = farm("slurm", "shot.####.exr", "-o", "nodir/ao.####.exr", "--dry-run", cwd=sequence)
    assert nodir.returncode != 0 and "nodir" in nodir.stderr and nodir.stdout == ""


def test_bad_command_lines(sequence):
    cases = [
        (["slurm", "shot.0001.exr", "-o", "out/a.exr", "--dry-run"], 2, "must be sequences"),
        (["slurm", "shot.####.exr", "-o", "out/a.####.exr", "--chunk", "0", "--dry-run"], 2, "--chunk"),
        (["slurm", "shot.####.exr", "-o", "out/a.####.exr", "--radius", "-1", "--dry-run"], 2, "--radius"),
        (["slurm", "shot.####.exr", "-o", "out/a.####.exr", "--report", "r.json", "--dry-run"], 2, "--report"),
        (["slurm", "none.####.exr", "-o", "out/a.####.exr", "--dry-run"], 1, "none.####.exr': no frames match"),
        (["summary", "out"], 1, "obscura_farm.json': cannot read"),
        (["summary"], 2, "which directory"),
        (["render"], 2, "slurm or summary"),
    ]
    for args, status, words in cases:
        proc = farm(*args, cwd=sequence)
        assert proc.returncode == status, (args, proc.stderr)
        err = proc.stderr.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("obscura: ") and words in err[0], (args, proc.stderr)


def test_write_append_reaches_every_task(sequence):
    import OpenImageIO as oiio
    proc = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--write", "append", "--frames", "1-3",
                "--chunk", "2", "--dry-run", cwd=sequence)
    assert proc.returncode == 0, proc.stderr
    assert "'--write' 'append'" in proc.stdout.splitlines()[-1]
    for task, done in run_tasks(proc.stdout, 2, sequence):
        assert done.returncode == 0, done.stderr
    for f in (1, 2, 3):
        inp = oiio.ImageInput.open(str(sequence / "out" / f"ao.{f:04d}.exr"))
        assert inp.seek_subimage(1, 0) and list(inp.spec().channelnames) == ["obscura.AO.Y"], f
        inp.close()
        assert json.loads((sequence / "out" / f"ao.{f:04d}.json").read_text())["write"]["mode"] == "append"


def fake_sbatch(tmp):
    """A stand-in for sbatch on PATH: records its arguments, prints a job id as --parsable does."""
    bin_dir = tmp / "bin"
    bin_dir.mkdir()
    (bin_dir / "sbatch").write_text(f"#!/bin/sh\necho \"$@\" >> {tmp}/sbatch.args\necho 4242\n")
    (bin_dir / "sbatch").chmod(0o755)
    return dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}")


def test_tasks_resume_and_summary(sequence):
    env = fake_sbatch(sequence)
    args = ["slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--radius", "0.5", "--frames", "1-7", "--chunk", "2",
            "--out-type", "float"]
    proc = farm(*args, env=env, cwd=sequence)
    assert proc.returncode == 0, proc.stderr
    assert "submitted job 4242: 7 frame(s) in 4 task(s)" in proc.stdout
    out = sequence / "out"
    # sbatch reads the script before it is renamed into place: a refused job replaces nothing.
    submitted = (sequence / "sbatch.args").read_text().split()
    assert submitted[0] == "--parsable" and submitted[1].startswith(str(out / "obscura_farm.sbatch.tmp-"))
    manifest = json.loads((out / "obscura_farm.json").read_text())
    assert manifest["frames"] == list(range(1, 8)) and manifest["chunks"] == ["1-2", "3-4", "5-6", "7"]
    assert manifest["job_id"] == "4242" and (out / "obscura_farm_logs").is_dir()
    script = (out / "obscura_farm.sbatch").read_text()

    # Nothing ran yet: all missing, exit status 1.
    s = farm("summary", out, "--json")
    assert s.returncode == 1
    assert json.loads(s.stdout)["missing"] == list(range(1, 8))

    # Frame 6's input is corrupt; task 3 (frame 7) never runs.
    (sequence / "shot.0006.exr").write_bytes(b"not an exr")
    results = dict(run_tasks(script, 3, sequence))
    assert results[0].returncode == 0 and results[1].returncode == 0, results[0].stderr + results[1].stderr
    assert results[2].returncode == 1 and "frame 6" in results[2].stderr
    s = farm("summary", out, "--json")
    assert s.returncode == 1
    summary = json.loads(s.stdout)
    assert summary["done"] == [1, 2, 3, 4, 5] and summary["missing"] == [7]
    assert list(summary["failed"]) == ["6"] and "shot.0006.exr" in summary["failed"]["6"]
    assert summary["temp_files"] == []
    reports = [json.loads((out / f"ao.{f:04d}.json").read_text()) for f in range(1, 6)]
    times = [r["total_s"] for r in reports]
    assert summary["seconds_per_frame"]["mean"] == pytest.approx(sum(times) / 5)
    assert summary["seconds_per_frame"]["max"] == pytest.approx(max(times))
    text = farm("summary", out).stdout
    assert "frames: 7: 5 done, 1 failed, 1 missing, 0 stale" in text and "missing: 7" in text and "failed 6:" in text

    # A resubmission after the input is fixed: finished frames are skipped (their files untouched).
    depth, normal = synthetic_scene(48, 32, 6)
    write_exr(sequence / "shot.0006.exr", depth, normal, sidecar=True)
    before = {f: os.stat(out / f"ao.{f:04d}.exr").st_mtime_ns for f in range(1, 6)}
    # A frame killed mid-write left its temp file (its process is gone): the retry removes it.
    stale = out / "ao.0007.exr.tmp-999999999"
    stale.write_bytes(b"half")
    for task, proc in run_tasks(script, 4, sequence):
        assert proc.returncode == 0, proc.stderr
    assert {f: os.stat(out / f"ao.{f:04d}.exr").st_mtime_ns for f in range(1, 6)} == before
    assert not stale.exists()
    s = farm("summary", out)
    assert s.returncode == 0, s.stdout
    assert "frames: 7: 7 done, 0 failed, 0 missing, 0 stale" in s.stdout

    # Resubmitted with another radius: the earlier job's frames are stale, not done, until its
    # tasks compute them again.
    args[args.index("0.5")] = "0.25"
    assert farm(*args, env=env, cwd=sequence).returncode == 0
    s = farm("summary", out, "--json")
    assert s.returncode == 1
    summary = json.loads(s.stdout)
    assert summary["done"] == [] and sorted(summary["stale"]) == [str(f) for f in range(1, 8)]
    assert summary["stale"]["1"] == "was written with other settings"
    for task, proc in run_tasks((out / "obscura_farm.sbatch").read_text(), 4, sequence):
        assert proc.returncode == 0, proc.stderr
    assert "frames: 7: 7 done, 0 failed, 0 missing, 0 stale" in farm("summary", out).stdout


def test_summary_merges_reference_error(tmp):
    # Two frames of a real Blender render with its ray-traced AO pass as the reference.
    for frame in (1, 2):
        (tmp / f"columns.{frame:04d}.exr").symlink_to(SAMPLES / "columns.exr")
        (tmp / f"columns.{frame:04d}.json").symlink_to(SAMPLES / "columns.json")
    (tmp / "out").mkdir()
    script = farm("slurm", "columns.####.exr", "-o", "out/ao.####.exr", "--write", "new", "--weighting", "cosine",
                  "--falloff", "none", "--radius", "1", "--reference", "ViewLayer.AO", "--chunk", "1", "--dry-run",
                  cwd=tmp).stdout
    env = fake_sbatch(tmp)
    assert farm("slurm", "columns.####.exr", "-o", "out/ao.####.exr", "--write", "new", "--weighting", "cosine",
                "--falloff", "none", "--radius", "1", "--reference", "ViewLayer.AO", "--chunk", "1",
                env=env, cwd=tmp).returncode == 0
    for task, proc in run_tasks(script, 2, tmp):
        assert proc.returncode == 0, proc.stderr
    summary = json.loads(farm("summary", tmp / "out", "--json").stdout)
    ref = summary["reference"]
    maes = [json.loads((tmp / "out" / f"ao.{f:04d}.json").read_text())["reference"]["mae"] for f in (1, 2)]
    assert ref["layer"] == "ViewLayer.AO"
    assert ref["mae"]["mean"] == pytest.approx(sum(maes) / 2) and ref["mae"]["max"] == pytest.approx(max(maes))
    # The same frame twice: the same error, and a real one (HBAO against Cycles' AO: small, not zero).
    assert maes[0] == maes[1] and 0.005 < maes[0] < 0.2
    assert "reference ViewLayer.AO" in farm("summary", tmp / "out").stdout


def test_keep_going_runs_the_frames_after_a_failing_one(sequence):
    (sequence / "shot.0002.exr").write_bytes(b"not an exr")
    args = [CLI, "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1-3", "--report", "out/ao.####.json"]
    stop = subprocess.run(args, capture_output=True, text=True, cwd=sequence, timeout=300)
    assert stop.returncode == 1 and "frame 2" in stop.stderr
    assert not (sequence / "out" / "ao.0003.exr").exists()
    go = subprocess.run(args + ["--keep-going", "--resume"], capture_output=True, text=True, cwd=sequence, timeout=300)
    assert go.returncode == 1
    assert (sequence / "out" / "ao.0003.exr").exists()
    last = go.stderr.strip().splitlines()[-1]
    assert last.endswith("1 of 3 frame(s) failed (--keep-going): 2"), go.stderr
    assert "error" in json.loads((sequence / "out" / "ao.0002.json").read_text())


def test_inspect_describes_a_sequence_by_its_first_frame(sequence):
    proc = subprocess.run([CLI, "shot.####.exr", "--inspect", "--json"], capture_output=True, text=True,
                          cwd=sequence, timeout=300)
    assert proc.returncode == 0, proc.stderr
    j = json.loads(proc.stdout)
    assert j["sequence"] == {"pattern": "shot.####.exr", "frames": 7, "described": 1}
    assert j["command_args"][1:4] == ["shot.0001.exr", "-o", "shot_ao.0001.exr"]
    assert any(n.startswith("sequence: 7 frame(s) of shot.####.exr") for n in j["command_notes"])
    none = subprocess.run([CLI, "none.####.exr", "--inspect"], capture_output=True, text=True, cwd=sequence,
                          timeout=300)
    assert none.returncode == 1 and none.stdout == ""
    assert none.stderr.strip() == "obscura: 'none.####.exr': no frames match"


def test_a_sequence_into_a_missing_directory_fails_before_computing(sequence):
    proc = subprocess.run([CLI, "shot.####.exr", "-o", "nodir/ao.####.exr", "--report", "out/"], capture_output=True,
                          text=True, cwd=sequence, timeout=300)
    assert proc.returncode == 1
    assert proc.stderr.strip() == "obscura: 'nodir/ao.0001.exr': cannot write: directory 'nodir' does not exist"
    assert os.listdir(sequence / "out") == []


def test_summary_reads_the_jobs_paths_from_where_it_was_submitted(sequence):
    """A relative --camera, as the tasks record it: the summary, run from elsewhere, counts the
    frames done, not stale."""
    env = fake_sbatch(sequence)
    args = ["slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--camera", "shot.0001.json", "--frames", "1-2",
            "--chunk", "1"]
    assert farm(*args, env=env, cwd=sequence).returncode == 0
    for task, proc in run_tasks((sequence / "out" / "obscura_farm.sbatch").read_text(), 2, sequence):
        assert proc.returncode == 0, proc.stderr
    summary = json.loads(farm("summary", sequence / "out", "--json").stdout)
    assert summary["done"] == [1, 2] and summary["stale"] == {}


def failing_sbatch(tmp):
    """A stand-in for sbatch that refuses every job, as a bad partition makes the real one."""
    bin_dir = tmp / "badbin"
    bin_dir.mkdir()
    (bin_dir / "sbatch").write_text("#!/bin/sh\necho 'sbatch: error: Invalid partition name specified' >&2\nexit 1\n")
    (bin_dir / "sbatch").chmod(0o755)
    return dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}")


def test_a_refused_submission_leaves_the_job_that_ran_as_it_was(sequence):
    args = ["slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1-2", "--chunk", "1"]
    assert farm(*args, env=fake_sbatch(sequence), cwd=sequence).returncode == 0
    out = sequence / "out"
    before = {name: (out / name).read_bytes() for name in ("obscura_farm.json", "obscura_farm.sbatch")}
    refused = farm(*args, "--radius", "0.25", env=failing_sbatch(sequence), cwd=sequence)
    assert refused.returncode == 1
    assert refused.stderr.strip() == "obscura: sbatch failed: sbatch: error: Invalid partition name specified"
    assert {name: (out / name).read_bytes() for name in before} == before
    assert not any(".tmp-" in p.name for p in out.iterdir())


def test_one_job_per_directory(sequence):
    """A second job (another output pattern) into the directory of a first is refused: its
    manifest and script would replace the first's, and the summary would judge the wrong frames.
    The first job submitted again is the same job."""
    env = fake_sbatch(sequence)
    first = ["slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1-2"]
    assert farm(*first, env=env, cwd=sequence).returncode == 0
    other = farm("slurm", "shot.####.exr", "-o", "out/other.####.exr", "--frames", "1-2", "--dry-run", env=env,
                 cwd=sequence)
    assert other.returncode == 1 and other.stdout == ""
    assert other.stderr.strip() == (f"obscura: '{sequence}/out/obscura_farm.json': holds the job for "
                                    f"{sequence}/out/ao.####.exr (its summary and script); give "
                                    "out/other.####.exr a directory of its own")
    assert farm(*first, "--radius", "0.25", env=env, cwd=sequence).returncode == 0
    # The same outputs spelled another way are the same job.
    assert farm("slurm", "shot.####.exr", "-o", "out/ao.%04d.exr", "--frames", "1-2", env=env,
                cwd=sequence).returncode == 0
    # A manifest that cannot be replaced is said before sbatch runs: no job whose files are not written.
    (sequence / "sbatch.args").unlink()
    (sequence / "out" / "obscura_farm.json").chmod(0o444)
    locked = farm(*first, env=env, cwd=sequence)
    assert locked.returncode == 1 and "obscura_farm.json" in locked.stderr, locked.stderr
    assert not (sequence / "sbatch.args").exists()


def test_odd_paths_reach_sbatch_quoted(tmp):
    """A blank, a quote or a '%' in the directory: the #SBATCH values are quoted, and '%' is
    doubled in the log pattern, where Slurm reads %x as the job's name."""
    odd = tmp / "My Show's 100%x"
    odd.mkdir()
    depth, normal = synthetic_scene(48, 32, 1)
    write_exr(odd / "shot.0001.exr", depth, normal, sidecar=True)
    (odd / "out").mkdir()
    proc = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--dry-run", cwd=odd)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert f'#SBATCH --chdir="{odd}"' in lines
    assert f'#SBATCH --output="{tmp}/My Show\'s 100%%x/out/obscura_farm_logs/%A_%a.log"' in lines


def test_submission_checks_the_tasks_files_as_a_run_does(sequence):
    """What would fail every task is refused before the job is submitted: a --report or --preview
    directory that does not exist, a report over the camera sidecar (--in-place's default report),
    a frame listed twice. A bad --frames is a bad command line."""
    base = ["slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--dry-run"]
    cases = [
        (["--report", "reports/ao.####.json"], 1, "'reports/ao.0001.json': cannot write: directory 'reports' does not exist"),
        (["--preview", "previews/ao.####.png"], 1, "'previews/ao.0001.png': cannot write: directory 'previews' does not exist"),
        (["--frames", "1,2,1"], 2, "is written for two frames"),
        (["--frames", "abc"], 2, "--frames"),
    ]
    for extra, status, words in cases:
        proc = farm(*base, *extra, cwd=sequence)
        assert proc.returncode == status and words in proc.stderr and proc.stdout == "", (extra, proc.stderr)
    in_place = farm("slurm", "shot.####.exr", "-o", "shot.####.exr", "--in-place", "--dry-run", cwd=sequence)
    assert in_place.returncode == 2 and "is the same file as the camera sidecar" in in_place.stderr, in_place.stderr
    # A directory for --report, as a run takes it: the report pattern in it.
    (sequence / "reports").mkdir()
    into_dir = farm(*base, "--report", "reports/", cwd=sequence)
    assert into_dir.returncode == 0, into_dir.stderr
    assert into_dir.stdout.splitlines()[-1].endswith(f"--report '{sequence}/reports/ao.####.json'")
    assert os.listdir(sequence / "out") == []


def test_summary_reads_a_hand_written_manifest(sequence, tmp):
    """Another engine's job (farm.md): relative paths are the manifest's directory's, "frames" may
    be a --frames text, and a manifest of the wrong shape is one line naming it."""
    for f in (1, 2):
        done = subprocess.run([CLI, f"shot.{f:04d}.exr", "-o", f"out/ao.{f:04d}.exr", "--report", f"out/ao.{f:04d}.json"],
                              capture_output=True, text=True, cwd=sequence, timeout=300)
        assert done.returncode == 0, done.stderr
    manifest = sequence / "out" / "obscura_farm.json"
    manifest.write_text(json.dumps({"frames": "1-3", "output": "ao.####.exr", "report": "ao.####.json"}))
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    s = farm("summary", manifest.parent, "--json", cwd=elsewhere)
    assert s.returncode == 1, s.stderr
    summary = json.loads(s.stdout)
    assert summary["done"] == [1, 2] and summary["missing"] == [3]
    for bad_manifest, words in [({"frames": [1, 2], "output": 5, "report": "ao.####.json"}, '"output" must be a string'),
                                ({"frames": [3000000000], "output": "ao.####.exr", "report": "ao.####.json"},
                                 '"frames" must be a list of frame numbers'),
                                ({"frames": "1-2000000000", "output": "ao.####.exr", "report": "ao.####.json"},
                                 "more than 10,000,000 frames"),
                                ({"frames": [1], "output": "ao.exr", "report": "ao.####.json"},
                                 '"output" and "report" must be frame patterns')]:
        manifest.write_text(json.dumps(bad_manifest))
        bad = farm("summary", manifest.parent)
        assert bad.returncode == 1 and bad.stderr.startswith(f"obscura: '{manifest}': "), bad.stderr
        assert words in bad.stderr and len(bad.stderr.strip().splitlines()) == 1, bad.stderr


def test_an_output_cut_short_is_not_done(sequence):
    """An output whose chunks are cut off (a copy interrupted) is neither done in the summary nor
    skipped by --resume: it reads back as a header, but not as an image."""
    env = fake_sbatch(sequence)
    assert farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--frames", "1-2", env=env,
                cwd=sequence).returncode == 0
    script = (sequence / "out" / "obscura_farm.sbatch").read_text()
    for task, proc in run_tasks(script, 1, sequence):
        assert proc.returncode == 0, proc.stderr
    cut = sequence / "out" / "ao.0002.exr"
    cut.write_bytes(cut.read_bytes()[: cut.stat().st_size // 2])
    summary = json.loads(farm("summary", sequence / "out", "--json").stdout)
    assert summary["done"] == [1] and summary["missing"] == [2]
    for task, proc in run_tasks(script, 1, sequence):
        assert proc.returncode == 0, proc.stderr
    assert json.loads(farm("summary", sequence / "out", "--json").stdout)["done"] == [1, 2]


def test_a_linked_project_is_named_by_its_link(sequence, tmp):
    """Submitted from a directory reached through a link: the script, logs, reports and manifest
    name it by the link, as the nodes mount it, not by where the link leads on this host."""
    link = tmp / "show"
    link.symlink_to(sequence)
    env = dict(os.environ, PWD=str(link))
    proc = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--dry-run", env=env, cwd=link)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert f'#SBATCH --chdir="{link}"' in lines
    assert f'#SBATCH --output="{link}/out/obscura_farm_logs/%A_%a.log"' in lines
    assert lines[-1].endswith(f"--report '{link}/out/ao.####.json'")
    # A $PWD that is not this directory's plain name is not used.
    odd = farm("slurm", "shot.####.exr", "-o", "out/ao.####.exr", "--dry-run",
               env=dict(os.environ, PWD=f"{link}/../show"), cwd=link)
    assert f'#SBATCH --chdir="{sequence}"' in odd.stdout.splitlines()
