#!/usr/bin/env python3
"""Independent oracle for the real flight-log fixtures (issue 34, part 8).

Reads each fixture of `host-tests/cli/data/logs/real/` with the autopilot projects' own
Python readers -- pyulog (PX4 ULog) and pymavlink's DFReader (ArduPilot DataFlash and PX4
sdlog2 `.px4log`) -- and writes `host-tests/cli/data/logs/real/facts.json`: per file its
format, size and sha256, and for each topic/message the rotorid importer uses

- `count`: messages (ULog: instance 0, i.e. the lowest multi id),
- `first_us`, `last_us`: first and last time stamp (us since boot),
- `median_interval_ms`: median interval between successive time stamps = the native logging
  rate (`rate_hz` = 1000 / that),
- `backward_steps`: intervals that are zero or negative (time-stamp glitches),
- `velocity_valid_rows` (ULog `vehicle_local_position`, sdlog2 `LPOS`): rows whose
  horizontal and vertical velocity the estimator flags valid (ULog `v_xy_valid` and
  `v_z_valid`; sdlog2 `PFlg` bits 2 and 3),

the largest absolute body rate (`peak_rate`, rad/s, with its time stamp: a crash shows
there, and `moving_us`, the span where a rate exceeds 0.5 rad/s), roll and pitch ranges
(`attitude_range_deg`), what the vehicle is (`vehicle`: board, firmware, frame parameters),
and the intervals the autopilot itself logged as armed and as in the air (`armed`,
`in_air`, each a list of `[from_us, to_us]`; an interval still open at the end of the log
ends at the log's last time stamp, and `open_at_end` says so).

Time stamps
- ULog: the topic's `timestamp` field (us since boot).
- DataFlash: `TimeUS` (us since boot).
- sdlog2 (`.px4log`): the records carry no time of their own; the logger writes a `TIME`
  record (`StartTime`, us since boot) at the start of each logging cycle, and each record is
  stamped here with the `StartTime` of the latest `TIME` before it (records before the
  first `TIME` are not counted). pymavlink parses the records (sdlog2 shares DataFlash's
  framing: `0xA3 0x95`, self-describing `FMT`), but stamps them from GPS time, which
  these logs do not always have; hence this small documented rule.

In-air sources
- ULog: `vehicle_land_detected.landed` (0 = in the air), armed from
  `vehicle_status.arming_state == 2` (ARMING_STATE_ARMED).
- DataFlash: `ARM.ArmState` (newer logs) or events `EV` 10 ARMED / 11 DISARMED; in the air
  from events 28 NOT_LANDED / 18 LAND_COMPLETE (ArduPilot `LogEvent`).
- sdlog2: `STAT.ArmS == 2` (armed) and `LAND.Landed` (logged on change).

Usage: scripts/real_log_facts.py [--check]
  (venv: python3 -m venv /work/venv-real && /work/venv-real/bin/pip install pyulog pymavlink numpy)
  --check compares the facts with the committed facts.json instead of writing it (exit 1
  on any difference).
"""

import argparse
import hashlib
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REAL = os.path.join(ROOT, "host-tests", "cli", "data", "logs", "real")
FACTS = os.path.join(REAL, "facts.json")

# The fixtures, relative to REAL (the PX4 motor-failure log is the existing import fixture
# `esc_status_log.ulg`: the same bytes as flight-review-rs's `motor_failure.ulg`, not copied
# twice).
FIXTURES = [
    "ekf_failure.ulg",
    "sample_appended_multiple.ulg",
    "../esc_status_log.ulg",
    "arducopter_spark404_log.bin",
    "trex550_sess005_log001.px4log",
    "trex550_sess006_log001.px4log",
    "battery_brownout.ulg",
    "gps_interference.ulg",
    "sample_px4_events.ulg",
    "ardusub_bench_small.bin",
]

ULOG_TOPICS = [
    "vehicle_attitude",
    "vehicle_local_position",
    "vehicle_angular_velocity",
    "vehicle_torque_setpoint",
    "vehicle_thrust_setpoint",
    "actuator_controls_0",
    "vehicle_land_detected",
    "vehicle_status",
]
DATAFLASH_MESSAGES = ["ATT", "RATE", "CTUN", "XKF1", "NKF1", "EV", "ARM"]
# RC (pilot sticks) and OUT0 (mixer outputs) are listed too: on the T-REX 550 logs the
# PX4 controller (ATTC) did not fly the helicopter, the pilot's RC inputs did.
SDLOG2_MESSAGES = ["TIME", "ATT", "LPOS", "GPOS", "ATTC", "STAT", "LAND", "RC", "OUT0"]

