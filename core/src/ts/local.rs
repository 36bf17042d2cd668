//! Local learning of a TS model: each rule's consequents by its own fuzzily weighted RLS.
//!
//! The paper (Section 4) learns all rules' parameters θ = [θ_1 … θ_R] with one RLS on the
//! regressor `Δ ⊗ ξ`: the *global* error `y − Σ_i ξ_i Δᵀθ_i` is shared out over every rule
//! that fired. That fits the sum well where the data are, but a rule that fires rarely (or
//! only together with others) can take any value that the others compensate, and a free run
//! that visits its region then goes wrong.
//!
//! Here every rule i keeps its own parameters θ_i (D terms) and its own covariance P_i
//! (`D(D+1)/2` packed entries) and fits the data *locally*: it minimises
//! `Σ_k λ^(…) ξ_i(k) (y(k) − Δ(k)ᵀθ_i)²`, the fuzzily weighted least squares of evolving TS
//! systems (Angelov and Filev, eTS, 2004). One step of it is an ordinary RLS update of a
//! measurement whose variance is `1/ξ_i` (the same as the regressor and target multiplied by
//! `√ξ_i`, without the square root), so each rule reuses [`Rls`]'s update as it is (its
//! learnt state without the settings, which every rule shares). The model
//! still predicts `ŷ = Σ_i ξ_i Δᵀθ_i`. Each θ_i is then the best linear model of the data
//! weighted by how much rule i describes them: a local linearisation, meaningful on its own.
//!
//! * **Forgetting** only where data arrive: rule i forgets with `λ_i = 1 − (1 − λ) ξ_i`, so a
//!   rule that does not fire keeps its covariance (no windup in regions the flight has left).
//!   The trace bound of [`RlsConfig::max_trace`] holds per rule.
//! * **Rules too weak to matter** (`ξ_i` < [`MIN_LOCAL_STRENGTH`]) are not updated: their
//!   weighted update would move θ_i by less than a thousandth of a full one, and skipping them
//!   bounds the cost of a step by the rules that describe the sample.
//! * **One rule** (ξ = 1): `√1 = 1`, `λ_1 = λ`, and the update is the global model's, bit for
//!   bit (a test checks it).
//!
//! Cost: one D-parameter update per rule that fires (`O(R_fired · D²)`) instead of one
//! `R·D`-parameter update (`O(R² D²)`); memory `R·(D + D(D+1)/2)` instead of
//! `R·D + R·D(R·D+1)/2`.

use super::{combine, constructors, predict_from_blocks, prepare_rows, Prepared, Scaling};
use crate::error::{Error, Quantity};
use crate::rls::{
    AllParameters, Compensation, Measurement, RegressorNoise, Rls, RlsConfig, RlsCore, RlsState,
    RlsView, TARGET_LIMIT,
};
use crate::rule_base::RuleBase;
use crate::scalar::{within, Real};

/// Rules with a normalised firing strength below this learn nothing from a sample (see the
/// [module docs](self)).
pub const MIN_LOCAL_STRENGTH: f64 = 1e-3;

/// A TS model over `V` premise variables and `R` rules of `D` consequent terms, each rule with
/// its own RLS of `DP = D(D+1)/2` packed covariance entries (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct LocalTsRls<T, const V: usize, const R: usize, const D: usize, const DP: usize> {
    rules: RuleBase<T, V, R>,
    /// Each rule's θ_i, P_i and counters.
    local: [RlsCore<T, D, DP>; R],
    scaling: Scaling<T, D>,
    /// The settings of every rule's estimator (one copy for all).
    config: RlsConfig<T>,
    /// What [`predict_keep`](Self::predict_keep) computed, for the update from the same
    /// premise (see [`Kept`]).
    kept: Kept<T, V, R, D>,
}

/// The firing strengths ξ and block products `b` of the last
/// [`predict_keep`](LocalTsRls::predict_keep). An identifier predicts from sample k at step k
/// and learns from sample k at step k+1, with the same premise and the same θ in between: the
/// update reuses them instead of computing them again. Valid only for the premise it was
/// computed from (compared bit for bit) and until θ changes (every `&mut` method but
/// `predict_keep` clears it), so reusing it gives the very bits a recomputation would.
///
/// A cache, not state: it takes no part in equality (an estimator that kept a prediction
/// equals one that did not), export or import.
#[derive(Clone, Copy, Debug)]
struct Kept<T, const V: usize, const R: usize, const D: usize> {
    premise: [T; V],
    strengths: [T; R],
    blocks: [T; D],
    valid: bool,
}

impl<T: Real, const V: usize, const R: usize, const D: usize> Kept<T, V, R, D> {
    fn none() -> Self {
        Self {
            premise: [T::zero(); V],
            strengths: [T::zero(); R],
            blocks: [T::zero(); D],
            valid: false,
        }
    }

