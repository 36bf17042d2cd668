//! ArduPilot DataFlash (`.bin`) → [`Channels`], streamed through this crate's own [`reader`]
//! (why not the `ardupilot-binlog` crate: see there). Time stamps from each message's `TimeUS`
//! (µs since boot; older logs' `TimeMS` × 1000), pushed in log order.
//!
//! | quantity | message and fields | unit in the log → here |
//! |---|---|---|
//! | attitude | `ANG` `Roll Pitch Yaw` (ArduPilot 4.7 on), else `ATT` `Roll Pitch Yaw` (ZYX Euler, yaw 0…360) | deg → rad, yaw wrapped to (−π, π] |
//! | velocity | `XKF1` `VN VE VD` (EKF3, core `C` = 0); older logs `NKF1` (EKF2), ArduCopter 3.2–3.4 `EKF1` | m/s |
//! | body rates | `RATE` `R P Y` (the rate controller's measured rates, FRD) | deg/s → rad/s (ArduCopter 3.3: centidegrees/s) |
//! | controls | `RATE` `YOut POut ROut` (rate controller outputs, −1…1) + collective `RATE` `AOut` (0…1; else `CTUN` `ThO`, held) | — (ArduCopter 3.3: outputs ±4500, `AOut` 0…1000, scaled) |
//! | attitude error | `ANG` or `ATT` `DesRoll Roll DesPitch Pitch`: the larger of the roll and pitch errors (for [`lost_control_cuts`](super::clean::lost_control_cuts)) | deg → rad |
//! | in air | `EV` `Id` (10 armed, 28 not landed → 1; 11 disarmed, 18 land complete → 0) and `ARM` `ArmState` (≠ 0 → 1) | 1 / 0 |
//!
//! The controls are the controllers' normalised outputs before the TradHeli swashplate mixer
//! (`RCOU` PWM would need the swashplate geometry and servo trims to undo): pedal = `YOut`,
//! longitudinal cyclic = `POut` (nose up), lateral = `ROut`, collective = `AOut`. `RATE` `AOut`
//! and `CTUN` `ThO` are the same quantity (`AP_Motors::get_throttle()`, which the TradHeli mixer
//! takes as its collective), but `CTUN` is written at 10 Hz and `RATE` with the attitude (up to
//! the main loop's rate with `LOG_BITMASK` `ATTITUDE_FAST`), so `AOut` is taken when the log
//! has it and `ThO` only for logs whose `RATE` lacks it.
//!
//! Likewise the attitude: from ArduPilot 4.7 `ATTITUDE_FAST` writes the AHRS attitude with the
//! attitude controller's targets as `ANG` (at the `RATE` rate) and `ATT` only at 10 Hz, so `ANG`
//! is taken when the log has it.
//!
//! Older logs: ArduCopter 3.3, the first to write `RATE`, wrote it from its own
//! `Copter::Log_Write_Rate` with the rates in centidegrees/s and the motors library's outputs in
//! its integer ranges (roll, pitch, yaw ±4500, throttle 0…1000); 3.4 moved it to the logging
//! library in deg/s and ±1, 0…1. Which firmware wrote the log is read from its `MSG` records
//! (up to 3.1 they carry no time stamp; an `EV` without one takes the last record's time), and
//! a 3.3 log's `RATE` is scaled to the later units, with a note.

pub mod reader;

use std::io::Read;

use super::malformed::{Malformation, ReadError};
use super::resample::{angle_difference, merge_held};
use super::ulog::read_error;
use super::{Channels, ImportError, Series};
use reader::Reader;

const FORMAT: &str = "DataFlash";

