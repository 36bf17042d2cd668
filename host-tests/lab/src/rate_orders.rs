//! The rate models' order, fitted offline (docs/rate-orders.md): does the flight structure's
//! rate model lack the previous control, and does its gyro-noise compensation leave a bias?
//!
//! A rate driven through a first-order flapping lag is, sampled with the controls held
//! between samples, exactly `ω(k+1) = a1 ω(k) + a2 ω(k−1) + b1 u(k) + b2 u(k−1)`: an ARX model
//! of order 2 in the rate **and** in the control. [`RateStructure::Flight`] has the first
//! (`δ ω(k)` and `η Δω(k−1)`) but only `u(k)`. Separately, its bias compensation
//! ([`RateModel::gyro_noise`]) removes the gyro noise of `ω(k)` but not that of `Δω(k−1)`.
//!
//! This study takes each rate model's terms from the core ([`RateModel::terms_in`], one rule,
//! so the terms are the product's own) and fits them by batch least squares on a training log,
//! with and without the lagged control `u(k−1)` (the axis's control product of the sample
//! before) and with three compensations: none, the product's (`ω(k)`'s noise) and the full one
//! (`Δω(k−1)`'s noise too, and its covariance with `ω(k)`'s), the noise σ being the product's
//! estimate from the training log ([`gyro_noise_of`]). Each fit is scored by the free run of
//! its own rate over 2 s windows of a verification log (the other two rates measured), beside
//! extended plain's and holding the measured rate. Batch least squares is not the product's
//! recursive, forgetting, fuzzy estimator: on the X-Cell's hover the flight fit with the
//! product's compensation lands within 0.01 of the product's ratios to extended plain
//! (docs/seeds.md), which is what makes the proxy worth reading.

use nalgebra::{DMatrix, DVector};
use rotorid::hover::{
    AttitudeInput, HoverSample, LocalRateModel, Premise, RateAxis, RateModel, RateStructure,
};
use rotorid::rls::RlsConfig;
use rotorid::rule_base::RuleBase;
use rotorid_cli::experiments::gyro_noise_of;
use serde::Serialize;

/// Which terms a candidate fits.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Terms {
    /// [`RateStructure::Extended`]: `[𝕀, γ, δ, β, c]`.
    Extended,
    /// [`RateStructure::Flight`]: `[𝕀, γ, δ, β, c, κ, η]`.
    Flight,
    /// The flight terms and the axis's control product of the sample before.
    FlightLagged,
}

/// Which gyro noise a candidate's fit removes.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Noise {
    /// None: ordinary least squares.
    Kept,
    /// The product's: the noise of `ω(k)` (the damping term) and its covariance with the
    /// target's.
    Product,
    /// The product's and the noise of `Δω(k−1)` (the second-order term): its variance `2σ²`,
    /// its covariance `σ²` with `ω(k)`'s.
    Full,
    /// [`Full`](Self::Full) where the compensated rate dynamics are stable (both roots of
    /// `z² − (1 + δ + η) z + η` inside the unit circle), else the product's.
    FullWhereStable,
}

/// One fitted rate model.
#[derive(Copy, Clone, Debug)]
pub struct Candidate {
    /// Its name in the tables.
    pub name: &'static str,
    /// Its terms.
    pub terms: Terms,
    /// The noise its fit removes.
    pub noise: Noise,
}

/// The candidates, extended plain's (the ratios' reference) first.
pub const CANDIDATES: [Candidate; 9] = [
    Candidate {
        name: "extended",
        terms: Terms::Extended,
        noise: Noise::Kept,
    },
    Candidate {
        name: "flight, uncompensated",
        terms: Terms::Flight,
        noise: Noise::Kept,
    },
    Candidate {
        name: "flight",
        terms: Terms::Flight,
        noise: Noise::Product,
    },
    Candidate {
        name: "flight, full compensation",
        terms: Terms::Flight,
        noise: Noise::Full,
    },
    Candidate {
        name: "flight, full compensation where stable",
        terms: Terms::Flight,
        noise: Noise::FullWhereStable,
    },
    Candidate {
        name: "flight + u(k−1), uncompensated",
        terms: Terms::FlightLagged,
        noise: Noise::Kept,
    },
    Candidate {
        name: "flight + u(k−1)",
        terms: Terms::FlightLagged,
        noise: Noise::Product,
    },
    Candidate {
        name: "flight + u(k−1), full compensation",
        terms: Terms::FlightLagged,
        noise: Noise::Full,
    },
    Candidate {
        name: "flight + u(k−1), full compensation where stable",
        terms: Terms::FlightLagged,
        noise: Noise::FullWhereStable,
    },
];

