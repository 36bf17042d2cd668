//! How a TS model learns its consequent parameters: the [`Learning`] value and the
//! [`TsEstimator`] trait that the global ([`TsRls`]) and the local ([`LocalTsRls`]) estimator
//! share, so that the helicopter models are written once over either.

use crate::error::Error;
use crate::rls::{Compensation, RegressorNoise, RlsConfig, RlsState, RlsView};
use crate::rule_base::RuleBase;
use crate::scalar::Real;
use crate::ts::local::{LocalState, LocalTsRls};
use crate::ts::{Prepared, Scaling, TsRls};

/// How the consequent parameters θ of a TS model are learnt.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Learning {
    /// The paper's Section 4: one RLS over every rule's parameters, on the regressor
    /// `Δ ⊗ ξ` ([`TsRls`]).
    Global,
    /// Each rule by its own RLS weighted by its firing strength ξ_i ([`LocalTsRls`]).
    Local,
}

/// A TS model with RLS-learnt consequents over `V` premise variables, `R` rules and `D`
/// consequent terms per rule. Sizes are const generics, so each [`Learning`] is its own type;
/// [`TsEstimator::LEARNING`] says which.
pub trait TsEstimator<T: Real, const V: usize, const R: usize, const D: usize>: Sized {
    /// What [`export`](Self::export) returns and [`import`](Self::import) takes.
    type State: Copy;
    /// How this estimator learns.
    const LEARNING: Learning;

