//! The extended structures, regressor scaling and the convergence indicator.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use crate::support::golden;

use rotorid::convergence::ConvergenceMonitor;
use rotorid::hover::{HoverSample, RegressorScaling, StateModel};
use rotorid::membership::MembershipFunction::{Gaussian, LeftShoulder, RightShoulder};
use rotorid::rls::RlsConfig;
use rotorid::rule_base::RuleBase;
use rotorid::ts::{Scaling, TsRls};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, FlightPlainIdentifier, HoverConfig,
    PaperFuzzyIdentifier,
};

fn config(scaling: RegressorScaling) -> HoverConfig<f64> {
    HoverConfig {
        scaling,
        ..HoverConfig::default()
    }
}

/// Replaces the prior of every model of the unscaled identifier by `P(0) = α/S_s²`: the scaled
/// model's prior `αI` on θ̃ = θ S_s/S_y with unit noise on ỹ = y/S_y is, in physical units, a
/// prior `α S_y²/S_s²` with noise variance `S_y²`, and RLS depends only on their ratio.
macro_rules! equivalent_prior {
    ($unscaled:expr, $scaled:expr, $(($model:ident, $accessor:ident)),+) => {{
        let mut snap = $unscaled.export();
        $(
            {
                let ts = $scaled.$accessor().ts();
                let sc = *ts.scaling();
                let r = ts.rules().rules().count();
                let n = snap.$model.theta.len();
                let alpha = ts.rls().config().initial_covariance;
                for j in 0..n {
                    let s = sc.terms[j / r];
                    snap.$model.factor[j * (j + 1) / 2 + j] = alpha / (s * s);
                }
            }
        )+
        snap
    }};
}

#[test]
fn scaling_changes_no_prediction_beyond_rounding() {
    let inputs: Vec<HoverSample<f64>> = golden::inputs(1500, 77)
        .iter()
        .map(golden::convert::<f64>)
        .collect();
    let mut scaled =
        ExtendedFuzzyIdentifier::<f64>::extended_fuzzy(config(RegressorScaling::Helicopter))
            .unwrap();
    let mut plain =
        ExtendedFuzzyIdentifier::<f64>::extended_fuzzy(config(RegressorScaling::None)).unwrap();
    let snap = equivalent_prior!(
        plain,
        scaled,
        (velocity, velocity_model),
        (pitch, pitch_model),
        (yaw, yaw_model),
        (roll, roll_model)
    );
    plain.import(&snap).unwrap();
    let mut range = [0.0f64; 6];
    for s in &inputs {
        for (r, x) in range.iter_mut().zip(s.state().to_array()) {
            *r = r.max(x.abs());
        }
    }
    let mut worst = 0.0f64;
    for s in &inputs {
        let a = scaled.step(s).unwrap().prediction.to_array();
        let b = plain.step(s).unwrap().prediction.to_array();
        for i in 0..6 {
            worst = worst.max((a[i] - b[i]).abs() / range[i]);
        }
    }
    assert!(worst < 1e-9, "worst relative difference {worst:e}");
    // Parameters in physical units agree too.
    let (sq, pq) = (scaled.pitch_model().ts(), plain.pitch_model().ts());
    for rule in 0..18 {
        for term in 0..5 {
            let (a, b) = (
                sq.physical_parameter(rule, term).unwrap(),
                pq.physical_parameter(rule, term).unwrap(),
            );
            assert!(
                (a - b).abs() <= 1e-6 * (1.0 + b.abs()),
                "rule {rule} term {term}: {a} vs {b}"
            );
        }
    }
}

/// A chain of samples that follows `truth` exactly: the next state is the truth's prediction.
fn generated_by<V, Q, R, P>(
    truth: &rotorid::HoverIdentifier<f64, V, Q, R, P>,
    n: usize,
    seed: u64,
) -> Vec<HoverSample<f64>>
where
    V: StateModel<f64>,
    Q: StateModel<f64>,
    R: StateModel<f64>,
    P: StateModel<f64>,
{
    let drive: Vec<HoverSample<f64>> = golden::inputs(n, seed)
        .iter()
        .map(golden::convert::<f64>)
        .collect();
    let mut out = Vec::with_capacity(n);
    let mut s = drive[0];
    for d in &drive[1..] {
        out.push(s);
        let next = truth.predict(&s).unwrap();
        s = HoverSample {
            time_us: d.time_us,
            attitude: d.attitude,
            controls: d.controls,
            velocity: next.velocity,
            rates: next.rates,
        };
    }
    out
}

