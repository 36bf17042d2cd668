#!/usr/bin/env bash
# Regenerates docs/robustness.md: the flight default against extended plain on helicopters it
# was not developed on. For each airframe (X-Cell 60, flybarless 600) it flies the airframe
# itself and PLANTS variations of it (`rotorid simulate --plant-variation SEED`, seeds
# 1..PLANTS), each through the hover pair (identification seed 1, verification seed 2, 300 s)
# and the envelope pair (seeds 1 and 2), runs `rotorid-lab identify` on each pair and writes the
# tables from the metrics files. Deterministic: same seeds, same bits.
#
# Usage: scripts/robustness.sh [PLANTS [OUTPUT]]   (default 12 per airframe, docs/robustness.md;
# about 2 min on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
plants=${1:-12}
output=$(realpath -m "${2:-docs/robustness.md}")

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
# The product's `rotorid` flies the flights; the studies' `rotorid-lab` identifies with the
# full catalogue (the ablations too, which the document's tables read) and writes the document.
# ROTORID_BIN and ROTORID_LAB: binaries already built (CI passes the workspace's, which
# `-p` alone would rebuild with other features).
if [ -z "${ROTORID_BIN:-}" ] || [ -z "${ROTORID_LAB:-}" ]; then
  cargo build -q --release -p rotorid-cli --bin rotorid -p rotorid-lab --bin rotorid-lab
fi
bin="${ROTORID_BIN:-$CARGO_TARGET_DIR/release/rotorid}"
lab="${ROTORID_LAB:-$CARGO_TARGET_DIR/release/rotorid-lab}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

# fly PLANT VARIATION|"" DIR: the four flights and the two identifications of one plant.
fly() {
  local plant=$1 variation=$2 dir=$3
  local v=()
  [ -z "$variation" ] || v=(--plant-variation "$variation")
  mkdir -p "$dir"
  (
    cd "$dir"
    "$bin" simulate --plant "$plant" "${v[@]}" --kind identification --seed 1 -o ident.csv
    "$bin" simulate --plant "$plant" "${v[@]}" --kind verification --seed 2 --duration 300 -o verify.csv
    "$bin" simulate --plant "$plant" "${v[@]}" --kind envelope --seed 1 -o envelope.csv
    "$bin" simulate --plant "$plant" "${v[@]}" --kind envelope-verification --seed 2 -o envelope-verify.csv
    "$lab" identify --train ident.csv --verify verify.csv --out hover --no-plots
    "$lab" identify --train envelope.csv --verify envelope-verify.csv --out envelope --no-plots
    "$lab" identify --train envelope.csv --verify envelope-verify.csv --out envelope-measured \
      --no-plots --free-run-velocity measured
  ) >"$dir.log" 2>&1
}

runs=()
skipped=""
for plant in xcell60 flybarless600; do
  if [ $plant = xcell60 ]; then title="X-Cell 60"; else title="flybarless 600"; fi
  # Two plants at a time (one per core).
  pids=()
  for variation in "" $(seq 1 "$plants"); do
    fly $plant "$variation" "$plant-${variation:-airframe}" &
    pids+=($!)
    if [ ${#pids[@]} -ge 2 ]; then wait "${pids[0]}" || true; pids=("${pids[@]:1}"); fi
  done
  for p in "${pids[@]}"; do wait "$p" || true; done
  for variation in "" $(seq 1 "$plants"); do
    dir=$plant-${variation:-airframe}
    if [ -z "$variation" ]; then label="the airframe itself (docs/results.md)"; else label="variation $variation"; fi
    if [ -f "$dir/envelope-measured/metrics.json" ] && [ -f "$dir/hover/metrics.json" ]; then
      runs+=(--run "$title family|$label|$dir/hover/metrics.json|$dir/envelope/metrics.json|$dir/envelope-measured/metrics.json")
    else
      echo "$title, $label: not flown (see below)" >&2
      tail -3 "$dir.log" >&2
      skipped+=" $plant:${variation:-airframe}"
    fi
  done
done

[ ${#runs[@]} -gt 0 ] || { echo "no plant could be flown" >&2; exit 1; }

how="scripts/robustness.sh $plants
  for each PLANT in xcell60 flybarless600, each SEED in 1..$plants (and the airframe itself, without --plant-variation):
  rotorid simulate --plant PLANT --plant-variation SEED --kind identification --seed 1 -o ident.csv
  rotorid simulate --plant PLANT --plant-variation SEED --kind verification --seed 2 --duration 300 -o verify.csv
  rotorid simulate --plant PLANT --plant-variation SEED --kind envelope --seed 1 -o envelope.csv
  rotorid simulate --plant PLANT --plant-variation SEED --kind envelope-verification --seed 2 -o envelope-verify.csv
  rotorid-lab identify --train ident.csv --verify verify.csv --out hover --no-plots
  rotorid-lab identify --train envelope.csv --verify envelope-verify.csv --out envelope --no-plots
  rotorid-lab identify --train envelope.csv --verify envelope-verify.csv --out envelope-measured --no-plots --free-run-velocity measured"
[ -z "$skipped" ] || how+="
not flown (the simulation failed):$skipped"
"$lab" robustness-report "${runs[@]}" --how "$how" -o "$output"
echo "wrote $output"