/// The rate axes in the order of the tables: `[q r p]`.
pub const AXES: [RateAxis; 3] = [RateAxis::Pitch, RateAxis::Yaw, RateAxis::Roll];

/// Free-run windows (s).
const WINDOW_S: f64 = 2.0;

/// A free run beyond this (deg/s) has diverged.
const DIVERGED: f64 = 1e4;

/// Index of the damping term `δ ω(k)` and of the second-order term `η Δω(k−1)`.
const DAMPING: usize = 2;
const SECOND_ORDER: usize = 6;

/// One candidate's scores on a verification log.
#[derive(Clone, Debug, Serialize)]
pub struct Scored {
    /// [`Candidate::name`].
    pub name: &'static str,
    /// Mean absolute free-run error of `[q r p]` (deg/s); `None`: the fit failed (singular
    /// normal equations) or a window diverged.
    pub free_run: [Option<f64>; 3],
}

/// What `rotorid-lab rate-orders` writes.
#[derive(Clone, Debug, Serialize)]
pub struct RateOrders {
    /// σ̂ of each gyro `[q r p]` (deg/s) from the training log, which the compensations remove.
    pub gyro_noise: [f64; 3],
    /// Holding the measured rate over the same windows: mean absolute error of `[q r p]`.
    pub hold: [f64; 3],
    /// Every candidate, in [`CANDIDATES`]' order.
    pub candidates: Vec<Scored>,
}

/// A one-rule model of one axis: what gives the core's terms of a structure.
enum Model {
    Extended(LocalRateModel<f32, 1, 5, 15>),
    Flight(LocalRateModel<f32, 1, 7, 28>),
}

impl Model {
    fn new(axis: RateAxis, terms: Terms) -> Result<Self, rotorid::Error> {
        Ok(match terms {
            Terms::Extended => Self::Extended(one_rule(axis, RateStructure::Extended)?),
            Terms::Flight | Terms::FlightLagged => {
                Self::Flight(one_rule(axis, RateStructure::Flight)?)
            }
        })
    }

    fn axis(&self) -> RateAxis {
        match self {
            Self::Extended(m) => m.axis(),
            Self::Flight(m) => m.axis(),
        }
    }

    /// The core's terms at `sample` with `before` the rates of the sample before.
    fn terms(&self, sample: &HoverSample<f32>, before: &[f32; 3]) -> Vec<f64> {
        let frame = sample.attitude.frame();
        match self {
            Self::Extended(m) => m.terms_in(sample, &frame, before).map(f64::from).to_vec(),
            Self::Flight(m) => m.terms_in(sample, &frame, before).map(f64::from).to_vec(),
        }
    }
}

/// A one-rule model of `axis` with `structure`'s terms (D of them) and nominal scales.
fn one_rule<const D: usize, const DP: usize>(
    axis: RateAxis,
    structure: RateStructure,
) -> Result<LocalRateModel<f32, 1, D, DP>, rotorid::Error> {
    RateModel::with_scaling(
        axis,
        RuleBase::single_rule()?,
        structure,
        Premise::Rates,
        RlsConfig::default(),
        structure.helicopter_scaling(axis),
    )
}

/// The axis's control product (the core's `γ` term) of sample `s`.
fn control(axis: RateAxis, s: &HoverSample<f32>) -> f64 {
    let u = &s.controls;
    f64::from(match axis {
        RateAxis::Pitch => u.lon * u.col,
        RateAxis::Yaw => u.ped,
        RateAxis::Roll => u.lat * u.col,
    })
}

/// The regressor of `candidate` at sample `k` of `log` with the axis's own rate replaced by
/// `own` (now) and `own_before` (the sample before): the core's terms, and the lagged control.
fn regressor(
    model: &Model,
    candidate: &Candidate,
    log: &[HoverSample<f32>],
    k: usize,
    own: f64,
    own_before: f64,
) -> Option<Vec<f64>> {
    let axis = model.axis();
    let (before, now) = (log.get(k.checked_sub(1)?)?, log.get(k)?);
    let mut sample = *now;
    *sample.rates.get_mut(axis.index())? = own as f32;
    let mut rates_before = before.rates;
    *rates_before.get_mut(axis.index())? = own_before as f32;
    let mut x = model.terms(&sample, &rates_before);
    if candidate.terms == Terms::FlightLagged {
        x.push(control(axis, before));
    }
    Some(x)
}

