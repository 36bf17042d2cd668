//! The flight default's evidence in docs/results.md: every variant against the extended plain
//! model on the hover and the envelope flights, and the local derivatives the flight
//! identifier's rules learnt in each speed region beside the plant's own.

use std::ops::Range;
use std::path::Path;

use rotorid::hover::{RateAxis, RateStructure, VelocityStructure};

use crate::error::ReportError;
use rotorid_cli::experiments::{ModelParameters, VariantResult};
use rotorid_cli::report::Metrics;
use rotorid_sim::plant::{derivative, trim_hover, Airframe, Helicopter, PlantError, State};

/// The variant every other is measured against.
pub const BASELINE: &str = "extended plain";
/// The variant a user should fly.
pub const FLIGHT: &str = "flight";
/// Hover: the flight default may be at most this much worse than [`BASELINE`] (ratio).
pub const HOVER_TOLERANCE: f64 = 1.03;
/// Envelope: the flight default's free-run error at most this fraction of [`BASELINE`]'s.
pub const ENVELOPE_TARGET: f64 = 0.7;

pub(crate) fn mark(ok: bool) -> &'static str {
    if ok {
        "✅"
    } else {
        "❌"
    }
}

/// Each distinct key once, in the order first seen (the tables of a report keep the order of
/// its rows).
pub(crate) fn first_seen<'a>(keys: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut seen: Vec<&str> = Vec::new();
    for k in keys {
        if !seen.contains(&k) {
            seen.push(k);
        }
    }
    seen
}

/// The largest ratio `a[i] / b[i]` over the six states, with the state's label.
pub(crate) fn worst_ratio(a: &[f64; 6], b: &[f64; 6]) -> (f64, &'static str) {
    const LABELS: [&str; 6] = ["v_x", "v_y", "v_z", "q", "r", "p"];
    (0..6)
        .map(|i| (a[i] / b[i], LABELS[i]))
        .fold((0.0f64, ""), |acc, x| if x.0 > acc.0 { x } else { acc })
}

fn ratios(m: &Metrics, pick: impl Fn(&VariantResult) -> [f64; 6]) -> String {
    let Some(base) = m.variants.iter().find(|v| v.name == BASELINE) else {
        return format!("(no `{BASELINE}` variant in the metrics)\n");
    };
    let b = pick(base);
    let mut s = String::from(
        "| variant | v_x | v_y | v_z | q | r | p |\n|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for v in &m.variants {
        let x = pick(v);
        let cells: Vec<String> = (0..6).map(|i| format!("{:.2}", x[i] / b[i])).collect();
        s += &format!("| {} | {} |\n", v.name, cells.join(" | "));
    }
    s
}

/// Every variant against [`BASELINE`] on the hover pair flown with noisier sensors (free run
/// and one step), and the flight default's worst hover ratio against [`HOVER_TOLERANCE`].
pub fn noisy_markdown(noisy: &Metrics) -> String {
    let mut s = String::new();
    let find = |n: &str| noisy.variants.iter().find(|v| v.name == n);
    if let (Some(f), Some(b)) = (find(FLIGHT), find(BASELINE)) {
        let (w2, l2) = worst_ratio(&f.free_run, &b.free_run);
        s += &one_step_lines("Flight default, hover", f, b);
        s += &format!(
            "* Flight default, hover free run: worst ratio {w2:.3} ({l2}) {}\n\n",
            mark(w2 <= HOVER_TOLERANCE)
        );
    }
    s += &format!(
        "Free run {} s, ratio to extended plain:\n\n",
        noisy.window_s
    );
    s += &ratios(noisy, |v| v.free_run);
    s += "\nOne step through each variant's observer (θ frozen), ratio to extended plain:\n\n";
    s += &ratios(noisy, |v| v.one_step_observed);
    s += "\nOne step from the measured state (θ frozen, Table 4's), ratio to extended plain:\n\n";
    s += &ratios(noisy, |v| v.one_step);
    s
}

