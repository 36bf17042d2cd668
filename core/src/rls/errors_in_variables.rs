//! Errors in variables: the bias that a noisy regressor puts into a least-squares estimate,
//! and its compensation (bias-compensated least squares).
//!
//! RLS minimises `Σ w (y − φᵀθ)²` over the *measured* regressors. When a regressor is itself a
//! noisy measurement (a gyro's rate in a rate model: `φ = φ₀ + n`, `y = y₀ + n_y`), the
//! normal equations converge to `(Σ₀ + Σₙ) θ_LS = c₀ + s` instead of `Σ₀ θ = c₀`, with
//! `Σₙ = E[n nᵀ]` and `s = E[n n_y]`. The estimate is then the best *one-step predictor from
//! noisy measurements*, but not the system's parameters: a free run (a simulation) from it
//! drifts. Bias-compensated least squares (Sagara and Wada, 1977; Zheng, 2002) solves the
//! corrected normal equations `(A − N Σₙ) θ = b − N s` instead, `A = P⁻¹`, that is
//!
//! `θ = θ_LS + N P (Σₙ θ − s)`.
//!
//! Here `Σₙ` has one non-zero entry: one regressor j is noisy with variance `σ_j²`, which is
//! what a rate model whose own rate is a regressor has (the noise of a difference of rates
//! also appears in the target: that is `s`, which may have any entries). Then the solution is
//! closed-form:
//!
//! `θ_j = (θ_LS,j − N (P s)_j) / (1 − N σ_j² P_jj)`,
//! `θ = θ_LS − N P s + N σ_j² θ_j P e_j`.
//!
//! * **N**, the estimator's (weighted, forgotten) number of samples, is read from the
//!   information of a regressor that is constant, the affine term c (value `c₀`):
//!   `(P⁻¹)_cc = Σ w c₀²` (plus the prior's `1/α`, 10⁻⁶ by default, which is neglected). No
//!   counter is kept.
//! * **Guard.** `ρ = N σ_j² P_jj` is the noise's share of regressor j's information. When it
//!   is ½ or more (the regressor moved no more than its noise), the correction would amplify
//!   the estimate's variance more than it removes bias, and the estimate is refused
//!   ([`NotCompensated::TooNoisy`]); so is one from fewer samples than parameters
//!   ([`NotCompensated::TooFewSamples`]).
//! * The U-D form only: the covariance form would need P inverted to read N
//!   ([`NotCompensated::Unsupported`]).
//!
//! **A second noisy regressor** ([`PairedNoise`]): a rate model of second order has the
//! increment `Δω(k−1) = ω(k) − ω(k−1)` as a regressor m too, whose noise `n(k) − n(k−1)` has
//! variance `2σ²` and covariance `σ²` with `ω(k)`'s. `Σₙ` then has the 2×2 block
//! `Σ_B = [[σ_j², c], [c, σ_m²]]` on `B = {j, m}`, and the solution is closed-form still:
//! `(I − N P_BB Σ_B) θ_B = (θ_LS − N P s)_B`, then `θ = θ_LS − N P s + N P_{·B} Σ_B θ_B`. The
//! guard asks both eigenvalues of `N P_BB Σ_B` below ½ (`det(½I − K) > 0` and
//! `tr(½I − K) > 0`, no square root), and the compensated rate's own dynamics
//! `ω(k+1) = (1 + δ + η) ω(k) − η ω(k−1)` to stay stable: a noise correction that turns a
//! damped rate into a growing one has amplified an estimate's error, not removed a bias. Where
//! either fails, j's noise alone is compensated (as without the pair), so that a pair never
//! leaves a rule less compensated than j alone would.
//!
//! [`Rls::bias_compensated`] returns the parameters and changes nothing; [`Rls::compensate`]
//! writes them into θ (P is kept).

use super::{col, Algorithm, Rls, RlsConfig, RlsCore, PARAMETER_LIMIT};
use crate::scalar::{within, Real};

/// The noise of one regressor, in the estimator's (scaled) units: what
/// [`Rls::bias_compensated`] removes.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RegressorNoise<T, const N: usize> {
    /// j: the regressor measured with noise.
    pub noisy: usize,
    /// `σ_j²`: the variance of its noise (≥ 0).
    pub variance: T,
    /// `s = E[n n_y]`: the covariance of each regressor's noise with the target's noise.
    pub with_target: [T; N],
    /// c: a regressor that is constant (the affine term), whose information counts the
    /// samples.
    pub unit: usize,
    /// The value of regressor c (1 unscaled; `1/S_c` scaled): N = `(P⁻¹)_cc / value²`.
    pub unit_value: T,
    /// A second noisy regressor whose noise correlates with j's (`None`: j alone is noisy).
    pub paired: Option<PairedNoise<T>>,
}

