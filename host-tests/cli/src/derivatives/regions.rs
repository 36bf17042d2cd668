//! Per operating region: which sticks were excited, each axis's fit, the rate axes' control
//! power and time constant, and [`derivatives`], the entry point.

use nalgebra::{DMatrix, DVector};
use rotorid_sim::plant::SensorSample;

use super::equations::{Equation, Term, EQUATIONS, RATE_AXES, STICK_NAMES};
use super::fit::{fit, stretches};
use super::samples::{points_of_run, usable_runs, Differentiator, Point};
use super::{
    deg_s2, AxisFit, Derivative, Derivatives, RateAxis, Region, StickExcitation,
    DETERMINED_SE_MULTIPLE, FORWARD_MIN_BODY_SPEED_MPS, HOVER_MAX_GROUND_SPEED_MPS, MAX_LAG_S,
    NEVER_EXCITED_FRACTION, SAMPLES_PER_PARAMETER,
};

pub(super) fn excitation(points: &[&Point]) -> Vec<StickExcitation> {
    (0..4)
        .map(|c| {
            let threshold = NEVER_EXCITED_FRACTION;
            let n = points.len() as f64;
            let std = (!points.is_empty())
                .then(|| {
                    let mean = points.iter().map(|p| p.raw_sticks[c]).sum::<f64>() / n;
                    (points
                        .iter()
                        .map(|p| (p.raw_sticks[c] - mean).powi(2))
                        .sum::<f64>()
                        / n)
                        .sqrt()
                })
                .filter(|s| s.is_finite());
            StickExcitation {
                stick: STICK_NAMES[c].to_string(),
                std,
                threshold,
                never_excited: std.is_none_or(|s| s < threshold),
            }
        })
        .collect()
}

pub(super) fn not_fitted(eq: &Equation, samples: usize, reason: String) -> AxisFit {
    let mut derivatives: Vec<Derivative> = eq
        .terms
        .iter()
        .map(|(_, sym, unit)| Derivative {
            symbol: sym.to_string(),
            unit: unit.to_string(),
            value: None,
            se: None,
            se_ols: None,
            determined: false,
            note: Some(reason.clone()),
        })
        .collect();
    derivatives.push(Derivative {
        symbol: eq.intercept.to_string(),
        unit: eq.lhs_unit.to_string(),
        value: None,
        se: None,
        se_ols: None,
        determined: false,
        note: Some(reason.clone()),
    });
    AxisFit {
        axis: eq.axis.to_string(),
        equation: eq.equation.to_string(),
        samples,
        fitted: false,
        reason: Some(reason),
        derivatives,
        r_squared: None,
        residual_rms: None,
        lags: None,
    }
}

