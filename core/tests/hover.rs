//! The hover identifier, sweep and frame conversion.
use nalgebra::{Rotation3, Vector3};
use rotorid::frames::{self, NedFrdSample};
use rotorid::hover::rotor_axis;
use rotorid::hover::SampleField;
use rotorid::hover::{Attitude, BodyFrame, Controls, HoverSample};
use rotorid::sweep::{Channel, Sweep, SweepSchedule, C2_EXACT};
use rotorid::{Error, HoverConfig, PaperFuzzyIdentifier, PaperPlainIdentifier, Quantity};

fn sample(k: u64) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    HoverSample {
        time_us: 1_000_000 + k * 20_000,
        attitude: Attitude {
            roll: 0.05 * (0.7 * t).sin(),
            pitch: -0.03 + 0.04 * (1.3 * t).cos(),
            yaw: 0.2 * t,
        },
        velocity: [
            0.3 * (0.5 * t).sin(),
            0.1 * (0.9 * t).cos(),
            -0.4 * (0.4 * t).sin(),
        ],
        rates: [
            5.0 * (2.0 * t).sin(),
            8.0 * (1.1 * t).cos(),
            -3.0 * (1.7 * t).sin(),
        ],
        controls: Controls {
            col: 0.5 + 0.05 * (0.3 * t).sin(),
            ped: 0.1 * (2.3 * t).sin(),
            lon: 0.1 * (1.9 * t).cos(),
            lat: 0.08 * (2.9 * t).sin(),
        },
    }
}

#[test]
fn rotor_axis_is_the_paper_column_of_m_rnb_mt() {
    // M maps FRD/NED to the paper's axes: i = +y, j = −z, k = −x.
    let m = nalgebra::Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, -1.0, -1.0, 0.0, 0.0);
    for (roll, pitch, yaw) in [
        (0.1f64, 0.2f64, 0.3f64),
        (-0.7, 0.4, 2.5),
        (0.0, 0.0, -1.0),
        (1.2, -1.1, 3.0),
    ] {
        let r_nb = Rotation3::from_euler_angles(roll, pitch, yaw).into_inner();
        let expected = m * r_nb * m.transpose() * Vector3::new(0.0, 1.0, 0.0);
        let e = rotor_axis(roll, pitch, yaw);
        for i in 0..3 {
            assert!((e[i] - expected[i]).abs() < 1e-14, "{e:?} vs {expected:?}");
        }
    }
}

#[test]
fn frame_conversion_maps_axes_and_units() {
    let s = NedFrdSample {
        time_us: 5,
        attitude: Attitude {
            roll: 0.1,
            pitch: 0.2,
            yaw: 0.3,
        },
        velocity_ned: Vector3::new(1.0, 2.0, 3.0),
        rates_frd: Vector3::new(0.1, 0.2, 0.3),
        controls: Controls {
            col: 0.5,
            ped: 0.0,
            lon: 0.0,
            lat: 0.0,
        },
    };
    let p = s.to_paper();
    // v^s = [v_e, −v_d, −v_n]; [q r p] in deg/s with conventional signs.
    assert_eq!(p.velocity, [2.0, -3.0, -1.0]);
    let deg = 180.0 / std::f64::consts::PI;
    assert!((p.rates[0] - 0.2 * deg).abs() < 1e-12);
    assert!((p.rates[1] - 0.3 * deg).abs() < 1e-12);
    assert!((p.rates[2] - 0.1 * deg).abs() < 1e-12);
    let back = NedFrdSample::from_paper(&p);
    assert_eq!(back.velocity_ned, s.velocity_ned);
    assert!((back.rates_frd - s.rates_frd).norm() < 1e-15);
    // A nose-up pitch rate is +q in both conventions; a climb is +v_y.
    let (v, w) = frames::state_to_ned_frd(&p.state());
    assert_eq!(v, s.velocity_ned);
    assert!((w - s.rates_frd).norm() < 1e-15);
}

