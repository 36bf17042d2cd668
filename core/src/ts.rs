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

use crate::error::{ConfigError, Error, Quantity};
use crate::rls::{Rls, RlsConfig, RlsState};
use crate::rule_base::RuleBase;
use crate::scalar::Real;

/// A TS rule base over `V` premise variables and `R` rules with `D` consequent terms per rule,
/// `N = R·D` parameters and `NP = N(N+1)/2` packed covariance entries.
#[derive(Clone, Debug, PartialEq)]
pub struct TsRls<T, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
{
    rules: RuleBase<T, V, R>,
    rls: Rls<T, N, NP>,
}

impl<T: Real, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
    TsRls<T, V, R, D, N, NP>
{
    const SIZES_OK: () = assert!(N == R * D && D >= 1, "TsRls needs N = R·D");

    /// A model with the given rule base and estimator settings (θ(0) = 0, P(0) = αI).
    pub fn new(rules: RuleBase<T, V, R>, config: RlsConfig<T>) -> Result<Self, Error> {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_OK;
        if N != R * D {
            return Err(ConfigError::Dimensions.into());
        }
        Ok(Self {
            rules,
            rls: Rls::new(config)?,
        })
    }

    /// The rule base.
    pub fn rules(&self) -> &RuleBase<T, V, R> {
        &self.rules
    }

    /// The estimator (parameters, covariance diagnostics).
    pub fn rls(&self) -> &Rls<T, N, NP> {
        &self.rls
    }

    /// Parameter α_{i,s} of rule i and term s (paper order: `θ[s·R + i]`).
    pub fn parameter(&self, rule: usize, term: usize) -> Option<T> {
        if rule >= R || term >= D {
            return None;
        }
        self.rls.parameters().get(term * R + rule).copied()
    }

    /// The regressor `ξ(k)` for a premise `x` and consequent terms `Δ`.
    pub fn regressor(&self, premise: &[T; V], terms: &[T; D]) -> Result<[T; N], Error> {
        let strengths = self.rules.firing_strengths(premise)?;
        for (s, t) in terms.iter().enumerate() {
            if !t.is_finite() {
                return Err(Error::NonFinite(Quantity::Regressor((s * R) as u16)));
            }
        }
        let mut xi = [T::zero(); N];
        for (block, &delta) in xi.chunks_exact_mut(R).zip(terms.iter()) {
            for (x, &w) in block.iter_mut().zip(strengths.iter()) {
                *x = delta * w;
            }
        }
        Ok(xi)
    }

    /// `ξᵀθ` for one output.
    pub fn predict(&self, premise: &[T; V], terms: &[T; D]) -> Result<T, Error> {
        let xi = self.regressor(premise, terms)?;
        self.rls.predict(&xi)
    }

    /// Learns from M outputs that share θ and the premise, output m having consequent terms
    /// `terms[m]` and target `targets[m]`. Returns the prior innovations. On `Err` nothing
    /// changed.
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
        let mut regressors = [[T::zero(); N]; M];
        for (xi, t) in regressors.iter_mut().zip(terms.iter()) {
            *xi = self.regressor(premise, t)?;
        }
        let innovations = self.rls.check(&regressors, targets)?;
        Ok(Prepared {
            regressors,
            targets: *targets,
            innovations,
        })
    }

    /// Learns from a [`Prepared`] update made by this model's [`prepare`](Self::prepare)
    /// with the model unchanged since.
    pub fn apply<const M: usize>(&mut self, prepared: &Prepared<T, N, M>) {
        self.rls.apply(
            &prepared.regressors,
            &prepared.targets,
            &prepared.innovations,
        );
    }

    /// Back to θ = 0, P = αI.
    pub fn reset(&mut self) {
        self.rls.reset();
    }

    /// Exports θ and the covariance factor.
    pub fn export(&self) -> RlsState<T, N, NP> {
        self.rls.export()
    }

    /// Imports θ and the covariance factor (warm start). On `Err` nothing changed.
    pub fn import(&mut self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        self.rls.import(state)
    }
}

/// A checked update of M outputs, ready to [`TsRls::apply`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Prepared<T, const N: usize, const M: usize> {
    regressors: [[T; N]; M],
    targets: [T; M],
    /// Prior innovations `y_m − ξ_mᵀθ(k)`.
    pub innovations: [T; M],
}