# ArduPilot LogEvent ids.
EV_ARMED, EV_DISARMED, EV_LAND_COMPLETE, EV_NOT_LANDED = 10, 11, 18, 28
PX4_ARMING_STATE_ARMED = 2
# A body rate (rad/s) above the noise of a vehicle at rest (about 0.03 rad/s on the logs here).
MOVING_RADPS = 0.5
# Parameters that say what the vehicle is and how it logs.
PX4_PARAMS = ["SYS_AUTOSTART", "MAV_TYPE", "SDLOG_PROFILE"]
ARDUPILOT_PARAMS = ["FRAME_CLASS", "FRAME_TYPE", "LOG_BITMASK", "AHRS_EKF_TYPE", "H_SWASH_TYPE"]


def timing(stamps):
    """Count, first/last stamp, median interval and backward steps of a list of us stamps."""
    t = np.asarray(stamps, dtype=np.int64)
    out = {"count": int(t.size)}
    if t.size == 0:
        return out
    out["first_us"] = int(t[0])
    out["last_us"] = int(t[-1])
    if t.size > 1:
        d = np.diff(t)
        med = float(np.median(d)) / 1000.0
        out["median_interval_ms"] = round(med, 3)
        out["rate_hz"] = round(1000.0 / med, 2) if med > 0 else None
        out["backward_steps"] = int(np.count_nonzero(d <= 0))
    return out


def peak(stamps, rows, source):
    """The largest absolute body rate (rad/s) in `rows` (one row of p q r per stamp) and its
    time stamp -- a crash or a glitch shows here -- and the first and last stamp where any
    rate exceeds MOVING_RADPS (`moving_us`, null if never): when the vehicle moved, by the
    data alone, whatever the autopilot's flags say."""
    if len(stamps) == 0:
        return None
    a = np.abs(np.asarray(rows, dtype=float))
    a[~np.isfinite(a)] = 0.0
    m = a.max(axis=1)
    k = int(np.argmax(m))
    moving = np.flatnonzero(m > MOVING_RADPS)
    span = [int(stamps[moving[0]]), int(stamps[moving[-1]])] if moving.size else None
    return {
        "radps": round(float(m[k]), 4),
        "at_us": int(stamps[k]),
        "moving_us": span,
        "source": source,
    }


def angle_range(roll, pitch):
    """Roll and pitch ranges `[min, max]` (deg, rounded to 0.1) of angles in rad."""
    out = {}
    for name, x in (("roll", roll), ("pitch", pitch)):
        x = np.degrees(np.asarray(x, dtype=float))
        x = x[np.isfinite(x)]
        out[name] = [round(float(x.min()), 1), round(float(x.max()), 1)] if x.size else None
    return out


def intervals(events, start_us, end_us, changes=False):
    """`[from, to]` intervals where the state is true, from `(t_us, bool)` samples in time
    order (repeats allowed); one still true at the end ends at `end_us` (`open_at_end`).
    `changes`: the samples are change events (ArduPilot EV / ARM), so a first event that
    turns the state off means it was on before it -- a log that starts in the air -- and the
    interval starts at `start_us` (`open_at_start`). State samples (ULog, sdlog2) are
    logged from the start, and a first false sample only says the state was false."""
    spans, start = [], None
    open_at_start = False
    seen = False
    for t, on in events:
        if changes and not seen and not on:
            start, open_at_start = start_us, True
        seen = True
        if on and start is None:
            start = t
        elif not on and start is not None:
            spans.append([int(start), int(t)])
            start = None
    open_at_end = start is not None
    if open_at_end:
        spans.append([int(start), int(end_us)])
    return {"intervals": spans, "open_at_start": open_at_start, "open_at_end": open_at_end}


