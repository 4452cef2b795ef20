#!/usr/bin/env bash
# Build obscura, generate the built-in demo scene and compute its ambient
# occlusion. Needs no data besides what the build generates.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export OBSCURA_BUILD_DIR=${OBSCURA_BUILD_DIR:-$ROOT/build}
BUILD_DIR=$OBSCURA_BUILD_DIR

# Only what the demo runs; scripts/test.sh builds everything.
bash "$ROOT/scripts/build.sh" obscura reference_render

DEMO_DIR=$BUILD_DIR/demo
mkdir -p "$DEMO_DIR"

echo "demo: ray tracing the demo scene (reference_render --scene studio)"
# Modest ray counts keep this to a few seconds; the reference AO layers it also
# writes are then a little noisy (the standard errors are printed).
"$BUILD_DIR/examples/reference/reference_render" --scene studio -o "$DEMO_DIR/demo.exr" \
  --width 640 --height 360 --ao-rays 64 --gi-rays 16

echo "demo: computing ambient occlusion"
"$BUILD_DIR/plugin/obscura" "$DEMO_DIR/demo.exr" \
  -o "$DEMO_DIR/demo_ao.exr" --preview "$DEMO_DIR/demo_ao.png" --radius 1.0

for f in "$DEMO_DIR/demo.exr" "$DEMO_DIR/demo.json" "$DEMO_DIR/demo_ao.exr" "$DEMO_DIR/demo_ao.png"; do
  if [[ ! -s "$f" ]]; then
    echo "demo: a step reported success but did not write $f" >&2
    exit 1
  fi
done

cat <<MSG

demo: outputs
  input scene (multilayer EXR) : $DEMO_DIR/demo.exr
  camera sidecar               : $DEMO_DIR/demo.json
  EXR with the AO layer added  : $DEMO_DIR/demo_ao.exr
  AO preview (PNG)             : $DEMO_DIR/demo_ao.png
  (demo.exr also holds ray-traced ground-truth AO layers, Reference.AO_*)
MSG