/// The second noisy regressor m of a [`RegressorNoise`]: in a rate model, the second-order
/// term `Δω(k−1)` beside the damping term `ω(k)` (regressor j). See the
/// [module docs](self).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PairedNoise<T> {
    /// m: the second regressor measured with noise.
    pub index: usize,
    /// `σ_m²`: the variance of its noise (≥ 0).
    pub variance: T,
    /// The covariance of its noise with regressor j's.
    pub covariance: T,
    /// `[f_j, f_m]`: the damping `δ = f_j θ_j` and the second-order coefficient `η = f_m θ_m`
    /// of the rate's own dynamics `ω(k+1) = (1 + δ + η) ω(k) − η ω(k−1)` (the target's scale
    /// over each term's), which the pair's compensation must keep stable (else j's noise
    /// alone is compensated).
    pub dynamics: [T; 2],
}

/// Why [`Rls::bias_compensated`] returned no parameters (the estimator's own stand).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum NotCompensated {
    /// The covariance form, or a slot outside the N parameters.
    Unsupported,
    /// A variance that is negative or not finite, or a covariance that is not finite.
    InvalidNoise,
    /// Fewer samples (N) than parameters: the estimate is still mostly the prior.
    TooFewSamples,
    /// The noise is half or more of the noisy regressor's information (ρ ≥ ½).
    TooNoisy,
    /// A factor entry or a result that is not finite, or a non-positive D entry.
    Numerical,
}

/// What compensating a model's rules did ([`TsEstimator::compensate`](crate::learning::TsEstimator::compensate)).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Compensation {
    /// Rules whose θ was replaced by its compensated estimate.
    pub compensated: u16,
    /// Rules left as they were.
    pub refused: u16,
    /// Why the last refused rule was.
    pub reason: Option<NotCompensated>,
}

impl Compensation {
    /// Counts one rule's outcome.
    pub fn record(&mut self, outcome: Result<(), NotCompensated>) {
        match outcome {
            Ok(()) => self.compensated = self.compensated.saturating_add(1),
            Err(why) => {
                self.refused = self.refused.saturating_add(1);
                self.reason = Some(why);
            }
        }
    }

    /// Both counts together (`other`'s reason if it has one).
    #[must_use]
    pub fn and(self, other: Self) -> Self {
        Self {
            compensated: self.compensated.saturating_add(other.compensated),
            refused: self.refused.saturating_add(other.refused),
            reason: other.reason.or(self.reason),
        }
    }
}

impl<T: Real, const N: usize, const NP: usize> Rls<T, N, NP> {
    /// Replaces θ by [`bias_compensated`](Self::bias_compensated)'s estimate (P is kept); on
    /// `Err` nothing changes.
    pub fn compensate(&mut self, noise: &RegressorNoise<T, N>) -> Result<(), NotCompensated> {
        self.core.compensate(&self.config, noise)
    }

    /// θ with the bias of `noise` removed (see [`errors_in_variables`](super::errors_in_variables)); the estimator is not
    /// changed. With zero noise it is θ, bit for bit.
    pub fn bias_compensated(&self, noise: &RegressorNoise<T, N>) -> Result<[T; N], NotCompensated> {
        self.core.bias_compensated(&self.config, noise)
    }
}

impl<T: Real, const N: usize, const NP: usize> RlsCore<T, N, NP> {
    /// [`Rls::compensate`].
    pub(crate) fn compensate(
        &mut self,
        config: &RlsConfig<T>,
        noise: &RegressorNoise<T, N>,
    ) -> Result<(), NotCompensated> {
        self.theta = self.bias_compensated(config, noise)?;
        Ok(())
    }