    /// ξ and `b` if they were computed from exactly this premise.
    fn for_premise(&self, premise: &[T; V]) -> Option<([T; R], [T; D])> {
        let same = premise
            .iter()
            .zip(self.premise.iter())
            .all(|(a, b)| a.to_bits_u64() == b.to_bits_u64());
        (self.valid && same).then_some((self.strengths, self.blocks))
    }
}

impl<T, const V: usize, const R: usize, const D: usize> PartialEq for Kept<T, V, R, D> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// AllParameters a [`LocalTsRls`] has learnt: each rule's θ_i and covariance factor, in rule
/// order (scaled coordinates).
pub type LocalState<T, const R: usize, const D: usize, const DP: usize> = [RlsState<T, D, DP>; R];

impl<T: Real, const V: usize, const R: usize, const D: usize, const DP: usize>
    LocalTsRls<T, V, R, D, DP>
{
    const SIZES_OK: () = assert!(R >= 1 && D >= 1, "LocalTsRls needs R ≥ 1 and D ≥ 1");

    constructors! {
        /// A model with the given rule base, estimator settings (every rule: θ_i(0) = 0,
        /// P_i(0) = αI) and scales.
        dimensions_wrong: R > 32,
        estimator: Rls<T, D, DP>,
        unchecked: |rules, config, scaling| Self {
            rules,
            local: RlsCore::fresh_array(&config),
            scaling,
            config,
            kept: Kept::none(),
        },
    }

    /// The rule base.
    pub fn rules(&self) -> &RuleBase<T, V, R> {
        &self.rules
    }

    /// Rule i's estimator (θ_i, P_i, counters, and the settings every rule shares), `None`
    /// for i ≥ R.
    pub fn rule(&self, i: usize) -> Option<RlsView<'_, T>> {
        Some(self.local.get(i)?.view(&self.config))
    }

    /// The scales.
    pub fn scaling(&self) -> &Scaling<T, D> {
        &self.scaling
    }

    /// The estimator settings (every rule has the same).
    pub fn config(&self) -> &RlsConfig<T> {
        &self.config
    }

    /// `α_{i,s}` of rule i, term s, in physical units (target unit per term unit).
    pub fn physical_parameter(&self, rule: usize, term: usize) -> Option<T> {
        let theta = self.local.get(rule)?.parameters().get(term).copied()?;
        let scale = self.scaling.terms.get(term).copied()?;
        Some(theta * self.scaling.target / scale)
    }

    /// `b_s = Σ_i ξ_i θ̃_{i,s}`: the rule-weighted parameter of each term.
    #[inline(always)]
    fn block_products(&self, strengths: &[T; R]) -> [T; D] {
        let mut b = [T::zero(); D];
        for (&w, rls) in strengths.iter().zip(self.local.iter()) {
            if w != T::zero() {
                for (bs, &t) in b.iter_mut().zip(rls.parameters().iter()) {
                    *bs += w * t;
                }
            }
        }
        b
    }

    /// `Σ_i ξ_i Δ_mᵀθ_i` for M outputs that share the premise, in the target's unit.
    pub fn predict_many<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        let (_, b) = self.strengths_and_blocks(premise)?;
        predict_from_blocks::<T, R, D, M>(&self.scaling, &b, terms)
    }

    /// [`predict_many`](Self::predict_many), keeping the firing strengths and block products
    /// for the update from the same premise at the next step ([`prepare`](Self::prepare)).
    ///
    /// `strengths`: the rule base's firing strengths at `premise` when the caller has them
    /// already (an estimator with the same rule base computed them from the same premise),
    /// taken as they are; `None`: computed here.
    pub fn predict_keep<const M: usize>(
        &mut self,
        premise: &[T; V],
        strengths: Option<&[T; R]>,
        terms: &[[T; D]; M],
    ) -> Result<[T; M], Error> {
        self.kept.valid = false;
        let (strengths, b) = match strengths {
            Some(xi) => (*xi, self.block_products(xi)),
            None => self.strengths_and_blocks(premise)?,
        };
        self.kept = Kept {
            premise: *premise,
            strengths,
            blocks: b,
            valid: true,
        };
        predict_from_blocks::<T, R, D, M>(&self.scaling, &b, terms)
    }

    /// The firing strengths the last [`predict_keep`](Self::predict_keep) computed or was
    /// given, while θ has not changed since (`None` otherwise).
    pub fn kept_strengths(&self) -> Option<&[T; R]> {
        self.kept.valid.then_some(&self.kept.strengths)
    }

    /// ξ and `b` for this premise: kept from the last prediction, or computed.
    fn strengths_and_blocks(&self, premise: &[T; V]) -> Result<([T; R], [T; D]), Error> {
        if let Some(kept) = self.kept.for_premise(premise) {
            return Ok(kept);
        }
        let strengths = self.rules.firing_strengths(premise)?;
        let b = self.block_products(&strengths);
        Ok((strengths, b))
    }

    /// Checks and computes an update of M outputs without changing anything (see
    /// [`TsRls::prepare`](crate::ts::TsRls::prepare); the rows are the same). Also checks every
    /// rule's own prior innovation on the first row against [`TARGET_LIMIT`].
    pub fn prepare<const M: usize>(
        &self,
        premise: &[T; V],
        terms: &[[T; D]; M],
        targets: &[T; M],
    ) -> Result<Prepared<T, R, D, M>, Error> {
        let (strengths, b) = self.strengths_and_blocks(premise)?;
        let prepared = prepare_rows(strengths, &b, &self.scaling, terms, targets)?;
        let limit = T::lit(TARGET_LIMIT);
        if let (Some(row), Some(&y)) = (prepared.rows.first(), prepared.targets.first()) {
            for rls in &self.local {
                if !within(y - combine(row, rls.parameters()), limit) {
                    return Err(Error::OutOfRange(Quantity::Target(0)));
                }
            }
        }
        Ok(prepared)
    }

    /// Learns from a [`Prepared`] update made by this model's [`prepare`](Self::prepare) with
    /// the model unchanged since: every rule with `ξ_i ≥` [`MIN_LOCAL_STRENGTH`] takes each row
    /// with weight `ξ_i` (measurement variance `1/ξ_i`), forgetting with `λ_i` once per
    /// sample.
    pub fn apply<const M: usize>(&mut self, prepared: &Prepared<T, R, D, M>) {
        // θ changes: what was kept is stale (clearing the flag is enough, and cheaper than
        // writing a whole `Kept::none()` at every step).
        self.kept.valid = false;
        let min = T::lit(MIN_LOCAL_STRENGTH);
        let last = prepared.count.saturating_sub(1);
        let config = &self.config;
        let lambda = config.forgetting;
        for (&w, rls) in prepared.strengths.iter().zip(self.local.iter_mut()) {
            // Strengths are finite, in [0, 1] (the rule base makes them so).
            if w < min {
                continue;
            }
            // ξ_i = 1 keeps λ_i and the variances exact (x/1 = x), so that one rule is the
            // global model.
            let lambda_i = if w == T::one() {
                lambda
            } else {
                T::one() - (T::one() - lambda) * w
            };
            for (r, (row, &y)) in prepared.rows_to_learn() {
                let e = y - combine(row, rls.parameters());
                let l = if r == last { lambda_i } else { T::one() };
                rls.update_row(
                    config,
                    row,
                    AllParameters(D),
                    Measurement::weighted(e, w, l),
                );
            }
        }
    }

    /// Replaces each rule's θ_i by its estimate with the bias of `noise` removed (see
    /// [`Rls::bias_compensated`]); the covariances are kept. A rule that cannot be
    /// compensated keeps its θ_i, and the result says so.
    pub fn compensate(&mut self, noise: &RegressorNoise<T, D>) -> Compensation {
        self.kept.valid = false;
        let mut outcome = Compensation::default();
        for rls in &mut self.local {
            outcome.record(rls.compensate(&self.config, noise));
        }
        outcome
    }

    /// Back to θ_i = 0, P_i = αI for every rule.
    pub fn reset(&mut self) {
        self.kept = Kept::none();
        for rls in &mut self.local {
            rls.reset(&self.config);
        }
    }

    /// Exports every rule's θ̃_i and covariance factor.
    pub fn export(&self) -> LocalState<T, R, D, DP> {
        self.local.each_ref().map(|rls| rls.export(&self.config))
    }

    /// The checks of [`import`](Self::import), without importing.
    pub fn check_import(&self, state: &LocalState<T, R, D, DP>) -> Result<(), Error> {
        for s in state {
            RlsCore::check_import(&self.config, s)?;
        }
        Ok(())
    }

    /// Imports every rule's state (warm start; same scaling expected). On `Err` nothing
    /// changed.
    pub fn import(&mut self, state: &LocalState<T, R, D, DP>) -> Result<(), Error> {
        self.check_import(state)?;
        self.kept = Kept::none();
        for (rls, s) in self.local.iter_mut().zip(state.iter()) {
            rls.import(&self.config, s)?;
        }
        Ok(())
    }

    /// New estimator settings and scales, in place, starting afresh. On `Err` nothing changed.
    pub fn reconfigure(
        &mut self,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Result<(), Error> {
        config.validate()?;
        scaling.validate()?;
        self.kept = Kept::none();
        for rls in &mut self.local {
            rls.reset(&config);
        }
        self.scaling = scaling;
        self.config = config;
        Ok(())
    }
}
