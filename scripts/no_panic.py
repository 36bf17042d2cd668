#!/usr/bin/env python3
"""Lists the panic paths of a Cortex-M ELF: every function that can reach a panic, by the
static call graph of its disassembly (direct `bl`/`b` calls; calls through function pointers
and vtables are not followed, so a panic behind one would be missed). Our own code (rotorid,
rotorid_link, rotorid_mavlink, rotorid_ffi, firmware_ident, firmware_example) is listed apart
from third-party, core and transport code. The deliberate panic of the fault-injection test
hook is not counted.

Usage: scripts/no_panic.py [ELF] [--strict]. With --strict it exits 1 if any function at all
(ours or not) can reach a panic: the gate that host-tests/tests/no_panic.rs (the Rust firmware)
and core/ffi/tests/c_interface.rs (the C firmware) apply."""
import re
import subprocess
import sys

elf = next((a for a in sys.argv[1:] if not a.startswith("--")),
           "firmware-example/target/thumbv7em-none-eabihf/release/firmware-example")
strict = "--strict" in sys.argv
dis = subprocess.run(["arm-none-eabi-objdump", "-d", "-C", "--no-show-raw-insn", elf],
                     capture_output=True, text=True, check=True).stdout
calls, cur = {}, None
for line in dis.splitlines():
    m = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
    if m:
        cur = m.group(1)
        calls.setdefault(cur, set())
        continue
    m = re.search(r"\b(?:bl|b\.w|b|beq\.w|bne\.w)\s+[0-9a-f]+ <([^>+]*)", line)
    if m and cur and m.group(1) != cur:
        calls[cur].add(m.group(1))
roots = {f for f in calls if f.startswith("core::panicking::") or f == "rust_begin_unwind"}
hook = lambda f: "inject_fault" in f  # the deliberate panic of the test hook
panics = set(roots)
changed = True
while changed:
    changed = False
    for f, cs in calls.items():
        if f not in panics and not hook(f) and cs & panics:
            panics.add(f)
            changed = True
ours = ("rotorid", "<rotorid", "firmware_ident", "<firmware_ident", "firmware_example", "<firmware_example")
mine = sorted(f for f in panics - roots if f.startswith(ours))
other = sorted(f for f in panics - roots if not f.startswith(ours))
print(f"{len(mine)} of our functions can reach a panic:")
for f in mine:
    print(f"  {f}  (calls {', '.join(sorted(c for c in calls[f] if c in panics))[:160]})")
print(f"{len(other)} other functions can (third-party, core, transport):")
for f in other:
    print(f"  {f}")
sys.exit(1 if strict and (mine or other) else 0)