    /// [`Rls::bias_compensated`].
    pub(crate) fn bias_compensated(
        &self,
        config: &RlsConfig<T>,
        noise: &RegressorNoise<T, N>,
    ) -> Result<[T; N], NotCompensated> {
        if config.algorithm != Algorithm::UdFactor || noise.noisy >= N || noise.unit >= N {
            return Err(NotCompensated::Unsupported);
        }
        if noise
            .paired
            .is_some_and(|m| m.index >= N || m.index == noise.noisy)
        {
            return Err(NotCompensated::Unsupported);
        }
        let paired_ok = noise.paired.is_none_or(|m| {
            m.variance >= T::zero()
                && m.variance.is_finite()
                && m.covariance.is_finite()
                && m.dynamics.iter().all(|f| f.is_finite())
        });
        let finite = paired_ok && noise.with_target.iter().all(|s| s.is_finite());
        let unit_ok = noise.unit_value.is_finite() && noise.unit_value != T::zero();
        if !(finite && unit_ok && noise.variance >= T::zero() && noise.variance.is_finite()) {
            return Err(NotCompensated::InvalidNoise);
        }
        let paired_zero = noise
            .paired
            .is_none_or(|m| m.variance == T::zero() && m.covariance == T::zero());
        if paired_zero
            && noise.variance == T::zero()
            && noise.with_target.iter().all(|&s| s == T::zero())
        {
            return Ok(self.theta);
        }
        let factor = self.factor.as_slice();
        let information =
            unit_information::<T, N>(factor, noise.unit).ok_or(NotCompensated::Numerical)?;
        let samples = information / (noise.unit_value * noise.unit_value);
        let p_s = ud_times::<T, N>(factor, &noise.with_target);
        let mut e_j = [T::zero(); N];
        if let Some(x) = e_j.get_mut(noise.noisy) {
            *x = T::one();
        }
        let p_j = ud_times::<T, N>(factor, &e_j);
        let at = |v: &[T; N]| v.get(noise.noisy).copied().unwrap_or_else(T::zero);
        let share = samples * noise.variance * at(&p_j);
        if !share.is_finite() {
            return Err(NotCompensated::Numerical);
        }
        if samples < T::lit(N as f64) {
            return Err(NotCompensated::TooFewSamples);
        }
        if share >= T::lit(0.5) {
            return Err(NotCompensated::TooNoisy);
        }
        let paired = noise
            .paired
            .map(|m| self.paired_compensated(noise, &m, samples, &p_s, &p_j));
        let theta = match paired {
            Some(Some(theta)) => theta,
            // j alone: without a pair, or where the pair is too noisy or its compensation
            // unstable (the data determine j's correction, not m's).
            _ => {
                let theta_j = (at(&self.theta) - samples * at(&p_s)) / (T::one() - share);
                let gain = samples * noise.variance * theta_j;
                let mut theta = self.theta;
                for ((t, &ps), &pj) in theta.iter_mut().zip(p_s.iter()).zip(p_j.iter()) {
                    *t = *t - samples * ps + gain * pj;
                }
                theta
            }
        };
        // Within the import bound: a compensated θ beyond it could make a later prediction
        // overflow after a step had written its update.
        if theta.iter().all(|&t| within(t, T::lit(PARAMETER_LIMIT))) {
            Ok(theta)
        } else {
            Err(NotCompensated::Numerical)
        }
    }

    /// θ compensated for two noisy regressors j and m (see the [module docs](self)), given
    /// N, `P s` and `P e_j`; `None` where the pair's noise share is too large or the result
    /// unstable.
    fn paired_compensated(
        &self,
        noise: &RegressorNoise<T, N>,
        paired: &PairedNoise<T>,
        samples: T,
        p_s: &[T; N],
        p_j: &[T; N],
    ) -> Option<[T; N]> {
        let (j, m) = (noise.noisy, paired.index);
        let mut e_m = [T::zero(); N];
        if let Some(x) = e_m.get_mut(m) {
            *x = T::one();
        }
        let p_m = ud_times::<T, N>(self.factor.as_slice(), &e_m);
        let at = |v: &[T; N], i: usize| v.get(i).copied().unwrap_or_else(T::zero);
        let (p_jj, p_jm, p_mm) = (at(p_j, j), at(p_j, m), at(&p_m, m));
        let (s_jj, s_jm, s_mm) = (noise.variance, paired.covariance, paired.variance);
        // K = N P_BB Σ_B.
        let k11 = samples * (p_jj * s_jj + p_jm * s_jm);
        let k12 = samples * (p_jj * s_jm + p_jm * s_mm);
        let k21 = samples * (p_jm * s_jj + p_mm * s_jm);
        let k22 = samples * (p_jm * s_jm + p_mm * s_mm);
        // Both eigenvalues of K below ½: those of ½I − K positive (they are real: K is the
        // product of two symmetric positive semi-definite matrices).
        let half = T::lit(0.5);
        let (h11, h22) = (half - k11, half - k22);
        let det_half = h11 * h22 - k12 * k21;
        if !(det_half.is_finite() && h11 + h22 > T::zero() && det_half > T::zero()) {
            return None;
        }
        // (I − K) θ_B = r.
        let (r1, r2) = (
            at(&self.theta, j) - samples * at(p_s, j),
            at(&self.theta, m) - samples * at(p_s, m),
        );
        let (a11, a22) = (T::one() - k11, T::one() - k22);
        let det = a11 * a22 - k12 * k21;
        let theta_j = (r1 * a22 + k12 * r2) / det;
        let theta_m = (a11 * r2 + k21 * r1) / det;
        let gain_j = samples * (s_jj * theta_j + s_jm * theta_m);
        let gain_m = samples * (s_jm * theta_j + s_mm * theta_m);
        let mut theta = self.theta;
        for (((t, &ps), &pj), &pm) in theta.iter_mut().zip(p_s).zip(p_j).zip(p_m.iter()) {
            *t = *t - samples * ps + gain_j * pj + gain_m * pm;
        }
        let [f_j, f_m] = paired.dynamics;
        stable_second_order(f_j * at(&theta, j), f_m * at(&theta, m)).then_some(theta)
    }
}

