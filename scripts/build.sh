#!/usr/bin/env bash
# Install dependencies (if missing), configure a Release build and build it
# incrementally on all cores. Build directory: $OBSCURA_BUILD_DIR or build/.
# Usage: scripts/build.sh [TARGET...]   (no target: build everything)
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${OBSCURA_BUILD_DIR:-$ROOT/build}

bash "$ROOT/scripts/setup.sh"

JOBS=$(nproc 2>/dev/null || echo 2)
# Configuring again is cheap when nothing changed, and repairs a build
# directory whose previous configure failed.
cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
if [[ $# -gt 0 ]]; then
  cmake --build "$BUILD_DIR" --parallel "$JOBS" --target "$@"
else
  cmake --build "$BUILD_DIR" --parallel "$JOBS"
fi
