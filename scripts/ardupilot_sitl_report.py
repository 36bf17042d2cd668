"""Writes docs/ardupilot-sitl.md from `rotorid identify` runs on the ArduPilot SITL helicopter
logs (scripts/ardupilot-sitl.sh).

Arguments: OUTPUT, then one LOG|RUN_DIR per log (RUN_DIR holds metrics.json when the run
succeeded, stdout.txt, stderr.txt and status).
"""
import json
import os
import sys

AXES = ["east velocity (m/s)", "down velocity (m/s)", "north velocity (m/s)",
        "pitch rate q (deg/s)", "yaw rate r (deg/s)", "roll rate p (deg/s)"]
ORDER = [2, 0, 1, 5, 3, 4]
FLIGHTS = {
    "sid": "hover: ArduPilot SystemID chirps at the mixer on roll, pitch and yaw, then stick "
           "doublets on each axis, in STABILIZE around 30 m",
    "envelope": "low-speed envelope: GUIDED body-frame velocity steps forward 1, 2, 3, 5 m/s "
                "and right 1, 2, 3 m/s, hover between them",
}


def delay_line(m):
    """The controls' delay identify applied, and how each candidate scored."""
    d = m.get("control_delay")
    if d is None:
        return "controls' delay: none applied (too little training data to choose one)"
    def cell(c):
        score = "—" if c["score"] is None else f"{c['score']:.2f}"
        n = c['diverged']
        diverged = f" ({n} window{'s' if n != 1 else ''} diverged)" if n else ""
        return f"{c['delay_s'] * 1e3:.0f} ms {score}{diverged}"
    scores = ", ".join(cell(c) for c in d.get("scores", []))
    how = (f"chosen on the training data (the flight default's free run / hold, geometric "
           f"mean over the six states, per candidate: {scores})" if scores else "given")
    return f"controls delayed by {d['delay_s'] * 1e3:.0f} ms, {how}"

def fmt_rate(r):
    return "—" if r is None else f"{r:.1f} Hz"


def ratio(a, b):
    return f"{a / b:.2f}" if b > 0 else "—"


def section(log, run):
    name = os.path.basename(log)
    kind = next((v for k, v in FLIGHTS.items() if k in name), "flight")
    lines = [f"## `{name}` ({kind})", ""]
    status = int(open(os.path.join(run, "status")).read().strip())
    stderr = open(os.path.join(run, "stderr.txt")).read().splitlines()
    stdout = open(os.path.join(run, "stdout.txt")).read().splitlines()
    if status != 0:
        err = [l for l in stderr if l.startswith("error:")]
        lines += ["Not identified. The tool's one line:", "", "```text",
                  *(l.replace(os.path.dirname(log) + "/", "") for l in err), "```", ""]
        return lines
    m = json.load(open(os.path.join(run, "metrics.json")))
    for s in m.get("logs", []):
        r = s.get("native_rates") or {}
        lines.append(
            f"- format {s['format']}; native rates: attitude {fmt_rate(r.get('attitude'))}, "
            f"velocity {fmt_rate(r.get('velocity'))}, body rates {fmt_rate(r.get('rates'))}, "
            f"controls {fmt_rate(r.get('controls'))}; identified at {m['rate_hz']:g} Hz; "
            f"{s['duration_s']:.1f} s in {s['segments']} segment(s); ground time from: "
            f"{s.get('in_air') or 'not looked for'}")
        for a, b, why in s["cuts"]:
            a = "start" if a is None else f"{a:.2f} s"
            b = "end" if b is None else f"{b:.2f} s"
            lines.append(f"- cut {a} to {b}: {why}")
    lines.append(f"- {m['split']}")
    lines.append(f"- {delay_line(m)}")
    lines.append("")
    v = {x["name"]: x for x in m["variants"]}
    flight, plain = v["flight"], v["extended plain"]
    lines += ["Free run (2 s windows) on the held-out part, mean absolute error, and ratios "
              "(below 1 is better):", "",
              "| axis | flight default | hold | extended plain | flight / hold | flight / ext. plain |",
              "|---|---:|---:|---:|---:|---:|"]
    worse = []
    for i in ORDER:
        f, h, p = flight["free_run"][i], flight["hold_free_run"][i], plain["free_run"][i]
        if f >= h:
            worse.append(AXES[i])
        lines.append(f"| {AXES[i]} | {f:.3f} | {h:.3f} | {p:.3f} | {ratio(f, h)} | {ratio(f, p)} |")
    lines.append("")
    # The identified derivatives per regime, as the tool prints them.
    deriv = [l for l in stdout if l.startswith("  all ") or l.startswith("  hover")
             or l.startswith("  forward") or l.startswith("    X_u")]
    if deriv:
        lines += ["Body-axis derivatives as `rotorid identify` prints them (control power in "
                  "deg/s² per 10 % stick):", "", "```text", *deriv, "```", ""]
    verdict = m.get("verdict")
    if not verdict:
        lines += [l for l in stdout if l.startswith("No verdict")] + [""]
    if verdict:
        if not verdict.get("fly", True):
            lines.append(f"Verdict: **no model to fly** (closest: {verdict['model']}); {verdict['why']}.")
        else:
            lines.append(f"Verdict: **{verdict['model']}**; {verdict['why']}.")
        lines.append("")
        for c in verdict["caveats"]:
            lines.append(f"- {c}")
    if worse:
        lines.append(f"- The flight default is worse than hold on: {', '.join(worse)}.")
    for w in stderr:
        if w.startswith("warning:") or w.startswith("note: at"):
            lines.append(f"- {w.replace(os.path.dirname(log) + '/', '')}")
    lines.append("")
    return lines


def main():
    output, runs = sys.argv[1], sys.argv[2:]
    out = ["# ArduPilot SITL helicopter logs (generated by `scripts/ardupilot-sitl.sh`; do not edit)",
           "",
           "`rotorid identify LOG` on each DataFlash log that ArduPilot's SITL helicopter (frame",
           "`heli`, ArduPilot's own TradHeli physics) wrote while `scripts/ardupilot_sitl_fly.py`",
           "flew it (provenance, parameters and licence in",
           "`host-tests/cli/data/logs/ardupilot-sitl/README.md`). The controls are the rate",
           "controllers' normalised outputs before the swashplate mixer (`RATE` `ROut POut YOut`)",
           "and the collective (`RATE` `AOut`); the SystemID chirps are added at the mixer, so they",
           "are in those outputs. ArduPilot's SITL helicopter is a simplified rigid-body model",
           "written by ArduPilot, not a flight test: these numbers say how rotorid does on logs",
           "written by a real flight stack flying closed loop, not on a real airframe.", "",
           "Logging for identification on ArduCopter 4.7 (from its source at the commit in the",
           "README; the rates below each log's heading are what the import measured):",
           "`LOG_BITMASK` bit 0 (ATTITUDE_FAST) writes `ANG` (attitude) and `RATE` (rates, rate",
           "outputs, collective `AOut`) every main-loop cycle (400 Hz on a helicopter);",
           "`LOG_FILE_RATEMAX` caps every streaming message (50 here, the fastest rate rotorid",
           "identifies at). The EKF velocity `XKF1` is written by the 25 Hz logging task whatever",
           "the bitmask, so an ArduCopter log is identified at 25 Hz at most; `ATT`, `CTUN`, `RCOU`",
           "are 10 Hz.", ""]
    for r in runs:
        log, run = r.split("|", 1)
        out += section(log, run)
    with open(output, "w") as f:
        f.write("\n".join(out).rstrip() + "\n")


if __name__ == "__main__":
    main()
