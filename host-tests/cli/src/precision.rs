//! f32 against f64: how closely the flight build's identified parameters follow the same
//! identification computed in double precision.

use rotorid::hover::{HoverSample, RateModel, StateModel, VelocityModel};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, HoverConfig, HoverIdentifier, Real,
};
use serde::{Deserialize, Serialize};

/// Parameters counted as well excited: posterior variance below this share of the prior α.
pub const WELL_EXCITED: f64 = 1e-5;
/// Parameters whose magnitude is below this share of their model's largest are not compared
/// relatively (a relative error of a parameter that is essentially zero means nothing).
pub const NEGLIGIBLE: f64 = 1e-3;

/// Agreement of one variant's physical parameters, f32 against f64.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PrecisionResult {
    /// Variant name.
    pub variant: String,
    /// Parameters in all.
    pub parameters: usize,
    /// Well-excited parameters compared.
    pub compared: usize,
    /// Largest `|θ_f32 − θ_f64| / |θ_f64|` over the compared parameters.
    pub max_relative: f64,
    /// Median of the same.
    pub median_relative: f64,
}

/// Physical parameters of a model with their posterior variance relative to the prior.
pub trait PhysicalParameters {
    /// `(α_{i,s}, P_jj/α)` for every parameter, in the model's θ order.
    fn physical(&self) -> Vec<(f64, f64)>;
}

macro_rules! physical_impl {
    ($model:ident) => {
        impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize>
            PhysicalParameters for $model<T, R, D, rotorid::ts::TsRls<T, 3, R, D, N, NP>>
        {
            fn physical(&self) -> Vec<(f64, f64)> {
                let ts = self.ts();
                let alpha = ts.rls().config().initial_covariance.to_f64();
                let diag = ts.rls().covariance_diagonal();
                (0..N)
                    .map(|j| {
                        let (term, rule) = (j / R, j % R);
                        let value = ts
                            .physical_parameter(rule, term)
                            .map_or(f64::NAN, Real::to_f64);
                        (value, diag[j].to_f64() / alpha)
                    })
                    .collect()
            }
        }
    };
}
physical_impl!(VelocityModel);
physical_impl!(RateModel);

macro_rules! physical_local_impl {
    ($model:ident) => {
        /// Rule by rule (θ_1's terms, then θ_2's, …).
        impl<T: Real, const R: usize, const D: usize, const DP: usize> PhysicalParameters
            for $model<T, R, D, rotorid::ts::local::LocalTsRls<T, 3, R, D, DP>>
        {
            fn physical(&self) -> Vec<(f64, f64)> {
                let ts = self.ts();
                let alpha = ts.config().initial_covariance.to_f64();
                (0..R)
                    .flat_map(|rule| {
                        let view = ts.rule(rule);
                        (0..D).map(move |term| {
                            let value = ts
                                .physical_parameter(rule, term)
                                .map_or(f64::NAN, Real::to_f64);
                            let p = view
                                .and_then(|v| v.covariance_diagonal_entry(term))
                                .map_or(f64::NAN, Real::to_f64);
                            (value, p / alpha)
                        })
                    })
                    .collect()
            }
        }
    };
}
physical_local_impl!(VelocityModel);
physical_local_impl!(RateModel);

fn train<T, V, Q, R, P>(id: &mut HoverIdentifier<T, V, Q, R, P>, logs: &[Vec<HoverSample<f32>>])
where
    T: Real,
    V: StateModel<T>,
    Q: StateModel<T>,
    R: StateModel<T>,
    P: StateModel<T>,
{
    for log in logs {
        let mut chained = false;
        for s in log {
            let s = s.cast::<T>();
            if !chained || id.step(&s).is_err() {
                chained = id.resume(&s).is_ok();
            }
        }
    }
}

fn all_models<T, V, Q, R, P>(id: &HoverIdentifier<T, V, Q, R, P>) -> Vec<Vec<(f64, f64)>>
where
    T: Real,
    V: StateModel<T> + PhysicalParameters,
    Q: StateModel<T> + PhysicalParameters,
    R: StateModel<T> + PhysicalParameters,
    P: StateModel<T> + PhysicalParameters,
{
    vec![
        id.velocity_model().physical(),
        id.pitch_model().physical(),
        id.yaw_model().physical(),
        id.roll_model().physical(),
    ]
}

fn compare(
    variant: &str,
    single: Vec<Vec<(f64, f64)>>,
    double: Vec<Vec<(f64, f64)>>,
) -> PrecisionResult {
    let mut rel = Vec::new();
    let mut parameters = 0;
    for (s, d) in single.iter().zip(&double) {
        parameters += d.len();
        let largest = d.iter().fold(0.0f64, |m, (v, _)| m.max(v.abs()));
        for ((a, _), (b, var)) in s.iter().zip(d) {
            if *var < WELL_EXCITED && b.abs() > NEGLIGIBLE * largest {
                rel.push((a - b).abs() / b.abs());
            }
        }
    }
    rel.sort_by(f64::total_cmp);
    PrecisionResult {
        variant: variant.to_string(),
        parameters,
        compared: rel.len(),
        max_relative: rel.last().copied().unwrap_or(0.0),
        median_relative: rel.get(rel.len() / 2).copied().unwrap_or(0.0),
    }
}

/// Trains the extended identifiers (flight default: U-D RLS, helicopter scaling) in f32 and in
/// f64 on the same logs and compares their well-excited physical parameters.
pub fn extended_f32_vs_f64(
    logs: &[Vec<HoverSample<f32>>],
) -> Result<Vec<PrecisionResult>, rotorid::Error> {
    let mut out = Vec::new();
    let mut a = ExtendedFuzzyIdentifier::<f32>::extended_fuzzy(HoverConfig::default())?;
    let mut b = ExtendedFuzzyIdentifier::<f64>::extended_fuzzy(HoverConfig::default())?;
    train(&mut a, logs);
    train(&mut b, logs);
    out.push(compare("extended fuzzy", all_models(&a), all_models(&b)));
    let mut a = ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default())?;
    let mut b = ExtendedPlainIdentifier::<f64>::extended_plain(HoverConfig::default())?;
    train(&mut a, logs);
    train(&mut b, logs);
    out.push(compare("extended plain", all_models(&a), all_models(&b)));
    Ok(out)
}
