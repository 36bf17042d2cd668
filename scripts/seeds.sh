#!/usr/bin/env bash
# Regenerates docs/seeds.md: how the models do over many pairs of flights, not one. For each
# airframe (X-Cell 60, flybarless 600) and each seed pair k = 1..PAIRS (training flight seed k,
# verification flight seed 100 + k), it flies the hover pair (identification, 300 s
# verification) and the envelope pair, runs `rotorid identify` on each, and reports per state
# the median and the worst over the pairs of each model's 2 s free-run error as a ratio to
# extended plain's and to holding the measured state (scripts/seeds_report.py).
# Deterministic: same seeds, same bits.
#
# Usage: scripts/seeds.sh [PAIRS [OUTPUT]]   (default 10 pairs, docs/seeds.md)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
pairs=${1:-10}
output=$(realpath -m "${2:-docs/seeds.md}")
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
# ROTORID_BIN: a binary already built (CI passes the workspace's, which `-p` alone would
# rebuild with other features).
[ -n "${ROTORID_BIN:-}" ] || cargo build -q --release -p rotorid-cli --bin rotorid
bin="${ROTORID_BIN:-$CARGO_TARGET_DIR/release/rotorid}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$(date +%s)

# fly PLANT K DIR: the four flights and the two identifications of seed pair K.
fly() {
  local plant=$1 k=$2 dir=$3 v=$((100 + $2))
  mkdir -p "$dir"
  (
    cd "$dir"
    "$bin" simulate --plant "$plant" --kind identification --seed "$k" -o ident.csv
    "$bin" simulate --plant "$plant" --kind verification --seed "$v" --duration 300 -o verify.csv
    "$bin" simulate --plant "$plant" --kind envelope --seed "$k" -o envelope.csv
    "$bin" simulate --plant "$plant" --kind envelope-verification --seed "$v" -o envelope-verify.csv
    "$bin" identify --train ident.csv --verify verify.csv --out hover --no-plots
    "$bin" identify --train envelope.csv --verify envelope-verify.csv --out envelope --no-plots
  ) >"$dir.log" 2>&1 || echo "$plant pair $k: failed (see its log)" >&2
}

pids=()
for plant in xcell60 flybarless600; do
  for k in $(seq 1 "$pairs"); do
    fly "$plant" "$k" "$work/$plant-$k" &
    pids+=($!)
    # Two pairs at a time (one per core).
    if [ ${#pids[@]} -ge 2 ]; then wait "${pids[0]}" || true; pids=("${pids[@]:1}"); fi
  done
done
for p in "${pids[@]}"; do wait "$p" || true; done
python3 scripts/seeds_report.py "$work" "$pairs" "$(($(date +%s) - start))" >"$output"
echo "wrote $output"
