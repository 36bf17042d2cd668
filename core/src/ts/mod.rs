//! A Takagi-Sugeno model whose consequent parameters are learnt by RLS (paper Section 4).
//!
//! Rule i says `ŷ_i = α_{i,1} Δ₁ + … + α_{i,D} Δ_D`; the model output is the firing-strength
//! weighted mean `ŷ = Σ ξ_i ŷ_i = ξᵀθ` with the regressor and parameters in the paper's order
//!
//! ```text
//! ξ(k) = [Δ₁ξ₁ … Δ₁ξ_R  …  Δ_Dξ₁ … Δ_Dξ_R]      θ = [α_{1,1} … α_{R,1}  …  α_{1,D} … α_{R,D}]
//! ```
//!
//! so `N = R·D`. The premise (which rules fire) and the consequent terms `Δ_s` are given
//! separately: the helicopter models of [`crate::hover`] compute both from a sample.
//!
//! # Scaling
//!
//! The terms of a helicopter model differ by orders of magnitude (a product of two rates in
//! (deg/s)² next to a product of two sticks of about 0.05), which makes the estimation problem
//! badly conditioned, and f32 loses the small parameters. A [`Scaling`] divides each term by a
//! nominal scale `S_s` and the target by `S_y`, so the estimator works on dimensionless numbers
//! of order one: `Δ̃_s = Δ_s/S_s`, `ỹ = y/S_y`, `θ̃_{i,s} = α_{i,s} S_s / S_y`. Predictions and
//! innovations are returned in physical units, and [`TsRls::physical_parameter`] gives
//! `α_{i,s}` back. With all scales 1 (the default) every number is bit-identical to the
//! unscaled model. Scaling changes the meaning of the prior `P(0) = αI` (it becomes
//! `α S_s²/S_y²` in physical units); with a large α that changes no prediction beyond rounding
//! once the data outweigh the prior.

use crate::error::{ConfigError, Error};
use crate::rls::{
    col, AllParameters, Compensation, Measurement, NotCompensated, RegressorNoise, Rls, RlsConfig,
    RlsState, Run, DENSE_SUMS_UP_TO,
};
use crate::rule_base::RuleBase;
use crate::scalar::Real;

pub mod local;
mod rows;

pub use rows::Prepared;
pub(crate) use rows::{combine, predict_from_blocks, prepare_rows, scaled_terms};
use rows::{fired_mask, fired_runs, regressor_of};

/// Nominal scales of a model's consequent terms and target (see the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Scaling<T, const D: usize> {
    /// `S_s`, in the unit of term s (each finite and > 0).
    pub terms: [T; D],
    /// `S_y`, in the unit of the target (finite and > 0).
    pub target: T,
}

impl<T: Real, const D: usize> Scaling<T, D> {
    /// All scales 1: the model computes exactly as unscaled.
    pub fn unit() -> Self {
        Self {
            terms: [T::one(); D],
            target: T::one(),
        }
    }

    /// Checks that every scale is finite and > 0.
    pub fn validate(&self) -> Result<(), Error> {
        let ok = |s: T| s.is_finite() && s > T::zero();
        if self.terms.iter().all(|&s| ok(s)) && ok(self.target) {
            Ok(())
        } else {
            Err(ConfigError::Scale.into())
        }
    }
}

impl<T: Real, const D: usize> Default for Scaling<T, D> {
    fn default() -> Self {
        Self::unit()
    }
}

