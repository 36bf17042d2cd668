//! The three forms of a sample's attitude (Euler angles, quaternion, rotation matrix): the
//! same body frame up to rounding, the same identification up to rounding, and every wrong
//! input refused with the identifier left bit for bit as it was.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use crate::support::golden;

use rotorid::hover::{
    flight_sets, Attitude, AttitudeInput, BodyFrame, HoverSample, Quaternion, RotationMatrix,
    SampleField,
};
use rotorid::{Error, FlightIdentifier, HoverConfig, Quantity};

/// The quaternion of an attitude computed in f64 and rounded to f32, as a flight stack that
/// holds a quaternion would report it.
fn quaternion_f32(a: &Attitude<f32>) -> Quaternion<f32> {
    let wide = Quaternion::from_euler(&Attitude {
        roll: f64::from(a.roll),
        pitch: f64::from(a.pitch),
        yaw: f64::from(a.yaw),
    });
    Quaternion {
        w: wide.w as f32,
        x: wide.x as f32,
        y: wide.y as f32,
        z: wide.z as f32,
    }
}

/// Attitudes over the whole accepted range (pitch short of ±90°, where Euler angles are
/// singular), drawn by an xorshift generator.
fn attitudes(n: usize) -> Vec<Attitude<f64>> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..n)
        .map(|_| Attitude {
            roll: 3.1 * uniform(),
            pitch: 1.45 * uniform(),
            yaw: 3.1 * uniform(),
        })
        .collect()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn quaternion_and_matrix_frames_equal_the_euler_frame_up_to_rounding() {
    for a in attitudes(2000) {
        let euler = BodyFrame::of(&a).to_array();
        let q = Quaternion::from_euler(&a);
        let from_q = BodyFrame::from_quaternion(&q).to_array();
        let m = RotationMatrix::from_quaternion(&q);
        let from_m = BodyFrame::from_matrix(&m).to_array();
        // f64: a few units in the last place, the heading's divided by cos θ ≥ cos 1.45.
        assert!(
            max_diff(&euler, &from_q) < 1e-14,
            "{a:?}: {euler:?} {from_q:?}"
        );
        // The matrix of a quaternion gives the quaternion's frame, bit for bit.
        let bits = |x: [f64; 8]| x.map(f64::to_bits);
        assert_eq!(bits(from_q), bits(from_m), "{a:?}");

        // f32, the flight type: the quaternion rounded from f64, the Euler angles too.
        let a32 = Attitude {
            roll: a.roll as f32,
            pitch: a.pitch as f32,
            yaw: a.yaw as f32,
        };
        let euler32 = BodyFrame::of(&a32).to_array().map(f64::from);
        let from_q32 = BodyFrame::from_quaternion(&quaternion_f32(&a32))
            .to_array()
            .map(f64::from);
        // ε(f32) ≈ 6e-8 per operation; the heading is divided by cos θ ≥ 0.12.
        let bound = 1e-6 / libm::cos(a.pitch);
        assert!(
            max_diff(&euler32, &from_q32) < bound,
            "{a32:?}: {:e}",
            max_diff(&euler32, &from_q32)
        );
    }
}

#[test]
fn a_quaternion_a_little_off_unit_norm_gives_the_same_axes() {
    for a in attitudes(200) {
        let q = Quaternion::from_euler(&a);
        let scaled = Quaternion {
            w: q.w * 1.004,
            x: q.x * 1.004,
            y: q.y * 1.004,
            z: q.z * 1.004,
        };
        assert!(scaled.check().is_ok());
        let d = max_diff(
            &BodyFrame::from_quaternion(&q).to_array(),
            &BodyFrame::from_quaternion(&scaled).to_array(),
        );
        assert!(d < 1e-14, "{a:?}: {d:e}");
    }
}

#[test]
fn a_vertical_nose_still_has_a_finite_unit_heading() {
    for (roll, yaw) in [(0.0, 0.3), (0.4, -2.0), (-1.0, 3.0)] {
        for pitch in [core::f64::consts::FRAC_PI_2, -core::f64::consts::FRAC_PI_2] {
            let q = Quaternion::from_euler(&Attitude { roll, pitch, yaw });
            let f = BodyFrame::from_quaternion(&q);
            let (s, c) = f.heading();
            assert!((s * s + c * c - 1.0).abs() < 1e-12, "{roll} {pitch} {yaw}");
            // The rotor axis is still the Euler one (it has no singularity).
            let e = BodyFrame::of(&Attitude { roll, pitch, yaw }).rotor_axis();
            let d = max_diff(&e, &f.rotor_axis());
            assert!(d < 1e-12, "{roll} {pitch} {yaw}: {d:e}");
        }
    }
}

fn identifier() -> FlightIdentifier<f32> {
    FlightIdentifier::flight(HoverConfig::default(), flight_sets()).expect("flight default")
}

/// Every prediction of a flight identifier stepped through `samples`.
fn predictions<A: AttitudeInput<f32>>(samples: &[HoverSample<f32, A>]) -> Vec<[f32; 6]> {
    let mut id = identifier();
    samples
        .iter()
        .map(|s| id.step(s).expect("a legal sample").prediction.to_array())
        .collect()
}