#[test]
fn sweep_frequency_follows_eq_32() {
    let mut s = Sweep::table2(Channel::Longitudinal, 0.2);
    assert_eq!(s.frequency(0.0), 1.0);
    // The paper's C2 ends 0.23 % of the band above ω_max (NOTES.md item 5).
    let end = s.frequency(s.duration_s);
    assert!((end - (1.0 + 1.0023 * 14.0)).abs() < 1e-3, "{end}");
    s.c2 = C2_EXACT;
    assert!((s.frequency(s.duration_s) - 15.0).abs() < 1e-12);
    // f'(t) = ν(t): central differences of the closed-form phase.
    for t in [0.5, 10.0, 30.0, 44.0] {
        let h = 1e-5;
        let d = (s.phase(t + h) - s.phase(t - h)) / (2.0 * h);
        assert!(
            (d - s.frequency(t)).abs() < 1e-6,
            "t = {t}: {d} vs {}",
            s.frequency(t)
        );
    }
    // Monotonic frequency, reduced amplitude at low frequency, zero in the trim pads.
    assert!(s.frequency(20.0) > s.frequency(10.0));
    assert!((s.amplitude_at(0.0) - 0.1).abs() < 1e-12);
    assert!((s.amplitude_at(s.duration_s) - 0.2).abs() < 1e-12);
    assert_eq!(s.offset(0.0), 0.0);
    assert_eq!(s.offset(2.99), 0.0);
    assert_eq!(s.offset(s.total_s() - 0.01), 0.0);
    assert!(s.offset(3.0 + 20.0).abs() > 0.0);
}

#[test]
fn table2_schedule_plays_the_four_sweeps_in_turn() {
    let sched = SweepSchedule::table2([0.1, 0.2, 0.15, 0.15], 50).unwrap();
    // (45 + 31 + 50 + 105) s of sweeps plus 4 × 6 s of trim, at 50 Hz.
    assert_eq!(sched.len(), (231 + 24) * 50);
    assert_eq!(sched.at(0).unwrap().channel, Channel::Longitudinal);
    assert_eq!(sched.at(51 * 50).unwrap().channel, Channel::Lateral);
    assert_eq!(
        sched.at(sched.len() - 1).unwrap().channel,
        Channel::Collective
    );
    assert!(sched.at(sched.len()).is_none());
    let peak = (0..sched.len())
        .map(|k| sched.at(k).unwrap().offset.abs())
        .fold(0.0, f64::max);
    assert!(peak <= 0.2 + 1e-12 && peak > 0.19, "{peak}");
    let mut bad = Sweep::table2(Channel::Pedal, 0.1);
    bad.omega_max = 1.0;
    assert!(SweepSchedule::new([bad], 50).is_err());
}

#[test]
fn identifier_learns_predicts_and_reports() {
    let mut id = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    let first = id.step(&sample(0)).unwrap();
    assert!(first.innovation.is_none());
    for k in 1..500 {
        let out = id.step(&sample(k)).unwrap();
        let inn = out.innovation.unwrap();
        assert!(inn
            .velocity
            .iter()
            .chain(inn.rates.iter())
            .all(|x| x.is_finite()));
        assert!(out.prediction.to_array().iter().all(|x| x.is_finite()));
    }
    // Eq. 27's v_x and v_z regressors are parallel and are learnt as one row: two rank-one
    // updates per sample.
    assert_eq!(id.velocity_model().ts().rls().counters().updates, 2 * 499);
    assert_eq!(id.pitch_model().ts().rls().counters().updates, 499);
}

