"""The dependency rule of docs/layout.md, checked on every quoted #include of the tree: a layer
includes only itself and the layers below it. From the bottom: kernels/, base/, then cpu/ and
gpu/ (neither includes the other), plugin/core, plugin/io, and the hosts (plugin/cli,
plugin/ofx, plugin/python), which reach the backends only through plugin/core.

Exits 1 listing every include that breaks the rule (FILE:LINE: "what" -- why)."""
import os
import re
import sys
from pathlib import Path

# A layer, the directories it lives in, and the include prefixes it may use.
BELOW_CORE = ("kernels/", "base/", "core/")
LAYERS = {
    "kernels": (("kernels/",), ("kernels/",)),
    "base": (("base/",), ("kernels/", "base/")),
    "cpu": (("cpu/",), ("kernels/", "base/", "cpu/")),
    "gpu": (("gpu/",), ("kernels/", "base/", "gpu/")),
    "core": (("plugin/core/",), ("kernels/", "base/", "cpu/", "gpu/", "core/")),
    # Colour conversions run on the CPU backend's thread pool, like the kernels.
    "io": (("plugin/io/",), BELOW_CORE + ("io/", "cpu/parallel.h")),
    "cli": (("plugin/cli/",), BELOW_CORE + ("io/", "cli/")),
    "ofx": (("plugin/ofx/",), BELOW_CORE + ("io/", "ofx/")),
    "python": (("plugin/python/",), BELOW_CORE + ("io/", "python/")),
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def layer_of(path):
    for name, (dirs, _) in LAYERS.items():
        if any(path.startswith(d) for d in dirs):
            return name
    return None


def source_files(root):
    """The tree's .h, .cpp and .glsl files, not descending into build directories or .git: tests
    running beside this one create and remove scratch directories there, which a walk through
    them can trip on."""
    for directory, subdirs, files in os.walk(root):
        subdirs[:] = [d for d in subdirs if not d.startswith("build") and d != ".git"]
        for name in files:
            if name.endswith((".h", ".cpp", ".glsl")):
                yield Path(directory) / name


def main(root):
    broken = []
    for file in sorted(source_files(root)):
        rel = file.relative_to(root).as_posix()
        layer = layer_of(rel)
        if not layer:
            continue
        allowed = LAYERS[layer][1]
        for number, line in enumerate(file.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m or "/" not in m.group(1):
                continue  # a file beside it ("lanes.h") is its own layer
            target = m.group(1)
            if not target.startswith(allowed):
                broken.append(f'{rel}:{number}: "{target}" -- {layer} may include only {", ".join(allowed)}')
    for b in broken:
        print(b)
    print(f"check_includes: {len(broken)} include(s) against the dependency rule", file=sys.stderr)
    return 1 if broken else 0


def self_test():
    """The check fails where it should: a tree whose cpu/ includes plugin/core, and whose host
    includes gpu/, breaks the rule twice; the same tree without them passes."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "cpu").mkdir()
        (root / "plugin/cli").mkdir(parents=True)
        (root / "cpu/a.h").write_text('#include "base/image.h"\n#include "core/operator.h"\n')
        (root / "plugin/cli/b.cpp").write_text('#include "io/frame_job.h"\n#include "gpu/gl_backend.h"\n')
        if main(root) != 1:
            return 1
        (root / "cpu/a.h").write_text('#include "base/image.h"\n')
        (root / "plugin/cli/b.cpp").write_text('#include "io/frame_job.h"\n')
        return main(root)


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    sys.exit(main(Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()))
