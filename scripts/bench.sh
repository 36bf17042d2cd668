#!/usr/bin/env bash
# Runs the RLS / HoverIdentifier benchmarks (about 3 minutes) and regenerates docs/benchmarks.md.
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir="${CARGO_TARGET_DIR:-target}"
cargo bench -p rotorid-bench --bench rls -- --noplot
mkdir -p docs
cargo run -q --release -p host-tests --bin bench_report -- "$target_dir/criterion" docs/benchmarks.md
