//! PX4 ULog (`.ulg`) → [`Channels`], streamed through this crate's own [`reader`] (why not the
//! `px4-ulog` crate: see there). Instance 0 of each topic (multi id 0); time stamps in µs since
//! boot (`timestamp_sample` where the topic has it, else `timestamp`), pushed in log order.
//!
//! | quantity | topic and fields | unit |
//! |---|---|---|
//! | attitude | `vehicle_attitude`: `q[0..4]` (w x y z, body FRD → NED) → ZYX Euler | rad |
//! | velocity | `vehicle_local_position`: `vx vy vz` (NED), while `v_xy_valid`/`v_z_valid` | m/s |
//! | body rates | `vehicle_angular_velocity`: `xyz[0..3]` (FRD); older logs: `vehicle_attitude` `rollspeed pitchspeed yawspeed` | rad/s |
//! | controls | `vehicle_torque_setpoint` `xyz` + `vehicle_thrust_setpoint` `xyz[2]`; older logs: `actuator_controls_0` `control[0..4]` | −1…1, thrust 0…1 |
//! | attitude error | `vehicle_attitude_setpoint` `q_d[0..4]` (held while under 0.25 s old) against `vehicle_attitude`: the larger of the roll and pitch errors (for [`lost_control_cuts`](super::clean::lost_control_cuts)) | rad |
//! | in air | `vehicle_land_detected` `landed` (in air = not landed); else `vehicle_status` `arming_state` (2 armed, 3 armed with error) | 1 / 0 |
//!
//! The controls are the attitude controller's normalised outputs before the mixer (what the
//! helicopter mixer turns into swashplate and tail commands): collective = −thrust z (FRD z is
//! down), pedal = torque z, longitudinal cyclic = torque y (nose up), lateral = torque x.

pub mod reader;

use std::collections::HashMap;
use std::io::Read;

use super::malformed::ReadError;
use super::resample::{angle_difference, merge_held, merge_recent};
use super::{Channels, ImportError, Series};
use reader::{Event, Field, Reader};

const FORMAT: &str = "ULog";

/// The topics read, and the fields of each (in the order [`Acc::push`] takes them).
const TOPICS: [(&str, &[&str]); 9] = [
    (
        "vehicle_attitude",
        &[
            "q[0]",
            "q[1]",
            "q[2]",
            "q[3]",
            "rollspeed",
            "pitchspeed",
            "yawspeed",
        ],
    ),
    (
        "vehicle_local_position",
        &["vx", "vy", "vz", "v_xy_valid", "v_z_valid"],
    ),
    ("vehicle_angular_velocity", &["xyz[0]", "xyz[1]", "xyz[2]"]),
    ("vehicle_torque_setpoint", &["xyz[0]", "xyz[1]", "xyz[2]"]),
    ("vehicle_thrust_setpoint", &["xyz[0]", "xyz[1]", "xyz[2]"]),
    (
        "actuator_controls_0",
        &["control[0]", "control[1]", "control[2]", "control[3]"],
    ),
    ("vehicle_land_detected", &["landed"]),
    ("vehicle_status", &["arming_state"]),
    (
        "vehicle_attitude_setpoint",
        &["q_d[0]", "q_d[1]", "q_d[2]", "q_d[3]"],
    ),
];

/// A subscription of instance 0 of one of [`TOPICS`]: which, and its located fields.
struct Sub {
    topic: usize,
    time: Field,
    fields: Vec<Option<Field>>,
}

/// The series gathered while reading.
#[derive(Default)]
struct Acc {
    attitude: Series<3>,
    attitude_rates: Series<3>,
    velocity: Series<3>,
    any_velocity: bool,
    angular_velocity: Series<3>,
    torque: Series<3>,
    thrust: Series<3>,
    actuator_controls: Series<4>,
    landed: Series<1>,
    armed: Series<1>,
    attitude_setpoint: Series<3>,
}

