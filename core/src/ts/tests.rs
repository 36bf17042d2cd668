//! Unit tests of the TS estimator: shortcuts that must not change a bit.

extern crate std;
use std::vec::Vec;

use super::*;
use crate::hover::table3::sets;
use crate::membership::MembershipFunction::{Gaussian, LeftShoulder, RightShoulder};
use crate::rls::{Algorithm, Run};

/// 36 rules (4 premise variables of 3, 3, 2 and 2 sets), so that rules from 32 on are
/// covered; narrow shoulders, so that most rules fire only now and then.
type Model = TsRls<f32, 4, 36, 2, 72, 2628>;

fn model(config: RlsConfig<f32>) -> Model {
    let three = || {
        sets(&[
            LeftShoulder {
                centre: -1.0,
                spread: 0.02,
            },
            Gaussian {
                centre: 0.0,
                spread: 0.3,
            },
            RightShoulder {
                centre: 1.0,
                spread: 0.02,
            },
        ])
    };
    let two = || {
        sets(&[
            LeftShoulder {
                centre: -0.5,
                spread: 0.05,
            },
            RightShoulder {
                centre: 0.5,
                spread: 0.05,
            },
        ])
    };
    let rules = RuleBase::new([three(), three(), two(), two()]).unwrap();
    TsRls::new(rules, config).unwrap()
}

/// θ then the packed factor, as bits.
fn bits(state: &RlsState<f32, 72, 2628>) -> Vec<u32> {
    state
        .theta
        .iter()
        .chain(state.factor.iter())
        .map(|x| x.to_bits())
        .collect()
}

/// `TsRls::apply` visits only the fired rules' parameters; an estimator updated over all
/// of them with the same rows and innovations ends with the same bits (both RLS forms,
/// with and without forgetting, and across an export and import).
#[test]
fn updates_over_the_fired_rules_equal_updates_over_all_parameters() {
    for (algorithm, lambda) in [
        (Algorithm::UdFactor, 1.0),
        (Algorithm::Covariance, 1.0),
        (Algorithm::UdFactor, 0.98),
        (Algorithm::Covariance, 0.98),
    ] {
        let config = RlsConfig {
            algorithm,
            ..RlsConfig::paper(100.0)
        }
        .with_forgetting(lambda, 1e6);
        let mut ts = model(config);
        let mut dense = Rls::<f32, 72, 2628>::new(config).unwrap();
        let mut state = 0x2545_f491u32;
        let mut uniform = |lo: f32, hi: f32| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            lo + (hi - lo) * (state >> 8) as f32 / (1u32 << 24) as f32
        };
        for k in 0..400 {
            // Mostly near the centre sets; now and then out on the shoulders.
            let wide = if k % 7 == 0 { 3.0 } else { 0.6 };
            let premise = [0; 4].map(|_| uniform(-wide, wide));
            let mut terms = [uniform(-2.0, 2.0), uniform(-2.0, 2.0)];
            if k % 4 == 1 {
                terms[k % 2] = 0.0;
            }
            let target = uniform(-1.0, 1.0);
            let prepared = ts.prepare(&premise, &[terms], &[target]).unwrap();
            for (r, row) in prepared.rows.iter().take(prepared.count).enumerate() {
                let xi: [f32; 72] = regressor_of(&prepared.strengths, row);
                let e = if r == 0 {
                    prepared.first
                } else {
                    prepared.targets[r] - dense.dot(&xi)
                };
                let l = if r + 1 == prepared.count { lambda } else { 1.0 };
                dense.update_row(&xi, AllParameters(72), Measurement::row(e, l));
            }
            ts.apply(&prepared);
            let (a, b) = (bits(&ts.export()), bits(&dense.export()));
            let first = a.iter().zip(&b).position(|(x, y)| x != y);
            assert_eq!(
                first, None,
                "{algorithm:?} λ {lambda} step {k}: θ then P entry"
            );
            if k == 200 {
                // A warm start: the support comes from the imported factor's couplings.
                let mut fresh = model(config);
                fresh.import(&ts.export()).unwrap();
                assert_eq!(fresh.fired, ts.fired & fresh.fired);
                ts = fresh;
            }
        }
        assert!(
            ts.fired != 0 && ts.fired != u32::MAX,
            "some rules fired, not all"
        );
    }
}

/// The runs of fired rules, repeated in each term's block and merged where at most
/// RUN_GAP apart; rules from 32 on always count.
#[test]
fn support_lists_the_fired_rules_parameters() {
    let mut ts = model(RlsConfig::default());
    let mut runs = [Run { start: 0, end: 0 }; 72];
    let list = |ts: &Model, runs: &mut [Run; 72]| {
        let n = fired_runs(ts.fired, 36, 2, runs);
        runs[..n]
            .iter()
            .map(|r| (r.start, r.end))
            .collect::<Vec<_>>()
    };
    assert_eq!(list(&ts, &mut runs), [(32, 36), (68, 72)]);
    // Rules 0, 1, 3, 10 and 31 (plus 32..36): gaps of up to RUN_GAP are walked through.
    ts.fired = 0b1011 | 1 << 10 | 1 << 31;
    assert_eq!(
        list(&ts, &mut runs),
        [(0, 4), (10, 11), (31, 40), (46, 47), (67, 72)]
    );
    ts.fired = u32::MAX;
    assert_eq!(list(&ts, &mut runs), [(0, 72)]);
}