/// The constructors of a TS estimator, written once for [`TsRls`] and
/// [`LocalTsRls`](crate::ts::local::LocalTsRls): `with_scaling` (documented by the caller); its checks,
/// `check_new`, which refuses wrong sizes (`dimensions_wrong`), then the scales, then the
/// settings of the RLS estimator type it is built from (`estimator`), in that order; and
/// `with_scaling_unchecked`, whose body (`unchecked`, over the parameter names it gives) is
/// the type's own. Both types have `SIZES_OK`.
macro_rules! constructors {
    (
        $(#[$doc:meta])*
        dimensions_wrong: $wrong:expr,
        estimator: $rls:ty,
        unchecked: |$rules:ident, $config:ident, $scaling:ident| $body:expr $(,)?
    ) => {
        $(#[$doc])*
        pub fn with_scaling(
            rules: $crate::rule_base::RuleBase<T, V, R>,
            config: $crate::rls::RlsConfig<T>,
            scaling: $crate::ts::Scaling<T, D>,
        ) -> Result<Self, $crate::error::Error> {
            Self::check_new(&config, &scaling)?;
            Ok(Self::with_scaling_unchecked(rules, config, scaling))
        }

        /// The checks of [`with_scaling`](Self::with_scaling).
        pub(crate) fn check_new(
            config: &$crate::rls::RlsConfig<T>,
            scaling: &$crate::ts::Scaling<T, D>,
        ) -> Result<(), $crate::error::Error> {
            #[allow(clippy::let_unit_value)]
            let () = Self::SIZES_OK;
            if $wrong {
                return Err($crate::error::ConfigError::Dimensions.into());
            }
            scaling.validate()?;
            <$rls>::check_new(config)
        }

        /// [`with_scaling`](Self::with_scaling) for inputs that passed
        /// [`check_new`](Self::check_new) (built in place, see `Rls::new_unchecked`).
        #[inline(always)]
        pub(crate) fn with_scaling_unchecked(
            $rules: $crate::rule_base::RuleBase<T, V, R>,
            $config: $crate::rls::RlsConfig<T>,
            $scaling: $crate::ts::Scaling<T, D>,
        ) -> Self {
            $body
        }
    };
}
pub(crate) use constructors;

/// A TS rule base over `V` premise variables and `R` rules with `D` consequent terms per rule,
/// `N = R·D` parameters and `NP = N(N+1)/2` packed covariance entries.
#[derive(Clone, Debug, PartialEq)]
pub struct TsRls<T, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
{
    rules: RuleBase<T, V, R>,
    rls: Rls<T, N, NP>,
    scaling: Scaling<T, D>,
    /// The rules that have fired (non-zero ξ_i) since the estimator started afresh, bit i
    /// for rule i; rules from 32 on count as fired always. Only their parameters can be
    /// coupled in P, so the updates visit only those (see [`TsRls::apply`]).
    fired: u32,
}

impl<T: Real, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
    TsRls<T, V, R, D, N, NP>
{
    const SIZES_OK: () = assert!(N == R * D && D >= 1, "TsRls needs N = R·D");

    /// A model with the given rule base and estimator settings (θ(0) = 0, P(0) = αI), unscaled.
    pub fn new(rules: RuleBase<T, V, R>, config: RlsConfig<T>) -> Result<Self, Error> {
        Self::with_scaling(rules, config, Scaling::unit())
    }

    constructors! {
        /// A model whose terms and target are divided by nominal scales.
        dimensions_wrong: N != R * D,
        estimator: Rls<T, N, NP>,
        unchecked: |rules, config, scaling| Self {
            rules,
            rls: Rls::new_unchecked(config),
            scaling,
            fired: 0,
        },
    }

    /// The rule base.
    pub fn rules(&self) -> &RuleBase<T, V, R> {
        &self.rules
    }

    /// The estimator (scaled parameters θ̃, covariance diagnostics).
    pub fn rls(&self) -> &Rls<T, N, NP> {
        &self.rls
    }

    /// With one rule (`N = D`), replaces θ by its estimate with the bias of `noise` removed
    /// (see [`Rls::bias_compensated`]); P is kept. With more rules nothing is compensated
    /// (the regressor `Δ ⊗ ξ` mixes the rules' terms) and the result says so.
    pub fn compensate(&mut self, noise: &RegressorNoise<T, D>) -> Compensation {
        let mut outcome = Compensation::default();
        if R != 1 || N != D {
            for _ in 0..R {
                outcome.record(Err(NotCompensated::Unsupported));
            }
            return outcome;
        }
        let mut with_target = [T::zero(); N];
        for (w, &s) in with_target.iter_mut().zip(noise.with_target.iter()) {
            *w = s;
        }
        let noise = RegressorNoise {
            noisy: noise.noisy,
            variance: noise.variance,
            with_target,
            unit: noise.unit,
            unit_value: noise.unit_value,
            paired: noise.paired,
        };
        outcome.record(self.rls.compensate(&noise));
        outcome
    }

    /// The scales.
    pub fn scaling(&self) -> &Scaling<T, D> {
        &self.scaling
    }

    /// Parameter α_{i,s} of rule i and term s in physical units (`θ̃[s·R + i]·S_y/S_s`).
    pub fn physical_parameter(&self, rule: usize, term: usize) -> Option<T> {
        if rule >= R || term >= D {
            return None;
        }
        let t = self.rls.parameters().get(term * R + rule).copied()?;
        let s = self.scaling.terms.get(term).copied()?;
        Some(t * self.scaling.target / s)
    }

    /// Parameter α_{i,s} as stored (the scaled θ̃; equal to the physical one when unscaled).
    pub fn parameter(&self, rule: usize, term: usize) -> Option<T> {
        if rule >= R || term >= D {
            return None;
        }
        self.rls.parameters().get(term * R + rule).copied()
    }

    /// The (scaled) regressor `ξ(k)` for a premise `x` and consequent terms `Δ`.
    pub fn regressor(&self, premise: &[T; V], terms: &[T; D]) -> Result<[T; N], Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        self.regressor_from(&strengths, terms)
    }

    /// The regressor for firing strengths already computed from the premise.
    #[inline]
    fn regressor_from(&self, strengths: &[T; R], terms: &[T; D]) -> Result<[T; N], Error> {
        Ok(regressor_of(
            strengths,
            &scaled_terms::<T, R, D>(&self.scaling, terms)?,
        ))
    }

    /// `b_s = Σ_i ξ_i θ̃_{s·R+i}`: the rule-weighted parameter of each term. An output with
    /// scaled terms Δ̃ predicts `ξᵀθ̃ = Σ_s Δ̃_s b_s` (see [`combine`]): D·R products for all
    /// outputs instead of N per output.
    fn block_products(&self, strengths: &[T; R]) -> [T; D] {
        let mut b = [T::zero(); D];
        for (bs, theta) in b.iter_mut().zip(self.rls.parameters().chunks_exact(R)) {
            let mut sum = T::zero();
            for (&w, &t) in strengths.iter().zip(theta.iter()) {
                if w != T::zero() {
                    sum += w * t;
                }
            }
            *bs = sum;
        }
        b
    }

    /// `ξᵀθ` for one output, in the target's physical unit.
    pub fn predict(&self, premise: &[T; V], terms: &[T; D]) -> Result<T, Error> {
        let [y] = self.predict_many(premise, &[*terms])?;
        Ok(y)
    }

    /// `ξ_mᵀθ` for M outputs that share the premise (the firing strengths are computed once),
    /// in the target's physical unit; each equal to [`predict`](Self::predict) of its terms.
    ///
    /// Computed as `Σ_s Δ̃_s (Σ_i ξ_i θ̃_{s,i})`, the same sum regrouped by term.
    pub fn predict_many<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        let b = self.block_products(&strengths);
        predict_from_blocks::<T, R, D, M>(&self.scaling, &b, terms)
    }

    /// Learns from M outputs that share θ and the premise, output m having consequent terms
    /// `terms[m]` and target `targets[m]`. Returns the prior innovations (physical units). On
    /// `Err` nothing changed.
    pub fn update<const M: usize>(
        &mut self,
        premise: &[T; V],
        terms: &[[T; D]; M],
        targets: &[T; M],
    ) -> Result<[T; M], Error> {
        let prepared = self.prepare(premise, terms, targets)?;
        self.apply(&prepared);
        Ok(prepared.innovations)
    }

    /// AllParameters [`update`](Self::update) checks and computes, without changing anything.
    /// Pass the result to [`apply`](Self::apply) to learn from it; this lets a caller check
    /// several models before it changes any of them.
    ///
    /// Every scaled term must be within [`REGRESSOR_LIMIT`](crate::rls::REGRESSOR_LIMIT), every scaled target and prior
    /// innovation within [`TARGET_LIMIT`](crate::rls::TARGET_LIMIT). Outputs whose regressors are parallel are learnt as
    /// one measurement (see [`Prepared`]).
    pub fn prepare<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
        targets: &[T; M],
    ) -> Result<Prepared<T, R, D, M>, Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        let b = self.block_products(&strengths);
        prepare_rows(strengths, &b, &self.scaling, terms, targets)
    }

    /// Learns from a [`Prepared`] update made by this model's [`prepare`](Self::prepare)
    /// with the model unchanged since.
    ///
    /// The parameters of a rule that has never fired have regressor entries 0 and rows and
    /// columns of P (or U) that are still those of αI: an update leaves them as they are. The
    /// estimator visits only the others, with the same bits as visiting all: a flight that
    /// excites 3 of the 27 translational rules pays for 6 parameters, not 54.
    pub fn apply<const M: usize>(&mut self, prepared: &Prepared<T, R, D, M>) {
        self.fired |= fired_mask(&prepared.strengths);
        // A model of one rule, or of a few parameters, has nothing (or little) to skip: it
        // takes the bare estimator's dense update, inlined for its size.
        let small = R == 1 || N <= DENSE_SUMS_UP_TO;
        let mut support = [Run { start: 0, end: 0 }; N];
        let runs = if small {
            0
        } else {
            fired_runs(self.fired, R, D, &mut support)
        };
        let support = support.get(..runs).unwrap_or(&[]);
        let last = prepared.count.saturating_sub(1);
        let forgetting = self.rls.config().forgetting;
        for (r, (row, &y)) in prepared.rows_to_learn() {
            let xi: [T; N] = regressor_of(&prepared.strengths, row);
            // Row 0's innovation was computed by `prepare` with this very θ; later rows see θ
            // after the earlier rows of this sample.
            let e = if r == 0 {
                prepared.first
            } else {
                y - self.rls.dot(&xi)
            };
            // λ once per sample: the earlier rows are plain measurement updates.
            let lambda = if r == last { forgetting } else { T::one() };
            if small {
                self.rls
                    .update_row(&xi, AllParameters(N), Measurement::row(e, lambda));
            } else {
                self.rls
                    .update_row(&xi, support, Measurement::row(e, lambda));
            }
        }
    }

    /// The rules whose parameters are coupled in an imported factor (an off-diagonal entry
    /// in one of their rows or columns is non-zero): those the imported flight fired.
    fn coupled_rules(state: &RlsState<T, N, NP>) -> u32 {
        let mut fired = 0u32;
        let mut mark = |p: usize| {
            let rule = p % R;
            if rule < 32 {
                fired |= 1 << rule;
            }
        };
        for j in 1..N {
            let start = col(j);
            let Some(above) = state.factor.get(start..start + j) else {
                break;
            };
            for (i, &u) in above.iter().enumerate() {
                if u != T::zero() {
                    mark(i);
                    mark(j);
                }
            }
        }
        fired
    }

    /// Back to θ = 0, P = αI.
    pub fn reset(&mut self) {
        self.rls.reset();
        self.fired = 0;
    }

    /// Exports θ̃ and the covariance factor (scaled coordinates).
    pub fn export(&self) -> RlsState<T, N, NP> {
        self.rls.export()
    }

    /// Imports θ̃ and the covariance factor (warm start; same scaling expected). On `Err`
    /// nothing changed.
    pub fn import(&mut self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        self.rls.import(state)?;
        self.fired = Self::coupled_rules(state);
        Ok(())
    }

    /// The checks of [`import`](Self::import), without importing.
    pub fn check_import(&self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        self.rls.check_import(state)
    }

    /// New estimator settings and scales, in place, starting afresh. On `Err` nothing changed.
    pub fn reconfigure(
        &mut self,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Result<(), Error> {
        config.validate()?;
        scaling.validate()?;
        self.rls.reconfigure(config)?;
        self.scaling = scaling;
        self.fired = 0;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