def ulog_facts(path):
    from pyulog import ULog

    u = ULog(path, ULOG_TOPICS)
    topics, first = {}, {}
    for d in u.data_list:
        if d.name not in first or d.multi_id < first[d.name].multi_id:
            first[d.name] = d
    for name in ULOG_TOPICS:
        d = first.get(name)
        topics[name] = timing(d.data["timestamp"]) if d else {"count": 0}
    start, end = int(u.start_timestamp), int(u.last_timestamp)
    info = u.msg_info_dict
    vehicle = {k: info.get(k) for k in ("ver_hw", "sys_name", "ver_sw")}
    vehicle.update({k: u.initial_parameters.get(k) for k in PX4_PARAMS})
    facts = {
        "format": "ULog",
        "vehicle": vehicle,
        "log_first_us": start,
        "log_last_us": end,
        "topics": topics,
    }
    att = first.get("vehicle_attitude")
    if att is not None:
        w, x, y, z = (att.data[f"q[{i}]"].astype(float) for i in range(4))
        roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
        pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1, 1))
        facts["attitude_range_deg"] = angle_range(roll, pitch)
    rates = first.get("vehicle_angular_velocity")
    if rates is not None:
        rows = np.column_stack([rates.data[f"xyz[{i}]"] for i in range(3)])
        facts["peak_rate"] = peak(rates.data["timestamp"], rows, "vehicle_angular_velocity xyz")
    elif "vehicle_attitude" in first and "rollspeed" in first["vehicle_attitude"].data:
        att = first["vehicle_attitude"].data
        rows = np.column_stack([att[f] for f in ("rollspeed", "pitchspeed", "yawspeed")])
        facts["peak_rate"] = peak(att["timestamp"], rows, "vehicle_attitude rollspeed pitchspeed yawspeed")
    local = first.get("vehicle_local_position")
    if local is not None and "v_xy_valid" in local.data:
        ok = (local.data["v_xy_valid"] != 0) & (local.data["v_z_valid"] != 0)
        topics["vehicle_local_position"]["velocity_valid_rows"] = int(np.count_nonzero(ok))
    land = first.get("vehicle_land_detected")
    if land is not None:
        ev = [(int(t), not bool(x)) for t, x in zip(land.data["timestamp"], land.data["landed"])]
        facts["in_air"] = dict(intervals(ev, start, end), source="vehicle_land_detected.landed")
    status = first.get("vehicle_status")
    if status is not None:
        ev = [
            (int(t), int(a) == PX4_ARMING_STATE_ARMED)
            for t, a in zip(status.data["timestamp"], status.data["arming_state"])
        ]
        facts["armed"] = dict(intervals(ev, start, end), source="vehicle_status.arming_state")
    return facts


def dataflash_facts(path):
    from pymavlink import DFReader

    r = DFReader.DFReader_binary(path)
    stamps = {m: [] for m in DATAFLASH_MESSAGES}
    armed, in_air, events = [], [], []
    rate_t, rate_rows = [], []
    roll, pitch, params, firmware = [], [], {}, None
    first = last = None
    while True:
        m = r.recv_msg()
        if m is None:
            break
        if m.get_type() == "PARM" and m.Name in ARDUPILOT_PARAMS:
            params.setdefault(m.Name, m.Value)
        if m.get_type() == "MSG" and firmware is None and str(m.Message).startswith("Ardu"):
            firmware = m.Message
        t = getattr(m, "TimeUS", None)
        if t is None:
            continue
        t = int(t)
        first = t if first is None else min(first, t)
        last = t if last is None else max(last, t)
        name = m.get_type()
        if name == "XKF1" and int(getattr(m, "C", 0)) != 0:
            continue  # EKF3 core 0 only (one row per core per cycle), as the importer
        if name in stamps:
            stamps[name].append(t)
        if name == "ATT":
            roll.append(np.radians(m.Roll))
            pitch.append(np.radians(m.Pitch))
        if name == "RATE":
            rate_t.append(t)
            rate_rows.append([np.radians(m.R), np.radians(m.P), np.radians(m.Y)])
        if name == "ARM":
            armed.append((t, int(m.ArmState) != 0))
        elif name == "EV":
            events.append([t, int(m.Id)])
            if m.Id in (EV_NOT_LANDED, EV_LAND_COMPLETE):
                in_air.append((t, m.Id == EV_NOT_LANDED))
    if not armed:
        armed = [(t, i == EV_ARMED) for t, i in events if i in (EV_ARMED, EV_DISARMED)]
        armed_source = "EV 10/11"
    else:
        armed_source = "ARM.ArmState"
    facts = {
        "format": "DataFlash",
        "vehicle": dict({"firmware": firmware}, **{k: params.get(k) for k in ARDUPILOT_PARAMS}),
        "log_first_us": first,
        "log_last_us": last,
        "topics": {m: timing(s) for m, s in stamps.items()},
        "attitude_range_deg": angle_range(roll, pitch),
        "peak_rate": peak(rate_t, rate_rows, "RATE R P Y (deg/s, here rad/s)"),
        "events": events,
        "armed": dict(intervals(armed, first, last, changes=True), source=armed_source),
        "in_air": dict(intervals(in_air, first, last, changes=True), source="EV 28/18"),
    }
    return facts


