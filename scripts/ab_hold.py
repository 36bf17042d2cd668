#!/usr/bin/env python3
"""Prints (markdown) a change judged against holding the measured state, for a change that moves
the linear baseline too (ab_report.py and ab_states.py divide by extended plain's free run,
which such a change alters as well): per airframe family and regime, each variant's 2 s
free-run error ÷ holding the measured state on every state, base (`hover-base/`,
`envelope-base/`) → this tree (`hover/`, `envelope/`), as the median over the plants of each
plant's median over its seed pairs, and the worst pair; then how many plants' medians moved by
more than 3 % either way.

Usage: ab_hold.py WORK VARIANT... (WORK: scripts/ab.sh's SEEDS_WORK)
"""
import pathlib
import statistics
import sys

from ab_lib import cell, to_hold, variants as load

work, variants = pathlib.Path(sys.argv[1]), sys.argv[2:]
STATES = ["v_x", "v_y", "v_z", "q", "r", "p"]
FAMILIES = [("xcell60", "X-Cell 60"), ("flybarless600", "flybarless 600")]
REGIMES = [("hover", "hover (identification flight, 300 s verification)"),
           ("envelope", "envelope")]
TOLERANCE = 0.03


def pairs_by_plant(family, regime, variant):
    """{plant: [(base ratios, head ratios)]} over the pairs both trees scored."""
    plants = {}
    for directory in sorted(work.glob(f"{family}-*")):
        if not directory.is_dir():
            continue
        parts = directory.name.split("-")
        plant = parts[1] if len(parts) == 3 else "airframe"
        b = to_hold(load(directory / f"{regime}-base" / "metrics.json"), variant)
        h = to_hold(load(directory / regime / "metrics.json"), variant)
        if b is not None and h is not None:
            plants.setdefault(plant, []).append((b, h))
    return plants


print("Free run ÷ holding the measured state (below 1: the model beats hold). Per state: the "
      "median over the plants of each plant's median over its seed pairs, then the worst pair "
      "(`base → this tree` where they differ); the last columns count the plants whose median "
      "got more than 3 % better or worse.")
for family, title in FAMILIES:
    for regime, regime_title in REGIMES:
        scored = [(v, pairs_by_plant(family, regime, v)) for v in variants]
        if not any(plants for _, plants in scored):
            continue
        print()
        print(f"## {title}, {regime_title}")
        print()
        print("| model | pairs | " + " | ".join(STATES) + " | plants better / worse by > 3 % (states) |")
        print("|---|---:|" + "---:|" * len(STATES) + "---|")
        for variant, plants in scored:
            if not plants:
                continue
            cells, better, worse = [], [], []
            for i, state in enumerate(STATES):
                medians = [(statistics.median(b[i] for b, _ in runs),
                            statistics.median(h[i] for _, h in runs)) for runs in plants.values()]
                worst = (max(b[i] for runs in plants.values() for b, _ in runs),
                         max(h[i] for runs in plants.values() for _, h in runs))
                mb = statistics.median(b for b, _ in medians)
                mh = statistics.median(h for _, h in medians)
                cells.append(f"{cell(mb, mh)} / {cell(*worst)}")
                up = sum(h < b * (1 - TOLERANCE) for b, h in medians)
                down = sum(h > b * (1 + TOLERANCE) for b, h in medians)
                if up:
                    better.append(f"{state} {up}")
                if down:
                    worse.append(f"{state} {down}")
            n = sum(len(r) for r in plants.values())
            print(f"| {variant} | {n} | " + " | ".join(cells) + f" | {', '.join(better) or 'none'}"
                  f" / {', '.join(worse) or 'none'} |")
