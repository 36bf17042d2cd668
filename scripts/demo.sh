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
cargo run -q -p host-tests --release --bin onboard_demo -- "$@"
