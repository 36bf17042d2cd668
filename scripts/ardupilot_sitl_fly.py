#!/usr/bin/env python3
"""Flies ArduPilot SITL's helicopter (frame `heli`) over MAVLink with pymavlink and leaves its
DataFlash log: the flights behind host-tests/cli/data/logs/ardupilot-sitl/ (issue 30).

It starts the SITL binary given with --sitl (an `arducopter-heli` built from ArduPilot; this
repository does not build it) in a fresh directory, talks to it on loopback only (SERIAL0 sends
UDP to 127.0.0.1:14550 + 10 × instance, the other serial ports are off) and flies one plan:

* `sid`: take off in STABILIZE, hover, then ArduPilot's SystemID mode (mode 25) once per axis
  with the chirp added at the mixer (SID_AXIS 10 roll, 11 pitch, 12 yaw: the rate controller's
  output plus the chirp, which is what RATE ROut/POut/YOut log), then stick doublets on each
  axis, hover, land.
* `envelope`: take off, hover, then GUIDED body-frame velocity steps forward 1, 2, 3, 5 m/s and
  sideways (right) 1, 2, 3 m/s, each held, with hover between them, land.

Times are simulated time (MAVLink `time_boot_ms`), so a slow machine only stretches wall time.
In STABILIZE and SystemID the collective is the stick (RC3 override); this script closes a slow
altitude loop on it (proportional-derivative-integral on the EKF height) so the hover stays near
the target height. Usage:
  ardupilot_sitl_fly.py --sitl PATH/arducopter-heli --ardupilot ARDUPILOT_DIR --plan sid --out DIR
"""

import argparse
import math
import os
import shutil
import subprocess
import sys
import time

from pymavlink import mavutil

# LOG_BITMASK: ATTITUDE_FAST (ANG, RATE every loop; EKF messages at 25 Hz) | CTUN | NTUN | RCOUT;
# LOG_FILE_RATEMAX caps every streaming message at 50 Hz (the fastest rate rotorid identifies
# at), so the attitude, rates and controls are logged at 50 Hz (the main loop runs at 400 Hz).
PARAMS = {
    "LOG_BITMASK": 1 | 16 | 32 | 1024,
    "LOG_FILE_RATEMAX": 50,
    "LOG_DISARMED": 0,
    "RC_OVERRIDE_TIME": -1,
}
# SystemID: the chirp's magnitude at the mixer (fraction of full output), sweep and timing.
SID = {
    "SID_MAGNITUDE": 0.15,
    "SID_F_START_HZ": 0.5,
    "SID_F_STOP_HZ": 8.0,
    "SID_T_FADE_IN": 2.0,
    "SID_T_REC": 25.0,
    "SID_T_FADE_OUT": 2.0,
}
SID_AXES = {"roll": 10, "pitch": 11, "yaw": 12}
HOME = "40.072842,-105.230575,1586,0"
TARGET_ALT_M = 30.0


