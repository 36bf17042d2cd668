"""What the A/B reports share (ab_states.py, ab_hold.py, ab_real_logs.py): reading a run's
variants and printing a base → changed cell."""
import json


def read(path):
    """The metrics.json at PATH, or None when there is none."""
    return json.loads(path.read_text()) if path.exists() else None


def variants_of(metrics):
    """{name: variant} of a run's metrics (None for None)."""
    return None if metrics is None else {v["name"]: v for v in metrics["variants"]}


def variants(path):
    """{name: variant} of the metrics.json at PATH, or None when there is none."""
    return variants_of(read(path))


def to_hold(by_name, variant):
    """VARIANT's free run ÷ holding the measured state per state, or None."""
    m = (by_name or {}).get(variant)
    if m is None:
        return None
    return [f / h if h > 0 else float("nan") for f, h in zip(m["free_run"], m["hold_free_run"])]


def cell(b, h):
    """`b` where both print alike, else `b → h` (two decimals)."""
    b, h = f"{b:.2f}", f"{h:.2f}"
    return b if b == h else f"{b} → {h}"