/// Whether `ω(k+1) = (1 + δ + η) ω(k) − η ω(k−1)` is stable: both roots of
/// `z² + c1 z + c0`, `c1 = −(1 + δ + η)`, `c0 = η`, inside the unit circle (Jury: `|c0| < 1`
/// and `|c1| < 1 + c0`). False for non-finite coefficients.
fn stable_second_order<T: Real>(delta: T, eta: T) -> bool {
    let c1 = -(T::one() + delta + eta);
    c1.abs() < T::one() + eta && eta.abs() < T::one()
}

/// `(P⁻¹)_cc` from the packed U-D factors: `Σ_k z_k² / d_k` with `z = U⁻¹ e_c` (back
/// substitution; U is unit upper triangular). `None` for a non-positive or non-finite D entry.
fn unit_information<T: Real, const N: usize>(factor: &[T], c: usize) -> Option<T> {
    let at = |i: usize, k: usize| factor.get(col(k) + i).copied();
    let mut z = [T::zero(); N];
    *z.get_mut(c)? = T::one();
    // z_k = −Σ_{k<j≤c} U_kj z_j, from k = c − 1 down to 0.
    for k in (0..c).rev() {
        let mut acc = T::zero();
        for j in k + 1..=c {
            acc += at(k, j)? * *z.get(j)?;
        }
        *z.get_mut(k)? = -acc;
    }
    let mut information = T::zero();
    for (k, &zk) in z.iter().enumerate().take(c + 1) {
        let d = at(k, k)?;
        if !(d > T::zero() && d.is_finite()) {
            return None;
        }
        information += zk * zk / d;
    }
    information.is_finite().then_some(information)
}

