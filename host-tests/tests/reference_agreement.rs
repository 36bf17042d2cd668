//! The core against the independent f64 reference written straight from the paper.
//!
//! * core f64, paper (covariance) form: every prediction, innovation, θ and diag(P) within
//!   1e-9 relative of the reference over a long run;
//! * core f64, U-D form: within 1e-7 ([`UD_F64_BOUND`]): the same estimator computed through
//!   its factors, so its rounding differs from the covariance form's and the difference is
//!   amplified by the problem's conditioning (α = 10⁶ and rules that barely fire make it
//!   ill-conditioned; see issue 5's analysis);
//! * core f32 (U-D without scaling, i.e. the same estimator): predictions within the documented bound
//!   [`F32_PREDICTION_BOUND`] of the reference, relative to the state's scale.
use host_tests::golden;
use rotorid::hover::{HoverSample, StateModel};
use rotorid::{HoverConfig, HoverIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier, Real};
use rotorid_reference::{self as reference, ReferenceHover};

const STEPS: usize = 3000;
/// Relative agreement of the f64 core with the reference.
const F64_BOUND: f64 = 1e-9;
/// Agreement of the f64 U-D form with the (covariance-form) reference.
const UD_F64_BOUND: f64 = 1e-7;
/// Agreement of the f32 flight build's one-step predictions with the f64 reference, relative to
/// the largest magnitude of the state over the run (m/s for velocities, deg/s for rates). The
/// worst case falls in the first second, while the 126 parameters are still underdetermined
/// and α = 10⁶ amplifies rounding; later steps agree to about 1e-5.
const F32_PREDICTION_BOUND: f64 = 5e-4;

fn to_reference(s: &HoverSample<f32>) -> reference::HoverSample {
    let c = |x: f32| f64::from(x);
    reference::HoverSample {
        roll: c(s.attitude.roll),
        pitch: c(s.attitude.pitch),
        yaw: c(s.attitude.yaw),
        v: s.velocity.map(c),
        omega: s.rates.map(c),
        u: s.controls.to_array().map(c),
    }
}

/// |a − b| relative to max(|a|, |b|, floor).
fn rel(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(floor)
}

struct Worst {
    what: String,
    err: f64,
}

impl Worst {
    fn see(&mut self, what: impl FnOnce() -> String, err: f64) {
        if err > self.err || err.is_nan() {
            self.err = err;
            self.what = what();
        }
    }
}