/// Yaw in degrees 0…360 (or any) → radians in (−π, π].
pub(super) fn wrap_deg(y: f64) -> f64 {
    let deg = std::f64::consts::PI / 180.0;
    (y * deg + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// Reads the channels of the DataFlash log `input` (streamed); `file` names it in errors.
pub fn channels(file: &str, input: impl Read) -> Result<(Channels, Vec<String>), ImportError> {
    let deg = std::f64::consts::PI / 180.0;
    let mut ch = Channels::default();
    let (mut ekf3, mut ekf2) = (Series::<3>::default(), Series::<3>::default());
    let (mut outs, mut collective) = (Series::<3>::default(), Series::<1>::default());
    // The collective from `RATE` `AOut`; `CTUN` `ThO` is kept apart and used only without it.
    let mut collective_ctun = Series::<1>::default();
    // The attitude from `ANG` (4.7 on, fast); `ATT` is kept apart and used only without it.
    let mut attitude_ang = Series::<3>::default();
    let mut error_ang = Series::<1>::default();
    // The attitude controller's tracking error, beside the attitude in the same record.
    let error = |e: &reader::Record| {
        e.fields(["DesRoll", "Roll", "DesPitch", "Pitch"])
            .map(|[dr, r, dp, p]| {
                let off = |d: f64, a: f64| angle_difference(d * deg, a * deg).abs();
                [off(dr, r).max(off(dp, p))]
            })
    };
    // The firmware's name from its first `MSG` ("ArduPlane V4.2.3", "APM:Copter V3.4.4").
    let mut firmware: Option<String> = None;
    // ArduCopter 3.2–3.4's EKF velocity, used without `XKF1` and `NKF1`.
    let mut ekf1 = Series::<3>::default();
    // The time of the last record that had one, for the events that have none (up to 3.1).
    let mut last_t: Option<f64> = None;
    let mut reader = Reader::new(input);
    let err = |e| read_error(file, FORMAT, e);
    while let Some(e) = reader.next_record().map_err(err)? {
        let name = e.format.name.as_str();
        if name == "MSG" && firmware.is_none() {
            firmware = e
                .text("Message")
                .filter(|m| m.starts_with("Ardu") || m.starts_with("APM:"))
                .map(|m| m.split(" (").next().unwrap_or_default().to_string());
        }
        let Some(t) = e
            .time_us()
            .map(|us| us / 1e6)
            .or(last_t.filter(|_| name == "EV"))
        else {
            continue;
        };
        last_t = Some(t);
        match name {
            "ATT" => {
                if let Some([r, p, y]) = e.fields(["Roll", "Pitch", "Yaw"]) {
                    ch.attitude.push(t, [r * deg, p * deg, wrap_deg(y)]);
                }
                if let Some(x) = error(&e) {
                    ch.attitude_error.push(t, x);
                }
            }
            "ANG" => {
                if let Some([r, p, y]) = e.fields(["Roll", "Pitch", "Yaw"]) {
                    attitude_ang.push(t, [r * deg, p * deg, wrap_deg(y)]);
                }
                if let Some(x) = error(&e) {
                    error_ang.push(t, x);
                }
            }
            "XKF1" if e.get("C").is_none_or(|c| c == 0.0) => {
                if let Some(v) = e.fields(["VN", "VE", "VD"]) {
                    ekf3.push(t, v);
                }
            }
            "NKF1" => {
                if let Some(v) = e.fields(["VN", "VE", "VD"]) {
                    ekf2.push(t, v);
                }
            }
            "EKF1" => {
                if let Some(v) = e.fields(["VN", "VE", "VD"]) {
                    ekf1.push(t, v);
                }
            }
            "RATE" => {
                if let Some([r, p, y]) = e.fields(["R", "P", "Y"]) {
                    ch.rates_frd.push(t, [r * deg, p * deg, y * deg]);
                }
                if let Some(u) = e.fields(["YOut", "POut", "ROut"]) {
                    outs.push(t, u);
                }
                if let Some(u) = e.fields(["AOut"]) {
                    collective.push(t, u);
                }
            }
            "CTUN" => {
                if let Some(u) = e.fields(["ThO"]) {
                    collective_ctun.push(t, u);
                }
            }
            "EV" => match e.get("Id") {
                Some(10.0 | 28.0) => ch.in_air.push(t, [1.0]),
                Some(11.0 | 18.0) => ch.in_air.push(t, [0.0]),
                _ => {}
            },
            "ARM" => {
                if let Some(s) = e.get("ArmState") {
                    ch.in_air.push(t, [if s != 0.0 { 1.0 } else { 0.0 }]);
                }
            }
            _ => {}
        }
    }
    if reader.records() == 0 {
        return Err(err(ReadError::Malformed {
            offset: 0,
            reason: Malformation::NoRecords,
        }));
    }
    let mut notes = reader.issues().notes(file);
    ch.velocity_ned = [ekf3, ekf2, ekf1]
        .into_iter()
        .find(|v| !v.t.is_empty())
        .unwrap_or_default();
    if let Some(name) = firmware.as_deref().filter(|f| legacy_rate_units(f)) {
        if !ch.rates_frd.t.is_empty() || !outs.t.is_empty() {
            for w in &mut ch.rates_frd.v {
                w.iter_mut().for_each(|x| *x /= 100.0);
            }
            for u in &mut outs.v {
                u.iter_mut().for_each(|x| *x /= 4500.0);
            }
            for c in &mut collective.v {
                c[0] /= 1000.0;
            }
            notes.push(format!(
                "{file}: written by {name}, whose `RATE` holds the rates in centidegrees/s, the outputs in ±4500 and `AOut` in 0…1000 (ArduCopter 3.3): scaled to deg/s, ±1 and 0…1"
            ));
        }
    }
    if collective.t.is_empty() {
        collective = collective_ctun;
    }
    if !attitude_ang.t.is_empty() {
        ch.attitude = attitude_ang;
        ch.attitude_error = error_ang;
    }
    ch.controls = merge_held(&outs, &collective, |o, c| [c[0], o[0], o[1], o[2]]);
    let remark = reader.issues().first().map(String::into_boxed_str);
    // Every missing quantity in one error: the first, and the others after it.
    let missing = [
        (
            ch.attitude.t.is_empty(),
            ("attitude", "`ANG` or `ATT` `Roll Pitch Yaw`"),
        ),
        (
            ch.velocity_ned.t.is_empty(),
            ("velocity", "`XKF1`, `NKF1` or `EKF1` `VN VE VD`"),
        ),
        (ch.rates_frd.t.is_empty(), ("body rates", "`RATE` `R P Y`")),
        (
            ch.controls.t.is_empty(),
            (
                "helicopter controls",
                "`RATE` `ROut POut YOut` with `RATE` `AOut` or `CTUN` `ThO`",
            ),
        ),
    ]
    .into_iter()
    .filter_map(|(absent, what)| absent.then_some(what));
    if let Some(e) = ImportError::missing_all(file, FORMAT, missing, remark, firmware) {
        return Err(e);
    }
    Ok((ch, notes))
}

/// The version `(major, minor)` of ArduCopter that `firmware` (its `MSG` name, "APM:Copter
/// V3.3.3", "ArduCopter V4.7.0-dev") names, `None` for another firmware.
pub(super) fn arducopter_version(firmware: &str) -> Option<(u32, u32)> {
    if !(firmware.starts_with("APM:Copter") || firmware.starts_with("ArduCopter")) {
        return None;
    }
    let v = firmware
        .split_whitespace()
        .find_map(|w| w.strip_prefix('V'))?;
    let mut parts = v.split(|c: char| !c.is_ascii_digit());
    let mut next = || parts.next().and_then(|p| p.parse::<u32>().ok());
    Some((next()?, next()?))
}

/// Whether a log written by `firmware` holds `RATE` in ArduCopter 3.3's units (see the
/// [module docs](self)): Copter below 3.4.
fn legacy_rate_units(firmware: &str) -> bool {
    arducopter_version(firmware).is_some_and(|v| v < (3, 4))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn padded<const N: usize>(s: &str) -> [u8; N] {
        let mut out = [0u8; N];
        out[..s.len()].copy_from_slice(s.as_bytes());
        out
    }

    fn fmt(buf: &mut Vec<u8>, kind: u8, name: &str, format: &str, labels: &str, len: usize) {
        buf.extend_from_slice(&[0xA3, 0x95, 0x80, kind, (3 + len) as u8]);
        buf.extend_from_slice(&padded::<4>(name));
        buf.extend_from_slice(&padded::<16>(format));
        buf.extend_from_slice(&padded::<64>(labels));
    }

    fn row(buf: &mut Vec<u8>, kind: u8, t_us: u64, values: &[f32]) {
        buf.extend_from_slice(&[0xA3, 0x95, kind]);
        buf.extend_from_slice(&t_us.to_le_bytes());
        for v in values {
            buf.extend_from_slice(&v.to_le_bytes());
        }
    }

    /// An untimed `MSG` format (type 0x86) and one record of it: how ArduCopter up to 3.1
    /// names its firmware.
    fn untimed_msg(buf: &mut Vec<u8>, message: &str) {
        fmt(buf, 0x86, "MSG", "Z", "Message", 67);
        buf.extend_from_slice(&[0xA3, 0x95, 0x86]);
        buf.extend_from_slice(&padded::<64>(message));
    }

    /// A log as ArduPilot writes it with `ATTITUDE_FAST`: `RATE` (with or without `AOut`) at
    /// 50 Hz, the collective ramping 0.4 → 0.6, and `CTUN` `ThO` at 10 Hz with a different
    /// value (0.2) so the test can tell which one was taken; `with_aout` is a 4.7 log, with
    /// `ANG` at 50 Hz and `ATT` at 10 Hz (different rolls, for the same reason).
    fn log(with_aout: bool) -> Vec<u8> {
        let mut buf = Vec::new();
        fmt(&mut buf, 0x81, "ATT", "Qfff", "TimeUS,Roll,Pitch,Yaw", 20);
        fmt(&mut buf, 0x82, "XKF1", "Qfff", "TimeUS,VN,VE,VD", 20);
        let (rate_format, rate_labels, rate_len) = if with_aout {
            ("Qfffffff", "TimeUS,R,P,Y,ROut,POut,YOut,AOut", 36)
        } else {
            ("Qffffff", "TimeUS,R,P,Y,ROut,POut,YOut", 32)
        };
        fmt(&mut buf, 0x83, "RATE", rate_format, rate_labels, rate_len);
        fmt(&mut buf, 0x84, "CTUN", "Qf", "TimeUS,ThO", 12);
        if with_aout {
            fmt(&mut buf, 0x85, "ANG", "Qfff", "TimeUS,Roll,Pitch,Yaw", 20);
        }
        for k in 0..100u64 {
            let t = 1_000_000 + k * 20_000;
            // 4.7 logs: `ATT` at 10 Hz (roll 9°), `ANG` with the rates at 50 Hz (roll 1°).
            if !with_aout || k % 5 == 0 {
                row(
                    &mut buf,
                    0x81,
                    t,
                    &[if with_aout { 9.0 } else { 0.0 }, 0.0, 10.0],
                );
            }
            if with_aout {
                row(&mut buf, 0x85, t, &[1.0, 0.0, 10.0]);
            }
            row(&mut buf, 0x82, t, &[0.0, 0.0, 0.0]);
            let col = 0.4 + 0.2 * k as f32 / 99.0;
            let mut rate = vec![0.0, 0.0, 0.0, 0.1, -0.1, 0.05];
            if with_aout {
                rate.push(col);
            }
            row(&mut buf, 0x83, t, &rate);
            if k % 5 == 0 {
                row(&mut buf, 0x84, t, &[0.2]);
            }
        }
        buf
    }

    /// A fixed-wing log (attitude and velocity, no `RATE`) is told in one line: every missing
    /// quantity, and which firmware wrote it (`MSG`), saying it is not a rotorcraft's.
    #[test]
    fn a_plane_log_names_everything_missing_and_its_firmware() {
        let mut buf = Vec::new();
        fmt(&mut buf, 0x81, "ATT", "Qfff", "TimeUS,Roll,Pitch,Yaw", 20);
        fmt(&mut buf, 0x82, "XKF1", "Qfff", "TimeUS,VN,VE,VD", 20);
        fmt(&mut buf, 0x86, "MSG", "QZ", "TimeUS,Message", 72);
        buf.extend_from_slice(&[0xA3, 0x95, 0x86]);
        buf.extend_from_slice(&1_000_000u64.to_le_bytes());
        buf.extend_from_slice(&padded::<64>("ArduPlane V4.2.3 (c0ffee00)"));
        for k in 0..10u64 {
            let t = 1_000_000 + k * 20_000;
            row(&mut buf, 0x81, t, &[0.0, 0.0, 10.0]);
            row(&mut buf, 0x82, t, &[0.0, 0.0, 0.0]);
        }
        let e = channels("plane.bin", &buf[..]).expect_err("no rates");
        let text = e.to_string();
        assert!(text.contains("no body rates"), "{text}");
        assert!(text.contains("also no helicopter controls"), "{text}");
        assert!(
            text.contains("written by ArduPlane V4.2.3, not a rotorcraft's firmware"),
            "{text}"
        );
        assert!(!text.contains("c0ffee00"), "{text}");
    }

    #[test]
    fn only_arducopter_before_3_4_has_the_old_rate_units() {
        for (firmware, legacy) in [
            ("APM:Copter V3.3.3", true),
            ("APM:Copter V3.3-dev", true),
            ("APM:Copter V3.2.1", true),
            ("ArduCopter V3.4.0", false),
            ("APM:Copter V3.4.4", false),
            ("ArduCopter V4.7.0-dev", false),
            ("ArduPlane V3.3.0", false),
            ("APM:Copter", false),
        ] {
            assert_eq!(legacy_rate_units(firmware), legacy, "{firmware}");
        }
    }

    /// An ArduCopter 3.3 log: a `MSG` without a time stamp names the firmware, `EKF1` holds the
    /// velocity, `RATE` is in centidegrees/s, ±4500 and 0…1000 (scaled, with a note), and an
    /// `EV` without a time stamp takes the last record's.
    #[test]
    fn an_arducopter_3_3_log_reads_in_the_later_units() {
        let mut buf = Vec::new();
        fmt(&mut buf, 0x81, "ATT", "Qfff", "TimeUS,Roll,Pitch,Yaw", 20);
        fmt(
            &mut buf,
            0x82,
            "EKF1",
            "Qffffff",
            "TimeUS,Roll,Pitch,Yaw,VN,VE,VD",
            32,
        );
        fmt(
            &mut buf,
            0x83,
            "RATE",
            "Qfffffff",
            "TimeUS,R,P,Y,ROut,POut,YOut,AOut",
            36,
        );
        fmt(&mut buf, 0x87, "EV", "B", "Id", 4);
        untimed_msg(&mut buf, "APM:Copter V3.3.3 (d6053245)");
        for k in 0..50u64 {
            let t = 1_000_000 + k * 20_000;
            row(&mut buf, 0x81, t, &[0.0, 0.0, 10.0]);
            row(&mut buf, 0x82, t, &[0.0, 0.0, 10.0, 1.5, -0.5, 0.25]);
            row(
                &mut buf,
                0x83,
                t,
                &[1000.0, -500.0, 250.0, 450.0, -900.0, 2250.0, 600.0],
            );
            if k == 10 {
                buf.extend_from_slice(&[0xA3, 0x95, 0x87, 10]);
            }
        }
        let (ch, notes) = channels("ac33.bin", &buf[..]).expect("imports");
        assert_eq!(ch.velocity_ned.t.len(), 50);
        assert_eq!(ch.velocity_ned.v[0], [1.5, -0.5, 0.25]);
        let deg = std::f64::consts::PI / 180.0;
        let w = ch.rates_frd.v[0];
        for (got, want) in w.iter().zip([10.0 * deg, -5.0 * deg, 2.5 * deg]) {
            assert!((got - want).abs() < 1e-12, "{w:?}");
        }
        // [collective, pedal, longitudinal, lateral].
        let u = ch.controls.v[0];
        for (got, want) in u.iter().zip([0.6, 0.5, -0.2, 0.1]) {
            assert!((got - want).abs() < 1e-6, "{u:?}");
        }
        assert!(
            notes
                .iter()
                .any(|n| n.contains("written by APM:Copter V3.3.3") && n.contains("scaled")),
            "{notes:?}"
        );
        assert_eq!(ch.in_air.t, vec![1.2]);
        assert_eq!(ch.in_air.v, vec![[1.0]]);
    }

    /// ArduCopter before 3.3 writes no `RATE`: the error says so rather than only that the
    /// message is missing.
    #[test]
    fn a_log_of_arducopter_before_3_3_says_it_cannot_be_identified() {
        let mut buf = Vec::new();
        fmt(&mut buf, 0x81, "ATT", "Qfff", "TimeUS,Roll,Pitch,Yaw", 20);
        fmt(&mut buf, 0x82, "EKF1", "Qfff", "TimeUS,VN,VE,VD", 20);
        untimed_msg(&mut buf, "ArduCopter V3.2.1 (36b405fb)");
        for k in 0..10u64 {
            let t = 1_000_000 + k * 20_000;
            row(&mut buf, 0x81, t, &[0.0, 0.0, 10.0]);
            row(&mut buf, 0x82, t, &[0.0, 0.0, 0.0]);
        }
        let text = channels("ac32.bin", &buf[..])
            .expect_err("no RATE")
            .to_string();
        assert!(text.contains("no body rates"), "{text}");
        assert!(text.contains("written by ArduCopter V3.2.1"), "{text}");
        assert!(text.contains("from 3.3 on"), "{text}");
        assert!(!text.contains("no velocity"), "{text}");
    }

    #[test]
    fn the_collective_comes_from_rate_aout_and_the_attitude_from_ang_when_the_log_has_them() {
        let (ch, _) = channels("heli.bin", &log(true)[..]).expect("imports");
        assert_eq!(ch.controls.t.len(), 100);
        let col: Vec<f64> = ch.controls.v.iter().map(|u| u[0]).collect();
        // 50 Hz ramp 0.4 → 0.6 from AOut, not the 10 Hz ThO of 0.2.
        assert!(
            (col[0] - 0.4).abs() < 1e-6 && (col[99] - 0.6).abs() < 1e-6,
            "{col:?}"
        );
        assert!(col.windows(2).all(|w| w[1] > w[0]), "not the 50 Hz ramp");
        // The attitude from the 50 Hz `ANG`, not the 10 Hz `ATT`.
        assert_eq!(ch.attitude.t.len(), 100);
        assert!(ch
            .attitude
            .v
            .iter()
            .all(|a| (a[0] - 1f64.to_radians()).abs() < 1e-6));
        let u = ch.controls.v[50];
        assert!(
            (u[1] - 0.05).abs() < 1e-6 && (u[2] + 0.1).abs() < 1e-6 && (u[3] - 0.1).abs() < 1e-6
        );
    }

    #[test]
    fn without_rate_aout_the_collective_is_ctun_tho_and_without_ang_the_attitude_att() {
        let (ch, _) = channels("quad.bin", &log(false)[..]).expect("imports");
        assert_eq!(ch.attitude.t.len(), 100);
        assert!(!ch.controls.t.is_empty());
        assert!(ch.controls.v.iter().all(|u| (u[0] - 0.2).abs() < 1e-6));
    }
}