/// `P v = U (D (Uᵀ v))` from the packed U-D factors (entry (i, k), i < k, of U at
/// `col(k) + i`; D on the diagonal).
fn ud_times<T: Real, const N: usize>(factor: &[T], v: &[T; N]) -> [T; N] {
    let at = |i: usize, k: usize| factor.get(col(k) + i).copied().unwrap_or_else(T::zero);
    // w = D Uᵀ v: w_k = d_k (v_k + Σ_{i<k} U_ik v_i).
    let mut w = [T::zero(); N];
    for (k, wk) in w.iter_mut().enumerate() {
        let mut acc = v.get(k).copied().unwrap_or_else(T::zero);
        for (i, &vi) in v.iter().enumerate().take(k) {
            acc += at(i, k) * vi;
        }
        *wk = at(k, k) * acc;
    }
    // x = U w: x_i = w_i + Σ_{k>i} U_ik w_k.
    let mut x = [T::zero(); N];
    for (i, xi) in x.iter_mut().enumerate() {
        let mut acc = w.get(i).copied().unwrap_or_else(T::zero);
        for (k, &wk) in w.iter().enumerate().skip(i + 1) {
            acc += at(i, k) * wk;
        }
        *xi = acc;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64: uniform in [−1, 1).
    struct Uniform(u64);
    impl Uniform {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// `ω₀(k+1) = a ω₀(k) + b u(k) + c`, measured `ω = ω₀ + n` (white, variance σ²); the
    /// estimator learns the increment `ω(k+1) − ω(k)` on `[ω(k), u(k), 1]`, so that the
    /// noise of `ω(k)` is in a regressor and (negated) in the target.
    fn learn(sigma: f64) -> (Rls<f64, 3, 6>, RegressorNoise<f64, 3>, [f64; 3]) {
        let (a, b, c) = (0.9, 0.5, 0.2);
        let mut rls = Rls::<f64, 3, 6>::new(RlsConfig::default()).unwrap();
        let mut rng = Uniform(0x9E37_79B9_7F4A_7C15);
        let noise_amplitude = sigma * 3f64.sqrt(); // uniform in [−√3σ, √3σ]: variance σ²
        let (mut omega0, mut u) = (0.0, 0.0);
        let mut measured = omega0 + noise_amplitude * rng.next();
        for k in 0..40_000 {
            if k % 25 == 0 {
                u = rng.next();
            }
            let next0 = a * omega0 + b * u + c;
            let next = next0 + noise_amplitude * rng.next();
            rls.update(&[measured, u, 1.0], next - measured).unwrap();
            (omega0, measured) = (next0, next);
        }
        let noise = RegressorNoise {
            noisy: 0,
            variance: sigma * sigma,
            with_target: [-sigma * sigma, 0.0, 0.0],
            unit: 2,
            unit_value: 1.0,
            paired: None,
        };
        (rls, noise, [a - 1.0, b, c])
    }

    #[test]
    fn removes_the_bias_of_a_noisy_regressor() {
        let (rls, noise, truth) = learn(0.3);
        let ls = *rls.parameters();
        let compensated = rls.bias_compensated(&noise).unwrap();
        // The noise pulls the damping a − 1 well away from the truth; compensated, it is
        // back within a fifth of that error, and so is every other parameter.
        let ls_error = (ls[0] - truth[0]).abs();
        assert!(ls_error > 0.02, "LS damping {} vs {}", ls[0], truth[0]);
        for j in 0..3 {
            let (e_ls, e_bc) = ((ls[j] - truth[j]).abs(), (compensated[j] - truth[j]).abs());
            assert!(
                e_bc < 0.2 * ls_error.max(e_ls),
                "θ_{j}: LS {} BC {} truth {}",
                ls[j],
                compensated[j],
                truth[j]
            );
        }
        // The estimator itself is unchanged; `compensate` writes the same θ.
        assert_eq!(rls.parameters().map(f64::to_bits), ls.map(f64::to_bits));
        let mut written = rls.clone();
        written.compensate(&noise).unwrap();
        assert_eq!(
            written.parameters().map(f64::to_bits),
            compensated.map(f64::to_bits)
        );
    }

    /// `ω₀(k+1) = a1 ω₀(k) + a2 ω₀(k−1) + b u(k) + c`, measured with white noise of variance
    /// σ²; learnt as the increment on `[ω(k), u(k), 1, Δω(k−1)]`, whose first and last
    /// regressors are noisy (their noises correlate). The truth in those terms:
    /// `δ = a1 + a2 − 1`, `η = −a2`.
    fn learn_second_order(sigma: f64) -> (Rls<f64, 4, 10>, RegressorNoise<f64, 4>, [f64; 4]) {
        let (a1, a2, b, c) = (1.5, -0.6, 0.5, 0.2);
        let mut rls = Rls::<f64, 4, 10>::new(RlsConfig::default()).unwrap();
        let mut rng = Uniform(0x2545_F491_4F6C_DD1D);
        let amplitude = sigma * 3f64.sqrt();
        let (mut now0, mut before0, mut u) = (0.0, 0.0, 0.0);
        let (mut now, mut before) = (amplitude * rng.next(), amplitude * rng.next());
        for k in 0..100_000 {
            if k % 5 == 0 {
                u = rng.next();
            }
            let next0 = a1 * now0 + a2 * before0 + b * u + c;
            let next = next0 + amplitude * rng.next();
            rls.update(&[now, u, 1.0, now - before], next - now)
                .unwrap();
            (before0, now0, before, now) = (now0, next0, now, next);
        }
        let v = sigma * sigma;
        let noise = RegressorNoise {
            noisy: 0,
            variance: v,
            with_target: [-v, 0.0, 0.0, -v],
            unit: 2,
            unit_value: 1.0,
            paired: Some(PairedNoise {
                index: 3,
                variance: 2.0 * v,
                covariance: v,
                dynamics: [1.0, 1.0],
            }),
        };
        (rls, noise, [a1 + a2 - 1.0, b, c, -a2])
    }

    #[test]
    fn removes_the_bias_of_two_correlated_noisy_regressors() {
        let (rls, noise, truth) = learn_second_order(0.15);
        let ls = *rls.parameters();
        let both = rls.bias_compensated(&noise).unwrap();
        let one = rls
            .bias_compensated(&RegressorNoise {
                paired: None,
                ..noise
            })
            .unwrap();
        let error = |theta: &[f64; 4]| {
            theta
                .iter()
                .zip(&truth)
                .map(|(t, x)| (t - x).abs())
                .fold(0.0, f64::max)
        };
        // The noise biases least squares; removing ω(k)'s alone leaves Δω(k−1)'s bias, both
        // together bring every parameter close to the truth.
        assert!(error(&ls) > 0.05, "LS {ls:?} vs {truth:?}");
        assert!(error(&one) > 0.05, "one {one:?} vs {truth:?}");
        assert!(
            error(&both) < 0.2 * error(&one),
            "both {both:?} vs {truth:?}"
        );
    }

    #[test]
    fn falls_back_to_one_regressor_where_the_pair_cannot_be_compensated() {
        let (rls, noise, _) = learn_second_order(0.15);
        let paired = noise.paired.unwrap();
        let alone = rls
            .bias_compensated(&RegressorNoise {
                paired: None,
                ..noise
            })
            .unwrap();
        // The same estimate read as a rate whose η is ten times the learnt one (|η| > 1,
        // unstable), and a pair whose noise is as large as its whole spread: j alone.
        let unstable = PairedNoise {
            dynamics: [1.0, 10.0],
            ..paired
        };
        let loud = PairedNoise {
            variance: 100.0,
            ..paired
        };
        for pair in [unstable, loud] {
            let theta = rls
                .bias_compensated(&RegressorNoise {
                    paired: Some(pair),
                    ..noise
                })
                .unwrap();
            assert_eq!(theta.map(f64::to_bits), alone.map(f64::to_bits));
        }
        let same_regressor = RegressorNoise {
            paired: Some(PairedNoise { index: 0, ..paired }),
            ..noise
        };
        assert_eq!(
            rls.bias_compensated(&same_regressor),
            Err(NotCompensated::Unsupported)
        );
        let nan = RegressorNoise {
            paired: Some(PairedNoise {
                covariance: f64::NAN,
                ..paired
            }),
            ..noise
        };
        assert_eq!(
            rls.bias_compensated(&nan),
            Err(NotCompensated::InvalidNoise)
        );
        assert!(stable_second_order(-0.05, -0.45));
        assert!(!stable_second_order(0.05, -0.55));
        assert!(!stable_second_order(0.0, 1.2));
        assert!(!stable_second_order(f64::NAN, 0.0));
    }

    #[test]
    fn zero_noise_gives_theta_bit_for_bit() {
        let (rls, mut noise, _) = learn(0.3);
        noise.variance = 0.0;
        noise.with_target = [0.0; 3];
        let theta = rls.bias_compensated(&noise).unwrap();
        assert_eq!(theta.map(f64::to_bits), rls.parameters().map(f64::to_bits));
    }

    #[test]
    fn refuses_what_it_cannot_compensate() {
        let (rls, noise, _) = learn(0.3);
        // Noise as large as the regressor's whole spread: ρ ≥ ½.
        let loud = RegressorNoise {
            variance: 100.0,
            ..noise
        };
        assert_eq!(rls.bias_compensated(&loud), Err(NotCompensated::TooNoisy));
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            let invalid = RegressorNoise {
                variance: bad,
                ..noise
            };
            assert_eq!(
                rls.bias_compensated(&invalid),
                Err(NotCompensated::InvalidNoise)
            );
        }
        let outside = RegressorNoise { unit: 3, ..noise };
        assert_eq!(
            rls.bias_compensated(&outside),
            Err(NotCompensated::Unsupported)
        );
        let mut refused = rls.clone();
        assert_eq!(refused.compensate(&loud), Err(NotCompensated::TooNoisy));
        assert_eq!(refused, rls);
        let covariance_form = Rls::<f64, 3, 6>::new(RlsConfig::paper(1e6)).unwrap();
        assert_eq!(
            covariance_form.bias_compensated(&noise),
            Err(NotCompensated::Unsupported)
        );
        // Nothing learnt: the unit term's information is the prior's 1/α.
        let fresh = Rls::<f64, 3, 6>::new(RlsConfig::default()).unwrap();
        assert_eq!(
            fresh.bias_compensated(&noise),
            Err(NotCompensated::TooFewSamples)
        );
    }
}
