"""Fleet-scale identification: one row of control powers per log, a per-airframe table, and
a data-driven drift flag (a worn or damaged rotor shows up as lower control power).

The functions are plain and picklable so that Dask (``client.map``), ``multiprocessing`` or
``identify_many`` can run them; ``examples/fleet_dask.py`` puts them together.
"""

from __future__ import annotations

import math
import os
import tempfile
from typing import Any, Dict, Iterable, List, Optional, Sequence

import pandas as pd

from . import identify, simulate

#: The control powers tracked per log: roll per lateral cyclic, pitch per longitudinal
#: cyclic, yaw per pedal (body-axis derivatives, deg/s² per 10 % stick as the CLI prints
#: them; the table keeps the derivatives' own unit, rad/s² per unit stick).
CONTROL_POWERS = ("L_lat", "M_lon", "N_ped")


def control_powers(result: Any, region: str = "all") -> Dict[str, float]:
    """The control powers (``CONTROL_POWERS``) and their standard errors of one
    ``IdentifyResult``, from its derivatives of ``region`` (``all``: the whole log);
    NaN where not fitted."""
    d = result.derivatives()
    d = d[d["region"] == region]
    row: Dict[str, float] = {}
    for symbol in CONTROL_POWERS:
        hit = d[d["symbol"] == symbol]
        row[symbol] = float(hit["value"].iloc[0]) if len(hit) else math.nan
        row[symbol + "_se"] = float(hit["se"].iloc[0]) if len(hit) else math.nan
    return row


def identify_log(path: str, airframe: str, flight: int, **options: Any) -> Dict[str, Any]:
    """Identifies one log (held-out verification, no files written) and returns its row:
    ``airframe``, ``flight`` (order within the airframe), ``path``, ``model`` and the
    control powers with their standard errors."""
    options.setdefault("plots", False)
    result = identify(path, **options)
    return {
        "airframe": airframe,
        "flight": flight,
        "path": path,
        "model": result.model,
        **control_powers(result),
    }


def simulate_and_identify(spec: Dict[str, Any]) -> Dict[str, Any]:
    """Flies one simulated log and identifies it (the unit of work of the fleet example):
    ``spec`` has ``airframe`` (a name), ``flight``, ``seed``, ``plant_variation`` and
    optionally ``plant``, ``kind``, ``duration`` (s), ``cyclic_power``, ``dir`` (where the
    CSV goes; default a temporary directory, removed after)."""
    directory = spec.get("dir")
    with tempfile.TemporaryDirectory() as tmp:
        base = directory or tmp
        path = os.path.join(base, f"{spec['airframe']}-{spec['flight']:03d}.csv")
        simulate(
            spec.get("kind", "verification"),
            seed=spec["seed"],
            plant=spec.get("plant", "xcell60"),
            plant_variation=spec["plant_variation"],
            duration=spec.get("duration", 60.0),
            cyclic_power=spec.get("cyclic_power", 1.0),
            out=path,
        )
        row = identify_log(path, spec["airframe"], spec["flight"])
    row["cyclic_power"] = spec.get("cyclic_power", 1.0)
    return row


def parameter_table(rows: Iterable[Dict[str, Any]]) -> pd.DataFrame:
    """The per-log rows as one table, sorted by airframe and flight."""
    return pd.DataFrame(list(rows)).sort_values(["airframe", "flight"]).reset_index(drop=True)


def flag_drift(
    table: pd.DataFrame,
    baseline: int = 10,
    recent: int = 10,
    k: float = 6.0,
    powers: Sequence[str] = ("L_lat", "M_lon"),
) -> pd.DataFrame:
    """Per airframe and control power: the mean of its first ``baseline`` flights against
    the mean of its last ``recent``, and the drift in standard errors of the difference
    (Welch: the spread between flights, not the per-log SE, so that the flight-to-flight
    scatter the airframe shows sets the scale). ``flagged`` when a power dropped or rose by
    more than ``k`` standard errors. One row per airframe and power."""
    out: List[Dict[str, Any]] = []
    for airframe, g in table.sort_values("flight").groupby("airframe"):
        early = g.head(baseline)
        late = g.tail(recent)
        for p in powers:
            a = early[p].dropna()
            b = late[p].dropna()
            if len(a) < 2 or len(b) < 2:
                z = math.nan
            else:
                se = math.sqrt(a.var(ddof=1) / len(a) + b.var(ddof=1) / len(b))
                z = (b.mean() - a.mean()) / se if se > 0 else math.inf
            out.append(
                {
                    "airframe": airframe,
                    "power": p,
                    "baseline_mean": a.mean(),
                    "recent_mean": b.mean(),
                    "change": b.mean() / a.mean() - 1 if a.mean() else math.nan,
                    "drift_se": z,
                    "flagged": bool(abs(z) > k) if not math.isnan(z) else False,
                }
            )
    return pd.DataFrame(out)


def flagged_airframes(drift: pd.DataFrame) -> List[str]:
    """The airframes with any flagged power."""
    return sorted(set(drift.loc[drift["flagged"], "airframe"]))


def fleet_specs(
    airframes: Dict[str, int],
    flights: int,
    damaged: Optional[str] = None,
    damaged_from: int = 0,
    cyclic_power: float = 0.75,
    duration: float = 60.0,
    seed0: int = 1000,
) -> List[Dict[str, Any]]:
    """The work list of a simulated fleet: ``flights`` logs of each airframe (name →
    ``plant_variation`` seed), every log its own seed; the ``damaged`` airframe's flights
    from ``damaged_from`` on fly with ``cyclic_power``."""
    specs = []
    for a, (name, variation) in enumerate(sorted(airframes.items())):
        for f in range(flights):
            specs.append(
                {
                    "airframe": name,
                    "flight": f,
                    "seed": seed0 + 1000 * a + f,
                    "plant_variation": variation,
                    "duration": duration,
                    "cyclic_power": cyclic_power
                    if (name == damaged and f >= damaged_from)
                    else 1.0,
                }
            )
    return specs