/// The criteria lines on the one step of `f` against `b`: through each one's observer (the
/// criterion) and from the measured state (Table 4's predictor, beside it).
fn one_step_lines(what: &str, f: &VariantResult, b: &VariantResult) -> String {
    let (w, l) = worst_ratio(&f.one_step_observed, &b.one_step_observed);
    let (m, lm) = worst_ratio(&f.one_step, &b.one_step);
    format!(
        "* {what} one step, each through its observer: worst ratio {w:.3} ({l}) {} (at most \
         {HOVER_TOLERANCE} on every state)\n\
         * {what} one step from the measured state (Table 4's predictor, least-squares \
         parameters): worst ratio {m:.3} ({lm}){}\n",
        mark(w <= HOVER_TOLERANCE),
        if m <= HOVER_TOLERANCE {
            ""
        } else {
            ", above the tolerance"
        }
    )
}

/// One more run of a pair of flights for the section "What limits the flight default"
/// (`rotorid report --condition`): the table it goes in, its row, its metrics and the
/// parameters the flight default exported in that run.
pub struct Condition {
    /// The table's title (rows of one group share a table, in the order given).
    pub group: String,
    /// The row's label.
    pub label: String,
    /// The run's metrics.json.
    pub metrics: Metrics,
    /// The run's params-flight.json.
    pub params: Vec<ModelParameters>,
    /// The run's params-flight-compensated.json, if its free run was compensated for the
    /// gyro noise.
    pub compensated_params: Option<Vec<ModelParameters>>,
    /// The run's params-extended-plain.json.
    pub baseline_params: Vec<ModelParameters>,
}

/// The drag that a velocity model's first rule learnt, from its exported parameters (scaled
/// θ, `structure`'s helicopter scaling), in 1/s (negative is drag): `[d_f/ΔT, d_r/ΔT,
/// d_u/ΔT]` along and across the heading and up for [`VelocityStructure::Flight`] (the flight
/// default's hover rule), the horizontal `[d_x/ΔT, d_z/ΔT]` (east, south) for
/// [`VelocityStructure::Extended`].
fn drag(
    params: &[ModelParameters],
    structure: VelocityStructure,
    period_s: f64,
) -> Option<Vec<f64>> {
    let scaling = structure.helicopter_scaling::<f64, 7>();
    let theta = params
        .iter()
        .find(|p| p.model == "velocity")?
        .theta
        .get(..7)?;
    let physical =
        |slot: usize| f64::from(theta[slot]) * scaling.target / scaling.terms[slot] / period_s;
    let slots: &[usize] = match structure {
        VelocityStructure::Extended => &[2, 4],
        _ => &[2, 3, 4],
    };
    Some(slots.iter().map(|&slot| physical(slot)).collect())
}

/// The speed stability `M_u` that the flight default's q model learnt in its first (hover)
/// rule, from its exported parameters (`κ`, [`RateStructure::Flight`]'s sixth term), in
/// (deg/s²)/(m/s): positive pitches the nose up with forward speed, as a rotor that flaps
/// back does.
fn speed_stability(params: &[ModelParameters], period_s: f64) -> Option<f64> {
    let scaling = RateStructure::Flight.helicopter_scaling::<f64, 7>(RateAxis::Pitch);
    let theta = params.iter().find(|p| p.model == "q")?.theta.get(..7)?;
    Some(f64::from(theta[5]) * scaling.target / scaling.terms[5] / period_s)
}

