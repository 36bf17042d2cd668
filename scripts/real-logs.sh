#!/usr/bin/env bash
# docs/real-logs.md: `rotorid identify` straight from each real public log committed under
# host-tests/cli/data/logs/ (no hand trimming, the default hold-out), and what it decided: the
# import's cuts and native rates, and the flight default's free run against holding the
# measured state and against the linear baseline per axis, or the one line that says what is
# missing. Usage: scripts/real-logs.sh [OUTPUT] (default docs/real-logs.md).
set -euo pipefail
cd "$(dirname "$0")/.."
output="${1:-docs/real-logs.md}"
cargo build -q --release -p rotorid-cli
bin="${CARGO_TARGET_DIR:-$PWD/target}/release/rotorid"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=scripts/lib/logs.sh
. scripts/lib/logs.sh
runs=()
for log in "${REAL_LOGS[@]}"; do
  name=$(basename "$log")
  out="$work/$name"
  mkdir -p "$out"
  set +e
  "$bin" identify "$log" --out "$out" --no-plots >"$out/stdout.txt" 2>"$out/stderr.txt"
  echo $? >"$out/status"
  set -e
  runs+=("$log|$out")
done
python3 scripts/real_logs_report.py "$output" "${runs[@]}"
echo "wrote $output"