#[test]
fn extended_structures_recover_the_parameters_that_generated_their_data() {
    // Truth: physical damping −0.1 per step on every rate, −0.05 on every velocity, control
    // gains, collective torque, small couplings, trims and side force; the same value for
    // every rule.
    fn truth_state<const N: usize, const NP: usize>(
        mut st: rotorid::rls::RlsState<f64, N, NP>,
        per_term: &[f64],
    ) -> rotorid::rls::RlsState<f64, N, NP> {
        let r = N / per_term.len();
        for (j, t) in st.theta.iter_mut().enumerate() {
            *t = per_term[j / r];
        }
        st
    }
    // Scaled coordinates (θ̃ = α S_s/S_y): rates S = [100, 0.05, 10, 0.5, 1], S_y = 1;
    // velocity S = [0.5, 1, 1, 1, 1, 1, 0.3], S_y = 0.05.
    let rate = [0.001 * 100.0, 8.0 * 0.05, -0.1 * 10.0, 0.5 * 0.5, 0.05];
    let vel = [
        0.3 * 0.5 / 0.05,
        -0.15 / 0.05,
        -0.05 / 0.05,
        -0.05 / 0.05,
        -0.05 / 0.05,
        0.01 / 0.05,
        0.02 * 0.3 / 0.05,
    ];

    let cfg = config(RegressorScaling::Helicopter);
    let mut plain_truth = ExtendedPlainIdentifier::<f64>::extended_plain(cfg).unwrap();
    let mut snap = plain_truth.export();
    snap.velocity = truth_state(snap.velocity, &vel);
    snap.pitch = truth_state(snap.pitch, &rate);
    snap.yaw = truth_state(snap.yaw, &rate);
    snap.roll = truth_state(snap.roll, &rate);
    plain_truth.import(&snap).unwrap();
    let data = generated_by(&plain_truth, 3000, 5);
    let mut learner = ExtendedPlainIdentifier::<f64>::extended_plain(cfg).unwrap();
    for s in &data {
        learner.step(s).unwrap();
    }
    let got = learner.export();
    for (a, b) in got
        .pitch
        .theta
        .iter()
        .chain(got.velocity.theta.iter())
        .zip(snap.pitch.theta.iter().chain(snap.velocity.theta.iter()))
    {
        assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "{a} vs {b}");
    }

    let mut fuzzy_truth = ExtendedFuzzyIdentifier::<f64>::extended_fuzzy(cfg).unwrap();
    let mut snap = fuzzy_truth.export();
    snap.velocity = truth_state(snap.velocity, &vel);
    snap.pitch = truth_state(snap.pitch, &rate);
    snap.yaw = truth_state(snap.yaw, &rate);
    snap.roll = truth_state(snap.roll, &rate);
    fuzzy_truth.import(&snap).unwrap();
    let data = generated_by(&fuzzy_truth, 4000, 6);
    let mut learner = ExtendedFuzzyIdentifier::<f64>::extended_fuzzy(cfg).unwrap();
    for s in &data {
        learner.step(s).unwrap();
    }
    // Every parameter the data determined (posterior variance below 1e-5 of the prior α = 1e6)
    // matches the truth; rules that Table 3's narrow shoulders never fire stay at the prior.
    let mut checked = 0;
    for (model_theta, truth_theta, diag) in [
        (
            learner.pitch_model().ts().rls().parameters().to_vec(),
            snap.pitch.theta.to_vec(),
            learner
                .pitch_model()
                .ts()
                .rls()
                .covariance_diagonal()
                .to_vec(),
        ),
        (
            learner.yaw_model().ts().rls().parameters().to_vec(),
            snap.yaw.theta.to_vec(),
            learner
                .yaw_model()
                .ts()
                .rls()
                .covariance_diagonal()
                .to_vec(),
        ),
        (
            learner.roll_model().ts().rls().parameters().to_vec(),
            snap.roll.theta.to_vec(),
            learner
                .roll_model()
                .ts()
                .rls()
                .covariance_diagonal()
                .to_vec(),
        ),
        (
            learner.velocity_model().ts().rls().parameters().to_vec(),
            snap.velocity.theta.to_vec(),
            learner
                .velocity_model()
                .ts()
                .rls()
                .covariance_diagonal()
                .to_vec(),
        ),
    ] {
        for ((a, b), p) in model_theta.iter().zip(truth_theta.iter()).zip(diag.iter()) {
            if *p < 10.0 {
                checked += 1;
                assert!(
                    (a - b).abs() < 1e-4 * (1.0 + b.abs()),
                    "{a} vs {b} (P_ii {p:e})"
                );
            }
        }
    }
    assert!(checked >= 150, "only {checked} parameters were determined");
}

