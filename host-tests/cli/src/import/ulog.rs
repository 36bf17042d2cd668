//! PX4 ULog (`.ulg`) → [`Channels`], with `px4-ulog` (PX4's parser). Instance 0 of each topic;
//! time stamps in µs since boot (`timestamp_sample` where the topic has it, else `timestamp`).
//!
//! | quantity | topic and fields | unit |
//! |---|---|---|
//! | attitude | `vehicle_attitude`: `q[0..4]` (w x y z, body FRD → NED) → ZYX Euler | rad |
//! | velocity | `vehicle_local_position`: `vx vy vz` (NED), while `v_xy_valid`/`v_z_valid` | m/s |
//! | body rates | `vehicle_angular_velocity`: `xyz[0..3]` (FRD); older logs: `vehicle_attitude` `rollspeed pitchspeed yawspeed` | rad/s |
//! | controls | `vehicle_torque_setpoint` `xyz` + `vehicle_thrust_setpoint` `xyz[2]`; older logs: `actuator_controls_0` `control[0..4]` | −1…1, thrust 0…1 |
//!
//! The controls are the attitude controller's normalised outputs before the mixer (what the
//! helicopter mixer turns into swashplate and tail commands): collective = −thrust z (FRD z is
//! down), pedal = torque z, longitudinal cyclic = torque y (nose up), lateral = torque x.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use px4_ulog::full_parser::{read_file, Completeness, SomeVec};

use super::resample::merge_held;
use super::{Channels, ImportError, Series};

const FORMAT: &str = "ULog";

type Topic = HashMap<String, SomeVec>;