#[test]
fn rejected_samples_leave_the_identifier_unchanged() {
    let mut id = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    for k in 0..50 {
        id.step(&sample(k)).unwrap();
    }
    let before = id.clone();
    let next = sample(50);
    let cases: Vec<(HoverSample<f32>, Error)> = vec![
        (
            {
                let mut s = next;
                s.attitude.roll = f32::NAN;
                s
            },
            Error::NonFinite(Quantity::Sample(SampleField::Roll)),
        ),
        (
            {
                let mut s = next;
                s.attitude.pitch = 2.0;
                s
            },
            Error::OutOfRange(Quantity::Sample(SampleField::Pitch)),
        ),
        (
            {
                let mut s = next;
                s.velocity[2] = f32::NEG_INFINITY;
                s
            },
            Error::NonFinite(Quantity::Sample(SampleField::Velocity(2))),
        ),
        (
            {
                let mut s = next;
                s.rates[1] = 5000.0;
                s
            },
            Error::OutOfRange(Quantity::Sample(SampleField::Rate(1))),
        ),
        (
            {
                let mut s = next;
                s.controls.lat = 1.5;
                s
            },
            Error::OutOfRange(Quantity::Sample(SampleField::Control(3))),
        ),
        (
            {
                let mut s = next;
                s.time_us -= 20_000;
                s
            },
            Error::NonMonotonicTime,
        ),
        (
            {
                let mut s = next;
                s.time_us += 40_000;
                s
            },
            Error::TimeStep {
                dt_us: 60_000,
                min_us: 10_000,
                max_us: 30_000,
            },
        ),
    ];
    for (s, e) in cases {
        assert_eq!(id.step(&s), Err(e));
        assert_eq!(id, before, "state changed after {e:?}");
    }
    // After a gap, resume restarts the chain without learning, then steps continue.
    let late = {
        let mut s = next;
        s.time_us += 1_000_000;
        s
    };
    id.resume(&late).unwrap();
    assert_eq!(
        id.velocity_model().ts().rls().counters().updates,
        before.velocity_model().ts().rls().counters().updates
    );
    let after = {
        let mut s = sample(51);
        s.time_us = late.time_us + 20_000;
        s
    };
    assert!(id.step(&after).unwrap().innovation.is_some());
}

#[test]
fn plain_and_fuzzy_share_one_api_and_warm_start_is_exact() {
    fn run<V, Q, R, P>(
        mut id: rotorid::HoverIdentifier<f32, V, Q, R, P>,
    ) -> (rotorid::HoverIdentifier<f32, V, Q, R, P>, Vec<u32>)
    where
        V: rotorid::hover::StateModel<f32>,
        Q: rotorid::hover::StateModel<f32>,
        R: rotorid::hover::StateModel<f32>,
        P: rotorid::hover::StateModel<f32>,
    {
        let mut bits = vec![];
        for k in 0..100 {
            let out = id.step(&sample(k)).unwrap();
            bits.extend(out.prediction.to_array().map(f32::to_bits));
        }
        (id, bits)
    }
    let (fuzzy, _) = run(PaperFuzzyIdentifier::paper_fuzzy(HoverConfig::paper()).unwrap());
    let (plain, _) = run(PaperPlainIdentifier::paper_plain(HoverConfig::paper()).unwrap());
    assert_ne!(
        fuzzy.predict(&sample(100)).unwrap(),
        plain.predict(&sample(100)).unwrap()
    );

    let mut warm = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).unwrap();
    warm.import(&fuzzy.export()).unwrap();
    let mut cont = fuzzy.clone();
    cont.resume(&sample(100)).unwrap();
    warm.resume(&sample(100)).unwrap();
    for k in 101..150 {
        let a = cont.step(&sample(k)).unwrap();
        let b = warm.step(&sample(k)).unwrap();
        assert_eq!(
            a.prediction.to_array().map(f32::to_bits),
            b.prediction.to_array().map(f32::to_bits)
        );
    }
}

#[test]
fn reconfigure_in_place_equals_a_fresh_identifier() {
    let mut id = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    for k in 0..30 {
        id.step(&sample(k)).unwrap();
    }
    id.reconfigure(HoverConfig::paper()).unwrap();
    assert_eq!(
        id,
        PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).unwrap()
    );
    let before = id.clone();
    let mut bad = HoverConfig::<f32>::paper();
    bad.rls.initial_covariance = -1.0;
    assert!(id.reconfigure(bad).is_err());
    assert_eq!(id, before);
}