    /// The checks of [`build`](Self::build).
    fn check_new(config: &RlsConfig<T>, scaling: &Scaling<T, D>) -> Result<(), Error>;
    /// A fresh estimator (θ = 0, P = αI) from settings that passed
    /// [`check_new`](Self::check_new).
    fn build(rules: RuleBase<T, V, R>, config: RlsConfig<T>, scaling: Scaling<T, D>) -> Self;
    /// The rule base.
    fn rules(&self) -> &RuleBase<T, V, R>;
    /// The estimator settings.
    fn config(&self) -> &RlsConfig<T>;
    /// The scales of the consequent terms and target.
    fn scaling(&self) -> &Scaling<T, D>;
    /// `α_{i,s}` of rule i, term s, in physical units.
    fn physical_parameter(&self, rule: usize, term: usize) -> Option<T>;
    /// Predictions of M outputs that share the premise (target unit).
    fn predict_many<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error>;
    /// [`predict_many`](Self::predict_many) from `&mut self`: the same predictions, and the
    /// estimator may keep what [`prepare`](Self::prepare) from the same premise needs next
    /// (the global estimator keeps nothing: the paper's identifier has no room for it).
    /// `strengths`: the rule base's firing strengths at `premise` if the caller has them
    /// (from an estimator with the same rule base), which the estimator may take instead of
    /// computing them (see [`LocalTsRls::predict_keep`]).
    fn predict_keep<const M: usize>(
        &mut self,
        premise: &[T; V],
        strengths: Option<&[T; R]>,
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        let _ = strengths;
        self.predict_many(premise, terms)
    }
    /// The firing strengths the last [`predict_keep`](Self::predict_keep) used, if the
    /// estimator kept them and θ has not changed since.
    fn kept_strengths(&self) -> Option<&[T; R]> {
        None
    }
    /// Checks and computes an update without changing anything.
    fn prepare<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
        targets: &[T; M],
    ) -> Result<Prepared<T, R, D, M>, Error>;
    /// Learns from a prepared update.
    fn apply<const M: usize>(&mut self, prepared: &Prepared<T, R, D, M>);
    /// Back to θ = 0, P = αI.
    fn reset(&mut self);
    /// Everything learnt (scaled coordinates).
    fn export(&self) -> Self::State;
    /// Warm start. On `Err` nothing changed.
    fn import(&mut self, state: &Self::State) -> Result<(), Error>;
    /// The checks of [`import`](Self::import).
    fn check_import(&self, state: &Self::State) -> Result<(), Error>;
    /// New settings and scales, starting afresh. On `Err` nothing changed.
    fn reconfigure(&mut self, config: RlsConfig<T>, scaling: Scaling<T, D>) -> Result<(), Error>;
    /// Calls `f` with a view of each RLS estimator, in export order (one when learnt
    /// globally; one per rule, rule 0 first, when learnt locally).
    fn for_each_rls(&self, f: &mut dyn FnMut(RlsView<'_, T>));
    /// Replaces each rule's θ by its estimate with the bias of a noisy regressor removed
    /// ([`Rls::bias_compensated`](crate::rls::Rls::bias_compensated)), keeping the covariances:
    /// the parameters for a simulation. Global learning compensates a one-rule model only
    /// (with more rules its regressor `Δ ⊗ ξ` mixes the rules' terms).
    fn compensate(&mut self, noise: &RegressorNoise<T, D>) -> Compensation;
}

/// The [`TsEstimator`] methods that both estimators forward, unchanged, to their inherent
/// methods of the same name and signature; each impl below adds only what differs (where the
/// settings are, which RLS estimators there are, and the local one's kept strengths).
macro_rules! forward_to_inherent {
    () => {
        fn check_new(config: &RlsConfig<T>, scaling: &Scaling<T, D>) -> Result<(), Error> {
            Self::check_new(config, scaling)
        }
        #[inline(always)]
        fn build(rules: RuleBase<T, V, R>, config: RlsConfig<T>, scaling: Scaling<T, D>) -> Self {
            Self::with_scaling_unchecked(rules, config, scaling)
        }
        fn rules(&self) -> &RuleBase<T, V, R> {
            self.rules()
        }
        fn scaling(&self) -> &Scaling<T, D> {
            self.scaling()
        }
        fn physical_parameter(&self, rule: usize, term: usize) -> Option<T> {
            self.physical_parameter(rule, term)
        }
        fn predict_many<const M: usize>(
            &self,
            premise: &[T; V],
            terms: &[[T; D]; M],
        ) -> Result<[T; M], Error> {
            self.predict_many(premise, terms)
        }
        fn prepare<const M: usize>(
            &self,
            premise: &[T; V],
            terms: &[[T; D]; M],
            targets: &[T; M],
        ) -> Result<Prepared<T, R, D, M>, Error> {
            self.prepare(premise, terms, targets)
        }
        fn apply<const M: usize>(&mut self, prepared: &Prepared<T, R, D, M>) {
            self.apply(prepared)
        }
        fn reset(&mut self) {
            self.reset()
        }
        fn export(&self) -> Self::State {
            self.export()
        }
        fn import(&mut self, state: &Self::State) -> Result<(), Error> {
            self.import(state)
        }
        fn check_import(&self, state: &Self::State) -> Result<(), Error> {
            self.check_import(state)
        }
        fn reconfigure(
            &mut self,
            config: RlsConfig<T>,
            scaling: Scaling<T, D>,
        ) -> Result<(), Error> {
            self.reconfigure(config, scaling)
        }
        fn compensate(&mut self, noise: &RegressorNoise<T, D>) -> Compensation {
            self.compensate(noise)
        }
    };
}

impl<T: Real, const V: usize, const R: usize, const D: usize, const N: usize, const NP: usize>
    TsEstimator<T, V, R, D> for TsRls<T, V, R, D, N, NP>
{
    type State = RlsState<T, N, NP>;
    const LEARNING: Learning = Learning::Global;

    forward_to_inherent!();

    fn config(&self) -> &RlsConfig<T> {
        self.rls().config()
    }
    fn for_each_rls(&self, f: &mut dyn FnMut(RlsView<'_, T>)) {
        f(self.rls().view())
    }
}

impl<T: Real, const V: usize, const R: usize, const D: usize, const DP: usize>
    TsEstimator<T, V, R, D> for LocalTsRls<T, V, R, D, DP>
{
    type State = LocalState<T, R, D, DP>;
    const LEARNING: Learning = Learning::Local;

    forward_to_inherent!();

    fn config(&self) -> &RlsConfig<T> {
        self.config()
    }
    fn predict_keep<const M: usize>(
        &mut self,
        premise: &[T; V],
        strengths: Option<&[T; R]>,
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        self.predict_keep(premise, strengths, terms)
    }
    fn kept_strengths(&self) -> Option<&[T; R]> {
        self.kept_strengths()
    }
    fn for_each_rls(&self, f: &mut dyn FnMut(RlsView<'_, T>)) {
        for rule in (0..R).filter_map(|i| self.rule(i)) {
            f(rule)
        }
    }
}
