//! Property tests of the core (proptest).
use host_tests::golden;
use proptest::prelude::*;
use rotorid::hover::SampleField;
use rotorid::hover::{HoverSample, SampleLimits};
use rotorid::membership::MembershipFunction;
use rotorid::rls::{Rls, RlsConfig};
use rotorid::rule_base::RuleBase;
use rotorid::{Error, HoverConfig, PaperFuzzyIdentifier, Quantity};

fn mf() -> impl Strategy<Value = MembershipFunction<f32>> {
    (0u8..3, -50.0f32..50.0, 0.001f32..20.0).prop_map(|(k, centre, spread)| match k {
        0 => MembershipFunction::Gaussian { centre, spread },
        1 => MembershipFunction::LeftShoulder { centre, spread },
        _ => MembershipFunction::RightShoulder { centre, spread },
    })
}

/// Cholesky of a symmetric matrix: true when positive definite.
fn positive_definite(p: &[Vec<f64>]) -> bool {
    let n = p.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                let d = p[i][i] - s;
                if d <= 0.0 || !d.is_finite() {
                    return false;
                }
                l[i][j] = d.sqrt();
            } else {
                l[i][j] = (p[i][j] - s) / l[j][j];
            }
        }
    }
    true
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn firing_strengths_sum_to_one(
        a in proptest::collection::vec(mf(), 3),
        b in proptest::collection::vec(mf(), 2),
        x in proptest::array::uniform2(-1e4f32..1e4),
    ) {
        let rb = RuleBase::<f32, 2, 6>::new([
            rotorid::hover::table3::sets(&a),
            rotorid::hover::table3::sets(&b),
        ]).unwrap();
        let xi = rb.firing_strengths(&x).unwrap();
        let sum: f32 = xi.iter().sum();
        prop_assert!((sum - 1.0).abs() <= 6.0 * f32::EPSILON, "sum {}", sum);
        prop_assert!(xi.iter().all(|w| (0.0..=1.0).contains(w)));
    }

    #[test]
    fn covariance_stays_symmetric_positive_definite(
        seed in any::<u64>(),
        alpha_exp in 0i32..7,
        lambda in prop_oneof![Just(1.0f64), 0.95f64..1.0],
    ) {
        // A long random run with sparse regressors (as TS regressors are).
        let mut g = seed | 1;
        let mut next = move || { g ^= g << 13; g ^= g >> 7; g ^= g << 17; (g >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0 };
        let alpha = 10f64.powi(alpha_exp);
        let mut cov = Rls::<f64, 8, 36>::new(RlsConfig::paper(alpha).with_forgetting(lambda, 1e6)).unwrap();
        let mut ud32 = Rls::<f32, 8, 36>::new(RlsConfig::robust(alpha as f32).with_forgetting(lambda as f32, 1e6)).unwrap();
        for _ in 0..1500 {
            let mut x = [0.0f64; 8];
            for v in x.iter_mut() {
                if next() > 0.2 { *v = next() * 10.0; }
            }
            let y = next();
            cov.update(&x, y).unwrap();
            ud32.update(&x.map(|v| v as f32), y as f32).unwrap();
        }
        let p: Vec<Vec<f64>> = cov.covariance_matrix().iter().map(|r| r.to_vec()).collect();
        prop_assert!(positive_definite(&p), "covariance form, f64");
        let p: Vec<Vec<f64>> = ud32.covariance_matrix().iter().map(|r| r.iter().map(|&v| f64::from(v)).collect()).collect();
        for (i, row) in p.iter().enumerate() {
            for (j, &x) in row.iter().enumerate() {
                prop_assert_eq!(x, p[j][i]);
            }
        }
        prop_assert!(positive_definite(&p), "U-D form, f32");
    }

    #[test]
    fn every_bad_input_is_rejected_and_changes_nothing(
        warmup in 2usize..60,
        field in 0usize..13,
        kind in 0u8..4,
        seed in any::<u64>(),
    ) {
        let inputs = golden::inputs(warmup + 1, seed);
        let mut id = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
        for s in &inputs[..warmup] { id.step(s).unwrap(); }
        let before = id.clone();
        let bad_value = match kind { 0 => f32::NAN, 1 => f32::INFINITY, 2 => f32::NEG_INFINITY, _ => 1e5 };
        let mut s: HoverSample<f32> = inputs[warmup];
        let (slot, q): (&mut f32, Quantity) = match field {
            0 => (&mut s.attitude.roll, Quantity::Sample(SampleField::Roll)),
            1 => (&mut s.attitude.pitch, Quantity::Sample(SampleField::Pitch)),
            2 => (&mut s.attitude.yaw, Quantity::Sample(SampleField::Yaw)),
            3..=5 => (&mut s.velocity[field - 3], Quantity::Sample(SampleField::Velocity((field - 3) as u8))),
            6..=8 => (&mut s.rates[field - 6], Quantity::Sample(SampleField::Rate((field - 6) as u8))),
            9 => (&mut s.controls.col, Quantity::Sample(SampleField::Control(0))),
            10 => (&mut s.controls.ped, Quantity::Sample(SampleField::Control(1))),
            11 => (&mut s.controls.lon, Quantity::Sample(SampleField::Control(2))),
            _ => (&mut s.controls.lat, Quantity::Sample(SampleField::Control(3))),
        };
        *slot = bad_value;
        let expected = if kind == 3 { Error::OutOfRange(q) } else { Error::NonFinite(q) };
        prop_assert_eq!(SampleLimits::check(&s), Err(expected));
        prop_assert_eq!(id.step(&s), Err(expected));
        prop_assert_eq!(id.predict(&s), Err(expected));
        prop_assert_eq!(id.resume(&s), Err(expected));
        prop_assert!(id == before);
    }

    #[test]
    fn export_then_import_continues_bit_for_bit(split in 2usize..150, seed in any::<u64>()) {
        let inputs = golden::inputs(200, seed);
        let mut a = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
        for s in &inputs[..split] { a.step(s).unwrap(); }
        let mut b = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
        b.import(&a.export()).unwrap();
        a.resume(&inputs[split]).unwrap();
        b.resume(&inputs[split]).unwrap();
        for s in &inputs[split + 1..] {
            let (x, y) = (a.step(s).unwrap(), b.step(s).unwrap());
            prop_assert_eq!(x.prediction.to_array().map(f32::to_bits), y.prediction.to_array().map(f32::to_bits));
            prop_assert_eq!(
                x.innovation.unwrap().to_array().map(f32::to_bits),
                y.innovation.unwrap().to_array().map(f32::to_bits)
            );
        }
        prop_assert!(a.export() == b.export());
    }
}
