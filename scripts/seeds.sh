#!/usr/bin/env bash
# Regenerates docs/seeds.md: how the models do over many pairs of flights, not one. For each
# airframe (X-Cell 60, flybarless 600) and each seed pair k = 1..PAIRS (training flight seed k,
# verification flight seed 100 + k), it flies the hover pair (identification, 300 s
# verification) and the envelope pair, runs `rotorid identify` on each, and reports per state
# the median and the worst over the pairs of each model's 2 s free-run error as a ratio to
# extended plain's and to holding the measured state (scripts/seeds_report.py). With VARIATIONS,
# plant variations 1..VARIATIONS of each airframe (`rotorid simulate --plant-variation`, as in
# docs/robustness.md) fly the same seed pairs, and the report gives each plant's median and
# worst over the pairs of the flight default's and the verdict's choice's ratios.
# Deterministic: same seeds, same bits.
#
# Usage: scripts/seeds.sh [PAIRS [OUTPUT [VARIATIONS]]]   (default 10 pairs, docs/seeds.md, no
# variations; the document is made with `scripts/seeds.sh 10 docs/seeds.md 12`, 35 min on
# 2 cores)
# Env: SEEDS_WORK=DIR keeps the flights and metrics there (default: a temporary directory).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
pairs=${1:-10}
output=$(realpath -m "${2:-docs/seeds.md}")
variations=${3:-0}
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
# ROTORID_BIN: a binary already built (CI passes the workspace's, which `-p` alone would
# rebuild with other features).
[ -n "${ROTORID_BIN:-}" ] || cargo build -q --release -p rotorid-cli --bin rotorid
bin="${ROTORID_BIN:-$CARGO_TARGET_DIR/release/rotorid}"
# shellcheck source=scripts/lib/pairs.sh
. scripts/lib/pairs.sh
work=$(seeds_work)
[ -n "${SEEDS_WORK:-}" ] || trap 'rm -rf "$work"' EXIT
start=$(date +%s)
reused=$(kept_pairs "$work")
fly_pairs "$work" "$pairs" "$variations"
python3 scripts/seeds_report.py "$work" "$pairs" "$(($(date +%s) - start))" "$variations" \
  "$reused" >"$output"
echo "wrote $output"
