//! ArduPilot DataFlash (`.bin`) → [`Channels`], with `ardupilot-binlog`. Time stamps from each
//! message's `TimeUS` (µs since boot).
//!
//! | quantity | message and fields | unit in the log → here |
//! |---|---|---|
//! | attitude | `ATT` `Roll Pitch Yaw` (ZYX Euler, yaw 0…360) | deg → rad, yaw wrapped to (−π, π] |
//! | velocity | `XKF1` `VN VE VD` (EKF3, core `C` = 0); older logs `NKF1` (EKF2) | m/s |
//! | body rates | `RATE` `R P Y` (the rate controller's measured rates, FRD) | deg/s → rad/s |
//! | controls | `RATE` `YOut POut ROut` (rate controller outputs, −1…1) + `CTUN` `ThO` (collective, 0…1, held) | — |
//!
//! The controls are the controllers' normalised outputs before the TradHeli swashplate mixer
//! (`RCOU` PWM would need the swashplate geometry and servo trims to undo): pedal = `YOut`,
//! longitudinal cyclic = `POut` (nose up), lateral = `ROut`, collective = `ThO`.

use std::io::Cursor;

use ardupilot_binlog::{Entry, Reader};

use super::resample::merge_held;
use super::{Channels, ImportError, Series};

const FORMAT: &str = "DataFlash";

fn fields<const N: usize>(e: &Entry, names: [&str; N]) -> Option<[f64; N]> {
    let v: Vec<f64> = names.iter().map(|n| e.get_f64(n)).collect::<Option<_>>()?;
    v.try_into().ok()
}

/// Reads the channels of a DataFlash log held in `bytes`; `file` names it in errors.
pub fn channels(file: &str, bytes: &[u8]) -> Result<(Channels, Vec<String>), ImportError> {
    let deg = std::f64::consts::PI / 180.0;
    let mut ch = Channels::default();
    let (mut ekf3, mut ekf2) = (Series::<3>::default(), Series::<3>::default());
    let (mut outs, mut collective) = (Series::<3>::default(), Series::<1>::default());
    let mut notes = Vec::new();
    for entry in Reader::new(Cursor::new(bytes)) {
        let e = match entry {
            Ok(e) => e,
            Err(err) => {
                notes.push(format!("{file}: reading stopped early: {err}"));
                break;
            }
        };
        let Some(t) = e.timestamp_usec.map(|us| us as f64 / 1e6) else {
            continue;
        };
        match e.name.as_str() {
            "ATT" => {
                if let Some([r, p, y]) = fields(&e, ["Roll", "Pitch", "Yaw"]) {
                    let yaw = (y * deg + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI;
                    ch.attitude.push(t, [r * deg, p * deg, yaw]);
                }
            }
            "XKF1" if e.get_f64("C").is_none_or(|c| c == 0.0) => {
                if let Some(v) = fields(&e, ["VN", "VE", "VD"]) {
                    ekf3.push(t, v);
                }
            }
            "NKF1" => {
                if let Some(v) = fields(&e, ["VN", "VE", "VD"]) {
                    ekf2.push(t, v);
                }
            }
            "RATE" => {
                if let Some([r, p, y]) = fields(&e, ["R", "P", "Y"]) {
                    ch.rates_frd.push(t, [r * deg, p * deg, y * deg]);
                }
                if let Some(u) = fields(&e, ["YOut", "POut", "ROut"]) {
                    outs.push(t, u);
                }
            }
            "CTUN" => {
                if let Some(u) = fields(&e, ["ThO"]) {
                    collective.push(t, u);
                }
            }
            _ => {}
        }
    }
    ch.velocity_ned = if ekf3.t.is_empty() { ekf2 } else { ekf3 };
    ch.controls = merge_held(&outs, &collective, |o, c| [c[0], o[0], o[1], o[2]]);
    let missing = |quantity, tried| ImportError::Missing {
        file: file.to_string(),
        format: FORMAT,
        quantity,
        tried,
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
