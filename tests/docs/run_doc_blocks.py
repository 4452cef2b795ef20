"""Runs every fenced code block of README.md, docs/ (notes included) and plugin/ofx/README.md (ctest:
docs.blocks), so the docs cannot drift from what obscura does: a block that stops working fails.

Each page runs in a directory of its own, its blocks in order as a reader would type them, with
`obscura` and `python3` (the interpreter the module is built for) first on PATH and the built
module on PYTHONPATH. The directory holds the files the blocks name, made by the project's own
reference renderer (examples/reference, Blender's pass names) at 64 x 48:

- shot.0001.exr, shot.1001.exr ... shot.1240.exr, each with its camera sidecar (NAME.json), and
  a ViewLayer.AO pass as Blender writes one (the renderer's cosine, binary AO within 1.0);
- shot_deep.0001.exr, the deep file of the same frame (--deep), and the same split into two deep
  elements as if rendered apart: shot_near.0001.exr (each pixel's nearest solid) and
  shot_far.0001.exr (the solids behind it);
- studio.hdr, a small lat-long environment.

Every block must say its language: ```sh (run with bash -e), ```python (run with python3) or
```text (sample output, not run). What cannot run here as written is checked another way, each
rule below saying what it checks:

- `bash scripts/NAME.sh` (demo.sh, test.sh install packages and build): the script exists and
  `bash -n` parses it.
- `python3 tests/layers/NAME.py .` (a check of the source tree): run on the checkout itself.
- `... python3 tests/bench/NAME.py FLAGS` (benchmarks taking minutes on an idle machine): the
  script runs with --help, and every --flag the block gives is in its help.
- `obscura farm slurm` submits with sbatch: a stand-in sbatch first on PATH runs every array task
  of the script obscura wrote, here, one after another, so the script is really run and
  `obscura farm summary` afterwards must find every frame done.
- A Dask `Client("tcp://...")` names the reader's scheduler: the block runs against an in-process
  cluster instead (the block is skipped, and says so, where distributed is not installed).

After each page, every file the test made must be byte-identical: no block overwrote an input.
"""
import argparse
import glob
import hashlib
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

LANGUAGES = ("sh", "python", "text")
FENCE = re.compile(r"^(\s*)```(.*)$")
SEQUENCE = list(range(1001, 1241))  # the frames the farm pages ask for; README asks for 1001-1100


class Block:
    def __init__(self, page, line, language, text):
        self.page, self.line, self.language, self.text = page, line, language, text

    def __str__(self):
        return f"{self.page}:{self.line} ({self.language or 'no language'})"


def blocks_of(root, page):
    """The fenced blocks of one Markdown page, with the line each opens on."""
    found, open_at, language, lines = [], None, None, []
    for number, line in enumerate((root / page).read_text().splitlines(), 1):
        fence = FENCE.match(line)
        if fence and open_at is None:
            open_at, language, lines = number, fence.group(2).strip(), []
        elif fence:
            found.append(Block(page, open_at, language, "\n".join(lines) + "\n"))
            open_at = None
        elif open_at is not None:
            lines.append(line)
    if open_at is not None:
        raise SystemExit(f"{page}:{open_at}: a code block that never closes")
    return found


def pages(root):
    names = ["README.md", *sorted(glob.glob("docs/**/*.md", root_dir=root, recursive=True)), "plugin/ofx/README.md"]
    return [n for n in names if (root / n).exists()]


# ---------------------------------------------------------------------------------------------
# The files the blocks name


def add_blender_ao(path):
    """Adds ViewLayer.AO.R/G/B, as Blender writes its AO pass, from the render's cosine AO."""
    import numpy as np
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = oiio.ImageSpec(inp.spec()), inp.read_image(oiio.FLOAT)
    inp.close()
    names = list(spec.channelnames)
    ao = pixels[..., names.index("Reference.AO_cosine_none.Y")]
    spec.nchannels = len(names) + 3
    spec.channelnames = tuple(names + ["ViewLayer.AO.R", "ViewLayer.AO.G", "ViewLayer.AO.B"])
    spec.channelformats = ()
    spec.set_format(oiio.FLOAT)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(np.concatenate([pixels, np.repeat(ao[..., None], 3, axis=-1)], axis=-1)), out.geterror()
    out.close()


