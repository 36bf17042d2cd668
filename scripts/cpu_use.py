#!/usr/bin/env python3
"""Runs a command and reports where its CPU time went: its own (with its children's) user and
system time, the part spent in QEMU processes (`qemu-system-*`, sampled from /proc every
0.2 s: a process's last sample before it exits), and how busy the machine was (all cores,
/proc/stat every 5 s). Linux only.

Usage: python3 scripts/cpu_use.py [--busy] COMMAND [ARGS...]
  e.g. python3 scripts/cpu_use.py cargo test -q -p host-tests --release --test integration
--busy prints the machine's busy share per 5 s interval too (how CI's idle stretches were
found, docs/workspace.md).
"""

import os
import resource
import subprocess
import sys
import threading
import time

HZ = os.sysconf("SC_CLK_TCK")


def machine_ticks():
    """(total, idle) jiffies over all cores."""
    with open("/proc/stat") as f:
        fields = [int(x) for x in f.readline().split()[1:9]]
    return sum(fields), fields[3] + fields[4]


def qemu_cpu(seen):
    """Updates `seen` (pid -> CPU seconds) with every running QEMU process."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/comm") as f:
                if not f.read().startswith("qemu-system"):
                    continue
            with open(f"/proc/{pid}/stat") as f:
                stat = f.read().rsplit(")", 1)[1].split()
            seen[pid] = (int(stat[11]) + int(stat[12])) / HZ
        except (OSError, IndexError, ValueError):
            pass  # the process ended between listing and reading


def main():
    args = sys.argv[1:]
    busy = bool(args) and args[0] == "--busy"
    if busy:
        args = args[1:]
    if not args:
        sys.exit(__doc__)
    seen = {}
    done = threading.Event()
    profile = []

    def sample():
        last = machine_ticks()
        next_busy = time.monotonic() + 5
        while not done.is_set():
            qemu_cpu(seen)
            if time.monotonic() >= next_busy:
                now = machine_ticks()
                total, idle = now[0] - last[0], now[1] - last[1]
                profile.append(100 * (total - idle) // max(total, 1))
                last, next_busy = now, next_busy + 5
            done.wait(0.2)

    sampler = threading.Thread(target=sample)
    start = time.monotonic()
    sampler.start()
    status = subprocess.call(args)
    done.set()
    sampler.join()
    wall = time.monotonic() - start
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    if busy:
        print("busy % per 5 s: " + " ".join(str(p) for p in profile), file=sys.stderr)
    print(
        f"cpu_use: wall {wall:.1f} s, CPU {use.ru_utime:.1f} s user + {use.ru_stime:.1f} s "
        f"system, of which QEMU {sum(seen.values()):.1f} s in {len(seen)} processes",
        file=sys.stderr,
    )
    sys.exit(status)


if __name__ == "__main__":
    main()