pub(super) fn fit_axis(
    eq: &Equation,
    points: &[&Point],
    exc: &[StickExcitation],
    max_lag: usize,
) -> AxisFit {
    let n = points.len();
    // Columns kept: terms whose stick was excited, then the intercept.
    let kept: Vec<usize> = (0..eq.terms.len())
        .filter(|&i| match eq.terms[i].0 {
            Term::Stick(c) => exc.get(c).is_some_and(|e| !e.never_excited),
            Term::State(_) => true,
        })
        .collect();
    let p = kept.len() + 1;
    if n < SAMPLES_PER_PARAMETER * p {
        return not_fitted(
            eq,
            n,
            format!(
                "{n} samples, fewer than {SAMPLES_PER_PARAMETER} per parameter ({p} parameters)"
            ),
        );
    }
    let axis_index = EQUATIONS
        .iter()
        .position(|e| e.axis == eq.axis)
        .unwrap_or(0);
    let x = DMatrix::from_fn(n, p, |i, c| match kept.get(c) {
        Some(&t) => match eq.terms[t].0 {
            Term::State(s) => points[i].x[s],
            Term::Stick(s) => points[i].sticks[s],
        },
        None => 1.0,
    });
    let y = DVector::from_fn(n, |i, _| points[i].y[axis_index]);
    let mut names: Vec<&str> = kept.iter().map(|&t| eq.terms[t].1).collect();
    names.push(eq.intercept);
    let runs = stretches(points);
    let result = match fit(&x, &y, &runs, &names, max_lag) {
        Ok(f) => f,
        Err(reason) => return not_fitted(eq, n, reason),
    };
    let estimate = |col: usize, symbol: &str, unit: &str| {
        let (v, se, se_ols) = (result.theta[col], result.se[col], result.se_ols[col]);
        Derivative {
            symbol: symbol.to_string(),
            unit: unit.to_string(),
            value: Some(v),
            se: Some(se),
            se_ols: Some(se_ols),
            determined: v.abs() >= DETERMINED_SE_MULTIPLE * se,
            note: result.note.clone(),
        }
    };
    let mut derivatives = Vec::with_capacity(eq.terms.len() + 1);
    for (t, (term, sym, unit)) in eq.terms.iter().enumerate() {
        match kept.iter().position(|&k| k == t) {
            Some(col) => derivatives.push(estimate(col, sym, unit)),
            None => {
                let why = match term {
                    Term::Stick(c) => {
                        let e = &exc[*c];
                        format!(
                            "not determined: the {} stick was never excited (std {} < {:.3})",
                            e.stick,
                            e.std.map_or("n/a".to_string(), |s| format!("{s:.4}")),
                            e.threshold
                        )
                    }
                    Term::State(_) => "not fitted".to_string(),
                };
                derivatives.push(Derivative {
                    symbol: sym.to_string(),
                    unit: unit.to_string(),
                    value: None,
                    se: None,
                    se_ols: None,
                    determined: false,
                    note: Some(why),
                });
            }
        }
    }
    derivatives.push(estimate(kept.len(), eq.intercept, eq.lhs_unit));
    AxisFit {
        axis: eq.axis.to_string(),
        equation: eq.equation.to_string(),
        samples: n,
        fitted: true,
        reason: None,
        derivatives,
        r_squared: Some(result.r_squared),
        residual_rms: Some(result.residual_rms),
        lags: Some(result.lags),
    }
}

pub(super) fn rate_axis(
    axes: &[AxisFit],
    (name, eq, damping, control): (&str, usize, &str, &str),
    dt: f64,
) -> RateAxis {
    let find = |sym: &str| {
        axes.get(eq)
            .and_then(|a| a.derivatives.iter().find(|d| d.symbol == sym))
    };
    let c = find(control);
    let d = find(damping);
    let power = c.and_then(|c| c.value).map(deg_s2);
    let (tau, tau_se, status) = match d.and_then(|d| d.value.zip(d.se).map(|v| (v, d.determined))) {
        Some(((v, se), true)) if v < 0.0 => (Some(-1.0 / v), Some(se / (v * v)), "determined"),
        Some((_, true)) => (None, None, "unstable"),
        Some((_, false)) => (None, None, "undetermined"),
        None => (None, None, "not fitted"),
    };
    let mut notes: Vec<String> = Vec::new();
    if let Some(c) = c.filter(|c| !c.determined) {
        notes.push(match &c.note {
            Some(n) => format!("{control} {n}"),
            None => format!("{control} not determined (|value| < 2 SE)"),
        });
    }
    // A response faster than the sampling cannot be fitted by a derivative of the samples:
    // say so rather than let a fitted number stand alone (module doc, "Sample rate").
    match (status, tau) {
        ("unstable", _) => notes.push(format!(
            "{damping} determined positive: an unstable axis, or one faster than the log's \
             {:.0} Hz resolves (its other numbers are then not to be trusted)",
            1.0 / dt
        )),
        ("determined", Some(t)) if t < 2.0 * dt => notes.push(format!(
            "τ = {t:.3} s is under two sample periods ({:.3} s): the log's rate barely \
             resolves this axis; log faster",
            2.0 * dt
        )),
        _ => {}
    }
    let note = (!notes.is_empty()).then(|| notes.join("; "));
    RateAxis {
        axis: name.to_string(),
        control: control.to_string(),
        control_power_deg_s2: power,
        control_power_deg_s2_per_10pct: power.map(|p| 0.1 * p),
        control_power_se_deg_s2: c.and_then(|c| c.se).map(deg_s2),
        control_determined: c.is_some_and(|c| c.determined),
        damping: damping.to_string(),
        time_constant_s: tau,
        time_constant_se_s: tau_se,
        time_constant_status: status.to_string(),
        note,
    }
}

