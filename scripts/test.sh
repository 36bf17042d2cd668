#!/usr/bin/env bash
# All of rotorid's tests: the core (unit, integration, doc tests), the host side (reference
# agreement, properties, golden bits, plant, tool) and the firmware under QEMU.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo test --workspace --release
cargo test --workspace
