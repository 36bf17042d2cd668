#!/usr/bin/env bash
# The 24-hour soak (4.32 M steps at 50 Hz, an hour without excitation): writes docs/soak.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release -q -p host-tests --bin soak -- --report "$@"
