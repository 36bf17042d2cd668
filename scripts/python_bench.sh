#!/usr/bin/env bash
# Regenerates docs/python.md: logs identified per second by the Python package against the
# number of workers (1, 2), with `rotorid.identify_many` (threads, the GIL released) and on a
# Dask LocalCluster (worker processes), over the same simulated logs. A benchmark, not a
# test: the numbers depend on the machine and its load.
#
# Usage: scripts/python_bench.sh [LOGS [OUTPUT]]   (default 24 logs, docs/python.md)
# Needs the venv with the wheel that scripts/python.sh builds (run that first).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
target="${CARGO_TARGET_DIR:-$root/target}"
py="$target/python-venv/bin/python"
if [ ! -x "$py" ]; then
  echo "error: $py missing: run scripts/python.sh first (it builds and installs the wheel)" >&2
  exit 1
fi
"$py" scripts/python_bench.py "${1:-24}" "$(realpath -m "${2:-docs/python.md}")"