pub(super) fn region(
    name: &str,
    definition: &str,
    points: &[&Point],
    max_lag: usize,
    dt: f64,
) -> Region {
    let exc = excitation(points);
    let axes: Vec<AxisFit> = EQUATIONS
        .iter()
        .map(|eq| fit_axis(eq, points, &exc, max_lag))
        .collect();
    let rate_axes = RATE_AXES
        .iter()
        .map(|&ra| rate_axis(&axes, ra, dt))
        .collect();
    let fitted = axes.iter().any(|a| a.fitted);
    let reason = (!fitted).then(|| {
        if points.len() < SAMPLES_PER_PARAMETER * 3 {
            format!(
                "{} samples, fewer than {SAMPLES_PER_PARAMETER} per parameter for any axis",
                points.len()
            )
        } else {
            "no axis could be fitted (see each axis' reason)".to_string()
        }
    });
    Region {
        name: name.to_string(),
        definition: definition.to_string(),
        samples: points.len(),
        fitted,
        reason,
        excitation: exc,
        axes,
        rate_axes,
    }
}

/// The body-axis derivatives of a log given as gap-free segments evenly sampled at `rate_hz`
/// (Hz), per operating region (see the module doc). Never panics; anything that cannot be
/// fitted carries its reason.
pub fn derivatives(segments: &[&[SensorSample]], rate_hz: f64) -> Derivatives {
    let mut notes = Vec::new();
    let rate_ok = rate_hz.is_finite() && rate_hz > 0.0;
    let rate = if rate_ok { rate_hz } else { 50.0 };
    if !rate_ok {
        notes.push(format!(
            "sample rate {rate_hz} Hz is not a positive number: nothing fitted (give the log's \
             rate in Hz)"
        ));
    }
    let diff = Differentiator::for_rate(rate);
    let dt = 1.0 / rate;
    let mut points = Vec::new();
    if rate_ok {
        let runs = usable_runs(segments, dt, &mut notes);
        let mut next = 0;
        for run in &runs {
            points_of_run(run, diff, dt, &mut next, &mut points);
        }
        let need = 2 * diff.half() + 1;
        let short = runs.iter().filter(|r| r.len() < need).count();
        if short > 0 {
            notes.push(format!(
                "{short} stretch(es) shorter than the differentiator's {need} samples left out"
            ));
        }
        if points.is_empty() {
            notes.push("no usable samples: nothing to fit".to_string());
        }
    }
    let max_lag = (MAX_LAG_S * rate).round() as usize;
    let all: Vec<&Point> = points.iter().collect();
    let hover: Vec<&Point> = points
        .iter()
        .filter(|p| p.ground_speed < HOVER_MAX_GROUND_SPEED_MPS)
        .collect();
    let forward: Vec<&Point> = points
        .iter()
        .filter(|p| p.u >= FORWARD_MIN_BODY_SPEED_MPS)
        .collect();
    let all_region = region(
        "all",
        "every usable sample (one linearisation of the whole log)",
        &all,
        max_lag,
        dt,
    );
    // A region holding every sample is the `all` fit under another name: reuse it.
    let sub = |name: &str, definition: &str, pts: &[&Point]| {
        if pts.len() == all.len() {
            Region {
                name: name.to_string(),
                definition: definition.to_string(),
                ..all_region.clone()
            }
        } else {
            region(name, definition, pts, max_lag, dt)
        }
    };
    let regions = vec![
        sub("hover", "horizontal ground speed < 3 m/s", &hover),
        sub("forward", "body forward speed u ≥ 3 m/s", &forward),
    ];
    let regions = std::iter::once(all_region).chain(regions).collect();
    Derivatives {
        rate_hz: rate_ok.then_some(rate_hz),
        differentiator: diff.name.to_string(),
        usable_samples: points.len(),
        notes,
        regions,
    }
}
