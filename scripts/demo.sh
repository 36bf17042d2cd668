#!/usr/bin/env bash
# Main job: onboard identification on an emulated Cortex-M4F. Builds the firmware, boots it in
# QEMU, streams the simulated identification and verification flights over the serial link,
# and prints the Table 4 analogue computed onboard with the bit-for-bit verdict vs the host.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run -q -p host-tests --release --bin onboard_demo
