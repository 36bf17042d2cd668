#!/usr/bin/env bash
# All of rotorid's tests: the core (unit, integration, doc tests), the host side (reference
# agreement, properties, golden bits, plant, tool) and the firmware under QEMU.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
part() { echo "-- $1 (at $((SECONDS / 60)) min $((SECONDS % 60)) s)"; }
# The core on its own, without its `std` feature (in a workspace build the host crate turns it
# on): its golden test proves the bits do not depend on the feature.
part core
cargo test -p rotorid
# The same golden bits in debug with `std` on (the host build's feature set), so that debug and
# release, with and without `std`, all reproduce the one committed set.
cargo test -p rotorid --features std --test integration golden::
# Everything, optimised.
part "workspace, release"
cargo test --workspace --release
# The CLI binary that build made, for the Python tests to compare with (building it again
# with `-p rotorid-cli` would unify features differently and rebuild 15 crates).
export ROTORID_BIN="${CARGO_TARGET_DIR:-$PWD/target}/release/rotorid"
# No second, unoptimised pass of the workspace: the release profile keeps integer overflow
# checks on (Cargo.toml), so the pass above checks every crate's arithmetic as debug would, and
# the core's bits are checked unoptimised above (the golden files, with and without `std`).
# The C interface (its own workspace: a static library aborts on panic): the header is up to
# date, and a C program on the host and a C firmware under QEMU match rotorid bit for bit.
part "C interface"
cargo test --manifest-path core/ffi/Cargo.toml
# The Python package: the wheel built and installed in a fresh venv, its tests (identical
# bytes to the CLI and the C interface, bad input, a Dask fleet, the example notebook).
part Python
bash scripts/python.sh
part done
