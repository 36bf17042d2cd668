#!/usr/bin/env bash
# All of rotorid's tests: the core (unit, integration, doc tests), the host side (reference
# agreement, properties, golden bits, plant, tool) and the firmware under QEMU.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# The core on its own, without its `std` feature (in a workspace build the host crate turns it
# on): its golden test proves the bits do not depend on the feature.
cargo test -p rotorid
# Everything, optimised and in debug: the golden files must come out of both.
cargo test --workspace --release
cargo test --workspace
# The C interface (its own workspace: a static library aborts on panic): the header is up to
# date, and a C program on the host and a C firmware under QEMU match rotorid bit for bit.
cargo test --manifest-path core/ffi/Cargo.toml
# The Python package: the wheel built and installed in a fresh venv, its tests (identical
# bytes to the CLI and the C interface, bad input, a Dask fleet, the example notebook).
bash scripts/python.sh
