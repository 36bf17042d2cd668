#!/usr/bin/env bash
# docs/ardupilot-sitl.md: `rotorid identify` on the ArduPilot SITL helicopter logs committed under
# host-tests/cli/data/logs/ardupilot-sitl/ (issue 30): per log (hover with SystemID chirps and
# doublets; the low-speed envelope), the import's rates and cuts, and per axis the flight default
# against extended plain and against holding the measured state.
#
# The logs themselves come from scripts/ardupilot_sitl_fly.py flying an ArduPilot SITL binary;
# that needs ArduPilot's source (fetched by hand, see the logs' README), which CI does not have,
# so the logs are committed and this script only identifies them.
# Usage: scripts/ardupilot-sitl.sh [OUTPUT] (default docs/ardupilot-sitl.md).
set -euo pipefail
cd "$(dirname "$0")/.."
output="${1:-docs/ardupilot-sitl.md}"
cargo build -q --release -p rotorid-cli
bin="${CARGO_TARGET_DIR:-$PWD/target}/release/rotorid"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
runs=()
# shellcheck source=scripts/lib/logs.sh
. scripts/lib/logs.sh
for log in "${SITL_LOGS[@]}"; do
  name=$(basename "$log")
  out="$work/$name"
  mkdir -p "$out"
  set +e
  "$bin" identify "$log" --out "$out" --no-plots >"$out/stdout.txt" 2>"$out/stderr.txt"
  echo $? >"$out/status"
  set -e
  runs+=("$log|$out")
done
python3 scripts/ardupilot_sitl_report.py "$output" "${runs[@]}"
echo "wrote $output"
