//! ArduPilot DataFlash (`.bin`) → [`Channels`], streamed through this crate's own [`reader`]
//! (why not the `ardupilot-binlog` crate: see there). Time stamps from each message's `TimeUS`
//! (µs since boot; older logs' `TimeMS` × 1000), pushed in log order.
//!
//! | quantity | message and fields | unit in the log → here |
//! |---|---|---|
//! | attitude | `ATT` `Roll Pitch Yaw` (ZYX Euler, yaw 0…360) | deg → rad, yaw wrapped to (−π, π] |
//! | velocity | `XKF1` `VN VE VD` (EKF3, core `C` = 0); older logs `NKF1` (EKF2) | m/s |
//! | body rates | `RATE` `R P Y` (the rate controller's measured rates, FRD) | deg/s → rad/s |
//! | controls | `RATE` `YOut POut ROut` (rate controller outputs, −1…1) + `CTUN` `ThO` (collective, 0…1, held) | — |
//! | in air | `EV` `Id` (10 armed, 28 not landed → 1; 11 disarmed, 18 land complete → 0) and `ARM` `ArmState` (≠ 0 → 1) | 1 / 0 |
//!
//! The controls are the controllers' normalised outputs before the TradHeli swashplate mixer
//! (`RCOU` PWM would need the swashplate geometry and servo trims to undo): pedal = `YOut`,
//! longitudinal cyclic = `POut` (nose up), lateral = `ROut`, collective = `ThO`.

pub mod reader;

use std::io::Read;

use super::malformed::{Malformation, ReadError};
use super::resample::merge_held;
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
    let mut reader = Reader::new(input);
    let err = |e| read_error(file, FORMAT, e);
    while let Some(e) = reader.next_record().map_err(err)? {
        let Some(t) = e.time_us().map(|us| us / 1e6) else {
            continue;
        };
        match e.format.name.as_str() {
            "ATT" => {
                if let Some([r, p, y]) = e.fields(["Roll", "Pitch", "Yaw"]) {
                    ch.attitude.push(t, [r * deg, p * deg, wrap_deg(y)]);
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
            "RATE" => {
                if let Some([r, p, y]) = e.fields(["R", "P", "Y"]) {
                    ch.rates_frd.push(t, [r * deg, p * deg, y * deg]);
                }
                if let Some(u) = e.fields(["YOut", "POut", "ROut"]) {
                    outs.push(t, u);
                }
            }
            "CTUN" => {
                if let Some(u) = e.fields(["ThO"]) {
                    collective.push(t, u);
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
    let notes = reader.issues().notes(file);
    ch.velocity_ned = if ekf3.t.is_empty() { ekf2 } else { ekf3 };
    ch.controls = merge_held(&outs, &collective, |o, c| [c[0], o[0], o[1], o[2]]);
    let remark = reader.issues().first();
    let missing = |quantity, tried| ImportError::Missing {
        file: file.to_string(),
        format: FORMAT,
        quantity,
        tried,
        remark: remark.clone(),
    };
    if ch.attitude.t.is_empty() {
        return Err(missing("attitude", "`ATT` `Roll Pitch Yaw`"));
    }
    if ch.velocity_ned.t.is_empty() {
        return Err(missing("velocity", "`XKF1` or `NKF1` `VN VE VD`"));
    }
    if ch.rates_frd.t.is_empty() {
        return Err(missing("body rates", "`RATE` `R P Y`"));
    }
    if ch.controls.t.is_empty() {
        return Err(missing(
            "helicopter controls",
            "`RATE` `ROut POut YOut` with `CTUN` `ThO`",
        ));
    }
    Ok((ch, notes))
}
