#!/usr/bin/env bash
# Build obscura and run its test suite; exits non-zero if any test fails.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export OBSCURA_BUILD_DIR=${OBSCURA_BUILD_DIR:-$ROOT/build}

bash "$ROOT/scripts/build.sh"
# --no-tests=error: a build that registered no tests must not pass.
ctest --test-dir "$OBSCURA_BUILD_DIR" --output-on-failure -j2 --no-tests=error
