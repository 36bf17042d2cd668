#!/usr/bin/env python3
"""Prints (markdown) the comparison scripts/ab.sh makes: per plant, the median and worst over
the seed pairs of one variant's free run ÷ extended plain's and ÷ holding the measured state,
identified by a base revision's `rotorid` (`hover-base/`, `envelope-base/`) and by this tree's
(`hover/`, `envelope/`), on the same flights.

Usage: ab_report.py WORK PAIRS VARIATIONS VARIANT BASE HEAD SECONDS (SECONDS: `-` when the
flights and identifications were made in several runs, so that no run time is known)
"""
import json
import pathlib
import statistics
import sys

work = pathlib.Path(sys.argv[1])
pairs, variations = int(sys.argv[2]), int(sys.argv[3])
variant, base, head, seconds = sys.argv[4], sys.argv[5], sys.argv[6], sys.argv[7]
PLANTS = [("xcell60", "X-Cell 60"), ("flybarless600", "flybarless 600")]
STATES = ["v_x", "v_y", "v_z", "q", "r", "p"]
TOLERANCE = 1.03


def load(path):
    if not path.exists():
        return None
    return {v["name"]: v for v in json.loads(path.read_text())["variants"]}


def ratios(v):
    """Per state, VARIANT's free run ÷ extended plain's, ÷ hold, ÷ flight plain's."""
    m = v[variant]
    return ([m["free_run"][i] / v["extended plain"]["free_run"][i] for i in range(6)],
            [m["free_run"][i] / m["hold_free_run"][i] for i in range(6)],
            [m["free_run"][i] / v["flight plain"]["free_run"][i] for i in range(6)])


def pair(directory, suffix):
    hover = load(directory / f"hover{suffix}" / "metrics.json")
    envelope = load(directory / f"envelope{suffix}" / "metrics.json")
    if hover is None or envelope is None or variant not in hover or variant not in envelope:
        return None
    (h, _, hp), (e, eh, ep) = ratios(hover), ratios(envelope)
    return {
        "hover q": h[3], "hover r": h[4], "hover p": h[5], "hover worst": max(h),
        "envelope q": e[3], "envelope r": e[4], "envelope p": e[5],
        "envelope r ÷ hold": eh[4],
        "worse than flight plain": sum(x > TOLERANCE for x in hp + ep),
    }


COLUMNS = ["hover q", "hover r", "hover p", "hover worst", "envelope q", "envelope r",
           "envelope p", "envelope r ÷ hold"]


def cell(before, after):
    """`median / worst` of both runs, with an arrow where they differ."""
    def fmt(xs):
        return f"{statistics.median(xs):.2f} / {max(xs):.2f}"
    b, a = fmt(before), fmt(after)
    return a if a == b else f"{b} → {a}"


print(f"# `{variant}`: {base} → {head}")
print()
timing = (f"run time {seconds} s on 2 cores" if seconds.isdigit()
          else "assembled from a kept `SEEDS_WORK`: run time not measured")
print(f"`scripts/ab.sh {base} {pairs} {variations} '{variant}'` ({timing}): "
      f"the flights of `scripts/seeds.sh` (training seed k, verification seed 100 + k, k = 1..{pairs}; "
      f"each airframe and its plant variations 1..{variations}), each identified by `rotorid` at "
      f"{base} and at {head}. Each cell is **median / worst** over the pairs of `{variant}`'s 2 s "
      "free-run error ÷ extended plain's (÷ holding the measured state where the column says so); "
      f"`a → b`: {base}'s, then {head}'s, where they differ. The last column counts the pairs' "
      f"states (hover and envelope, six each) where `{variant}` is more than 3 % worse than "
      "`flight plain`. Only pairs both revisions identified are scored.")
summary = {"base": {c: [] for c in COLUMNS}, "head": {c: [] for c in COLUMNS}}
for plant, title in PLANTS:
    print()
    print(f"## {title} family")
    print()
    print("| plant | pairs | " + " | ".join(COLUMNS) + f" | states > 3 % worse than flight plain |")
    print("|---|---:|" + "---:|" * (len(COLUMNS) + 1))
    for variation in [None] + list(range(1, variations + 1)):
        name = plant + (f"-v{variation}" if variation else "")
        runs = []
        for k in range(1, pairs + 1):
            directory = work / f"{name}-{k}"
            b, h = pair(directory, "-base"), pair(directory, "")
            if b is not None and h is not None:
                runs.append((b, h))
        if not runs:
            continue
        cells = []
        for c in COLUMNS:
            before, after = [b[c] for b, _ in runs], [h[c] for _, h in runs]
            summary["base"][c].append(statistics.median(before))
            summary["head"][c].append(statistics.median(after))
            cells.append(cell(before, after))
        worse = (sum(b["worse than flight plain"] for b, _ in runs),
                 sum(h["worse than flight plain"] for _, h in runs))
        label = "the airframe" if variation is None else f"variation {variation}"
        print(f"| {label} | {len(runs)} | " + " | ".join(cells)
              + f" | {worse[0]}" + ("" if worse[0] == worse[1] else f" → {worse[1]}") + " |")
plants = len(summary["head"][COLUMNS[0]])
print()
print(f"## Over the {plants} plants")
print()
print("Per column, the median over the plants of each plant's median, and the plants whose "
      "median is at most 0.7 and below 1 (base → head):")
print()
print("| column | median over the plants | plants at most 0.7 | plants below 1 |")
print("|---|---:|---:|---:|")
for c in COLUMNS:
    b, h = summary["base"][c], summary["head"][c]
    if not b:
        continue
    print(f"| {c} | {statistics.median(b):.2f} → {statistics.median(h):.2f} | "
          f"{sum(x <= 0.7 for x in b)} → {sum(x <= 0.7 for x in h)} | "
          f"{sum(x < 1 for x in b)} → {sum(x < 1 for x in h)} |")