#[test]
fn convergence_indicator_is_identical_in_other_units() {
    // One TS model fed the same data in two unit systems: (a) as given, (b) every premise,
    // term, target and scale multiplied by a unit factor c. With c a power of two every
    // number inside is the same and the indicator is bit-identical; with c = π/180 (deg → rad)
    // it agrees to rounding.
    fn run(c: f64) -> Vec<[f64; 3]> {
        let sets = |k: f64| {
            rotorid::hover::table3::sets(&[
                LeftShoulder {
                    centre: -10.0 * k,
                    spread: 5.0 * k,
                },
                Gaussian {
                    centre: 0.0,
                    spread: 8.0 * k,
                },
                RightShoulder {
                    centre: 10.0 * k,
                    spread: 5.0 * k,
                },
            ])
        };
        let rules = RuleBase::<f64, 1, 3>::new([sets(c)]).unwrap();
        let scaling = Scaling {
            terms: [100.0 * c * c, 0.05],
            target: c,
        };
        let mut m =
            TsRls::<f64, 1, 3, 2, 6, 21>::with_scaling(rules, RlsConfig::robust(1e6), scaling)
                .unwrap();
        let mut mon = ConvergenceMonitor::<f64, 1>::new(100, 0.05, 3).unwrap();
        let mut out = vec![];
        let inputs = golden::inputs(2000, 3);
        for s in inputs.windows(2) {
            let (a, b) = (golden::convert::<f64>(&s[0]), golden::convert::<f64>(&s[1]));
            let [q, r, p] = a.rates.map(|x| x * c);
            let terms = [r * p, a.controls.lon * a.controls.col];
            // A plant the model can describe: the increment follows its structure plus noise.
            let target = 0.002 * terms[0] / c + 3.0 * c * terms[1] - 0.05 * q
                + c * 0.01 * (b.rates[2] - a.rates[2]);
            let [e] = m.update(&[q], &[terms], &[target]).unwrap();
            if let Some(st) = mon.observe(&[e], &[target]).unwrap() {
                out.push([
                    st.ratio[0],
                    st.change[0],
                    f64::from(u8::from(st.converged[0])),
                ]);
            }
        }
        out
    }
    let base = run(1.0);
    assert_eq!(base.len(), 19);
    let quad = run(4.0);
    for (a, b) in base.iter().zip(&quad) {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{a:?} vs {b:?}");
    }
    let rad = run(std::f64::consts::PI / 180.0);
    for (a, b) in base.iter().zip(&rad) {
        assert!(
            (a[0] - b[0]).abs() <= 1e-9 * a[0].abs().max(1e-12),
            "{a:?} vs {b:?}"
        );
        assert_eq!(a[2], b[2]);
    }
    // The model learns: ρ falls well below 1 and settles.
    assert!(base.last().unwrap()[0] < 0.5, "{base:?}");
}

#[test]
fn paper_defaults_are_unscaled_and_flight_defaults_are_scaled() {
    let p = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).unwrap();
    assert_eq!(p.pitch_model().ts().scaling(), &Scaling::unit());
    let d = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    assert_eq!(d.pitch_model().ts().scaling().terms, [100.0, 0.05]);
}

