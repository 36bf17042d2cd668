//! Placing a premise variable's fuzzy sets from a training flight.
//!
//! Table 3's sets were placed by hand for X-Plane, and most of their shoulders are narrower
//! than a real sensor's noise: a noisy rate near such a shoulder switches its rule on and off.
//! [`quantile_sets`] places the sets where the data are instead, and keeps them wider than the
//! noise:
//!
//! * **Centres** at the quantiles `(j + ½)/S` of the variable over the flight (S sets, j = 0…S−1):
//!   each set describes an equal share of the data, so that every rule is learnt from about
//!   `1/S` of the samples. The first set is a left shoulder and the last a right shoulder, so
//!   that values beyond the flight's range belong fully to the outermost rule.
//! * **Spreads** σ = half the distance to the neighbouring centre (the sets cross at
//!   `μ = e^{−1/2} ≈ 0.6`), but at least [`NOISE_SPREADS`] times the noise σ_n of the variable,
//!   estimated from the data themselves by [`noise_std`]: a set narrower than that would
//!   follow the noise, not the operating point.
//!
//! Everything is computed in place on a buffer the caller provides (no heap); the values are
//! sorted (all are checked finite first).

use core::cmp::Ordering;

use crate::error::{ConfigError, Error};
use crate::membership::MembershipFunction;
use crate::rule_base::{PremiseSets, MAX_SETS};
use crate::scalar::Real;

/// Smallest spread of a placed set, in multiples of the premise variable's noise σ_n.
pub const NOISE_SPREADS: f64 = 3.0;

/// The noise standard deviation of a sampled signal, estimated from its first differences:
/// `σ_n = median|x(k+1) − x(k)| / (0.6745 · √2)`.
///
/// At a sample rate well above the signal's bandwidth, consecutive samples differ mostly by
/// noise; the difference of two independent noise samples has σ·√2, and the median absolute
/// value of a Gaussian is 0.6745 σ (the median makes the estimate robust to the manoeuvres).
/// `scratch` must hold `x.len() − 1` values; returns `None` for fewer than 3 samples or a
/// non-finite value.
pub fn noise_std<T: Real>(x: &[T], scratch: &mut [T]) -> Option<T> {
    let n = x.len().checked_sub(1)?;
    if n < 2 || scratch.len() < n {
        return None;
    }
    let d = scratch.get_mut(..n)?;
    for (slot, pair) in d.iter_mut().zip(x.windows(2)) {
        let (a, b) = (*pair.first()?, *pair.get(1)?);
        if !(a.is_finite() && b.is_finite()) {
            return None;
        }
        *slot = (b - a).abs();
    }
    d.sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(Ordering::Equal));
    let median = *d.get(n / 2)?;
    Some(median / (T::lit(0.6745) * T::lit(core::f64::consts::SQRT_2)))
}

