#!/usr/bin/env bash
# Main job: onboard identification on an emulated Cortex-M4F. Builds the firmware, boots it in
# QEMU, streams the simulated envelope flights (those of docs/results.md) over the serial link:
# the flight default (FlightIdentifier) and its baseline (ExtendedPlainIdentifier) learn over
# the identification flight, then, θ frozen, predict one step and free-run 2 s windows over
# the verification flight. Prints the errors per state computed onboard, the ratio flight /
# extended plain, whether they equal `rotorid identify`'s on the host, and the bit-for-bit
# verdict vs the host. `./scripts/demo.sh --paper`: the paper's pair on the hover flights
# (the Table 4 analogue).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# The build first, with cargo's progress shown: from a fresh clone it takes about a minute on
# 2 cores, before the demo prints its first line (docs/workspace.md). The demo binary uses
# rotorid-cli without its figures and command line (host-tests/Cargo.toml), so plotters'
# image stack and clap are not built. The firmware builds
# beside it, quietly: the release profile compiles each large crate on one core, so the
# other is free most of the time. (The demo builds the firmware again, finding it done, and
# shows cargo's error if this build failed.)
echo "rotorid demo: building the host tools and the firmware (a fresh clone: about a minute)..."
(cd firmware-example && env -u CARGO_TARGET_DIR -u RUSTFLAGS -u CARGO_BUILD_TARGET \
  cargo build -q --release >/dev/null 2>&1) &
firmware=$!
cargo build --release -p host-tests --bin onboard_demo
wait "$firmware" || true
cargo run -q -p host-tests --release --bin onboard_demo -- "$@"
