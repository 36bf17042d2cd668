//! Old PX4 `sdlog2` logs (`.px4log`, PX4 before ULog, 2013–2017) → [`Channels`]. They use the
//! DataFlash framing ([`super::dataflash::reader`]) with PX4's own messages; their messages
//! carry no time stamp: a `TIME` message (`StartTime`, µs since boot) precedes each batch, and
//! every message takes the latest `StartTime`.
//!
//! | quantity | message and fields | unit |
//! |---|---|---|
//! | attitude | `ATT` `Roll Pitch Yaw` (ZYX Euler) | rad (yaw wrapped to (−π, π]) |
//! | velocity | `LPOS` `VX VY VZ` (NED) while `PFlg` flags it valid; else `GPOS` `VelN VelE VelD` | m/s |
//! | body rates | `ATT` `RollRate PitchRate YawRate` (FRD) | rad/s |
//! | controls | `ATTC` `Thrust Yaw Pitch Roll` (`actuator_controls_0` 3, 2, 1, 0) | 0…1, −1…1 |
//! | in air | `LAND` `Landed` (in air = not landed); else `STAT` `ArmS` (2 armed, 3 armed with error) or older `Armed` (≠ 0) | 1 / 0 |
//!
//! Field names checked against the T-REX 550 logs of `dronefreak/system-identification-helicopter`
//! (PX4 of 2016: `ATT` with `qw…` and `GX…` besides, `STAT` with `ArmS`, `LAND` `Landed`).

use std::io::Read;

use super::dataflash::reader::Reader;
use super::malformed::{Malformation, ReadError};
use super::ulog::read_error;
use super::{Channels, ImportError, Series};

const FORMAT: &str = "PX4 sdlog2";

/// `LPOS` `PFlg` bits of a valid horizontal (2) and vertical (3) velocity.
const VELOCITY_VALID: u32 = 0b1100;

/// Whether the formats (from the first `FMT` records of a DataFlash-framed file) are an
/// sdlog2 log's: a `TIME` message with `StartTime` or PX4's `ATT` (with `RollRate`), and no
/// message with ArduPilot's `TimeUS` or `TimeMS` first field. So a log whose `TIME` messages
/// are lost is still told as sdlog2, and [`channels`] says that its rows carry no time
/// rather than DataFlash's reader saying that `ATT` is missing.
pub fn is_sdlog2<'a>(
    formats: impl Iterator<Item = &'a super::dataflash::reader::MessageFormat>,
) -> bool {
    let (mut sdlog2, mut ardupilot) = (false, false);
    for f in formats {
        sdlog2 |=
            (f.name == "TIME" && f.has("StartTime")) || (f.name == "ATT" && f.has("RollRate"));
        ardupilot |= f
            .labels()
            .next()
            .is_some_and(|l| l == "TimeUS" || l == "TimeMS");
    }
    sdlog2 && !ardupilot
}

/// Reads the channels of the sdlog2 log `input` (streamed); `file` names it in errors.
pub fn channels(file: &str, input: impl Read) -> Result<(Channels, Vec<String>), ImportError> {
    let mut ch = Channels::default();
    let (mut lpos, mut gpos) = (Series::<3>::default(), Series::<3>::default());
    let mut lpos_rows = 0usize;
    let (mut landed, mut armed) = (Series::<1>::default(), Series::<1>::default());
    let mut reader = Reader::new(input);
    let err = |e| read_error(file, FORMAT, e);
    let mut now: Option<f64> = None;
    let mut untimed = false;
    while let Some(e) = reader.next_record().map_err(err)? {
        if e.format.name == "TIME" {
            now = e.get("StartTime").map(|us| us / 1e6).or(now);
            continue;
        }
        untimed |= now.is_none();
        let Some(t) = now else {
            continue;
        };
        match e.format.name.as_str() {
            "ATT" => {
                if let Some([r, p, y]) = e.fields(["Roll", "Pitch", "Yaw"]) {
                    let yaw = super::dataflash::wrap_deg(y.to_degrees());
                    ch.attitude.push(t, [r, p, yaw]);
                }
                if let Some(w) = e.fields(["RollRate", "PitchRate", "YawRate"]) {
                    ch.rates_frd.push(t, w);
                }
            }
            "LPOS" => {
                // Only while the estimator flags the velocity valid (`PFlg` bit 2 horizontal,
                // bit 3 vertical); older logs without `PFlg` are taken as they are.
                let valid = e
                    .get("PFlg")
                    .is_none_or(|f| (f as u32) & VELOCITY_VALID == VELOCITY_VALID);
                if let Some(v) = e.fields(["VX", "VY", "VZ"]) {
                    lpos_rows += 1;
                    if valid {
                        lpos.push(t, v);
                    }
                }
            }
            "GPOS" => {
                if let Some(v) = e.fields(["VelN", "VelE", "VelD"]) {
                    gpos.push(t, v);
                }
            }
            "ATTC" => {
                if let Some([r, p, y, f]) = e.fields(["Roll", "Pitch", "Yaw", "Thrust"]) {
                    ch.controls.push(t, [f, y, p, r]);
                }
            }
            "LAND" => {
                if let Some(l) = e.get("Landed") {
                    landed.push(t, [if l != 0.0 { 0.0 } else { 1.0 }]);
                }
            }
            "STAT" => {
                let a = match (e.get("ArmS"), e.get("Armed")) {
                    (Some(s), _) => Some(s == 2.0 || s == 3.0),
                    (None, Some(a)) => Some(a != 0.0),
                    _ => None,
                };
                if let Some(a) = a {
                    armed.push(t, [if a { 1.0 } else { 0.0 }]);
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
    ch.velocity_ned = if lpos.t.is_empty() { gpos } else { lpos };
    ch.in_air = if landed.t.is_empty() { armed } else { landed };
    // A message logged once (sdlog2 writes each topic at start) is no channel either.
    let remark = reader.issues().first().map(String::into_boxed_str);
    let missing = |quantity, tried| ImportError::Missing {
        file: file.to_string(),
        format: FORMAT,
        quantity,
        tried,
        remark: remark.clone(),
        context: Box::default(),
    };
    if now.is_none() && untimed {
        // Rows, and not one `TIME` among them: nothing says when any was logged.
        return Err(missing(
            "time stamps",
            "`TIME` `StartTime` (sdlog2 writes one before each batch of messages; its other messages carry no time of their own)",
        ));
    }
    if ch.attitude.t.len() < 2 {
        return Err(missing("attitude", "`ATT` `Roll Pitch Yaw` after a `TIME`"));
    }
    if ch.velocity_ned.t.len() < 2 {
        if lpos_rows > 1 {
            return Err(missing(
                "valid velocity",
                "`LPOS` rows with the velocity flagged valid (`PFlg` bits 2 and 3), `GPOS` `VelN VelE VelD`",
            ));
        }
        return Err(missing(
            "velocity",
            "`LPOS` `VX VY VZ`, `GPOS` `VelN VelE VelD`",
        ));
    }
    if ch.rates_frd.t.len() < 2 {
        return Err(missing("body rates", "`ATT` `RollRate PitchRate YawRate`"));
    }
    if ch.controls.t.len() < 2 {
        return Err(missing(
            "helicopter controls",
            "`ATTC` `Roll Pitch Yaw Thrust` (actuator_controls_0)",
        ));
    }
    Ok((ch, notes))
}
