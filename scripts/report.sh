#!/usr/bin/env bash
# The error-against-run-time report: builds obscura_report, then runs every method x
# quality preset x device on every reference scene. Writes into build/report/ (or
# $OBSCURA_REPORT_DIR): results.csv, results.json, <scene>_sheet.png, error_vs_time.png
# (+ error_vs_time_by_scene.png). Converged references are cached in <dir>/cache and
# reused by later runs.
#   OBSCURA_REPORT_QUICK=1 bash scripts/report.sh   # tiny run: one scene, 64x48, cpu, preset low
#   bash scripts/report.sh --scenes corner,city --devices cpu   # extra flags go to obscura_report
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export OBSCURA_BUILD_DIR=${OBSCURA_BUILD_DIR:-$ROOT/build}
BUILD_DIR=$OBSCURA_BUILD_DIR
OUT_DIR=${OBSCURA_REPORT_DIR:-$BUILD_DIR/report}

echo "report: building obscura_report"
bash "$ROOT/scripts/build.sh" obscura_report

ARGS=(--out "$OUT_DIR")
if [[ "${OBSCURA_REPORT_QUICK:-0}" == "1" ]]; then
  ARGS+=(--quick)
  echo "report: quick mode (OBSCURA_REPORT_QUICK=1)"
fi
echo "report: running obscura_report ${ARGS[*]} $*"
start=$(date +%s)
"$BUILD_DIR/examples/report/obscura_report" "${ARGS[@]}" "$@"
echo "report: finished in $(( $(date +%s) - start )) s; outputs in $OUT_DIR"