class Flight:
    def __init__(self, master, log):
        self.m = master
        self.log = log
        self.t_ms = 0
        self.rc = [1500, 1500, 1000, 1500, 1500, 1500, 1500, 1000]
        self.alt = 0.0
        self.climb = 0.0
        self.alt_hold = False
        self.col_base = 1500.0
        self.velocity = None  # body-frame (forward, right) m/s in GUIDED
        self.last_send = 0.0
        self.mode = None
        self.armed = False

    def say(self, text):
        line = f"[{self.t_ms / 1000:8.2f} s] {text}"
        print(line, flush=True)
        self.log.write(line + "\n")

    def handle(self, msg):
        t = getattr(msg, "time_boot_ms", None)
        if t is not None and t > self.t_ms:
            self.t_ms = t
        kind = msg.get_type()
        if kind == "GLOBAL_POSITION_INT":
            self.alt = msg.relative_alt / 1000.0
            self.climb = -msg.vz / 100.0
        elif kind == "HEARTBEAT" and msg.type == mavutil.mavlink.MAV_TYPE_HELICOPTER:
            self.mode = msg.custom_mode
            self.armed = bool(msg.base_mode & mavutil.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
        elif kind == "STATUSTEXT":
            self.say("autopilot: " + msg.text)

    def pump(self, seconds, until=None):
        """Runs for `seconds` of simulated time (or until `until()`), keeping the overrides and
        setpoints flowing and the altitude loop closed. Returns whether `until` was met."""
        end = self.t_ms + seconds * 1000.0
        last_loop = self.t_ms
        while self.t_ms < end:
            msg = self.m.recv_match(blocking=True, timeout=0.05)
            if msg is not None:
                self.handle(msg)
            if until is not None and until():
                return True
            if self.alt_hold and self.t_ms - last_loop >= 100:
                dt = (self.t_ms - last_loop) / 1000.0
                last_loop = self.t_ms
                err = TARGET_ALT_M - self.alt
                self.col_base += 4.0 * err * dt
                self.col_base = min(max(self.col_base, 1300.0), 1750.0)
                self.rc[2] = int(min(max(self.col_base + 12.0 * err - 40.0 * self.climb, 1200), 1800))
            now = time.monotonic()
            if now - self.last_send > 0.1:
                self.last_send = now
                self.m.mav.rc_channels_override_send(
                    self.m.target_system, self.m.target_component, *self.rc)
                if self.velocity is not None:
                    fwd, right = self.velocity
                    self.m.mav.set_position_target_local_ned_send(
                        0, self.m.target_system, self.m.target_component,
                        mavutil.mavlink.MAV_FRAME_BODY_OFFSET_NED,
                        0b0000_1111_1100_0111, 0, 0, 0, fwd, right, 0, 0, 0, 0, 0, 0)
        return False

    def set_param(self, name, value):
        for _ in range(5):
            self.m.mav.param_set_send(self.m.target_system, self.m.target_component,
                                      name.encode(), float(value),
                                      mavutil.mavlink.MAV_PARAM_TYPE_REAL32)
            end = time.monotonic() + 3
            while time.monotonic() < end:
                msg = self.m.recv_match(blocking=True, timeout=0.2)
                if msg is None:
                    continue
                self.handle(msg)
                if msg.get_type() == "PARAM_VALUE" and msg.param_id == name:
                    if abs(msg.param_value - value) < 1e-4 * max(1.0, abs(value)):
                        self.say(f"{name} = {value}")
                        return
        raise SystemExit(f"parameter {name} was not set to {value}")

    def set_mode(self, name):
        number = self.m.mode_mapping()[name]
        for _ in range(5):
            self.m.set_mode(number)
            if self.pump(3, until=lambda: self.mode == number):
                self.say(f"mode {name}")
                return
        raise SystemExit(f"mode {name} was refused")


def start_sitl(args, workdir):
    defaults = os.path.join(args.ardupilot, "Tools/autotest/default_params/copter-heli.parm")
    cmd = [os.path.abspath(args.sitl), "--model", "heli", "--speedup", str(args.speedup),
           "--defaults", defaults, f"-I{args.instance}", "--wipe", "--home", HOME,
           "--serial0", f"udpclient:127.0.0.1:{14550 + 10 * args.instance}", "--serial1", "none", "--serial2", "none"]
    out = open(os.path.join(workdir, "sitl.out"), "w")
    return subprocess.Popen(cmd, cwd=workdir, stdout=out, stderr=subprocess.STDOUT), cmd


def takeoff(f):
    f.say("waiting for the EKF's absolute position")
    f.m.mav.request_data_stream_send(f.m.target_system, f.m.target_component,
                                     mavutil.mavlink.MAV_DATA_STREAM_ALL, 10, 1)
    state = {"ok": False}

    def ekf_ok():
        msg = f.m.messages.get("EKF_STATUS_REPORT")
        return msg is not None and (msg.flags & mavutil.mavlink.EKF_POS_HORIZ_ABS) != 0

    if not f.pump(180, until=ekf_ok):
        raise SystemExit("the EKF never had an absolute position")
    f.pump(10)
    f.set_mode("STABILIZE")
    for _ in range(20):
        f.m.arducopter_arm()
        if f.pump(3, until=lambda: f.armed):
            state["ok"] = True
            break
        f.pump(5)
    if not state["ok"]:
        raise SystemExit("arming refused (see the autopilot's messages above)")
    f.say("armed; rotor run-up (RC8 interlock high)")
    f.rc[7] = 2000
    f.pump(20)
    f.say("climbing")
    f.alt_hold = True
    f.col_base = 1550.0
    f.pump(60, until=lambda: f.alt > TARGET_ALT_M - 2)
    f.pump(15)
    f.say(f"hover at {f.alt:.1f} m")


def land(f):
    f.velocity = None
    f.set_mode("LAND")
    f.alt_hold = False
    f.rc[2] = 1500
    f.pump(120, until=lambda: not f.armed)
    f.say("landed and disarmed" if not f.armed else "still armed after 120 s")


def doublet(f, channel, amplitude=200, half=1.0):
    f.rc[channel] = 1500 + amplitude
    f.pump(half)
    f.rc[channel] = 1500 - amplitude
    f.pump(half)
    f.rc[channel] = 1500
    f.pump(6)


def plan_sid(f):
    f.pump(20)  # hover
    for name, axis in SID_AXES.items():
        f.set_param("SID_AXIS", axis)
        for key, value in SID.items():
            f.set_param(key, value)
        f.set_mode("SYSTEMID")
        f.say(f"SystemID {name} (SID_AXIS {axis})")
        total = SID["SID_T_FADE_IN"] + SID["SID_T_REC"] + SID["SID_T_FADE_OUT"] + 2 / SID["SID_F_START_HZ"]
        f.pump(total + 3)
        f.set_mode("STABILIZE")
        f.pump(10)
    for name, channel in (("roll", 0), ("pitch", 1), ("yaw", 3)):
        f.say(f"doublet {name}")
        doublet(f, channel)
    f.pump(10)


def plan_envelope(f):
    f.pump(15)
    f.set_mode("GUIDED")
    f.alt_hold = False
    f.rc[2] = 1500
    f.velocity = (0.0, 0.0)
    f.pump(5)
    for fwd, right in ((1, 0), (2, 0), (3, 0), (5, 0), (0, 1), (0, 2), (0, 3)):
        f.say(f"GUIDED body velocity forward {fwd} m/s, right {right} m/s")
        f.velocity = (float(fwd), float(right))
        f.pump(12)
        f.velocity = (0.0, 0.0)
        f.pump(6)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sitl", required=True, help="the arducopter-heli SITL binary")
    p.add_argument("--ardupilot", required=True, help="ArduPilot source tree (default params)")
    p.add_argument("--plan", choices=["sid", "envelope"], required=True)
    p.add_argument("--out", required=True, help="directory for the log and the transcript")
    p.add_argument("--speedup", type=float, default=1.0)
    p.add_argument("--instance", type=int, default=0,
                   help="SITL instance (-I); its MAVLink goes to UDP 14550 + 10 × instance")
    args = p.parse_args()
    workdir = os.path.abspath(os.path.join(args.out, args.plan))
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    sitl, cmd = start_sitl(args, workdir)
    log = open(os.path.join(workdir, "transcript.txt"), "w")
    log.write("SITL: " + " ".join(cmd) + "\n")
    try:
        master = mavutil.mavlink_connection(
            f"udpin:127.0.0.1:{14550 + 10 * args.instance}", source_system=255)
        master.wait_heartbeat(timeout=120)
        f = Flight(master, log)
        for key, value in PARAMS.items():
            f.set_param(key, value)
        takeoff(f)
        {"sid": plan_sid, "envelope": plan_envelope}[args.plan](f)
        land(f)
        f.pump(3)
    finally:
        sitl.terminate()
        try:
            sitl.wait(10)
        except subprocess.TimeoutExpired:
            sitl.kill()
        log.close()
    logs = sorted(os.listdir(os.path.join(workdir, "logs")))
    print("logs:", logs)


if __name__ == "__main__":
    sys.exit(main())
