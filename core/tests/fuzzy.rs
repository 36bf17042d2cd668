//! Membership functions and rule bases.
use rotorid::hover::table3;
use rotorid::membership::MembershipFunction::{Gaussian, LeftShoulder, RightShoulder};
use rotorid::rule_base::{PremiseSets, RuleBase};
use rotorid::{ConfigError, Error, Quantity};

#[test]
fn membership_functions_follow_table_1() {
    let g = Gaussian {
        centre: 1.0f64,
        spread: 2.0,
    };
    assert_eq!(g.degree(1.0), 1.0);
    assert!((g.degree(3.0) - (-0.5f64).exp()).abs() < 1e-15);
    assert!((g.degree(-1.0) - (-0.5f64).exp()).abs() < 1e-15);
    let l = LeftShoulder {
        centre: 0.0f64,
        spread: 1.0,
    };
    assert_eq!(l.degree(-100.0), 1.0);
    assert_eq!(l.degree(0.0), 1.0);
    assert!((l.degree(1.0) - (-0.5f64).exp()).abs() < 1e-15);
    let r = RightShoulder {
        centre: 0.0f64,
        spread: 1.0,
    };
    assert_eq!(r.degree(100.0), 1.0);
    assert!((r.degree(-1.0) - (-0.5f64).exp()).abs() < 1e-15);
    // Far away a narrow set underflows to exactly zero, never NaN.
    let narrow = Gaussian {
        centre: 0.0f32,
        spread: 0.01,
    };
    assert_eq!(narrow.degree(10.0), 0.0);
}

#[test]
fn table3_rule_counts_match_the_paper() {
    assert_eq!(table3::velocity::<f32>().unwrap().rules().count(), 27);
    assert_eq!(table3::pitch_rate::<f32>().unwrap().rules().count(), 18);
    assert_eq!(table3::yaw_rate::<f32>().unwrap().rules().count(), 9);
    assert_eq!(table3::roll_rate::<f32>().unwrap().rules().count(), 9);
}

#[test]
fn firing_strengths_are_normalised_and_in_rule_order() {
    let rb = table3::velocity::<f64>().unwrap();
    for x in [
        [0.0, 0.0, 0.0],
        [0.3, -2.0, 0.7],
        [5.0, 5.0, -5.0],
        [-0.49, 0.99, 1.2],
    ] {
        let xi = rb.firing_strengths(&x).unwrap();
        let sum: f64 = xi.iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
        assert!(xi.iter().all(|&w| (0.0..=1.0).contains(&w)));
    }
    // In f32 at v = 0 only rules built from centre sets of v_x and v_y fire (shoulders ±0.5,
    // ±1 with spreads 0.01, 0.03 underflow to exactly 0); v_z's three sets all fire. Centre =
    // set 1, so the rules are (1, 1, 0..3) = indices 12, 13, 14.
    let rb = table3::velocity::<f32>().unwrap();
    let xi = rb.firing_strengths(&[0.0, 0.0, 0.0]).unwrap();
    for (i, &w) in xi.iter().enumerate() {
        assert_eq!(w > 0.0, (12..15).contains(&i), "rule {i}: {w}");
    }
}

#[test]
fn all_rules_underflowing_is_defined_and_finite() {
    let sets: PremiseSets<f32> = table3::sets(&[
        Gaussian {
            centre: -1.0,
            spread: 0.001,
        },
        Gaussian {
            centre: 1.0,
            spread: 0.001,
        },
    ]);
    let rb = RuleBase::<f32, 1, 2>::new([sets]).unwrap();
    // Both degrees underflow at x = 0.5; the log-domain form gives the nearer set all weight.
    let xi = rb.firing_strengths(&[0.5]).unwrap();
    assert_eq!(xi, [0.0, 1.0]);
    // Exactly half way: equal weights.
    let xi = rb.firing_strengths(&[0.0]).unwrap();
    assert_eq!(xi, [0.5, 0.5]);
}

#[test]
fn invalid_sets_and_counts_are_refused() {
    let bad: PremiseSets<f32> = table3::sets(&[Gaussian {
        centre: 0.0,
        spread: 0.0,
    }]);
    assert_eq!(
        RuleBase::<f32, 1, 1>::new([bad]),
        Err(Error::Config(ConfigError::MembershipFunction {
            variable: 0,
            set: 0
        }))
    );
    let nan: PremiseSets<f32> = table3::sets(&[Gaussian {
        centre: f32::NAN,
        spread: 1.0,
    }]);
    assert!(RuleBase::<f32, 1, 1>::new([nan]).is_err());
    let three = table3::three_sets::<f32>((-1.0, 1.0), (0.0, 1.0), (1.0, 1.0));
    assert_eq!(
        RuleBase::<f32, 1, 4>::new([three.clone()]),
        Err(Error::Config(ConfigError::RuleCount {
            expected: 4,
            found: 3
        }))
    );
    let rb = RuleBase::<f32, 1, 3>::new([three]).unwrap();
    assert_eq!(
        rb.firing_strengths(&[f32::INFINITY]),
        Err(Error::NonFinite(Quantity::Premise(0)))
    );
}

#[test]
fn single_rule_base_is_the_plain_model() {
    let rb = RuleBase::<f64, 3, 1>::single_rule().unwrap();
    assert_eq!(rb.firing_strengths(&[1.0, -7.0, 1e6]).unwrap(), [1.0]);
}