def write_environment(path):
    """A 32 x 16 lat-long map: a bright sky over a darker ground."""
    import numpy as np
    import OpenImageIO as oiio
    env = np.zeros((16, 32, 3), np.float32)
    env[:8] = (1.0, 0.95, 0.9)
    env[8:] = (0.2, 0.18, 0.15)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(32, 16, 3, oiio.FLOAT)), out.geterror()
    assert out.write_image(env), out.geterror()
    out.close()


def split_deep(path, near, far):
    """Each pixel's first sample into `near`, the rest into `far`: two elements of one frame."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    spec = oiio.ImageSpec(inp.spec())
    whole = inp.read_native_deep_image()
    inp.close()
    for out_path, keep in ((near, lambda s: s == 0), (far, lambda s: s > 0)):
        dd = oiio.DeepData()
        dd.init(spec)
        for p in range(whole.pixels):
            dd.set_samples(p, sum(1 for s in range(whole.samples(p)) if keep(s)))
        for p in range(whole.pixels):
            kept = [s for s in range(whole.samples(p)) if keep(s)]
            for i, s in enumerate(kept):
                for c in range(spec.nchannels):
                    dd.set_deep_value(p, c, i, whole.deep_value(p, c, s))
        out = oiio.ImageOutput.create(str(out_path))
        assert out.open(str(out_path), spec) and out.write_deep_image(dd), out.geterror()
        out.close()


def make_fixture(directory, reference_render):
    directory.mkdir(parents=True)
    base = directory / "shot.0001.exr"
    subprocess.run([reference_render, "--scene", "studio", "--width", "64", "--height", "48", "--ao-rays", "16",
                    "--gi-rays", "8", "-o", base, "--deep", directory / "shot_deep.0001.exr", "--quiet"], check=True)
    add_blender_ao(base)
    split_deep(directory / "shot_deep.0001.exr", directory / "shot_near.0001.exr", directory / "shot_far.0001.exr")
    write_environment(directory / "studio.hdr")
    for frame in SEQUENCE:  # hard links: every frame is the same small render
        for ext in (".exr", ".json"):
            os.link(base.with_suffix(ext), directory / f"shot.{frame}{ext}")


def checksums(directory, names):
    return {n: hashlib.sha256((directory / n).read_bytes()).hexdigest() for n in names}


def stage(fixture, directory):
    if directory.exists():
        shutil.rmtree(directory)
    directory.mkdir(parents=True)
    for p in fixture.iterdir():
        os.link(p, directory / p.name)


# ---------------------------------------------------------------------------------------------
# Commands that cannot run here as written, and what is checked instead

REWRITES = [
    (re.compile(r"^bash\s+(scripts/[\w.-]+\.sh)\b.*$"), r'bash -n "$OBSCURA_ROOT/\1"'),
    # A check of the source tree (the dependency rule): run for real, on the checkout.
    (re.compile(r"^python3\s+(tests/layers/[\w.-]+\.py)\s+\.$"), r'python3 "$OBSCURA_ROOT/\1" "$OBSCURA_ROOT"'),
    (re.compile(r"^(?:\w+=\S+\s+)*\S*python3\s+(tests/bench/[\w.-]+\.py)\s*(.*?)\s*$"),
     r'docs-check-flags "$OBSCURA_ROOT/\1" \2'),
]

SBATCH = """#!/bin/bash
# Stand-in for Slurm's sbatch (tests/docs/run_doc_blocks.py): runs every array task of the
# script, here, in turn, then prints a job id as `sbatch --parsable` does.
script="${@: -1}"
last=$(sed -n 's/^#SBATCH --array=0-//p' "$script")
for ((task = 0; task <= last; task++)); do
  SLURM_ARRAY_JOB_ID=4242 SLURM_ARRAY_TASK_ID=$task bash "$script" >>sbatch-standin.log 2>&1 || exit 1
done
echo 4242
"""

DASK_PRELUDE = """\
# The block's Client(address) names the reader's scheduler: an in-process cluster stands in.
import distributed as _distributed
_Client = _distributed.Client
def _local_client(address=None, *args, **kwargs):
    cluster = _distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                        dashboard_address=None)
    return _Client(cluster, *args, **kwargs)
