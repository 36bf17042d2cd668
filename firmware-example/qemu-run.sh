#!/usr/bin/env bash
# Cargo runner: boots a firmware ELF on QEMU's mps2-an386 and decodes its defmt log.
#
#   qemu-run.sh ELF [extra qemu args...]
#
# UART0 (the telemetry link) is a TCP server on 127.0.0.1:${ROTORID_UART_PORT:-4444} that does
# not wait for a client; connect a host tool to talk to the firmware. Semihosting carries the
# defmt log (QEMU's stdout) and the exit code. The log is decoded by `defmt-print`
# (`cargo install defmt-print --locked`); without it the raw log is saved next to the ELF.
set -euo pipefail
elf="$1"
shift
port="${ROTORID_UART_PORT:-4444}"
qemu=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -display none -monitor none
  -semihosting-config enable=on,target=native
  -serial "tcp:127.0.0.1:${port},server=on,wait=off,nodelay=on"
  "$@" -kernel "$elf")
if command -v defmt-print >/dev/null 2>&1; then
  "${qemu[@]}" | defmt-print -e "$elf"
else
  echo "qemu-run.sh: defmt-print not found (cargo install defmt-print --locked);" \
    "raw defmt log goes to $elf.defmt" >&2
  "${qemu[@]}" >"$elf.defmt"
fi