#[test]
fn flight_drag_is_learnt_without_the_bias_of_noisy_velocities() {
    // Truth: extended plain with the same small drag on both horizontal axes (−0.004 per
    // step, −0.2/s), so that its drag along and across any heading is that too.
    let (drag, sigma) = (-0.004, 0.1);
    let rate = [0.001 * 100.0, 8.0 * 0.05, -0.1 * 10.0, 0.5 * 0.5, 0.05];
    let vel = [
        0.3 * 0.5 / 0.05,
        -0.15 / 0.05,
        drag / 0.05,
        -0.05 / 0.05,
        drag / 0.05,
        0.01 / 0.05,
        0.02 * 0.3 / 0.05,
    ];
    let cfg = config(RegressorScaling::Helicopter);
    let mut truth = ExtendedPlainIdentifier::<f64>::extended_plain(cfg).unwrap();
    let mut snap = truth.export();
    snap.velocity.theta = vel;
    for model in [&mut snap.pitch, &mut snap.yaw, &mut snap.roll] {
        model.theta = rate;
    }
    truth.import(&snap).unwrap();
    let clean = generated_by(&truth, 6000, 7);
    // The same flight measured with white velocity noise of σ = 0.1 m/s (a 64-bit LCG's top
    // bits, uniform with that standard deviation), on the horizontal axes only or on all three.
    let measured = |axes: &[usize]| {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut noise = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * sigma * 12f64.sqrt()
        };
        clean
            .iter()
            .map(|s| {
                let mut m = *s;
                for (i, v) in m.velocity.iter_mut().enumerate() {
                    let n = noise();
                    if axes.contains(&i) {
                        *v += n;
                    }
                }
                m
            })
            .collect::<Vec<HoverSample<f64>>>()
    };
    // Horizontal drag per step: extended plain's d_x, d_z (terms 2, 4) and the flight
    // structure's d_f, d_r (terms 2, 3).
    let learnt = |data: &[HoverSample<f64>]| {
        let mut extended = ExtendedPlainIdentifier::<f64>::extended_plain(cfg).unwrap();
        let mut flight = FlightPlainIdentifier::<f64>::flight_plain(cfg).unwrap();
        for s in data {
            extended.step(s).unwrap();
            flight.step(s).unwrap();
        }
        let e = extended.velocity_model().ts();
        let f = flight.velocity_model().ts();
        [
            e.physical_parameter(0, 2).unwrap(),
            e.physical_parameter(0, 4).unwrap(),
            f.physical_parameter(0, 2).unwrap(),
            f.physical_parameter(0, 3).unwrap(),
        ]
    };
    // Without noise both find the drag (the flight structure's on v(k−1) within a few per
    // cent: the truth's is on v(k)).
    for d in learnt(&clean) {
        assert!(
            (d - drag).abs() < 0.05 * drag.abs(),
            "noise-free: {d} vs {drag}"
        );
    }
    // Horizontal noise: a fit on v(k) learns more drag than there is (errors in variables),
    // the fit on v(k−1) does not.
    let [ex, ez, ff, fr] = learnt(&measured(&[0, 2]));
    for d in [ex, ez] {
        assert!(d < 1.3 * drag, "extended plain: {d} vs {drag}");
    }
    for d in [ff, fr] {
        assert!((d - drag).abs() < 0.1 * drag.abs(), "flight: {d} vs {drag}");
    }
    // Noise on v_y too: the heave damping is fitted on v_y(k) and takes the bias, and some of
    // it reaches the horizontal drag through the parameters the three outputs share; still
    // well under half of extended plain's error.
    let [ex, ez, ff, fr] = learnt(&measured(&[0, 1, 2]));
    let extended_error = (ex - drag).abs() + (ez - drag).abs();
    let flight_error = (ff - drag).abs() + (fr - drag).abs();
    assert!(
        flight_error < 0.4 * extended_error,
        "flight {ff} {fr}, extended plain {ex} {ez}, truth {drag}"
    );
}
