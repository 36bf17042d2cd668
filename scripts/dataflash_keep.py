#!/usr/bin/env python3
"""Copies a DataFlash log keeping only some message types, record for record (the bytes as
ArduPilot wrote them, read with pymavlink's DFReader): how the ArduPilot SITL fixtures
(host-tests/cli/data/logs/ardupilot-sitl/) were cut to a few MB. SITL's own simulator messages
(SIM, SIM2, ESC, …) and the EKF's other messages are most of a SITL log and not used here.

Usage: dataflash_keep.py IN.BIN OUT.bin
"""
import sys

from pymavlink import DFReader

# Metadata (formats, units, parameters, messages, version) and what rotorid reads or what tells
# the flight's story: the attitude (ANG fast, ATT 10 Hz), rates and controls (RATE), EKF3
# velocity (XKF1, core 0 only), collective and height (CTUN), servo outputs (RCOU), swashplate
# (SWSH), modes, events, arming, SystemID's start and stop (SIDS) and its waveform (SIDD).
KEEP = {"FMT", "FMTU", "UNIT", "MULT", "PARM", "MSG", "VER", "MODE", "EV", "ARM", "ANG", "ATT",
        "RATE", "XKF1", "CTUN", "RCOU", "SWSH", "SIDS", "SIDD"}


def main():
    src, dst = sys.argv[1], sys.argv[2]
    reader = DFReader.DFReader_binary(src, zero_time_base=True)
    kept = dropped = 0
    with open(dst, "wb") as out:
        while True:
            m = reader.recv_msg()
            if m is None:
                break
            name = m.get_type()
            if name not in KEEP or (name == "XKF1" and int(getattr(m, "C", 0)) != 0):
                dropped += 1
                continue
            out.write(m.get_msgbuf())
            kept += 1
    print(f"{dst}: kept {kept} records, dropped {dropped}")


if __name__ == "__main__":
    main()