/// Runs core and reference side by side; returns the worst relative differences of
/// (predictions and innovations, θ and diag P).
fn compare<T, V, Q, R, P>(mut id: HoverIdentifier<T, V, Q, R, P>, fuzzy: bool) -> (Worst, Worst)
where
    T: Real,
    V: StateModel<T> + golden::HasDiagnostics<T>,
    Q: StateModel<T> + golden::HasDiagnostics<T>,
    R: StateModel<T> + golden::HasDiagnostics<T>,
    P: StateModel<T> + golden::HasDiagnostics<T>,
{
    let inputs = golden::inputs(STEPS, 0x5eed_2024);
    // Each state's range over the run (m/s or deg/s): the scale its errors are measured on.
    let mut range = [0.0f64; 6];
    for s in &inputs {
        for (r, x) in range
            .iter_mut()
            .zip(golden::convert::<f64>(s).state().to_array())
        {
            *r = r.max(x.abs());
        }
    }
    let mut reference = ReferenceHover::new(1e6);
    let mut outputs = Worst {
        what: String::new(),
        err: 0.0,
    };
    let mut params = Worst {
        what: String::new(),
        err: 0.0,
    };
    for (k, s) in inputs.iter().enumerate() {
        let out = id.step(&golden::convert::<T>(s)).unwrap();
        let Some(step) = reference.push(to_reference(s)) else {
            continue;
        };
        let models = if fuzzy { &step.fuzzy } else { &step.plain };
        let pred: Vec<f64> = models.iter().flat_map(|m| m.predictions.clone()).collect();
        let inn: Vec<f64> = models.iter().flat_map(|m| m.innovations.clone()).collect();
        let core_pred = out.prediction.to_array().map(Real::to_f64);
        let core_inn = out.innovation.unwrap().to_array().map(Real::to_f64);
        for i in 0..6 {
            // Relative to the state's range: predictions and innovations pass through zero,
            // so their errors are measured on the scale of the signal they predict.
            outputs.see(
                || format!("step {k} prediction {i}: {} vs {}", core_pred[i], pred[i]),
                rel(core_pred[i], pred[i], range[i]),
            );
            outputs.see(
                || format!("step {k} innovation {i}: {} vs {}", core_inn[i], inn[i]),
                rel(core_inn[i], inn[i], range[i]),
            );
        }
        if k + 1 == STEPS {
            let core_theta = [
                id.velocity_model().theta(),
                id.pitch_model().theta(),
                id.yaw_model().theta(),
                id.roll_model().theta(),
            ];
            let core_diag = [
                id.velocity_model().diagonal(),
                id.pitch_model().diagonal(),
                id.yaw_model().diagonal(),
                id.roll_model().diagonal(),
            ];
            for (m, model) in models.iter().enumerate() {
                let n = model.theta.len();
                // θ: norm-wise, ‖θ_core − θ_ref‖∞ / ‖θ_ref‖∞ per model.
                let scale = model.theta.iter().fold(0.0f64, |a, t| a.max(t.abs()));
                for i in 0..n {
                    let (c, r) = (core_theta[m][i].to_f64(), model.theta[i]);
                    params.see(
                        || format!("step {k} model {m} θ[{i}]: {c} vs {r}"),
                        (c - r).abs() / scale.max(1e-300),
                    );
                    let (c, r) = (core_diag[m][i].to_f64(), model.p[i * n + i]);
                    params.see(
                        || format!("step {k} model {m} P[{i}][{i}]: {c} vs {r}"),
                        rel(c, r, 1e-12),
                    );
                }
            }
        }
    }
    (outputs, params)
}

#[test]
fn f64_paper_form_agrees_with_the_reference() {
    for fuzzy in [true, false] {
        let (o, p) = if fuzzy {
            compare(
                PaperFuzzyIdentifier::<f64>::paper_fuzzy(HoverConfig::paper()).unwrap(),
                true,
            )
        } else {
            compare(
                PaperPlainIdentifier::<f64>::paper_plain(HoverConfig::paper()).unwrap(),
                false,
            )
        };
        println!(
            "fuzzy={fuzzy} paper form: worst output {:.3e} ({}), worst parameter {:.3e} ({})",
            o.err, o.what, p.err, p.what
        );
        assert!(o.err <= F64_BOUND, "{}: {:e}", o.what, o.err);
        assert!(p.err <= F64_BOUND, "{}: {:e}", p.what, p.err);
    }
}

#[test]
fn f64_ud_form_agrees_with_the_reference() {
    let (o, p) = compare(
        PaperFuzzyIdentifier::<f64>::paper_fuzzy(HoverConfig::paper_robust()).unwrap(),
        true,
    );
    println!(
        "U-D f64: worst output {:.3e} ({}), worst parameter {:.3e} ({})",
        o.err, o.what, p.err, p.what
    );
    assert!(o.err <= UD_F64_BOUND, "{}: {:e}", o.what, o.err);
    assert!(p.err <= UD_F64_BOUND, "{}: {:e}", p.what, p.err);
}

#[test]
fn f32_flight_build_stays_within_its_documented_bound() {
    let (o, p) = compare(
        PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper_robust()).unwrap(),
        true,
    );
    println!(
        "U-D f32: worst output {:.3e} ({}), worst parameter {:.3e} ({})",
        o.err, o.what, p.err, p.what
    );
    assert!(o.err <= F32_PREDICTION_BOUND, "{}: {:e}", o.what, o.err);
}
