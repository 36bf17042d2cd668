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

use crate::error::{ConfigError, Error, Quantity};
use crate::rls::{Rls, RlsConfig, RlsState};
use crate::rule_base::RuleBase;
use crate::scalar::Real;

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

/// A TS rule base over `V` premise variables and `R` rules with `D` consequent terms per rule,
/// `N = R·D` parameters and `NP = N(N+1)/2` packed covariance entries.
#[derive(Clone, Debug, PartialEq)]
pub struct TsRls<T, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
{
    rules: RuleBase<T, V, R>,
    rls: Rls<T, N, NP>,
    scaling: Scaling<T, D>,
}

impl<T: Real, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
    TsRls<T, V, R, D, N, NP>
{
    const SIZES_OK: () = assert!(N == R * D && D >= 1, "TsRls needs N = R·D");

    /// A model with the given rule base and estimator settings (θ(0) = 0, P(0) = αI), unscaled.
    pub fn new(rules: RuleBase<T, V, R>, config: RlsConfig<T>) -> Result<Self, Error> {
        Self::with_scaling(rules, config, Scaling::unit())
    }

    /// A model whose terms and target are divided by nominal scales.
    pub fn with_scaling(
        rules: RuleBase<T, V, R>,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Result<Self, Error> {
        Self::check_new(&config, &scaling)?;
        Ok(Self::with_scaling_unchecked(rules, config, scaling))
    }

    /// The checks of [`with_scaling`](Self::with_scaling).
    pub(crate) fn check_new(config: &RlsConfig<T>, scaling: &Scaling<T, D>) -> Result<(), Error> {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_OK;
        if N != R * D {
            return Err(ConfigError::Dimensions.into());
        }
        scaling.validate()?;
        Rls::<T, N, NP>::check_new(config)
    }

    /// [`with_scaling`](Self::with_scaling) for inputs that passed
    /// [`check_new`](Self::check_new) (built in place, see `Rls::new_unchecked`).
    #[inline(always)]
    pub(crate) fn with_scaling_unchecked(
        rules: RuleBase<T, V, R>,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Self {
        Self {
            rules,
            rls: Rls::new_unchecked(config),
            scaling,
        }
    }

    /// The rule base.
    pub fn rules(&self) -> &RuleBase<T, V, R> {
        &self.rules
    }

    /// The estimator (scaled parameters θ̃, covariance diagnostics).
    pub fn rls(&self) -> &Rls<T, N, NP> {
        &self.rls
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
        for (s, t) in terms.iter().enumerate() {
            if !t.is_finite() {
                return Err(Error::NonFinite(Quantity::Regressor((s * R) as u16)));
            }
        }
        let mut xi = [T::zero(); N];
        for ((block, &delta), &scale) in xi
            .chunks_exact_mut(R)
            .zip(terms.iter())
            .zip(self.scaling.terms.iter())
        {
            let d = delta / scale;
            for (x, &w) in block.iter_mut().zip(strengths.iter()) {
                *x = d * w;
            }
        }
        Ok(xi)
    }

    /// `ξᵀθ` for one output, in the target's physical unit.
    pub fn predict(&self, premise: &[T; V], terms: &[T; D]) -> Result<T, Error> {
        let [y] = self.predict_many(premise, &[*terms])?;
        Ok(y)
    }

    /// `ξ_mᵀθ` for M outputs that share the premise (the firing strengths are computed once),
    /// in the target's physical unit; each equal to [`predict`](Self::predict) of its terms.
    pub fn predict_many<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        let mut out = [T::zero(); M];
        for (o, t) in out.iter_mut().zip(terms.iter()) {
            let xi = self.regressor_from(&strengths, t)?;
            *o = self.rls.predict(&xi)? * self.scaling.target;
        }
        Ok(out)
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

    /// Everything [`update`](Self::update) checks and computes, without changing anything.
    /// Pass the result to [`apply`](Self::apply) to learn from it; this lets a caller check
    /// several models before it changes any of them.
    pub fn prepare<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
        targets: &[T; M],
    ) -> Result<Prepared<T, N, M>, Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        let mut regressors = [[T::zero(); N]; M];
        for (xi, t) in regressors.iter_mut().zip(terms.iter()) {
            *xi = self.regressor_from(&strengths, t)?;
        }
        let mut scaled = [T::zero(); M];
        for (m, (s, &y)) in scaled.iter_mut().zip(targets.iter()).enumerate() {
            if !y.is_finite() {
                return Err(Error::NonFinite(Quantity::Target(m as u8)));
            }
            *s = y / self.scaling.target;
        }
        let scaled_innovations = self.rls.check(&regressors, &scaled)?;
        Ok(Prepared {
            regressors,
            targets: scaled,
            scaled_innovations,
            innovations: scaled_innovations.map(|e| e * self.scaling.target),
        })
    }

    /// Learns from a [`Prepared`] update made by this model's [`prepare`](Self::prepare)
    /// with the model unchanged since.
    pub fn apply<const M: usize>(&mut self, prepared: &Prepared<T, N, M>) {
        self.rls.apply(
            &prepared.regressors,
            &prepared.targets,
            &prepared.scaled_innovations,
        );
    }

    /// Back to θ = 0, P = αI.
    pub fn reset(&mut self) {
        self.rls.reset();
    }

    /// Exports θ̃ and the covariance factor (scaled coordinates).
    pub fn export(&self) -> RlsState<T, N, NP> {
        self.rls.export()
    }

    /// Imports θ̃ and the covariance factor (warm start; same scaling expected). On `Err`
    /// nothing changed.
    pub fn import(&mut self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        self.rls.import(state)
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
        self.scaling = scaling;
        self.rls.reconfigure(config)
    }
}

/// A checked update of M outputs, ready to [`TsRls::apply`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Prepared<T, const N: usize, const M: usize> {
    regressors: [[T; N]; M],
    targets: [T; M],
    scaled_innovations: [T; M],
    /// Prior innovations `y_m − ŷ_m(k)` in physical units.
    pub innovations: [T; M],
}
