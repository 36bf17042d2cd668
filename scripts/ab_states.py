#!/usr/bin/env python3
"""Prints (markdown) every state of scripts/ab.sh's comparison: per plant and regime, the median
over the seed pairs of one variant's free run ÷ extended plain's on each of the six states
(ab_report.py shows the rates and the worst state only), base (`hover-base/`,
`envelope-base/`) → this tree (`hover/`, `envelope/`), and per regime the median over the
plants of each plant's median. First, per airframe family and regime, how many of this tree's
pairs have a model's rules on another speed (the verdict's `terms_off`; `flight selected`'s
premise candidates, `rotorid identify`'s default).

Usage: ab_states.py WORK VARIANT (WORK: ab.sh's SEEDS_WORK)
"""
import json
import pathlib
import statistics
import sys

from ab_lib import cell

work, variant = pathlib.Path(sys.argv[1]), sys.argv[2]
STATES = ["v_x", "v_y", "v_z", "q", "r", "p"]


def ratios(path):
    """VARIANT's free run ÷ extended plain's per state, or None."""
    if not path.exists():
        return None
    v = {x["name"]: x for x in json.loads(path.read_text())["variants"]}
    if variant not in v:
        return None
    return [v[variant]["free_run"][i] / v["extended plain"]["free_run"][i] for i in range(6)]


def plant_of(name):
    """`xcell60-v3-7` → (`xcell60`, `variation 3`); `xcell60-7` → (`xcell60`, `the airframe`)."""
    parts = name.split("-")
    label = f"variation {parts[1][1:]}" if len(parts) == 3 else "the airframe"
    return parts[0], label


moved, pairs = {}, {}
for d in sorted(p for p in work.iterdir() if p.is_dir()):
    for regime in ["hover", "envelope"]:
        path = d / regime / "metrics.json"
        if not path.exists():
            continue
        key = ("X-Cell 60" if plant_of(d.name)[0] == "xcell60" else "flybarless 600", regime)
        pairs[key] = pairs.get(key, 0) + 1
        for t in json.loads(path.read_text())["verdict"]["terms_off"]:
            if ": rules on the " in t:
                name = t.replace(": rules on the ", " on the ")
                moved.setdefault(key, {}).setdefault(name, 0)
                moved[key][name] += 1
print("| family, regime | pairs | rules moved to another speed (pairs) |")
print("|---|---:|---|")
for key in sorted(pairs, key=lambda k: (k[0] != "X-Cell 60", k[1] != "hover")):
    counts = sorted(moved.get(key, {}).items(), key=lambda kv: (-kv[1], kv[0]))
    text = ", ".join(f"{n} {c}" for n, c in counts) or "none"
    print(f"| {key[0]}, {key[1]} | {pairs[key]} | {text} |")

for regime in ["hover", "envelope"]:
    plants = {}
    for d in sorted(p for p in work.iterdir() if p.is_dir()):
        base, head = ratios(d / f"{regime}-base" / "metrics.json"), ratios(d / regime / "metrics.json")
        if base is None or head is None:
            continue
        plants.setdefault(plant_of(d.name), []).append((base, head))
    print(f"\n### {regime.capitalize()}: `{variant}` ÷ extended plain, median over the pairs\n")
    print("| plant | pairs | " + " | ".join(STATES) + " |")
    print("|---|---:|" + "---:|" * 6)
    medians = []
    for (family, label), rows in sorted(plants.items(), key=lambda kv: (kv[0][0] != "xcell60", kv[0])):
        m = [(statistics.median(r[0][i] for r in rows), statistics.median(r[1][i] for r in rows))
             for i in range(6)]
        medians.append(m)
        name = "X-Cell 60" if family == "xcell60" else "flybarless 600"
        print(f"| {name}, {label} | {len(rows)} | " + " | ".join(cell(*x) for x in m) + " |")
    over = [cell(statistics.median(m[i][0] for m in medians), statistics.median(m[i][1] for m in medians))
            for i in range(6)]
    print(f"| median over the {len(medians)} plants | | " + " | ".join(over) + " |")
