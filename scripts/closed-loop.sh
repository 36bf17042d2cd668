#!/usr/bin/env bash
# Regenerates docs/closed-loop.md: how the pilot's feedback during the identification flight
# biases what `rotorid identify` learns (issue 32, item 6). A helicopter at hover is unstable,
# so there is no open-loop flight to compare with: the same plant is flown with the pilot's
# gains times SCALE (`rotorid simulate --pilot-gain-scale`), and for each scale and seed pair
# k = 1..PAIRS (identification seed k, verification seed 100 + k, the verification flight
# always flown by the default pilot) `rotorid identify` is run; scripts/closed_loop_report.py
# compares the body-axis derivatives with the simulator's hover linearisation
# (host-tests/sim/examples/hover_linearisation.rs) and the flight default's free run, and
# (scripts/closed_loop_iv.py) fits the pitch and yaw rates by least squares and with the
# commanded sweep as instrument (host-tests/sim/examples/sweep_excitation.rs).
# Deterministic: same seeds, same bits. Not run by CI (a few minutes on 2 cores).
#
# Usage: scripts/closed-loop.sh [PAIRS [OUTPUT]]   (default 10 pairs, docs/closed-loop.md)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
pairs=${1:-10}
output=$(realpath -m "${2:-docs/closed-loop.md}")
# Feedback scales: 0.25–2 hold hover without saturating a stick; from 3 up the attitude loops
# ring against the stick limits (the 50 Hz hold erodes the body-flap modes' damping), which is
# not a pilot anyone flies with.
scales=(0.25 0.5 1 2)
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
cargo build -q --release -p rotorid-cli --bin rotorid
cargo build -q --release -p rotorid-sim --example hover_linearisation --example sweep_excitation
bin="$CARGO_TARGET_DIR/release/rotorid"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
"$CARGO_TARGET_DIR/release/examples/hover_linearisation" >"$work/truth.json"
"$CARGO_TARGET_DIR/release/examples/sweep_excitation" >"$work/excitation.csv"

# fly K: the verification flight of pair K and, per scale, its identification flight and
# identification (a flight that cannot be flown leaves its metrics out; the report counts it).
fly() {
  local k=$1 v=$((100 + $1)) dir="$work/$1"
  mkdir -p "$dir"
  (
    cd "$dir"
    "$bin" simulate --kind verification --seed "$v" -o verify.csv
    for s in "${scales[@]}"; do
      if "$bin" simulate --kind identification --seed "$k" --pilot-gain-scale "$s" -o "ident-$s.csv"; then
        "$bin" identify --train "ident-$s.csv" --verify verify.csv --out "scale-$s" --no-plots \
          || echo "pair $k, scale $s: identify failed"
      else
        echo "pair $k, scale $s: the flight could not be flown"
      fi
    done
  ) >"$dir.log" 2>&1 || echo "pair $k: failed (see its log)" >&2
}

pids=()
for k in $(seq 1 "$pairs"); do
  fly "$k" &
  pids+=($!)
  # Two pairs at a time (one per core).
  if [ ${#pids[@]} -ge 2 ]; then wait "${pids[0]}" || true; pids=("${pids[@]:1}"); fi
done
for p in "${pids[@]}"; do wait "$p" || true; done
PYTHONDONTWRITEBYTECODE=1 python3 scripts/closed_loop_report.py "$work" "$pairs" "$(($(date +%s) - start))" "${scales[@]}" >"$output"
echo "wrote $output"