impl Acc {
    /// One data record of topic `topic` at `t` (s), its fields' values.
    fn push(&mut self, topic: usize, t: f64, v: &[Option<f64>]) {
        let get = |i: usize| v.get(i).copied().flatten();
        let arr = |from: usize| -> Option<[f64; 3]> {
            Some([get(from)?, get(from + 1)?, get(from + 2)?])
        };
        match topic {
            0 => {
                if let (Some(xyz), Some(w)) = (arr(1), get(0)) {
                    self.attitude
                        .push(t, quaternion_to_euler([w, xyz[0], xyz[1], xyz[2]]));
                }
                if let Some(r) = arr(4) {
                    self.attitude_rates.push(t, r);
                }
            }
            1 => {
                if let Some(vel) = arr(0) {
                    self.any_velocity = true;
                    // Only while the estimator flags it valid (older logs have no flags).
                    if [get(3), get(4)].iter().all(|f| f.is_none_or(|f| f != 0.0)) {
                        self.velocity.push(t, vel);
                    }
                }
            }
            2 => arr(0)
                .into_iter()
                .for_each(|x| self.angular_velocity.push(t, x)),
            3 => arr(0).into_iter().for_each(|x| self.torque.push(t, x)),
            4 => arr(0).into_iter().for_each(|x| self.thrust.push(t, x)),
            5 => {
                if let (Some(c), Some(c3)) = (arr(0), get(3)) {
                    self.actuator_controls.push(t, [c3, c[2], c[1], c[0]]);
                }
            }
            6 => get(0).into_iter().for_each(|l| {
                self.landed.push(t, [if l != 0.0 { 0.0 } else { 1.0 }]);
            }),
            7 => get(0).into_iter().for_each(|s| {
                self.armed
                    .push(t, [if s == 2.0 || s == 3.0 { 1.0 } else { 0.0 }]);
            }),
            8 => {
                if let (Some(xyz), Some(w)) = (arr(1), get(0)) {
                    self.attitude_setpoint
                        .push(t, quaternion_to_euler([w, xyz[0], xyz[1], xyz[2]]));
                }
            }
            _ => {}
        }
    }
}