def sdlog2_facts(path):
    from pymavlink import DFReader

    r = DFReader.DFReader_binary(path)
    stamps = {m: [] for m in SDLOG2_MESSAGES}
    armed, landed = [], []
    rate_t, rate_rows = [], []
    valid_velocity = 0
    roll, pitch, params, version = [], [], {}, {}
    now = None
    while True:
        m = r.recv_msg()
        if m is None:
            break
        name = m.get_type()
        if name == "PARM" and m.Name in PX4_PARAMS:
            params.setdefault(m.Name, m.Value)
        if name == "VER":
            version = {"arch": m.Arch, "fw_git": m.FwGit}
        if name == "TIME":
            now = int(m.StartTime)
        if now is None:
            continue
        if name in stamps:
            stamps[name].append(now)
        if name == "ATT":
            roll.append(m.Roll)
            pitch.append(m.Pitch)
            rate_t.append(now)
            rate_rows.append([m.RollRate, m.PitchRate, m.YawRate])
        if name == "LPOS" and int(m.PFlg) & 0b1100 == 0b1100:
            valid_velocity += 1
        if name == "STAT":
            armed.append((now, int(m.ArmS) == PX4_ARMING_STATE_ARMED))
        elif name == "LAND":
            landed.append((now, not bool(m.Landed)))
    t = stamps["TIME"]
    end = t[-1] if t else None
    lpos = timing(stamps["LPOS"])
    lpos["velocity_valid_rows"] = valid_velocity
    facts = {
        "format": "sdlog2",
        "vehicle": dict(version, **{k: params.get(k) for k in PX4_PARAMS}),
        "log_first_us": t[0] if t else None,
        "log_last_us": end,
        "topics": dict({m: timing(s) for m, s in stamps.items()}, LPOS=lpos),
        "attitude_range_deg": angle_range(roll, pitch),
        "peak_rate": peak(rate_t, rate_rows, "ATT RollRate PitchRate YawRate"),
        "armed": dict(intervals(armed, t[0] if t else None, end), source="STAT.ArmS"),
    }
    if landed:
        facts["in_air"] = dict(intervals(landed, t[0] if t else None, end), source="LAND.Landed")
    return facts


def file_format(head):
    if head.startswith(b"ULog\x01\x12\x35"):
        return "ULog"
    return "DataFlash" if head.startswith(b"\xa3\x95") else None


def facts_of(rel):
    path = os.path.normpath(os.path.join(REAL, rel))
    with open(path, "rb") as f:
        data = f.read()
    kind = file_format(data[:8])
    if kind == "ULog":
        facts = ulog_facts(path)
    elif kind == "DataFlash" and rel.endswith(".px4log"):
        facts = sdlog2_facts(path)
    elif kind == "DataFlash":
        facts = dataflash_facts(path)
    else:
        raise SystemExit(f"{rel}: neither ULog nor DataFlash/sdlog2 (a Git LFS pointer?)")
    return dict(
        {"file": rel, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}, **facts
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="compare with facts.json")
    args = ap.parse_args()
    facts = {"generated_by": "scripts/real_log_facts.py", "logs": [facts_of(f) for f in FIXTURES]}
    text = json.dumps(facts, indent=1) + "\n"
    if args.check:
        with open(FACTS) as f:
            same = f.read() == text
        print("facts.json is up to date" if same else "facts.json differs: rerun without --check")
        sys.exit(0 if same else 1)
    with open(FACTS, "w") as f:
        f.write(text)
    print(f"wrote {os.path.relpath(FACTS, ROOT)} ({len(facts['logs'])} logs)")


if __name__ == "__main__":
    main()