/// θ of `candidate` for `axis` by (bias-compensated) batch least squares on `training`.
fn fit(
    model: &Model,
    candidate: &Candidate,
    training: &[HoverSample<f32>],
    sigma: f64,
) -> Option<DVector<f64>> {
    let axis = model.axis().index();
    let rate = |k: usize| {
        training
            .get(k)
            .and_then(|s| s.rates.get(axis))
            .map(|&r| f64::from(r))
    };
    let mut a: Option<DMatrix<f64>> = None;
    let mut b: Option<DVector<f64>> = None;
    let mut n = 0.0;
    for k in 1..training.len().saturating_sub(1) {
        let x = DVector::from_vec(regressor(
            model,
            candidate,
            training,
            k,
            rate(k)?,
            rate(k - 1)?,
        )?);
        let y = rate(k + 1)? - rate(k)?;
        let d = x.len();
        *a.get_or_insert_with(|| DMatrix::zeros(d, d)) += &x * x.transpose();
        *b.get_or_insert_with(|| DVector::zeros(d)) += &x * y;
        n += 1.0;
    }
    let (a, b) = (a?, b?);
    let noise = n * sigma * sigma;
    let solve = |which| compensated(a.clone(), b.clone(), noise, candidate.terms, which);
    match candidate.noise {
        Noise::FullWhereStable => solve(Noise::Full)
            .filter(stable)
            .or_else(|| solve(Noise::Product)),
        which => solve(which),
    }
}

/// The solution of the normal equations `a θ = b` with the gyro noise (`noise` = N σ², N
/// samples) removed as `which` says.
fn compensated(
    mut a: DMatrix<f64>,
    mut b: DVector<f64>,
    noise: f64,
    terms: Terms,
    which: Noise,
) -> Option<DVector<f64>> {
    let second_order = terms != Terms::Extended;
    if which != Noise::Kept {
        // E[n nᵀ] of the noisy regressors and E[n n_y] with the target's noise −n(k).
        a[(DAMPING, DAMPING)] -= noise;
        b[DAMPING] += noise;
        if second_order {
            b[SECOND_ORDER] += noise;
        }
    }
    if matches!(which, Noise::Full | Noise::FullWhereStable) && second_order {
        a[(SECOND_ORDER, SECOND_ORDER)] -= 2.0 * noise;
        a[(DAMPING, SECOND_ORDER)] -= noise;
        a[(SECOND_ORDER, DAMPING)] -= noise;
    }
    a.lu().solve(&b)
}

/// Whether the rate's own dynamics `ω(k+1) = (1 + δ + η) ω(k) − η ω(k−1)` are stable (Jury:
/// `z² + c1 z + c0` with `c1 = −(1 + δ + η)`, `c0 = η` has both roots inside the unit circle
/// iff `|c0| < 1` and `|c1| < 1 + c0`). The terms are unscaled here, so θ's entries are the
/// physical coefficients.
fn stable(theta: &DVector<f64>) -> bool {
    match (theta.get(DAMPING), theta.get(SECOND_ORDER)) {
        (Some(&delta), Some(&eta)) => {
            let (c1, c0) = (-(1.0 + delta + eta), eta);
            c0.abs() < 1.0 && c1.abs() < 1.0 + c0
        }
        _ => false,
    }
}

/// Mean absolute free-run error of the axis's rate over `WINDOW_S` windows of `log`, each
/// started from the measured rate (the other rates measured throughout); `None` if a window
/// diverged.
fn free_run(
    model: &Model,
    candidate: &Candidate,
    theta: &DVector<f64>,
    log: &[HoverSample<f32>],
    window: usize,
) -> Option<f64> {
    let axis = model.axis().index();
    let rate = |k: usize| {
        log.get(k)
            .and_then(|s| s.rates.get(axis))
            .map(|&r| f64::from(r))
    };
    let (mut sum, mut count) = (0.0, 0usize);
    let mut start = 1;
    while start + window < log.len() {
        let (mut own, mut before) = (rate(start)?, rate(start - 1)?);
        for k in start..start + window {
            let x = DVector::from_vec(regressor(model, candidate, log, k, own, before)?);
            let next = own + x.dot(theta);
            if !next.is_finite() || next.abs() > DIVERGED {
                return None;
            }
            (before, own) = (own, next);
            sum += (own - rate(k + 1)?).abs();
            count += 1;
        }
        start += window;
    }
    (count > 0).then(|| sum / count as f64)
}

/// Holding the measured rate over the same windows.
fn hold(log: &[HoverSample<f32>], axis: usize, window: usize) -> f64 {
    let rate = |k: usize| {
        log.get(k)
            .and_then(|s| s.rates.get(axis))
            .map_or(0.0, |&r| f64::from(r))
    };
    let (mut sum, mut count) = (0.0, 0usize);
    let mut start = 1;
    while start + window < log.len() {
        for k in start..start + window {
            sum += (rate(start) - rate(k + 1)).abs();
            count += 1;
        }
        start += window;
    }
    if count == 0 {
        0.0
    } else {
        sum / count as f64
    }
}