#[test]
fn import_checks_every_model_before_writing_any() {
    let mut a = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    for k in 0..40 {
        a.step(&sample(k)).unwrap();
    }
    let mut b = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    let before = b.clone();
    let mut snap = a.export();
    snap.roll.theta[3] = f32::NAN; // the last model checked is bad
    assert_eq!(
        b.import(&snap),
        Err(Error::NonFinite(Quantity::Parameter(3)))
    );
    assert_eq!(b, before);
    // One model at a time, through the mutable accessors.
    use rotorid::hover::StateModel;
    b.velocity_model_mut().import(&a.export().velocity).unwrap();
    assert_eq!(b.export().velocity, a.export().velocity);
}

/// The body frame is computed with one `sincos` per angle and kept from the previous step:
/// both must give exactly what separate `sin`/`cos` and a fresh computation give.
#[test]
fn body_frame_matches_separate_sin_cos_bit_for_bit() {
    use rotorid::hover::{right_axis, BodyFrame};
    let angles = (-4000..=4000).map(|i| i as f32 * 1.0e-3 * core::f32::consts::PI);
    for a in angles {
        let (s, c) = (libm::sinf(a), libm::cosf(a));
        let b = (a * 0.37, a * -0.61);
        let f = BodyFrame::new(a, b.0, b.1);
        let want_up = [
            s * libm::cosf(b.1) - c * libm::sinf(b.0) * libm::sinf(b.1),
            c * libm::cosf(b.0),
            s * libm::sinf(b.1) + c * libm::sinf(b.0) * libm::cosf(b.1),
        ];
        let bits = |v: [f32; 3]| v.map(f32::to_bits);
        assert_eq!(bits(f.rotor_axis()), bits(want_up), "angle {a}");
        assert_eq!(bits(rotor_axis(a, b.0, b.1)), bits(want_up));
        assert_eq!(bits(f.right_axis()), bits(right_axis(a, b.0, b.1)));
    }
}

/// A step that uses the kept frame and the once-computed firing strengths predicts exactly
/// what `predict` computes from scratch.
#[test]
fn step_prediction_equals_fresh_predict() {
    let mut id = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    for k in 0..50 {
        let s = sample(k);
        let out = id.step(&s).unwrap();
        let fresh = id.predict(&s).unwrap();
        assert_eq!(out.prediction, fresh, "step {k}");
    }
    // end_chain: the next step only anchors.
    id.end_chain();
    assert!(id.previous_sample().is_none());
    assert!(id.step(&sample(50)).unwrap().innovation.is_none());
}

/// The chain keeps the last sample's time stamp as two 32-bit words: every bit of a `u64`
/// comes back, across the 2³² µs boundary (71.6 minutes of flight) and at the top of the range,
/// and the interval check sees the real interval there.
#[test]
fn the_kept_sample_is_the_sample_whatever_its_time_stamp() {
    let mut id = PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::default()).unwrap();
    for start in [0u64, (1 << 32) - 30_000, u64::MAX - 1_000_000] {
        id.end_chain();
        for k in 0..3 {
            let mut s = sample(k);
            s.time_us = start + k * 20_000;
            id.step(&s).unwrap();
            let framed = s.with_attitude(BodyFrame::of(&s.attitude));
            assert_eq!(
                id.previous_sample(),
                Some(framed),
                "start {start}, sample {k}"
            );
        }
        // 30 ms after the last one: refused (outside 20 ± 10 ms), and nothing changed.
        let mut late = sample(3);
        late.time_us = start + 2 * 20_000 + 30_001;
        let kept = id.clone();
        assert!(id.step(&late).is_err());
        assert_eq!(id, kept);
    }
}