_distributed.Client = _local_client
"""


def rewrite_sh(text):
    """The block with each command that cannot run here replaced by its check (line by line,
    after joining continued lines)."""
    out = []
    for command in text.replace("\\\n", " ").splitlines():
        for pattern, replacement in REWRITES:
            if pattern.match(command.strip()):
                command = pattern.sub(replacement, command.strip())
                break
        out.append(command)
    return "\n".join(out) + "\n"


def check_flags(script, args):
    """--check-flags: SCRIPT --help runs, and lists every --flag of ARGS."""
    proc = subprocess.run([sys.executable, script, "--help"], capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{script} --help: exit {proc.returncode}: {proc.stderr.strip()}")
    missing = [a.split("=")[0] for a in args if a.startswith("--") and a.split("=")[0] not in proc.stdout]
    if missing:
        sys.exit(f"{script} has no {', '.join(missing)} (its --help does not list them)")


def tools(bin_dir, cli):
    """obscura, python3, sbatch and docs-check-flags, first on the blocks' PATH."""
    bin_dir.mkdir(parents=True, exist_ok=True)
    for name, target in (("obscura", cli), ("python3", sys.executable)):
        link = bin_dir / name
        if link.is_symlink() or link.exists():
            link.unlink()
        link.symlink_to(target)
    (bin_dir / "sbatch").write_text(SBATCH)
    (bin_dir / "docs-check-flags").write_text(
        f'#!/bin/sh\nexec "{sys.executable}" "{Path(__file__).resolve()}" --check-flags "$@"\n')
    for name in ("sbatch", "docs-check-flags"):
        (bin_dir / name).chmod(0o755)


# ---------------------------------------------------------------------------------------------
# Running


def run_block(block, cwd, env):
    """(exit status, output) of one block; None when it cannot run on this machine."""
    if block.language == "sh":
        command = ["bash", "-e", "-o", "pipefail", "-c", rewrite_sh(block.text)]
    else:
        code = block.text
        if re.search(r"\bClient\(\s*[\"']tcp://", code):
            try:
                import distributed  # noqa: F401
            except ImportError:
                return None
            code = DASK_PRELUDE + code
        command = [sys.executable, "-c", code]
    proc = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def run_page(page, page_blocks, work, fixture, sums, env):
    """The failures of one page's blocks, run in order in a directory of their own."""
    directory = work / page.replace("/", "_")
    stage(fixture, directory)
    failures = []
    for block in page_blocks:
        if block.language not in LANGUAGES:
            failures.append(f"{block}: say the block's language: ```sh, ```python or ```text")
            continue
        if block.language == "text":
            continue
        start = time.monotonic()
        result = run_block(block, directory, env)
        if result is None:
            print(f"skipped {block}: distributed (Dask) is not installed")
            continue
        status, output = result
        print(f"{'ok' if status == 0 else 'FAILED'} {block} {time.monotonic() - start:.1f} s")
        if status != 0:
            failures.append(f"{block}: exit {status}\n{block.text}---\n{output[-3000:]}")
    changed = [n for n, s in checksums(directory, sums).items() if sums[n] != s]
    if changed:
        failures.append(f"{page}: its blocks changed the files they were given: {', '.join(changed)}")
    return failures


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--check-flags":
        return check_flags(sys.argv[2], sys.argv[3:])
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, required=True, help="the source tree")
    ap.add_argument("--cli", required=True, help="the built obscura")
    ap.add_argument("--module-dir", required=True, help="where `import obscura` finds the built module")
    ap.add_argument("--reference-render", required=True)
    ap.add_argument("--work", type=Path, required=True, help="scratch directory (emptied)")
    args = ap.parse_args()

    if args.work.exists():
        shutil.rmtree(args.work)
    fixture = args.work / "fixture"
    make_fixture(fixture, args.reference_render)
    sums = checksums(fixture, sorted(p.name for p in fixture.iterdir()))
    tools(args.work / "bin", args.cli)
    env = dict(os.environ, PATH=f"{args.work / 'bin'}:{os.environ['PATH']}", PYTHONPATH=args.module_dir,
               OBSCURA_ROOT=str(args.root), PYTHONDONTWRITEBYTECODE="1")

    failures, count = [], 0
    for page in pages(args.root):
        page_blocks = blocks_of(args.root, page)
        count += len(page_blocks)
        if page_blocks:
            failures += run_page(page, page_blocks, args.work, fixture, sums, env)
    print(f"{count} blocks in {len(pages(args.root))} pages, {len(failures)} failing")
    for f in failures:
        print(f"\n{f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
