#!/usr/bin/env python3
"""Prints (markdown) a change's effect on the real logs of scripts/real-logs.sh and the SITL
helicopter's of scripts/ardupilot-sitl.sh: per log, the flight default's and `flight
selected`'s 2 s free-run error ÷ holding the measured state on each axis, and the verdict's
model to fly, identified by the base revision (`BASE/NAME/`) and by the changed tree
(`HEAD/NAME/`), each `rotorid identify LOG --out DIR` with the default hold-out.

Usage: ab_real_logs.py BASE HEAD NAME...
"""
import pathlib
import sys

from ab_lib import cell, read, to_hold, variants_of

base, head, names = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), sys.argv[3:]
STATES = ["v_x", "v_y", "v_z", "q", "r", "p"]
VARIANTS = ["flight", "flight selected"]


def verdict(metrics):
    """The verdict's model to fly, or `none`."""
    v = metrics.get("verdict") or {}
    return v.get("model", "none") if v.get("fly") else "none"


def ok(r):
    """Whether q and p are no worse than hold."""
    return "yes" if r[3] <= 1 and r[5] <= 1 else "no"


print("Free run ÷ holding the measured state on the held-out part (paper axes: `v_x` east, "
      "`v_y` up, `v_z` south; below 1: the model beats hold), `base → changed` where they "
      "differ. A log that either run could not identify is left out.")
print()
print("| log | model | " + " | ".join(STATES) + " | q and p at most hold | model to fly |")
print("|---|---|" + "---:|" * len(STATES) + "---|---|")
for name in names:
    b, h = read(base / name / "metrics.json"), read(head / name / "metrics.json")
    if b is None or h is None:
        continue
    vb, vh = verdict(b), verdict(h)
    for variant in VARIANTS:
        rb, rh = to_hold(variants_of(b), variant), to_hold(variants_of(h), variant)
        if rb is None or rh is None:
            continue
        cells = " | ".join(cell(x, y) for x, y in zip(rb, rh))
        okb, okh = ok(rb), ok(rh)
        print(f"| `{name}` | {variant} | {cells} | {okb if okb == okh else f'{okb} → {okh}'} | "
              f"{vb if vb == vh else f'{vb} → {vh}'} |")
