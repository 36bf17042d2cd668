#!/usr/bin/env bash
# Main job. Until the onboard demonstration lands, this runs the core's memory report.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run -q -p rotorid --release --example memory
