"""What `rotorid identify` did to a log before identifying it, as report lines: shared by
scripts/real_logs_report.py and scripts/ardupilot_sitl_report.py."""

import json
import os


def load_run(log, run):
    """`identify`'s run on LOG kept in directory RUN (status, stderr.txt, metrics.json):
    (metrics, None) when it identified the log, else (None, the report's lines quoting the
    tool's one error line)."""
    status = int(open(os.path.join(run, "status")).read().strip())
    if status == 0:
        return json.load(open(os.path.join(run, "metrics.json"))), None
    stderr = open(os.path.join(run, "stderr.txt")).read().splitlines()
    err = [l for l in stderr if l.startswith("error:")]
    return None, ["Not identified. The tool's one line:", "", "```text",
                  *(l.replace(os.path.dirname(log) + "/", "") for l in err), "```", ""]


def fmt_rate(r):
    return "—" if r is None else f"{r:.1f} Hz"


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


def import_lines(m):
    """Per log of metrics.json `m`: format, native rates, segments, cuts; then the hold-out
    split and the controls' delay."""
    lines = []
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
    return lines
