#!/usr/bin/env bash
# Installs what a fresh machine lacks for rotorid's builds and tests. Idempotent and quiet
# when everything is already there.
set -euo pipefail

if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
  rustup target add thumbv7em-none-eabihf
fi
for c in rustfmt clippy; do
  rustup component list --installed | grep -q "^$c" || rustup component add "$c"
done

need_apt=()
command -v qemu-system-arm >/dev/null 2>&1 || need_apt+=(qemu-system-arm)
command -v arm-none-eabi-size >/dev/null 2>&1 || need_apt+=(binutils-arm-none-eabi)
# The C interface's tests: a C compiler for the host and one for the Cortex-M4F firmware.
command -v cc >/dev/null 2>&1 || need_apt+=(gcc)
command -v arm-none-eabi-gcc >/dev/null 2>&1 || need_apt+=(gcc-arm-none-eabi)
# python3 with venv for pymavlink (the MAVLink test, host-tests/tests/mavlink_pymavlink.rs).
python3 -c 'import ensurepip' >/dev/null 2>&1 || need_apt+=(python3 python3-venv)
if [ ${#need_apt[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}" >/dev/null
fi

# pymavlink in .venv/ at the repository root, where the MAVLink test looks first.
venv="$(cd "$(dirname "$0")/.." && pwd)/.venv"
if ! "$venv/bin/python3" -c 'import pymavlink.generator.mavgen' >/dev/null 2>&1; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q 'pymavlink==2.4.50'
fi
