//! The flight structure's translational model takes the main rotor's thrust as affine in the
//! collective, `(α1 u_col + α0) R e2` (`VelocityStructure::Flight`), where Eq. 27 has it
//! proportional, `α1 u_col R e2`.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use rotorid::hover::{rotor_axis, Attitude, Controls, HoverSample, StateModel};
use rotorid::{ExtendedPlainIdentifier, FlightPlainIdentifier, HoverConfig, HoverIdentifier};

const G: f64 = 9.80665;
const DT: f64 = 0.02;
/// Collective of zero thrust and of hover: a stick mapping that does not put zero lift at zero.
const ZERO_LIFT: f64 = 0.1;
const TRIM: f64 = 0.35;
/// Thrust per unit collective over the weight (1/stick): hover at `TRIM`.
const K: f64 = G / (TRIM - ZERO_LIFT);

/// A noise-free helicopter in still air whose only forces are its weight and a thrust
/// `K (u_col − ZERO_LIFT)` along the rotor axis, tilting and turning, its collective moving
/// about hover (paper axes: x east, y up, z south).
fn flight_log(samples: u64) -> Vec<HoverSample<f32>> {
    let mut v = [0.0f64; 3];
    let mut log = Vec::new();
    for k in 0..samples {
        let t = k as f64 * DT;
        let (roll, pitch, yaw) = (
            0.1 * (0.7 * t).sin(),
            0.08 * (1.1 * t).cos(),
            2.5 * (0.2 * t).sin(),
        );
        let col = TRIM + 0.04 * (0.5 * t).sin() + 0.02 * (2.3 * t).cos();
        let sample = HoverSample {
            time_us: 1_000_000 + k * 20_000,
            attitude: Attitude {
                roll: roll as f32,
                pitch: pitch as f32,
                yaw: yaw as f32,
            },
            velocity: v.map(|x| x as f32),
            rates: [0.0; 3],
            controls: Controls {
                col: col as f32,
                ped: 0.4,
                lon: 0.0,
                lat: 0.0,
            },
        };
        // The axis of the attitude as the model reads it (f32), so that only the model's
        // structure, not the data's rounding, separates the two identifiers.
        let e = rotor_axis(
            sample.attitude.roll,
            sample.attitude.pitch,
            sample.attitude.yaw,
        );
        let thrust = K * (col - ZERO_LIFT);
        for (i, x) in v.iter_mut().enumerate() {
            *x += DT * (thrust * e[i] as f64 - if i == 1 { G } else { 0.0 });
        }
        log.push(sample);
    }
    log
}

/// Mean one-step error of the velocity (m/s) of `id` after training on `train`, on `verify`.
fn velocity_error<V, Q, R, P>(
    id: &mut HoverIdentifier<f32, V, Q, R, P>,
    train: &[HoverSample<f32>],
    verify: &[HoverSample<f32>],
) -> f64
where
    V: StateModel<f32>,
    Q: StateModel<f32>,
    R: StateModel<f32>,
    P: StateModel<f32>,
{
    for s in train {
        id.step(s).expect("accepted sample");
    }
    let mut sum = 0.0;
    for pair in verify.windows(2) {
        let next = id.predict(&pair[0]).expect("prediction").velocity;
        for (a, b) in next.iter().zip(pair[1].velocity.iter()) {
            sum += (a - b).abs() as f64;
        }
    }
    sum / (3 * (verify.len() - 1)) as f64
}

#[test]
fn affine_thrust_is_learnt_where_proportional_thrust_cannot_fit() {
    let log = flight_log(9000);
    let (train, verify) = log.split_at(6000);

    let mut flight = FlightPlainIdentifier::<f32>::flight_plain(HoverConfig::default()).unwrap();
    let flight_error = velocity_error(&mut flight, train, verify);
    let mut extended =
        ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()).unwrap();
    let extended_error = velocity_error(&mut extended, train, verify);

    // The thrust's slope, its value at zero collective and the weight, per step (m/s).
    let ts = flight.velocity_model().ts();
    let learnt = |term| ts.physical_parameter(0, term).unwrap() as f64;
    let (alpha1, alpha2, alpha0) = (learnt(0), learnt(1), learnt(7));
    assert!((alpha1 / (K * DT) - 1.0).abs() < 0.01, "α1 = {alpha1}");
    assert!(
        (alpha0 / (-K * ZERO_LIFT * DT) - 1.0).abs() < 0.01,
        "α0 = {alpha0}"
    );
    assert!((alpha2 / (-G * DT) - 1.0).abs() < 0.01, "α2 = {alpha2}");

    // One α1 for both the climb's response to the collective and the tilt's horizontal
    // acceleration misses one of them or both; the affine thrust fits the data to rounding.
    assert!(
        flight_error * 20.0 < extended_error,
        "flight {flight_error} m/s, extended {extended_error} m/s"
    );
}