/// One table per group of [`Condition`]s: the flight default's free-run error ratio to
/// [`BASELINE`] per state, its worst one-step ratio, the drag both learnt ([`drag`]) and the
/// flight default's hover speed stability ([`speed_stability`]).
pub fn conditions_markdown(conditions: &[Condition]) -> String {
    let mut s = String::new();
    for group in first_seen(conditions.iter().map(|c| c.group.as_str())) {
        s += &format!(
            "#### {group}\n\n| run | v_x | v_y | v_z | q | r | p | one step, worst: observer; measured state | flight: d_f, d_r, d_u (1/s) | extended plain: d_x, d_z (1/s) | flight: M_u ((deg/s²)/(m/s); learnt → compensated) |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
        );
        for c in conditions.iter().filter(|c| c.group == group) {
            let find = |n: &str| c.metrics.variants.iter().find(|v| v.name == n);
            let (Some(f), Some(b)) = (find(FLIGHT), find(BASELINE)) else {
                s += &format!("| {} | (flight or baseline variant missing) |\n", c.label);
                continue;
            };
            // A state that did not run free (`--free-run-velocity measured`) has no ratio.
            let cells: Vec<String> = (0..6)
                .map(|i| match b.free_run[i] {
                    e if e > 0.0 => format!("{:.2}", f.free_run[i] / e),
                    _ => "–".to_string(),
                })
                .collect();
            let (observed, observed_state) =
                worst_ratio(&f.one_step_observed, &b.one_step_observed);
            let (measured, measured_state) = worst_ratio(&f.one_step, &b.one_step);
            let cell = |params: &[ModelParameters], structure| {
                drag(params, structure, 0.02).map_or_else(
                    || "–".to_string(),
                    |d| {
                        d.iter()
                            .map(|x| format!("{x:.2}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    },
                )
            };
            let flight = cell(&c.params, VelocityStructure::Flight);
            let base = cell(&c.baseline_params, VelocityStructure::Extended);
            let m_u = |params: &[ModelParameters]| {
                speed_stability(params, 0.02).map_or_else(|| "–".into(), |m| format!("{m:.1}"))
            };
            let m_u = match &c.compensated_params {
                Some(compensated) => format!("{} → {}", m_u(&c.params), m_u(compensated)),
                None => m_u(&c.params),
            };
            s += &format!(
                "| {} | {} | {observed:.2} ({observed_state}); {measured:.2} ({measured_state}) | {flight} | {base} | {m_u} |\n",
                c.label,
                cells.join(" | ")
            );
        }
        s += "\n";
    }
    s
}

/// The flight default's and the baseline's results: hover flight, hover baseline, envelope
/// flight, envelope baseline.
fn flight_and_baseline(hover: &Metrics, envelope: &Metrics) -> Option<[VariantResult; 4]> {
    Some([
        variant(hover, FLIGHT)?,
        variant(hover, BASELINE)?,
        variant(envelope, FLIGHT)?,
        variant(envelope, BASELINE)?,
    ])
}

/// The results of the variant called `name`, if it was run.
fn variant(m: &Metrics, name: &str) -> Option<VariantResult> {
    m.variants.iter().find(|v| v.name == name).cloned()
}

/// `v`'s free-run error as ratios to `b`'s on `states` (indices into `[v_x v_y v_z q r p]`),
/// e.g. "0.30, 0.60, 0.59".
fn free_run_ratios(v: &VariantResult, b: &VariantResult, states: Range<usize>) -> String {
    let r: Vec<String> = states
        .map(|i| format!("{:.2}", v.free_run[i] / b.free_run[i]))
        .collect();
    r.join(", ")
}

/// The criteria of the flight default, checked on the metrics.
fn criteria(hover: &Metrics, envelope: &Metrics) -> String {
    let Some([hf, hb, ef, eb]) = flight_and_baseline(hover, envelope) else {
        return "(flight or baseline variant missing)\n".into();
    };
    let mut s = String::new();
    let (w2, l2) = worst_ratio(&hf.free_run, &hb.free_run);
    s += &one_step_lines("Hover,", &hf, &hb);
    s += &format!(
        "* Hover, free run: worst ratio {w2:.3} ({l2}) {}\n",
        mark(w2 <= HOVER_TOLERANCE)
    );
    s += &first_order_rates(hover, envelope, [&hf, &hb, &ef, &eb]);
    s += &proportional_thrust(hover, envelope, [&hf, &hb, &ef, &eb]);
    let r: Vec<f64> = (0..6).map(|i| ef.free_run[i] / eb.free_run[i]).collect();
    let rates_ok = r[3..].iter().all(|&x| x <= ENVELOPE_TARGET);
    let velocities = r[..3].iter().filter(|&&x| x <= ENVELOPE_TARGET).count();
    s += &format!(
        "* Envelope, free run on q, r, p: {:.2}, {:.2}, {:.2} {} (each at most {ENVELOPE_TARGET})\n",
        r[3],
        r[4],
        r[5],
        mark(rates_ok)
    );
    s += &format!(
        "* Envelope, free run on v_x, v_y, v_z: {:.2}, {:.2}, {:.2}: {velocities} of 3 at most {ENVELOPE_TARGET} {} (at least 2)\n",
        r[0],
        r[1],
        r[2],
        mark(velocities >= 2)
    );
    s
}

/// The variant whose rate models learn without their second-order term.
pub(crate) const FIRST_ORDER_RATES: &str = "flight first-order rates";

/// A criteria line on [`FIRST_ORDER_RATES`]: its worst hover one-step ratio and its free-run
/// ratios on the rates, beside the flight default's (empty without that variant).
fn first_order_rates(
    hover: &Metrics,
    envelope: &Metrics,
    [hf, hb, ef, eb]: [&VariantResult; 4],
) -> String {
    let (Some(h1), Some(e1)) = (
        variant(hover, FIRST_ORDER_RATES),
        variant(envelope, FIRST_ORDER_RATES),
    ) else {
        return String::new();
    };
    let rates = |v: &VariantResult, b: &VariantResult| free_run_ratios(v, b, 3..6);
    let (w, l) = worst_ratio(&h1.one_step, &hb.one_step);
    let (o, lo) = worst_ratio(&h1.one_step_observed, &hb.one_step_observed);
    format!(
        "* Without the rate models' second-order term (`{FIRST_ORDER_RATES}`): hover one step, \
         worst ratio {o:.3} ({lo}) through the observer and {w:.3} ({l}) from the measured \
         state; free run on q, r, p {} in hover and {} on the envelope (the flight default: {} \
         and {})\n",
        rates(&h1, hb),
        rates(&e1, eb),
        rates(hf, hb),
        rates(ef, eb),
    )
}

/// The variant whose translational model's thrust is proportional to the collective.
pub(crate) const PROPORTIONAL_THRUST: &str = "flight proportional thrust";

/// A criteria line on [`PROPORTIONAL_THRUST`]: its free-run ratios on every state in hover and
/// on the envelope, beside the flight default's (empty without that variant).
fn proportional_thrust(
    hover: &Metrics,
    envelope: &Metrics,
    [hf, hb, ef, eb]: [&VariantResult; 4],
) -> String {
    let (Some(h1), Some(e1)) = (
        variant(hover, PROPORTIONAL_THRUST),
        variant(envelope, PROPORTIONAL_THRUST),
    ) else {
        return String::new();
    };
    let all = |v: &VariantResult, b: &VariantResult| free_run_ratios(v, b, 0..6);
    format!(
        "* With the thrust proportional to the collective (`{PROPORTIONAL_THRUST}`, no `α0`): \
         free run on v_x, v_y, v_z, q, r, p {} in hover and {} on the envelope (the flight \
         default: {} and {})\n",
        all(&h1, hb),
        all(&e1, eb),
        all(hf, hb),
        all(ef, eb),
    )
}

/// Rate derivatives of the plant at the hover trim state flown at `forward` m/s (body x):
/// `[∂ω̇/∂ω (1/s), ∂ω̇/∂(speed) (deg/s² per m/s)]` for q, r, p, with the speed of each rate
/// model's κ term (forward for q, rightward for r and p). Central differences, flapping held.
fn plant_derivatives(params: &Helicopter, forward: f64) -> Result<[[f64; 2]; 3], PlantError> {
    let trim = trim_hover(params, 0.0)?;
    let pitch = params.blade_pitch(&trim.sticks);
    let mut at = trim.state;
    at.vel_body.x = forward;
    let eval = |s: &State, axis: usize| {
        derivative(params, s, &pitch, &nalgebra::Vector3::zeros())
            .0
            .omega[axis]
    };
    let h = 1e-3;
    // ω = [p, q, r] (FRD); the models are q, r, p.
    let axes = [1usize, 2, 0];
    let mut out = [[0.0; 2]; 3];
    for (o, &axis) in out.iter_mut().zip(axes.iter()) {
        let diff = |f: &dyn Fn(&mut State, f64)| {
            let (mut a, mut b) = (at, at);
            f(&mut a, h);
            f(&mut b, -h);
            (eval(&a, axis) - eval(&b, axis)) / (2.0 * h)
        };
        let damping = diff(&|s, d| s.omega[axis] += d);
        let speed = if axis == 1 {
            diff(&|s, d| s.vel_body.x += d)
        } else {
            diff(&|s, d| s.vel_body.y += d)
        };
        *o = [damping, speed.to_degrees()];
    }
    Ok(out)
}

/// The identified local derivatives of the flight identifier's rate models, per rule, from
/// its exported parameters (scaled θ): `[δ/ΔT (1/s), κ/ΔT (deg/s² per m/s)]`.
fn identified(params: &[ModelParameters], period_s: f64) -> Option<Vec<[[f64; 2]; 3]>> {
    let mut rules = vec![[[0.0; 2]; 3]; 3];
    let axes = [RateAxis::Pitch, RateAxis::Yaw, RateAxis::Roll];
    for (m, (name, axis)) in ["q", "r", "p"].iter().zip(axes).enumerate() {
        let scaling = RateStructure::Flight.helicopter_scaling::<f64, 7>(axis);
        let (sd, sk, sy) = (scaling.terms[2], scaling.terms[5], scaling.target);
        let p = params.iter().find(|p| p.model == *name)?;
        for (rule, out) in rules.iter_mut().enumerate() {
            let theta = p.theta.get(rule * 7..rule * 7 + 7)?;
            let delta = f64::from(theta[2]) * sy / sd;
            let kappa = f64::from(theta[5]) * sy / sk;
            out[m] = [delta / period_s, kappa / period_s];
        }
    }
    Some(rules)
}

/// The flight default against [`BASELINE`], state by state: the ratio of its error to the
/// baseline's on the hover and envelope flights, each marked against its criterion (hover: at
/// most [`HOVER_TOLERANCE`]; envelope free run: at most [`ENVELOPE_TARGET`]; the envelope's
/// one-step ratio has no criterion).
pub fn flight_by_state(hover: &Metrics, envelope: &Metrics) -> String {
    let Some([hf, hb, ef, eb]) = flight_and_baseline(hover, envelope) else {
        return "(flight or baseline variant missing)\n".into();
    };
    let cell = |a: f64, b: f64, limit: Option<f64>| {
        let r = a / b;
        match limit {
            Some(l) => format!("{r:.2} {}", mark(r <= l)),
            None => format!("{r:.2}"),
        }
    };
    let mut s = String::from(
        "| state | hover, one step (observer) | hover, one step (measured state) | hover, free run | envelope, one step (observer) | envelope, free run |\n|---|---:|---:|---:|---:|---:|\n"
    );
    let labels = ["v_x", "v_y", "v_z", "q", "r", "p"];
    for (i, label) in labels.iter().enumerate() {
        s += &format!(
            "| {label} | {} | {} | {} | {} | {} |\n",
            cell(
                hf.one_step_observed[i],
                hb.one_step_observed[i],
                Some(HOVER_TOLERANCE)
            ),
            cell(hf.one_step[i], hb.one_step[i], None),
            cell(hf.free_run[i], hb.free_run[i], Some(HOVER_TOLERANCE)),
            cell(ef.one_step_observed[i], eb.one_step_observed[i], None),
            cell(ef.free_run[i], eb.free_run[i], Some(ENVELOPE_TARGET)),
        );
    }
    let misses = |a: &[f64; 6], b: &[f64; 6], limit: f64| {
        let m: Vec<&str> = (0..6)
            .filter(|&i| a[i] / b[i] > limit)
            .map(|i| labels[i])
            .collect();
        if m.is_empty() {
            "none".to_string()
        } else {
            m.join(", ")
        }
    };
    s += &format!(
        "\nMissed: hover one step (observer) on {}; hover free run on {}; envelope free run on {}.\n",
        misses(&hf.one_step_observed, &hb.one_step_observed, HOVER_TOLERANCE),
        misses(&hf.free_run, &hb.free_run, HOVER_TOLERANCE),
        misses(&ef.free_run, &eb.free_run, ENVELOPE_TARGET),
    );
    s
}

/// Every variant's observer gain on the hover and the envelope pair, one row each.
fn gains(hover: &Metrics, envelope: &Metrics) -> String {
    let mut s = String::from("| variant | hover pair | envelope pair |\n|---|---|---|\n");
    let list = |k: &[f32; 6]| {
        k.iter()
            .map(|x| format!("{x:.1}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for v in &hover.variants {
        let e = variant(envelope, &v.name).map_or("–".into(), |e| list(&e.observer_gain));
        s += &format!("| {} | {} | {e} |\n", v.name, list(&v.observer_gain));
    }
    s
}

/// The section of docs/results.md on the flight default, for the flights of `airframe`.
pub fn flight_markdown(
    hover: &Metrics,
    envelope: &Metrics,
    envelope_dir: &Path,
    airframe: Airframe,
) -> Result<String, ReportError> {
    let mut s = String::new();
    s += "### Criteria\n\n";
    s += &criteria(hover, envelope);
    s += "\n### Envelope flights: error ratio to extended plain, free run ";
    s += &format!("{} s\n\n", envelope.window_s);
    s += &ratios(envelope, |v| v.free_run);
    s += "\n### Envelope flights: error ratio to extended plain, one step through the observer (θ frozen)\n\n";
    s += &ratios(envelope, |v| v.one_step_observed);
    s += "\n### Envelope flights: error ratio to extended plain, one step from the measured state (θ frozen)\n\n";
    s += &ratios(envelope, |v| v.one_step);
    s += "\n### Hover flights: error ratio to extended plain, free run\n\n";
    s += &ratios(hover, |v| v.free_run);
    s += "\n### Hover flights: error ratio to extended plain, one step through the observer (θ frozen)\n\n";
    s += &ratios(hover, |v| v.one_step_observed);
    s += "\n### Hover flights: error ratio to extended plain, one step from the measured state (θ frozen)\n\n";
    s += &ratios(hover, |v| v.one_step);
    s += "\n### The observers' gains K (v_x, v_y, v_z, q, r, p), found on the training flights\n\n";
    s += &gains(hover, envelope);
    s += "\n### Envelope flights: absolute errors\n\n";
    s += &crate::tables::variants_markdown(envelope);

    let path = envelope_dir.join(format!("params-{FLIGHT}.json"));
    let text = std::fs::read_to_string(&path).map_err(|source| ReportError::Read {
        path: path.clone(),
        source,
    })?;
    let params: Vec<ModelParameters> =
        serde_json::from_str(&text).map_err(|source| ReportError::Json {
            path: path.clone(),
            source,
        })?;
    let period = 0.02;
    let learnt = identified(&params, period).ok_or(ReportError::Layout { path })?;
    let plant = airframe.params();
    s += "\n### Why: what each speed region learnt\n\n";
    s += "Each rate model's rules are local linear models of their speed region. Identified \
          (per rule, physical units): the damping `δ/ΔT` (1/s) and the speed term `κ/ΔT` \
          (deg/s² per m/s of forward speed for q, of rightward speed for r and p). Plant: the \
          partial derivatives of the plant's angular acceleration at the hover trim flown \
          at the rule's centre speed, with the rotor's flapping held (so they leave out the \
          flapping's own share of the damping, which the identified δ, with the \
          second-order term η, includes): they show how strongly the physics changes with \
          speed, not the identified numbers' expected values.\n\n";
    s += "| rule (centre) | q: δ/ΔT | q: κ/ΔT | r: δ/ΔT | r: κ/ΔT | p: δ/ΔT | p: κ/ΔT | plant N_r | plant N_v | plant M_u | plant L_v |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (rule, centre) in [0.0, 5.0, 10.0].iter().enumerate() {
        let l = &learnt[rule];
        let d = plant_derivatives(&plant, *centre).map_err(|source| ReportError::Plant {
            airframe: airframe.name(),
            source,
        })?;
        s += &format!(
            "| {rule} ({centre} m/s) | {:.2} | {:.3} | {:.2} | {:.3} | {:.2} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
            l[0][0], l[0][1], l[1][0], l[1][1], l[2][0], l[2][1], d[1][0], d[1][1], d[0][1], d[2][1]
        );
    }
    s += &regime_bias(envelope);
    Ok(s)
}

/// Variant whose yaw model is scheduled on side speed too (its r column in [`regime_bias`]).
const SIDE_SPEED_YAW: &str = "flight yaw on side speed";

/// The flight default's and [`BASELINE`]'s frozen one-step bias on the rates per flight
/// regime of the envelope verification flight ([`rotorid_cli::experiments::one_step_bias`]), and
/// r's for [`SIDE_SPEED_YAW`] when it was run.
fn regime_bias(envelope: &Metrics) -> String {
    let find = |n: &str| {
        envelope
            .variants
            .iter()
            .find(|v| v.name == n && !v.one_step_bias.is_empty())
    };
    let (Some(flight), Some(base)) = (find(FLIGHT), find(BASELINE)) else {
        return String::new();
    };
    let side = find(SIDE_SPEED_YAW);
    let mut s = String::from(
        "\n### Where the trim is wrong: one-step bias by flight regime\n\n\
         The frozen models' mean **signed** one-step error on the envelope verification flight, \
         per regime of the sample predicted from (heading-frame velocity; \
         `rotorid_cli::experiments::Regime`), divided by the sample period: the angular \
         acceleration (deg/s²) a model predicts that is not there. The mean absolute one-step \
         error hides it under the gyro noise; a free run integrates it into a drift of the rate \
         (which its damping δ only bounds), so a regime with a large bias is where that \
         state's free run is lost. A bias of the same sign in both sideways directions is a \
         yaw moment that is even in the side speed (the main rotor's torque falls with \
         airspeed in any direction; the tail rotor's thrust changes steeply with the flow \
         through it): extended plain has no term for it (see its r column), the flight \
         default's yaw model has `𝕀 |v|` (`RateStructure::Flight`). The last column \
         schedules the flight default's yaw model on side speed too (`flight yaw on side \
         speed`, 9 rules): what scheduling adds to that term. The vertical columns are the \
         same for the vertical speed (m/s² up): the thrust the model gets wrong. Translational \
         lift raises the thrust per collective with the speed in any direction; the flight \
         default's translational model is scheduled on the horizontal speed \
         (`Premise::HorizontalSpeed`), so its sideways regimes are not learnt as hover.\n\n",
    );
    s += "| regime | samples | flight: q | flight: r | flight: p | flight: vertical | extended plain: q | extended plain: r | extended plain: p | extended plain: vertical | yaw on side speed: r |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (k, (f, b)) in flight
        .one_step_bias
        .iter()
        .zip(base.one_step_bias.iter())
        .enumerate()
    {
        let side_r = side
            .and_then(|v| v.one_step_bias.get(k))
            .map_or("–".to_string(), |x| format!("{:+.1}", x.bias_per_s[4]));
        s += &format!(
            "| {} | {} | {:+.1} | {:+.1} | {:+.1} | {:+.2} | {:+.1} | {:+.1} | {:+.1} | {:+.2} | {side_r} |\n",
            f.regime.label(),
            f.samples,
            f.bias_per_s[3],
            f.bias_per_s[4],
            f.bias_per_s[5],
            f.bias_per_s[1],
            b.bias_per_s[3],
            b.bias_per_s[4],
            b.bias_per_s[5],
            b.bias_per_s[1],
        );
    }
    s
}