/// ZYX Euler angles `[φ θ ψ]` (rad) of a unit quaternion `[w x y z]`.
pub fn quaternion_to_euler([w, x, y, z]: [f64; 4]) -> [f64; 3] {
    [
        (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y)),
        (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin(),
        (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
    ]
}

/// An error of the reader as an [`ImportError`] naming `file`.
pub(super) fn read_error(file: &str, format: &'static str, e: ReadError) -> ImportError {
    match e {
        ReadError::Io(e) => ImportError::Read {
            file: file.to_string(),
            source: std::sync::Arc::new(e),
        },
        ReadError::Malformed { offset, reason } => ImportError::Malformed {
            file: file.to_string(),
            format,
            offset,
            reason,
        },
    }
}

/// Reads the channels of the ULog `input` (streamed); `file` names it in errors and notes.
pub fn channels(file: &str, input: impl Read) -> Result<(Channels, Vec<String>), ImportError> {
    let err = |e| read_error(file, FORMAT, e);
    let mut reader = Reader::new(input).map_err(err)?;
    let mut subs: HashMap<u16, Sub> = HashMap::new();
    let mut acc = Acc::default();
    let (mut dropouts, mut dropout_ms, mut first_dropout) = (0u64, 0u64, None);
    let mut values = Vec::new();
    while let Some(event) = reader.next_event().map_err(err)? {
        match event {
            Event::Subscribed {
                msg_id,
                topic,
                multi_id,
            } => {
                subs.remove(&msg_id);
                let Some(k) = TOPICS.iter().position(|(name, _)| *name == topic) else {
                    continue;
                };
                if multi_id != 0 {
                    continue;
                }
                let time = reader
                    .locate(msg_id, "timestamp_sample")
                    .or_else(|| reader.locate(msg_id, "timestamp"));
                if let Some(time) = time {
                    let fields = TOPICS[k]
                        .1
                        .iter()
                        .map(|f| reader.locate(msg_id, f))
                        .collect();
                    subs.insert(
                        msg_id,
                        Sub {
                            topic: k,
                            time,
                            fields,
                        },
                    );
                }
            }
            Event::Data { msg_id, data, .. } => {
                let Some(sub) = subs.get(&msg_id) else {
                    continue;
                };
                let Some(us) = sub.time.read(data) else {
                    continue;
                };
                values.clear();
                values.extend(sub.fields.iter().map(|f| f.and_then(|f| f.read(data))));
                acc.push(sub.topic, us / 1e6, &values);
            }
            Event::Dropout { offset, ms } => {
                dropouts += 1;
                dropout_ms += u64::from(ms);
                first_dropout.get_or_insert(offset);
            }
        }
    }
    let mut notes = reader.issues().notes(file);
    if let Some(at) = first_dropout {
        notes.push(format!(
            "{file}: the logger dropped data {dropouts} times ({dropout_ms} ms in all), first at byte {at}"
        ));
    }
    let remark = reader.issues().first().map(String::into_boxed_str);
    // The demand is published only in the modes that control the attitude: a stale one is
    // not held against later samples.
    let attitude_error = merge_recent(
        &acc.attitude,
        &acc.attitude_setpoint,
        super::resample::MAX_SOURCE_GAP_S,
        |a, d| {
            let off = |i: usize| angle_difference(d[i], a[i]).abs();
            [off(0).max(off(1))]
        },
    );
    let nonempty = |s: Series<3>| (!s.t.is_empty()).then_some(s);
    let attitude = nonempty(acc.attitude);
    let velocity_ned = nonempty(acc.velocity);
    let rates_frd = nonempty(acc.angular_velocity).or_else(|| nonempty(acc.attitude_rates));
    let controls = Some(merge_held(&acc.torque, &acc.thrust, |m, f| {
        [-f[2], m[2], m[1], m[0]]
    }))
    .filter(|s| !s.t.is_empty())
    .or_else(|| Some(acc.actuator_controls).filter(|s| !s.t.is_empty()));
    let absent = [
        attitude.is_none(),
        velocity_ned.is_none(),
        rates_frd.is_none(),
        controls.is_none(),
    ];
    let (Some(attitude), Some(velocity_ned), Some(rates_frd), Some(controls)) =
        (attitude, velocity_ned, rates_frd, controls)
    else {
        // Every missing quantity in one error: the first, and the others after it.
        let velocity = if acc.any_velocity {
            (
                "valid velocity",
                "`vehicle_local_position` rows with `v_xy_valid` and `v_z_valid` set",
            )
        } else {
            ("velocity", "`vehicle_local_position` `vx vy vz`")
        };
        let missing = [
            ("attitude", "`vehicle_attitude` `q[0..4]`"),
            velocity,
            (
                "body rates",
                "`vehicle_angular_velocity` `xyz`, `vehicle_attitude` `rollspeed pitchspeed yawspeed`",
            ),
            (
                "helicopter controls",
                "`vehicle_torque_setpoint` + `vehicle_thrust_setpoint`, `actuator_controls_0`",
            ),
        ]
        .into_iter()
        .zip(absent)
        .filter_map(|(what, absent)| absent.then_some(what));
        // One of the four is `None` here, so the list is not empty.
        return Err(
            ImportError::missing_all(file, FORMAT, missing, remark, None).unwrap_or(
                ImportError::NotALog {
                    file: file.to_string(),
                },
            ),
        );
    };
    let in_air = if acc.landed.t.is_empty() {
        acc.armed
    } else {
        acc.landed
    };
    Ok((
        Channels {
            attitude,
            velocity_ned,
            rates_frd,
            controls,
            in_air,
            attitude_error,
        },
        notes,
    ))
}