/// `count` sets (1 to [`MAX_SETS`]) for a premise variable whose training values are in
/// `values` (sorted in place) and whose noise σ_n is `noise` (e.g. from [`noise_std`], in the
/// variable's unit). See the [module docs](self).
///
/// One set is a Gaussian at the median that covers everything (σ = the data's spread between
/// quantiles 1/6 and 5/6, at least the noise floor): a single rule.
pub fn quantile_sets<T: Real>(
    values: &mut [T],
    count: usize,
    noise: T,
) -> Result<PremiseSets<T>, Error> {
    if count == 0 || count > MAX_SETS || values.is_empty() {
        return Err(ConfigError::Dimensions.into());
    }
    if values.iter().any(|v| !v.is_finite()) || !(noise.is_finite() && noise >= T::zero()) {
        return Err(ConfigError::MembershipFunction {
            variable: 0,
            set: 0,
        }
        .into());
    }
    values.sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(Ordering::Equal));
    let quantile = |q: f64| -> T {
        let last = values.len() - 1;
        // Nearest rank (q ≥ 0, so the cast floors `+ ½`).
        let i = (q * last as f64 + 0.5) as usize;
        values.get(i.min(last)).copied().unwrap_or_else(T::zero)
    };
    let floor = noise * T::lit(NOISE_SPREADS);
    // A spread must be positive even for constant data (a rule base checks σ > 0).
    let floor = if floor > T::zero() {
        floor
    } else {
        T::lit(1e-3)
    };
    let mut centres = [T::zero(); MAX_SETS];
    for (j, c) in centres.iter_mut().take(count).enumerate() {
        *c = quantile((j as f64 + 0.5) / count as f64);
    }
    let mut sets = PremiseSets::new();
    for j in 0..count {
        let c = centres.get(j).copied().unwrap_or_else(T::zero);
        let left = j
            .checked_sub(1)
            .and_then(|i| centres.get(i))
            .map(|&l| c - l);
        let right = centres.get(j + 1).filter(|_| j + 1 < count).map(|&r| r - c);
        let half = match (left, right) {
            (Some(l), Some(r)) => l.min(r) * T::lit(0.5),
            (Some(d), None) | (None, Some(d)) => d * T::lit(0.5),
            (None, None) => (quantile(5.0 / 6.0) - quantile(1.0 / 6.0)) * T::lit(0.5),
        };
        let spread = if half > floor { half } else { floor };
        let mf = match (count, j) {
            (1, _) => MembershipFunction::Gaussian { centre: c, spread },
            (_, 0) => MembershipFunction::LeftShoulder { centre: c, spread },
            (_, j) if j + 1 == count => MembershipFunction::RightShoulder { centre: c, spread },
            _ => MembershipFunction::Gaussian { centre: c, spread },
        };
        if sets.push(mf).is_err() {
            break;
        }
    }
    Ok(sets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_of_a_slow_ramp_plus_alternating_noise() {
        // A ramp of 0.001 per sample plus ±0.1: differences are ±0.2 + 0.001.
        let x: [f64; 101] =
            core::array::from_fn(|k| k as f64 * 1e-3 + if k % 2 == 0 { 0.1 } else { -0.1 });
        let mut s = [0.0; 100];
        let n = noise_std(&x, &mut s).unwrap();
        assert!(
            (n - 0.2 / (0.6745 * core::f64::consts::SQRT_2)).abs() < 2e-3,
            "{n}"
        );
    }

    #[test]
    fn three_sets_at_quantiles_with_noise_floor() {
        let mut v: [f64; 1200] = core::array::from_fn(|k| (k % 4) as f64 * 4.0);
        let sets = quantile_sets(&mut v, 3, 0.1).unwrap();
        let p: [(f64, f64); 3] = core::array::from_fn(|j| sets[j].parameters());
        assert_eq!(p[0].0, 0.0);
        assert_eq!(p[1].0, 8.0);
        assert_eq!(p[2].0, 12.0);
        assert!(matches!(sets[0], MembershipFunction::LeftShoulder { .. }));
        assert!(matches!(sets[2], MembershipFunction::RightShoulder { .. }));
        assert_eq!(p[1].1, 2.0);
        // A noise floor above half the spacing wins.
        let mut v: [f64; 1200] = core::array::from_fn(|k| (k % 4) as f64 * 4.0);
        let sets = quantile_sets(&mut v, 3, 2.0).unwrap();
        assert_eq!(sets[1].parameters().1, 6.0);
    }

    #[test]
    fn refuses_bad_input() {
        let mut v = [1.0, f64::NAN];
        assert!(quantile_sets(&mut v, 2, 0.1).is_err());
        let mut v = [1.0, 2.0];
        assert!(quantile_sets(&mut v, 0, 0.1).is_err());
        assert!(quantile_sets(&mut v, 4, 0.1).is_err());
        assert!(quantile_sets(&mut v, 2, f64::INFINITY).is_err());
        let mut e: [f64; 0] = [];
        assert!(quantile_sets(&mut e, 1, 0.1).is_err());
    }
}
