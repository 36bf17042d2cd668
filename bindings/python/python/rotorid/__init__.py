"""rotorid for Python: read flight logs, identify hover models, step identifiers.

Units and axes
--------------
Logs (``read_log``, ``simulate``) are in the flight computer's frame, SI units, the unit in
each column name: time ``time_s`` (s), sticks ``u_col u_ped u_lon u_lat`` (−1…1),
attitude ``roll_rad pitch_rad yaw_rad`` (ZYX Euler), velocity ``v_north_mps v_east_mps
v_down_mps`` (NED), body rates ``p_radps q_radps r_radps`` (FRD).

Identifiers (``FlightIdentifier`` and the other kinds) take the core's samples, as the C
interface does: time (µs), attitude ``[φ θ ψ]`` (rad), velocity ``[v_x v_y v_z]`` (m/s,
paper axes: x east, y up, z south), rates ``[q r p]`` (deg/s), controls ``[u_col u_ped
u_lon u_lat]``; ``hover_samples(df)`` converts a log to them.

Every error is a ``RotoridError`` (subclasses: ``InputError``, ``LogError``,
``IdentifyError``, ``SimulateError``, ``CoreError`` and its variants), with ``kind``
naming the Rust error.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np
import pandas as pd

from . import _rotorid
from ._rotorid import (
    KINDS,
    ConfigError,
    CoreError,
    IdentifyError,
    IncompatibleError,
    InputError,
    LogError,
    NonFiniteError,
    NonMonotonicTimeError,
    NumericalError,
    OutOfRangeError,
    RotoridError,
    SimulateError,
    TimeStepError,
)

__all__ = [
    "KINDS",
    "LOG_COLUMNS",
    "STATES",
    "read_log",
    "simulate",
    "hover_samples",
    "identify",
    "identify_many",
    "IdentifyResult",
    "Identifier",
    "flight_premises",
    "FlightIdentifier",
    "FlightPlainIdentifier",
    "PaperFuzzyIdentifier",
    "PaperPlainIdentifier",
    "ExtendedFuzzyIdentifier",
    "ExtendedPlainIdentifier",
    "PaperLocalIdentifier",
    "ExtendedLocalIdentifier",
    "RotoridError",
    "InputError",
    "LogError",
    "IdentifyError",
    "SimulateError",
    "CoreError",
    "NonFiniteError",
    "OutOfRangeError",
    "TimeStepError",
    "NonMonotonicTimeError",
    "ConfigError",
    "IncompatibleError",
    "NumericalError",
]

PathLike = Union[str, "os.PathLike[str]"]

#: Log columns, units in the names (rotorid's CSV format, docs/log-format.md).
LOG_COLUMNS: List[str] = list(_rotorid.log_columns())
#: The identifiers' state ``[v_x v_y v_z q r p]`` (m/s paper axes, deg/s).
STATES: List[str] = ["v_x_mps", "v_y_mps", "v_z_mps", "q_degps", "r_degps", "p_degps"]

_F = _rotorid.FLOATS_PER_SAMPLE


def _frame(block: bytes, columns: Sequence[str]) -> pd.DataFrame:
    data = np.frombuffer(block, dtype="<f8").reshape(-1, len(columns))
    return pd.DataFrame(data.copy(), columns=list(columns))


def read_log(
    path: PathLike,
    rate: Optional[float] = None,
    from_s: Optional[float] = None,
    to_s: Optional[float] = None,
) -> pd.DataFrame:
    """Reads a log (CSV, PX4 ULog ``.ulg``, ArduPilot DataFlash ``.bin``, PX4 sdlog2) as
    ``rotorid identify`` does: ground time and implausible stretches cut, resampled at
    ``rate`` (Hz; None: the fastest of 50, 25, 20, 10, 5 Hz every channel supports), only
    from ``from_s`` to ``to_s`` (s, log time) when given.

    Returns a DataFrame with ``segment`` (gap-free stretch, from 1) and ``LOG_COLUMNS``
    (units in the names). ``df.attrs`` holds ``format``, ``rate_hz``, ``notes``,
    ``warnings``, ``cuts`` (each ``from_s``, ``to_s``, ``reason``) and ``path``.

    Raises ``LogError`` for a file that cannot be read or imported.
    """
    block, info = _rotorid.read_log(os.fspath(path), rate, from_s, to_s)
    df = _frame(block, ["segment"] + LOG_COLUMNS)
    df["segment"] = df["segment"].astype("int64")
    df.attrs.update(json.loads(info))
    df.attrs["path"] = os.fspath(path)
    return df


def simulate(
    kind: str,
    seed: int = 1,
    plant: str = "xcell60",
    plant_variation: Optional[int] = None,
    duration: Optional[float] = None,
    clean: bool = False,
    noise_scale: float = 1.0,
    cyclic_power: float = 1.0,
    out: Optional[PathLike] = None,
) -> Union[pd.DataFrame, str]:
    """Flies the helicopter simulator as ``rotorid simulate`` does.

    ``kind``: identification, verification, envelope or envelope-verification;
    ``plant``: xcell60 or flybarless600; ``plant_variation``: seed of a varied airframe;
    ``duration`` (s; not for envelope flights); ``noise_scale``: measurement noise times
    the default; ``cyclic_power``: cyclic control power as a fraction of the airframe's
    (0.1–2; a damaged rotor). Returns the log as a DataFrame (``LOG_COLUMNS``), or with
    ``out`` writes the CSV there (the command's bytes) and returns its path.
    """
    block = _rotorid.simulate(
        kind,
        seed,
        plant,
        plant_variation,
        duration,
        clean,
        noise_scale,
        cyclic_power,
        None if out is None else os.fspath(out),
    )
    if out is not None:
        return os.fspath(out)
    if block is None:  # cannot happen: without `out` the native call returns the samples
        raise SimulateError("simulate returned no samples")
    return _frame(block, LOG_COLUMNS)


def _float_column(df: pd.DataFrame, name: str) -> np.ndarray:
    if name not in df.columns:
        raise InputError(
            f"missing column {name!r}; a log needs {', '.join(LOG_COLUMNS)} (see read_log)"
        )
    values = df[name].to_numpy()
    if values.dtype.kind not in "fiu":
        raise InputError(f"column {name!r} has dtype {values.dtype}; expected numbers")
    return values.astype("<f8")


def hover_samples(df: pd.DataFrame) -> Dict[str, np.ndarray]:
    """The core's samples of a log DataFrame (``read_log``/``simulate`` columns), as
    ``rotorid identify`` converts them: a dict of ``time_us`` (n, uint64), ``attitude``
    (n×3 rad), ``velocity`` (n×3 m/s paper axes), ``rates`` (n×3 deg/s ``[q r p]``),
    ``controls`` (n×4), ready for ``Identifier.step_many(**samples)``.

    A log of several segments has gaps between them, which a step refuses
    (``TimeStepError``): step each ``df.groupby("segment")`` part, calling ``resume`` with
    the first sample of every part after the first."""
    block = np.column_stack([_float_column(df, c) for c in LOG_COLUMNS])
    times, floats = _rotorid.hover_block(np.ascontiguousarray(block).tobytes())
    t = np.frombuffer(times, dtype="<u8").copy()
    f = np.frombuffer(floats, dtype="<f4").reshape(-1, _F).copy()
    return {
        "time_us": t,
        "attitude": f[:, 0:3],
        "velocity": f[:, 3:6],
        "rates": f[:, 6:9],
        "controls": f[:, 9:13],
    }


def _array(name: str, values: Any, width: int, n: Optional[int]) -> np.ndarray:
    a = np.asarray(values)
    if a.dtype.kind not in "fiu":
        raise InputError(f"{name}: dtype {a.dtype}; expected a float array")
    if a.ndim != 2 or a.shape[1] != width or (n is not None and a.shape[0] != n):
        raise InputError(
            f"{name}: shape {a.shape}; expected ({n if n is not None else 'n'}, {width})"
        )
    return a.astype("<f4")


class Identifier(_rotorid.Identifier):
    """A hover identifier of one of ``KINDS``, as the C interface's ``rotorid_init`` makes it
    with default settings (U-D RLS, α = 10⁶, λ = 1, 50 Hz sample period ± tolerance).

    ``step`` takes one sample, ``step_many`` arrays of them (the GIL released), ``export``
    gives the C interface's export bytes, ``import_`` takes them back.

    ``Identifier("flight", premises=...)`` (or ``FlightIdentifier(premises=...)``) puts each
    model's three rules (velocity, q̂, r̂, p̂) on the speed and sets given, as the C
    interface's ``rotorid_init_flight_scheduled``: ``(speed, centres, spreads)`` per model,
    ``speed`` one of ``"speed"``, ``"side_speed"`` (rate models), ``"vertical_speed"``,
    centres and spreads (m/s) of the left shoulder, Gaussian and right shoulder.
    ``flight_premises("params-flight-selected.json")`` reads what ``identify`` chose; import
    its ``snapshot-flight-selected.ridx`` into an identifier built with them to fly that model
    (a snapshot carries θ and P, not the sets: it imports into any flight identifier, but
    predicts as learnt only under the premises it was learnt with).
    """

    def step_many(
        self,
        time_us: Any,
        attitude: Any,
        velocity: Any,
        rates: Any,
        controls: Any,
    ) -> Dict[str, np.ndarray]:
        """Steps over n samples: ``time_us`` (n, integers, µs), ``attitude`` (n×3 rad),
        ``velocity`` (n×3 m/s paper axes), ``rates`` (n×3 deg/s ``[q r p]``), ``controls``
        (n×4). Returns ``prediction`` and ``innovation`` (n×6 float32 ``STATES``; the
        innovation is NaN where a step only started a sample chain).

        Raises ``InputError`` for a wrong dtype or shape, a ``CoreError`` subclass at the
        first refused sample (its message names the sample; the steps before it stay
        learnt).
        """
        t = np.asarray(time_us)
        if t.dtype.kind not in "iu" or t.ndim != 1:
            raise InputError(
                f"time_us: dtype {t.dtype}, shape {t.shape}; expected 1-D integers (µs)"
            )
        if t.size and t.min() < 0:
            raise InputError("time_us: negative time stamps")
        n = t.shape[0]
        floats = np.concatenate(
            [
                _array("attitude", attitude, 3, n),
                _array("velocity", velocity, 3, n),
                _array("rates", rates, 3, n),
                _array("controls", controls, 4, n),
            ],
            axis=1,
        )
        pred, innov = self._step_block(
            np.ascontiguousarray(t.astype("<u8")).tobytes(),
            np.ascontiguousarray(floats).tobytes(),
        )
        return {
            "prediction": np.frombuffer(pred, dtype="<f4").reshape(-1, 6).copy(),
            "innovation": np.frombuffer(innov, dtype="<f4").reshape(-1, 6).copy(),
        }


#: The speed each premise variable of a params-*.json model schedules on: the velocity
#: model's premise is [horizontal speed, up], a rate model's [forward, right, up].
_SCHEDULES = {
    "horizontal-speed": ("speed", "vertical_speed"),
    "heading-velocity": ("speed", "side_speed", "vertical_speed"),
}


def flight_premises(params: Union[str, "os.PathLike[str]"]) -> List[Any]:
    """The ``premises`` of ``Identifier("flight", premises=...)`` that a flight-structure
    ``params-*.json`` written by ``identify`` describes (``params-flight-selected.json``: the
    speed each model's rules are on and their sets; a model with one rule has
    ``rotorid_flight_sets_unscheduled``'s sets on the speed). Raises ``InputError`` for a
    file that does not describe three shoulder-Gaussian-shoulder sets on one variable per
    model."""
    with open(params, encoding="utf-8") as f:
        models = json.load(f)
    out = []
    names = [m.get("model") for m in models] if isinstance(models, list) else None
    if names != ["velocity", "q", "r", "p"]:
        raise InputError(f"{params}: models {names}; expected velocity, q, r, p")
    for m in models:
        premise = m.get("premise") or {}
        schedules = _SCHEDULES.get(premise.get("kind"))
        variables = premise.get("variables") or []
        used = [(i, v) for i, v in enumerate(variables) if v]
        if schedules is None or len(used) != 1 or used[0][0] >= len(schedules):
            raise InputError(f"{params}: model {m['model']}: premise {premise.get('kind')!r} with sets on "
                             f"{len(used)} variables; expected a flight model's, on one")
        i, sets = used[0]
        if [s.get("shape") for s in sets] != ["left", "gaussian", "right"]:
            raise InputError(f"{params}: model {m['model']}: sets {[s.get('shape') for s in sets]}; "
                             "expected left, gaussian, right")
        out.append((schedules[i], [float(s["centre"]) for s in sets], [float(s["spread"]) for s in sets]))
    return out


def _kind_class(kind: str, doc: str) -> type:
    def __new__(cls: type, *args: Any, **kwargs: Any) -> Any:  # noqa: N807
        return Identifier.__new__(cls, kind, *args, **kwargs)

    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        pass

    name = "".join(p.capitalize() for p in kind.split("_")) + "Identifier"
    return type(name, (Identifier,), {"__new__": __new__, "__init__": __init__, "__doc__": doc})


FlightIdentifier = _kind_class(
    "flight", "The flight default: extended flight structures, three speed rules (the rates on the forward speed, the velocity on the horizontal speed), local learning (ROTORID_KIND_FLIGHT)."
)
FlightPlainIdentifier = _kind_class("flight_plain", "The flight structures with one rule (ROTORID_KIND_FLIGHT_PLAIN).")
PaperFuzzyIdentifier = _kind_class("paper_fuzzy", "The paper's fuzzy identifier, Table 3 sets, global RLS (ROTORID_KIND_PAPER_FUZZY).")
PaperPlainIdentifier = _kind_class("paper_plain", "The paper's plain identifier, one rule (ROTORID_KIND_PAPER_PLAIN).")
ExtendedFuzzyIdentifier = _kind_class("extended_fuzzy", "Extended structures, Table 3 sets, global RLS (ROTORID_KIND_EXTENDED_FUZZY).")
ExtendedPlainIdentifier = _kind_class("extended_plain", "Extended structures, one rule (ROTORID_KIND_EXTENDED_PLAIN).")
PaperLocalIdentifier = _kind_class("paper_local", "The paper's structures and sets, learnt locally (ROTORID_KIND_PAPER_LOCAL).")
ExtendedLocalIdentifier = _kind_class("extended_local", "Extended structures, Table 3 sets, learnt locally (ROTORID_KIND_EXTENDED_LOCAL).")


class IdentifyResult:
    """What ``identify`` gives: the verdict, every variant's scores and parameters, the
    body-axis derivatives, and metrics.json's text (``to_json``)."""

    def __init__(self, metrics_json: str, parameters_json: str, report: str, notes: List[str]):
        self._json = metrics_json
        #: metrics.json as a dict.
        self.metrics: Dict[str, Any] = json.loads(metrics_json)
        self._parameters: Dict[str, Any] = json.loads(parameters_json)
        #: What ``rotorid identify`` prints on stdout (verdict, derivatives).
        self.report: str = report
        #: The import's notes and warnings, and the identification's (the command's stderr).
        self.notes: List[str] = list(notes)

    def to_json(self) -> str:
        """metrics.json's text, byte for byte what ``rotorid identify`` writes for the same
        logs and options."""
        return self._json

    @property
    def verdict(self) -> Optional[Dict[str, Any]]:
        """The verdict (``model``, ``why``, per-axis scores, ``caveats``), or None when no
        model could be scored."""
        return self.metrics.get("verdict")

    @property
    def model(self) -> Optional[str]:
        """The name of the model to fly, or None."""
        v = self.verdict
        return None if v is None else v.get("model")

    @property
    def states(self) -> List[str]:
        """State names with units, in the order of every per-state array."""
        return list(self.metrics["states"])

    def variant_metrics(self) -> pd.DataFrame:
        """Per variant and state: mean |error| of the one-step prediction and the free run
        (state units: m/s, deg/s), and of holding the measured state."""
        rows = []
        for v in self.metrics["variants"]:
            for k, state in enumerate(self.metrics["states"]):
                rows.append(
                    {
                        "variant": v["name"],
                        "state": state,
                        "one_step": v["one_step"][k],
                        "free_run": v["free_run"][k],
                        "hold_one_step": v["hold_one_step"][k],
                        "hold_free_run": v["hold_free_run"][k],
                    }
                )
        return pd.DataFrame(rows)

    def parameters(self, variant: Optional[str] = None) -> pd.DataFrame:
        """Trained θ per variant, model (velocity, q, r, p) and index (params-*.json's
        ``theta``); one variant's with ``variant``."""
        rows = []
        for name, models in self._parameters.items():
            if variant is not None and name != variant:
                continue
            for m in models or []:
                for i, theta in enumerate(m["theta"]):
                    rows.append({"variant": name, "model": m["model"], "index": i, "theta": theta})
        if variant is not None and not rows:
            raise InputError(f"no variant {variant!r}; have {', '.join(self._parameters)}")
        return pd.DataFrame(rows, columns=["variant", "model", "index", "theta"])

    def derivatives(self) -> pd.DataFrame:
        """Body-axis stability and control derivatives per region and axis: value, standard
        error (corrected), unit, and whether it is determined (|value| ≥ 2 SE)."""
        rows = []
        d = self.metrics.get("derivatives") or {}
        for region in d.get("regions", []):
            for axis in region.get("axes", []) or []:
                for x in axis.get("derivatives", []) or []:
                    rows.append(
                        {
                            "region": region["name"],
                            "axis": axis["axis"],
                            "symbol": x["symbol"],
                            "unit": x["unit"],
                            "value": x["value"],
                            "se": x["se"],
                            "determined": x["determined"],
                        }
                    )
        return pd.DataFrame(
            rows, columns=["region", "axis", "symbol", "unit", "value", "se", "determined"]
        )

    def __repr__(self) -> str:
        return f"<IdentifyResult model={self.model!r} files={self.metrics['training_files']}>"


def identify(
    train: Union[PathLike, Sequence[PathLike]],
    verify: Optional[PathLike] = None,
    holdout: float = 0.3,
    out: Optional[PathLike] = None,
    rate: Optional[float] = None,
    from_s: Optional[float] = None,
    to_s: Optional[float] = None,
    window: float = 2.0,
    plots: bool = True,
    warm_start: Optional[PathLike] = None,
    gyro_noise: Union[str, float, Sequence[float]] = "auto",
    free_run_velocity: str = "model",
    observer_gain: Union[str, float, Sequence[float]] = "auto",
    control_delay: Optional[float] = None,
) -> IdentifyResult:
    """Identifies hover models from logs, as ``rotorid identify --train TRAIN... [--verify
    VERIFY] [--holdout H] [--out OUT]`` with its defaults: every variant trained, scored
    one step ahead and in ``window``-second free runs (s) on ``verify`` (its longest
    segment) or on the later ``holdout`` fraction of the training data (another part where
    that would take most of a stick's excitation; ``result.report`` says which); the verdict says
    which model to fly. The GIL is released meanwhile.

    With ``out`` writes metrics.json, params-*.json and (``plots``) the figures there.
    ``result.to_json()`` is metrics.json byte for byte (paths as given here).

    The command's other options: ``warm_start`` (a params-*.json), ``gyro_noise`` ("auto",
    "none", a σ or ``(q, r, p)`` σ in deg/s), ``free_run_velocity`` ("model" or
    "measured"), ``observer_gain`` ("auto", a gain or six, 0–1), ``rate`` (Hz),
    ``from_s``/``to_s`` (s), ``control_delay`` (s, 0–1: how much later than logged the
    controls act; default chosen on an autopilot log's training data, 0 for CSV).

    Raises ``LogError`` (a log), ``IdentifyError`` (too little data, a file not written),
    ``InputError`` (an argument).
    """
    if isinstance(train, (str, bytes, os.PathLike)):
        train = [train]
    paths = [os.fspath(p) for p in train]
    return IdentifyResult(
        *_rotorid.identify(
            paths,
            None if verify is None else os.fspath(verify),
            holdout,
            rate,
            from_s,
            to_s,
            None if out is None else os.fspath(out),
            window,
            plots,
            None if warm_start is None else os.fspath(warm_start),
            _option_text(gyro_noise),
            free_run_velocity,
            _option_text(observer_gain),
            control_delay,
        )
    )


def _option_text(value: Union[str, float, Sequence[float]]) -> str:
    """An option in the command's syntax: a word as it is, numbers comma-separated."""
    if isinstance(value, str):
        return value
    if isinstance(value, (int, float)):
        return repr(float(value))
    return ",".join(repr(float(v)) for v in value)


def identify_many(
    paths: Iterable[PathLike],
    workers: Optional[int] = None,
    progress: bool = True,
    errors: str = "raise",
    **options: Any,
) -> List[Any]:
    """Identifies each log on its own (``identify(path, **options)``), ``workers`` at a
    time in threads (the GIL is released while identifying, so threads run in parallel;
    default: the CPU count). Results come in the order of ``paths``.

    ``progress``: a tqdm bar when tqdm is installed, else a counter on stderr.
    ``errors``: "raise" (the first failure raises) or "return" (the exception takes the
    log's place in the list).
    """
    import concurrent.futures
    import sys

    if errors not in ("raise", "return"):
        raise InputError(f"errors must be 'raise' or 'return', got {errors!r}")
    paths = [os.fspath(p) for p in paths]
    workers = workers or os.cpu_count() or 1
    if workers < 1:
        raise InputError(f"workers must be ≥ 1, got {workers}")
    bar = None
    if progress:
        try:
            from tqdm.auto import tqdm  # type: ignore[import-not-found,import-untyped,unused-ignore]

            bar = tqdm(total=len(paths), unit="log")
        except ImportError:
            bar = None
    results: List[Any] = [None] * len(paths)
    done = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(identify, p, **options): k for k, p in enumerate(paths)}
        for f in concurrent.futures.as_completed(futures):
            k = futures[f]
            try:
                results[k] = f.result()
            except RotoridError as e:
                if errors == "raise":
                    for other in futures:
                        other.cancel()
                    raise
                results[k] = e
            done += 1
            if bar is not None:
                bar.update(1)
            elif progress:
                print(f"\ridentified {done}/{len(paths)} logs", end="", file=sys.stderr)
    if bar is not None:
        bar.close()
    elif progress:
        print(file=sys.stderr)
    return results