fn as_f64(v: &SomeVec) -> Vec<f64> {
    match v {
        SomeVec::Int8(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::UInt8(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::Int16(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::UInt16(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::Int32(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::UInt32(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::Int64(x) => x.iter().map(|&a| a as f64).collect(),
        SomeVec::UInt64(x) => x.iter().map(|&a| a as f64).collect(),
        SomeVec::Float(x) => x.iter().map(|&a| f64::from(a)).collect(),
        SomeVec::Double(x) => x.clone(),
        SomeVec::Bool(x) => x.iter().map(|&a| f64::from(u8::from(a))).collect(),
        SomeVec::Char(x) => x.iter().map(|&a| f64::from(u32::from(a))).collect(),
    }
}

/// Columns `fields` of `topic` with its time stamps (s), rows where all are present.
fn columns<const N: usize>(topic: &Topic, fields: [&str; N]) -> Option<(Vec<f64>, Vec<[f64; N]>)> {
    let t = topic
        .get("timestamp_sample")
        .or_else(|| topic.get("timestamp"))
        .map(as_f64)?;
    let cols: Vec<Vec<f64>> = fields
        .iter()
        .map(|f| topic.get(*f).map(as_f64))
        .collect::<Option<_>>()?;
    let n = cols.iter().map(Vec::len).fold(t.len(), usize::min);
    let t = t[..n].iter().map(|us| us / 1e6).collect();
    let rows = (0..n)
        .map(|k| core::array::from_fn(|i| cols[i][k]))
        .collect();
    Some((t, rows))
}

/// A series from `fields` of `topic`, each row mapped by `map(row index, values)` (`None`
/// drops the row).
fn series<const N: usize, const M: usize>(
    topic: Option<&Topic>,
    fields: [&str; N],
    mut map: impl FnMut(usize, [f64; N]) -> Option<[f64; M]>,
) -> Option<Series<M>> {
    let (t, rows) = columns(topic?, fields)?;
    let mut s = Series::default();
    for (k, (t, r)) in t.into_iter().zip(rows).enumerate() {
        if let Some(v) = map(k, r) {
            s.push(t, v);
        }
    }
    (!s.t.is_empty()).then_some(s)
}

/// Keeps every row.
fn all<const N: usize>(_: usize, v: [f64; N]) -> Option<[f64; N]> {
    Some(v)
}

/// ZYX Euler angles `[φ θ ψ]` (rad) of a unit quaternion `[w x y z]`.
pub fn quaternion_to_euler([w, x, y, z]: [f64; 4]) -> [f64; 3] {
    [
        (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y)),
        (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin(),
        (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
    ]
}

/// Reads the channels of a ULog file; `file` names it in errors and notes.
pub fn channels(file: &str, path: &Path) -> Result<(Channels, Vec<String>), ImportError> {
    let path_str = path.to_str().ok_or_else(|| ImportError::PathNotUtf8 {
        file: file.to_string(),
        format: FORMAT,
    })?;
    let data = read_file(path_str).map_err(|e| ImportError::Malformed {
        file: file.to_string(),
        format: FORMAT,
        source: Arc::new(e),
    })?;
    let mut notes = Vec::new();
    match &data.completeness {
        Completeness::Complete => {}
        Completeness::Truncated => notes.push(format!(
            "{file}: the log is truncated (cut mid-record); using the data before the cut"
        )),
        Completeness::MalformedRecord(r) => notes.push(format!(
            "{file}: a malformed record ends the data ({r}); using the data before it"
        )),
    }
    // Instance 0 of each topic (the lowest multi id logged).
    let topic = |name: &str| {
        data.messages
            .get(name)
            .and_then(|m| m.iter().min_by_key(|(id, _)| id.value()).map(|(_, t)| t))
    };
    let missing = |quantity, tried| ImportError::Missing {
        file: file.to_string(),
        format: FORMAT,
        quantity,
        tried,
    };
    let attitude = series(
        topic("vehicle_attitude"),
        ["q[0]", "q[1]", "q[2]", "q[3]"],
        |_, q| Some(quaternion_to_euler(q)),
    )
    .ok_or_else(|| missing("attitude", "`vehicle_attitude` `q[0..4]`"))?;
    // Velocity only while the estimator flags it valid (older logs have no flags).
    let local = topic("vehicle_local_position");
    let flag = |name: &str| local.and_then(|t| t.get(name)).map(as_f64);
    let flags = [flag("v_xy_valid"), flag("v_z_valid")];
    let velocity_ned = series(local, ["vx", "vy", "vz"], |k, v| {
        let valid = flags.iter().all(|f| {
            f.as_ref()
                .is_none_or(|f| f.get(k).is_none_or(|x| *x != 0.0))
        });
        valid.then_some(v)
    })
    .ok_or_else(|| {
        if series(local, ["vx", "vy", "vz"], all).is_some() {
            missing(
                "valid velocity",
                "`vehicle_local_position` rows with `v_xy_valid` and `v_z_valid` set",
            )
        } else {
            missing("velocity", "`vehicle_local_position` `vx vy vz`")
        }
    })?;
    let rates_frd = series(
        topic("vehicle_angular_velocity"),
        ["xyz[0]", "xyz[1]", "xyz[2]"],
        all,
    )
    .or_else(|| {
        series(
            topic("vehicle_attitude"),
            ["rollspeed", "pitchspeed", "yawspeed"],
            all,
        )
    })
    .ok_or_else(|| {
        missing(
            "body rates",
            "`vehicle_angular_velocity` `xyz`, `vehicle_attitude` `rollspeed pitchspeed yawspeed`",
        )
    })?;
    let torque = series(
        topic("vehicle_torque_setpoint"),
        ["xyz[0]", "xyz[1]", "xyz[2]"],
        all,
    );
    let thrust = series(
        topic("vehicle_thrust_setpoint"),
        ["xyz[0]", "xyz[1]", "xyz[2]"],
        all,
    );
    let controls = match (torque, thrust) {
        (Some(m), Some(f)) => {
            Some(merge_held(&m, &f, |m, f| [-f[2], m[2], m[1], m[0]])).filter(|s| !s.t.is_empty())
        }
        _ => None,
    }
    .or_else(|| {
        series(
            topic("actuator_controls_0"),
            ["control[3]", "control[2]", "control[1]", "control[0]"],
            all,
        )
    })
    .ok_or_else(|| {
        missing(
            "helicopter controls",
            "`vehicle_torque_setpoint` + `vehicle_thrust_setpoint`, `actuator_controls_0`",
        )
    })?;
    Ok((
        Channels {
            attitude,
            velocity_ned,
            rates_frd,
            controls,
            in_air: Series::default(),
        },
        notes,
    ))
}