/// Fits every candidate on `training` and scores it on `verification` (sample period
/// `period_s`).
pub fn rate_orders(
    training: &[HoverSample<f32>],
    verification: &[HoverSample<f32>],
    period_s: f64,
) -> Result<RateOrders, rotorid::Error> {
    let window = (WINDOW_S / period_s).round().max(1.0) as usize;
    let sigma = gyro_noise_of(&[training.to_vec()]).map_or([0.0; 3], |s| s.map(f64::from));
    let mut candidates = Vec::new();
    for candidate in &CANDIDATES {
        let mut scores = [None; 3];
        for (slot, &axis) in scores.iter_mut().zip(AXES.iter()) {
            let m = Model::new(axis, candidate.terms)?;
            let s = sigma.get(axis.index()).copied().unwrap_or(0.0);
            *slot = fit(&m, candidate, training, s)
                .and_then(|theta| free_run(&m, candidate, &theta, verification, window));
        }
        candidates.push(Scored {
            name: candidate.name,
            free_run: scores,
        });
    }
    Ok(RateOrders {
        gyro_noise: sigma,
        hold: AXES.map(|a| hold(verification, a.index(), window)),
        candidates,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotorid::hover::Controls;

    /// A log whose roll rate is exactly an ARX(2, 2) in the lateral control (deg/s), the other
    /// rates zero, level and still: what a rate behind a first-order flapping lag is at the
    /// sample scale.
    fn arx_log(n: usize, seed: u64) -> Vec<HoverSample<f32>> {
        let mut state = seed;
        let mut noise = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f64 / (1u64 << 31) as f64) - 0.5
        };
        let (mut p, mut p_before, mut u_before) = (0.0f64, 0.0f64, 0.0f64);
        let (mut lat, mut col) = (0.0, 0.5);
        (0..n)
            .map(|k| {
                if k % 25 == 0 {
                    lat = 0.2 * noise();
                    col = 0.5 + 0.1 * noise();
                }
                // The other rates and the speed move (so that every term has information)
                // but do not drive the roll.
                let s = HoverSample {
                    time_us: k as u64 * 20_000,
                    velocity: [noise() as f32, noise() as f32, noise() as f32],
                    rates: [10.0 * noise() as f32, 10.0 * noise() as f32, p as f32],
                    controls: Controls {
                        col: col as f32,
                        ped: 0.0,
                        lon: 0.0,
                        lat: lat as f32,
                    },
                    ..HoverSample::default()
                };
                let u = f64::from(lat as f32 * col as f32);
                let next = 1.6 * p - 0.65 * p_before + 40.0 * u + 30.0 * u_before;
                (p_before, p, u_before) = (p, f64::from(next as f32), u);
                s
            })
            .collect()
    }

    #[test]
    fn the_lagged_control_fits_an_arx_rate_exactly_and_the_flight_terms_do_not() {
        let (training, verification) = (arx_log(3000, 1), arx_log(3000, 2));
        let orders = rate_orders(&training, &verification, 0.02).unwrap();
        let roll = |name: &str| {
            orders
                .candidates
                .iter()
                .find(|c| c.name == name)
                .and_then(|c| c.free_run[2])
                .unwrap()
        };
        let hold = orders.hold[2];
        assert!(hold > 1.0, "the roll rate moves: hold error {hold}");
        // No noise: σ̂ is zero and every compensation is the plain fit.
        let (lagged, flight) = (
            roll("flight + u(k−1), uncompensated"),
            roll("flight, uncompensated"),
        );
        assert!(lagged < 1e-4 * hold, "{lagged} against hold's {hold}");
        assert!(flight > 0.01 * hold && flight > 100.0 * lagged, "{flight}");
    }

    #[test]
    fn stability_is_that_of_both_roots() {
        let theta = |delta: f64, eta: f64| {
            let mut t = DVector::zeros(7);
            t[DAMPING] = delta;
            t[SECOND_ORDER] = eta;
            t
        };
        // ω(k+1) = (1 + δ + η) ω(k) − η ω(k−1): roots 0.9 and 0.5 (δ = −0.05, η = −0.45)…
        assert!(stable(&theta(-0.05, -0.45)));
        // …a root at 1.1 (z² − 1.6 z + 0.55: δ = 0.05, η = −0.55)…
        assert!(!stable(&theta(0.05, -0.55)));
        // …and a pair of modulus √1.2.
        assert!(!stable(&theta(0.0, 1.2)));
        assert!(!stable(&DVector::zeros(3)));
    }
}
