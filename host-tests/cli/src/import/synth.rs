//! Minimal writers of ULog, DataFlash and PX4 sdlog2 logs from [`SensorSample`]s, after the
//! formats' specifications (PX4 "ULog File Format", ArduPilot `LogStructure.h`, PX4's
//! `sdlog2_messages.h`): only the topics and messages [`super::ulog`], [`super::dataflash`]
//! and [`super::sdlog2`] read, one sample per row. They make helicopter logs for tests,
//! examples and fuzz seeds (no real helicopter log with all these topics is public under a
//! licence that allows committing it).

use rotorid_sim::plant::SensorSample;

/// Time stamp (µs) of a sample: `t` after a 1 s boot.
fn micros(t: f64) -> u64 {
    (t * 1e6).round() as u64 + 1_000_000
}

/// Unit quaternion `[w x y z]` of ZYX Euler angles (rad).
pub fn euler_to_quaternion(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (sr, cr) = (roll / 2.0).sin_cos();
    let (sp, cp) = (pitch / 2.0).sin_cos();
    let (sy, cy) = (yaw / 2.0).sin_cos();
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

fn ulog_message(buf: &mut Vec<u8>, kind: u8, payload: &[u8]) {
    buf.extend_from_slice(&(payload.len() as u16).to_le_bytes());
    buf.push(kind);
    buf.extend_from_slice(payload);
}

fn floats(values: &[f64]) -> Vec<u8> {
    values
        .iter()
        .flat_map(|x| (*x as f32).to_le_bytes())
        .collect()
}

/// A ULog with `vehicle_attitude`, `vehicle_local_position`, `vehicle_angular_velocity` and,
/// with `controls`, `vehicle_torque_setpoint` and `vehicle_thrust_setpoint` (thrust z =
/// −collective).
pub fn ulog(samples: &[SensorSample], controls: bool) -> Vec<u8> {
    let mut buf = b"ULog\x01\x12\x35\x01".to_vec();
    buf.extend_from_slice(&1_000_000u64.to_le_bytes());
    ulog_message(&mut buf, b'B', &[0u8; 40]);
    let mut topics = vec![
        ("vehicle_attitude", "float[4] q;"),
        ("vehicle_local_position", "float vx;float vy;float vz;"),
        ("vehicle_angular_velocity", "float[3] xyz;"),
    ];
    if controls {
        topics.push(("vehicle_torque_setpoint", "float[3] xyz;"));
        topics.push(("vehicle_thrust_setpoint", "float[3] xyz;"));
    }
    for (name, fields) in &topics {
        let f = format!("{name}:uint64_t timestamp;{fields}");
        ulog_message(&mut buf, b'F', f.as_bytes());
    }
    for (id, (name, _)) in topics.iter().enumerate() {
        let mut a = vec![0u8];
        a.extend_from_slice(&(id as u16).to_le_bytes());
        a.extend_from_slice(name.as_bytes());
        ulog_message(&mut buf, b'A', &a);
    }
    for s in samples {
        let q = euler_to_quaternion(s.roll, s.pitch, s.yaw);
        let u = &s.sticks;
        let rows = [
            floats(&q),
            floats(&[s.v_north, s.v_east, s.v_down]),
            floats(&[s.p, s.q, s.r]),
            floats(&[u.lat, u.lon, u.ped]),
            floats(&[0.0, 0.0, -u.col]),
        ];
        for (id, row) in rows.iter().take(topics.len()).enumerate() {
            let mut d = (id as u16).to_le_bytes().to_vec();
            d.extend_from_slice(&micros(s.t).to_le_bytes());
            d.extend_from_slice(row);
            ulog_message(&mut buf, b'D', &d);
        }
    }
    buf
}

fn padded<const N: usize>(text: &str) -> [u8; N] {
    let mut out = [0u8; N];
    out.iter_mut().zip(text.bytes()).for_each(|(o, b)| *o = b);
    out
}

/// A DataFlash log with `ATT` (deg), `XKF1` (core 0), `RATE` (deg/s and outputs) and, with
/// `controls`, `CTUN` `ThO`.
pub fn dataflash(samples: &[SensorSample], controls: bool) -> Vec<u8> {
    dataflash_with_demand(samples, controls, None)
}

/// The attitude controller's roll and pitch demand `[φ_d θ_d]` (rad) of a sample.
pub type Demand<'a> = &'a dyn Fn(&SensorSample) -> [f64; 2];

/// [`dataflash`], with `ATT` `DesRoll DesPitch` from `demand` when given.
pub fn dataflash_with_demand(
    samples: &[SensorSample],
    controls: bool,
    demand: Option<Demand<'_>>,
) -> Vec<u8> {
    // (type, name, format, labels); payload lengths from the format characters Q = 8, f = 4, B = 1.
    let att = if demand.is_some() {
        (
            0x81u8,
            "ATT",
            "Qfffff",
            "TimeUS,DesRoll,Roll,DesPitch,Pitch,Yaw",
            8 + 20,
        )
    } else {
        (0x81u8, "ATT", "Qfff", "TimeUS,Roll,Pitch,Yaw", 8 + 12)
    };
    let mut formats = vec![
        att,
        (0x82, "XKF1", "QBfff", "TimeUS,C,VN,VE,VD", 8 + 1 + 12),
        (
            0x83,
            "RATE",
            "Qffffff",
            "TimeUS,R,P,Y,ROut,POut,YOut",
            8 + 24,
        ),
    ];
    if controls {
        formats.push((0x84, "CTUN", "Qf", "TimeUS,ThO", 8 + 4));
    }
    let mut buf = Vec::new();
    for (kind, name, format, labels, len) in &formats {
        buf.extend_from_slice(&[0xA3, 0x95, 0x80, *kind, (3 + len) as u8]);
        buf.extend_from_slice(&padded::<4>(name));
        buf.extend_from_slice(&padded::<16>(format));
        buf.extend_from_slice(&padded::<64>(labels));
    }
    let deg = 180.0 / std::f64::consts::PI;
    for s in samples {
        let u = &s.sticks;
        let yaw = (s.yaw * deg).rem_euclid(360.0);
        let attitude = match demand {
            Some(d) => {
                let [dr, dp] = d(s);
                floats(&[dr * deg, s.roll * deg, dp * deg, s.pitch * deg, yaw])
            }
            None => floats(&[s.roll * deg, s.pitch * deg, yaw]),
        };
        let rows: [(u8, Vec<u8>); 4] = [
            (0x81, attitude),
            (
                0x82,
                [vec![0u8], floats(&[s.v_north, s.v_east, s.v_down])].concat(),
            ),
            (
                0x83,
                floats(&[s.p * deg, s.q * deg, s.r * deg, u.lat, u.lon, u.ped]),
            ),
            (0x84, floats(&[u.col])),
        ];
        for (kind, row) in rows.iter().take(formats.len()) {
            buf.extend_from_slice(&[0xA3, 0x95, *kind]);
            buf.extend_from_slice(&micros(s.t).to_le_bytes());
            buf.extend_from_slice(row);
        }
    }
    buf
}

/// An old PX4 `sdlog2` log (DataFlash framing, PX4's messages of 2016): per sample a `TIME`
/// (`StartTime`, µs), `ATT` (rad, rad/s), `LPOS` (`VX VY VZ`), `STAT` (`ArmS` = 2, armed)
/// and, with `controls`, `ATTC` (`Roll Pitch Yaw Thrust` = lat, lon, ped, col).
pub fn sdlog2(samples: &[SensorSample], controls: bool) -> Vec<u8> {
    sdlog2_with(samples, controls, true)
}

/// [`sdlog2`] with its `TIME` messages left out (`time` false): DataFlash framing whose rows
/// carry no time at all, neither sdlog2's nor ArduPilot's.
pub fn sdlog2_with(samples: &[SensorSample], controls: bool, time: bool) -> Vec<u8> {
    // (type, name, format, labels, payload length), as the T-REX 550 logs define them
    // (trimmed to the fields read).
    let mut formats = vec![
        (129u8, "TIME", "Q", "StartTime", 8),
        (
            2,
            "ATT",
            "ffffff",
            "Roll,Pitch,Yaw,RollRate,PitchRate,YawRate",
            24,
        ),
        (6, "LPOS", "fff", "VX,VY,VZ", 12),
        (
            10,
            "STAT",
            "BBBBf",
            "MainState,NavState,ArmS,Failsafe,Load",
            8,
        ),
    ];
    if controls {
        formats.push((9, "ATTC", "ffff", "Roll,Pitch,Yaw,Thrust", 16));
    }
    let mut buf = Vec::new();
    for (kind, name, format, labels, len) in formats.iter().skip(usize::from(!time)) {
        buf.extend_from_slice(&[0xA3, 0x95, 0x80, *kind, (3 + len) as u8]);
        buf.extend_from_slice(&padded::<4>(name));
        buf.extend_from_slice(&padded::<16>(format));
        buf.extend_from_slice(&padded::<64>(labels));
    }
    for s in samples {
        let u = &s.sticks;
        let rows: [(u8, Vec<u8>); 5] = [
            (129, micros(s.t).to_le_bytes().to_vec()),
            (2, floats(&[s.roll, s.pitch, s.yaw, s.p, s.q, s.r])),
            (6, floats(&[s.v_north, s.v_east, s.v_down])),
            (10, [&[1u8, 1, 2, 0][..], &0.5f32.to_le_bytes()].concat()),
            (9, floats(&[u.lat, u.lon, u.ped, u.col])),
        ];
        for (kind, row) in rows.iter().take(formats.len()).skip(usize::from(!time)) {
            buf.extend_from_slice(&[0xA3, 0x95, *kind]);
            buf.extend_from_slice(row);
        }
    }
    buf
}
