#!/usr/bin/env python3
"""Prints (markdown) a change's effect on the real logs of scripts/real-logs.sh and the SITL
helicopter's of scripts/ardupilot-sitl.sh: per log, the flight default's and `flight
selected`'s 2 s free-run error ÷ holding the measured state on each axis, and the verdict's
model to fly, identified by the base revision (`BASE/NAME/`) and by the changed tree
(`HEAD/NAME/`), each `rotorid identify LOG --out DIR` with the default hold-out.

Usage: ab_real_logs.py BASE HEAD NAME...
"""
import json
import pathlib
import sys

base, head, names = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), sys.argv[3:]
STATES = ["v_x", "v_y", "v_z", "q", "r", "p"]
VARIANTS = ["flight", "flight selected"]


def load(directory):
    path = directory / "metrics.json"
    return json.loads(path.read_text()) if path.exists() else None


def to_hold(metrics, variant):
    m = {v["name"]: v for v in metrics["variants"]}.get(variant)
    if m is None:
        return None
    return [f / h if h > 0 else float("nan") for f, h in zip(m["free_run"], m["hold_free_run"])]


def verdict(metrics):
    """The verdict's model to fly, or `none`."""
    v = metrics.get("verdict") or {}
    return v.get("model", "none") if v.get("fly") else "none"


def ok(r):
    """Whether q and p are no worse than hold."""
    return "yes" if r[3] <= 1 and r[5] <= 1 else "no"


def fmt(b, h):
    b, h = f"{b:.2f}", f"{h:.2f}"
    return b if b == h else f"{b} → {h}"


print("Free run ÷ holding the measured state on the held-out part (paper axes: `v_x` east, "
      "`v_y` up, `v_z` south; below 1: the model beats hold), `base → changed` where they "
      "differ. A log that either run could not identify is left out.")
print()
print("| log | model | " + " | ".join(STATES) + " | q and p at most hold | model to fly |")
print("|---|---|" + "---:|" * len(STATES) + "---|---|")
for name in names:
    b, h = load(base / name), load(head / name)
    if b is None or h is None:
        continue
    for variant in VARIANTS:
        rb, rh = to_hold(b, variant), to_hold(h, variant)
        if rb is None or rh is None:
            continue
        cells = " | ".join(fmt(x, y) for x, y in zip(rb, rh))
        okb, okh = ok(rb), ok(rh)
        vb, vh = verdict(b), verdict(h)
        print(f"| `{name}` | {variant} | {cells} | {okb if okb == okh else f'{okb} → {okh}'} | "
              f"{vb if vb == vh else f'{vb} → {vh}'} |")