#[test]
fn identification_from_a_quaternion_or_a_matrix_follows_the_euler_run() {
    let euler = golden::inputs(3000, 7);
    let quat: Vec<_> = euler
        .iter()
        .map(|s| s.with_attitude(quaternion_f32(&s.attitude)))
        .collect();
    let matrix: Vec<_> = quat
        .iter()
        .map(|s| s.with_attitude(RotationMatrix::from_quaternion(&s.attitude)))
        .collect();
    let (pe, pq, pm) = (
        predictions(&euler),
        predictions(&quat),
        predictions(&matrix),
    );
    // The matrix holds the quaternion's own rows, so its run is the quaternion's; both stay
    // within rounding of the Euler run: the largest difference of any prediction over 60 s,
    // relative to the state's largest magnitude.
    assert!(
        pq == pm,
        "the matrix of a quaternion identifies as the quaternion"
    );
    for (name, other) in [("quaternion", &pq), ("matrix", &pm)] {
        for i in 0..6 {
            let scale = pe.iter().map(|p| p[i].abs()).fold(0.0f32, f32::max);
            let diff = pe
                .iter()
                .zip(other.iter())
                .map(|(a, b)| (a[i] - b[i]).abs())
                .fold(0.0f32, f32::max);
            let late = pe[500..]
                .iter()
                .zip(other[500..].iter())
                .map(|(a, b)| (a[i] - b[i]).abs())
                .fold(0.0f32, f32::max);
            // Measured: at most 2.5e-4 of the scale in the first seconds, while the covariance
            // is large and amplifies rounding; at most 1.5e-6 once it has shrunk (after 10 s).
            assert!(
                diff <= 1e-3 * scale && late <= 1e-5 * scale,
                "{name}, state {i}: largest difference {diff:e} ({late:e} after 10 s), scale {scale:e}"
            );
        }
    }
}

#[test]
fn a_wrong_quaternion_or_matrix_is_refused_and_changes_nothing() {
    let samples = golden::inputs(40, 3);
    let mut id = identifier();
    for s in &samples {
        id.step(&s.with_attitude(quaternion_f32(&s.attitude)))
            .expect("legal");
    }
    let before = id.clone();
    let next = samples[39].with_attitude(quaternion_f32(&samples[39].attitude));
    let next = HoverSample {
        time_us: next.time_us + 20_000,
        ..next
    };
    let field = |f| Quantity::Sample(f);
    let cases: Vec<(HoverSample<f32, Quaternion<f32>>, Error)> = vec![
        (
            HoverSample {
                attitude: Quaternion {
                    x: f32::NAN,
                    ..next.attitude
                },
                ..next
            },
            Error::NonFinite(field(SampleField::Quaternion(1))),
        ),
        (
            HoverSample {
                attitude: Quaternion {
                    z: f32::INFINITY,
                    ..next.attitude
                },
                ..next
            },
            Error::NonFinite(field(SampleField::Quaternion(3))),
        ),
        (
            HoverSample {
                attitude: Quaternion {
                    w: 0.0,
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                },
                ..next
            },
            Error::OutOfRange(field(SampleField::QuaternionNorm)),
        ),
        (
            HoverSample {
                attitude: Quaternion {
                    w: next.attitude.w * 1.01,
                    x: next.attitude.x * 1.01,
                    y: next.attitude.y * 1.01,
                    z: next.attitude.z * 1.01,
                },
                ..next
            },
            Error::OutOfRange(field(SampleField::QuaternionNorm)),
        ),
        (
            HoverSample {
                attitude: Quaternion {
                    w: 3e38,
                    ..next.attitude
                },
                ..next
            },
            Error::OutOfRange(field(SampleField::QuaternionNorm)),
        ),
    ];
    for (sample, expected) in cases {
        assert_eq!(id.step(&sample).map(|_| ()), Err(expected));
        assert_eq!(id.resume(&sample).map(|_| ()), Err(expected));
        assert_eq!(id.predict(&sample).map(|_| ()), Err(expected));
        assert!(id == before, "a refused sample changed the identifier");
    }
    let m = RotationMatrix::from_quaternion(&next.attitude);
    let mut sheared = m;
    sheared.rows[0][1] += 0.05;
    let mut nan = m;
    nan.rows[2][0] = f32::NAN;
    let mut huge = m;
    huge.rows[1][1] = -1e30;
    for (attitude, expected) in [
        (
            sheared,
            Error::OutOfRange(field(SampleField::MatrixOrthonormality)),
        ),
        (nan, Error::NonFinite(field(SampleField::Matrix(6)))),
        (huge, Error::OutOfRange(field(SampleField::Matrix(4)))),
    ] {
        let sample = next.with_attitude(attitude);
        assert_eq!(id.step(&sample).map(|_| ()), Err(expected));
        assert!(id == before, "a refused sample changed the identifier");
    }
    // The same sample with a good attitude is taken.
    assert!(id.step(&next).is_ok());
    assert!(id.step(&next.with_attitude(m)).is_err(), "same time stamp");
}

#[test]
fn any_attitude_gives_each_form_its_own_bits() {
    use rotorid::hover::AnyAttitude;
    let euler = golden::inputs(600, 11);
    let quat: Vec<_> = euler
        .iter()
        .map(|s| s.with_attitude(quaternion_f32(&s.attitude)))
        .collect();
    let any = |s: &[HoverSample<f32, AnyAttitude<f32>>]| predictions(s);
    let as_any = |a: AnyAttitude<f32>, s: &HoverSample<f32>| s.with_attitude(a);
    let mixed_euler: Vec<_> = euler.iter().map(|s| as_any(s.attitude.into(), s)).collect();
    let mixed_quat: Vec<_> = euler
        .iter()
        .zip(&quat)
        .map(|(s, q)| as_any(q.attitude.into(), s))
        .collect();
    let bits = |p: Vec<[f32; 6]>| -> Vec<[u32; 6]> {
        p.into_iter().map(|x| x.map(f32::to_bits)).collect()
    };
    assert_eq!(bits(any(&mixed_euler)), bits(predictions(&euler)));
    assert_eq!(bits(any(&mixed_quat)), bits(predictions(&quat)));
}
