//! A Takagi-Sugeno model whose consequent parameters are learnt by RLS (paper Section 4).
//!
//! (Over 600 lines: the estimator, its premise and scaling handling and the checked two-phase update are one
//! concept; its unit tests are in `tests.rs`.)
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
use crate::rls::{
    col, AllParameters, Compensation, Measurement, NotCompensated, RegressorNoise, Rls, RlsConfig,
    RlsState, Run, DENSE_SUMS_UP_TO, REGRESSOR_LIMIT, TARGET_LIMIT,
};
use crate::rule_base::RuleBase;
use crate::scalar::{within, Real};

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
/// [`LocalTsRls`](crate::LocalTsRls): `with_scaling` (documented by the caller); its checks,
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
    /// Every scaled term must be within [`REGRESSOR_LIMIT`], every scaled target and prior
    /// innovation within [`TARGET_LIMIT`]. Outputs whose regressors are parallel are learnt as
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

/// The consequent terms divided by their scales, `Δ̃_s = Δ_s/S_s`, each checked finite and
/// within [`REGRESSOR_LIMIT`]. Since every firing strength is in [0, 1], that bounds every
/// regressor entry `Δ̃_s ξ_i` as the estimator requires.
#[inline]
pub(crate) fn scaled_terms<T: Real, const R: usize, const D: usize>(
    scaling: &Scaling<T, D>,
    terms: &[T; D],
) -> Result<[T; D], Error> {
    let limit = T::lit(REGRESSOR_LIMIT);
    let mut scaled = [T::zero(); D];
    for (s, ((d, &t), &scale)) in scaled
        .iter_mut()
        .zip(terms.iter())
        .zip(scaling.terms.iter())
        .enumerate()
    {
        let at = Quantity::Regressor((s * R) as u16);
        if !t.is_finite() {
            return Err(Error::NonFinite(at));
        }
        *d = t / scale;
        if !within(*d, limit) {
            return Err(Error::OutOfRange(at));
        }
    }
    Ok(scaled)
}

/// The checks and rows of an update of M outputs (see [`TsRls::prepare`]), given the firing
/// strengths and the rule-weighted parameters `b` of the current θ (see `block_products`).
/// Shared by the global and the local estimator: both predict `Σ_s Δ̃_s b_s`.
pub(crate) fn prepare_rows<T: Real, const R: usize, const D: usize, const M: usize>(
    strengths: [T; R],
    b: &[T; D],
    scaling: &Scaling<T, D>,
    terms: &[[T; D]; M],
    targets: &[T; M],
) -> Result<Prepared<T, R, D, M>, Error> {
    let limit = T::lit(TARGET_LIMIT);
    let mut all_terms = [[T::zero(); D]; M];
    let mut scaled = [T::zero(); M];
    let mut innovations = [T::zero(); M];
    for (m, (((st, y), e), (t, &target))) in all_terms
        .iter_mut()
        .zip(scaled.iter_mut())
        .zip(innovations.iter_mut())
        .zip(terms.iter().zip(targets.iter()))
        .enumerate()
    {
        let at = Quantity::Target(m as u8);
        *st = scaled_terms::<T, R, D>(scaling, t)?;
        if !target.is_finite() {
            return Err(Error::NonFinite(at));
        }
        *y = target / scaling.target;
        *e = *y - combine(st, b);
        if !(within(*y, limit) && within(*e, limit)) {
            return Err(Error::OutOfRange(at));
        }
    }

    // The rows to learn from. Output m's regressor is `Δ̃_m ⊗ ξ`; when Δ̃_m has a single
    // non-zero term s, it is `Δ̃_{m,s}` times the fixed vector `e_s ⊗ ξ`. Outputs with the
    // same single term are therefore parallel, and their rank-one updates sum to one:
    // `Σ_m d_m² g gᵀ = φ φᵀ` and `Σ_m d_m ỹ_m g = φ ỹ` with `φ = ‖d‖ g`, `ỹ = Σ d_m ỹ_m/‖d‖`.
    // One update instead of several (Eq. 27's v_x and v_z), equal in exact arithmetic.
    let mut rows = [[T::zero(); D]; M];
    let mut row_targets = [T::zero(); M];
    let mut groups = [Group::<T>::default(); M];
    let mut count = 0;
    for (st, &y) in all_terms.iter().zip(scaled.iter()) {
        let term = single_term(st);
        match term {
            // Δ̃_m = 0: a zero regressor carries no information and gets no row.
            Term::Zero => continue,
            Term::Single(slot, d, sq) => {
                let mut same = groups.iter_mut().take(count);
                if let Some(g) = same.find(|g| g.slot == Some(slot)) {
                    g.sum_sq += sq;
                    g.weighted_target += d * y;
                    g.members += 1;
                    continue;
                }
            }
            Term::Several => {}
        }
        let (Some(row), Some(t), Some(g)) = (
            rows.get_mut(count),
            row_targets.get_mut(count),
            groups.get_mut(count),
        ) else {
            break;
        };
        *row = *st;
        *t = y;
        if let Term::Single(slot, d, sq) = term {
            *g = Group {
                slot: Some(slot),
                sum_sq: sq,
                weighted_target: d * y,
                members: 1,
            };
        }
        count += 1;
    }
    if count == 0 {
        // Every output is zero: learn from output 0's (zero) row all the same, so that the
        // sample still counts, and forgets, once.
        if let (Some(t), Some(&y)) = (row_targets.first_mut(), scaled.first()) {
            *t = y;
            count = 1;
        }
    }
    let regressor_limit = T::lit(REGRESSOR_LIMIT);
    for (m, ((g, row), y)) in groups
        .iter()
        .zip(rows.iter_mut())
        .zip(row_targets.iter_mut())
        .take(count)
        .enumerate()
    {
        if let (Some(slot), true) = (g.slot, g.members > 1) {
            let norm = g.sum_sq.sqrt();
            *y = g.weighted_target / norm;
            if let Some(d) = row.get_mut(slot) {
                *d = norm;
            }
            if !within(norm, regressor_limit) {
                return Err(Error::OutOfRange(Quantity::Regressor((slot * R) as u16)));
            }
            if !within(*y, limit) {
                return Err(Error::OutOfRange(Quantity::Target(m as u8)));
            }
        }
    }
    let first = match (rows.first(), row_targets.first()) {
        (Some(row), Some(&y)) => y - combine(row, b),
        _ => T::zero(),
    };
    if !within(first, limit) {
        return Err(Error::OutOfRange(Quantity::Target(0)));
    }
    Ok(Prepared {
        strengths,
        rows,
        targets: row_targets,
        count,
        first,
        innovations: innovations.map(|e| e * scaling.target),
    })
}

/// Runs of fired parameters this close (or closer) are merged into one.
const RUN_GAP: u16 = 3;

/// The parameters of the rules in `fired` (bit i: rule i; rules from 32 on always count) as
/// ascending runs, merged where they are at most [`RUN_GAP`] apart, for `rules` rules of `terms` consequent terms
/// each (parameter `s·rules + i` is term s of rule i). Returns how many runs it wrote.
///
/// Not generic: one copy serves every rule base of a firmware.
#[inline(never)]
fn fired_runs(fired: u32, rules: usize, terms: usize, runs: &mut [Run]) -> usize {
    // The fired rules as runs `first..end`, from the mask. At most 16 runs start below 32,
    // plus the one from 32 on.
    let mut rule_runs = [(0u16, 0u16); 17];
    let mut n = 0;
    let in_base = if rules >= 64 {
        u64::MAX
    } else {
        (1u64 << rules) - 1
    };
    let mut mask = (u64::from(fired) | !u64::from(u32::MAX)) & in_base;
    while mask != 0 {
        let first = mask.trailing_zeros();
        let end = first + (mask >> first).trailing_ones();
        if let Some(r) = rule_runs.get_mut(n) {
            // A run reaching bit 63 goes on to the last rule (`rules` ≤ 512, checked by Rls).
            let end = if end >= 64 { rules } else { end as usize };
            *r = (first as u16, end as u16);
            n += 1;
        }
        if end >= 64 {
            break;
        }
        mask &= !((1u64 << end) - 1);
    }
    // The same runs in every term's block of `rules` parameters.
    let mut count: usize = 0;
    for slot in 0..terms {
        let base = (slot * rules) as u16;
        for &(first, end) in rule_runs.get(..n).unwrap_or(&[]) {
            let (start, end) = (base + first, base + end);
            match count.checked_sub(1).and_then(|k| runs.get_mut(k)) {
                // A short gap is cheaper to walk through than a new run (its parameters are
                // unchanged by an update either way).
                Some(prev) if start - prev.end <= RUN_GAP => prev.end = end,
                _ => {
                    if let Some(run) = runs.get_mut(count) {
                        *run = Run { start, end };
                        count += 1;
                    }
                }
            }
        }
    }
    count
}

/// Bit i set for every non-zero ξ_i, i < 32.
fn fired_mask<T: Real>(strengths: &[T]) -> u32 {
    let mut mask = 0;
    for (i, &w) in strengths.iter().enumerate().take(32) {
        if w != T::zero() {
            mask |= 1 << i;
        }
    }
    mask
}

/// A checked update of M outputs, ready to [`TsRls::apply`].
///
/// It holds the measurement rows the estimator will learn from, as consequent terms over the
/// firing strengths: one per output, except that outputs whose regressors are parallel (their
/// consequent terms have the same single non-zero term, as Eq. 27's `v_x` and `v_z`, both
/// `α1 (R e2) u_col`) are combined into one row with the same information, `φ = ‖d‖ g` and
/// `ỹ = Σ d_m ỹ_m / ‖d‖`. That is one rank-one update instead of several; in exact arithmetic
/// the estimate is the same. An output whose terms are all zero carries no information and
/// has no row (unless all are zero).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Prepared<T, const R: usize, const D: usize, const M: usize> {
    pub(crate) strengths: [T; R],
    pub(crate) rows: [[T; D]; M],
    pub(crate) targets: [T; M],
    pub(crate) count: usize,
    first: T,
    /// Prior innovations `y_m − ŷ_m(k)` in physical units, one per output.
    pub innovations: [T; M],
}

impl<T, const R: usize, const D: usize, const M: usize> Prepared<T, R, D, M> {
    /// The rows to learn from, in order, each with its index and target: what both
    /// estimators' `apply` walk.
    #[inline(always)]
    pub(crate) fn rows_to_learn(&self) -> impl Iterator<Item = (usize, (&[T; D], &T))> {
        self.rows
            .iter()
            .zip(self.targets.iter())
            .take(self.count)
            .enumerate()
    }
}

/// Outputs being combined into one row (see [`Prepared`]).
#[derive(Copy, Clone, Default)]
struct Group<T> {
    /// The single non-zero consequent term, if there is exactly one.
    slot: Option<usize>,
    /// `Σ d_m²` of the members.
    sum_sq: T,
    /// `Σ d_m ỹ_m` of the members.
    weighted_target: T,
    members: u8,
}

/// The non-zero consequent terms of an output.
#[derive(Copy, Clone)]
enum Term<T> {
    /// All zero.
    Zero,
    /// Only term `slot` is non-zero: its value d and d², a normal number (so that `‖d‖`
    /// neither underflows nor overflows).
    Single(usize, T, T),
    /// Several, or one too small or too large to combine.
    Several,
}

fn single_term<T: Real, const D: usize>(terms: &[T; D]) -> Term<T> {
    let mut found = Term::Zero;
    for (s, &d) in terms.iter().enumerate() {
        if d != T::zero() {
            if !matches!(found, Term::Zero) {
                return Term::Several;
            }
            let sq = d * d;
            found = if sq.is_finite() && sq >= T::MIN_POSITIVE {
                Term::Single(s, d, sq)
            } else {
                Term::Several
            };
        }
    }
    found
}

/// `Σ_s Δ̃_s b_s` in the target's physical unit for each of M outputs, from the rule-weighted
/// parameters `b` (see `block_products`): how the global and the local estimator both
/// predict. Each output's terms are checked as [`scaled_terms`] does.
#[inline(always)]
pub(crate) fn predict_from_blocks<T: Real, const R: usize, const D: usize, const M: usize>(
    scaling: &Scaling<T, D>,
    b: &[T; D],
    terms: &[[T; D]; M],
) -> Result<[T; M], Error> {
    let mut out = [T::zero(); M];
    for (o, t) in out.iter_mut().zip(terms.iter()) {
        *o = combine(&scaled_terms::<T, R, D>(scaling, t)?, b) * scaling.target;
    }
    Ok(out)
}

/// `Σ_s Δ̃_s b_s`: an output's prediction from [`TsRls`]'s block products.
///
/// Every term is summed, zero or not, without a branch (cheaper on the Cortex-M4F than a test
/// per term). The same bits as summing the non-zero terms only: `b` is finite (θ is), so a
/// zero `Δ̃_s` adds ±0, and a sum from +0 is never −0, so adding ±0 leaves it as it is.
#[inline]
pub(crate) fn combine<T: Real, const D: usize>(terms: &[T; D], b: &[T; D]) -> T {
    let mut sum = T::zero();
    for (&d, &bs) in terms.iter().zip(b.iter()) {
        sum += d * bs;
    }
    sum
}

/// `ξ = Δ̃ ⊗ ξ_rules` in the paper's order (term-major blocks of R).
#[inline]
fn regressor_of<T: Real, const R: usize, const D: usize, const N: usize>(
    strengths: &[T; R],
    scaled_terms: &[T; D],
) -> [T; N] {
    let mut xi = [T::zero(); N];
    for (block, &d) in xi.chunks_exact_mut(R).zip(scaled_terms.iter()) {
        for (x, &w) in block.iter_mut().zip(strengths.iter()) {
            *x = d * w;
        }
    }
    xi
}

#[cfg(test)]
mod tests;
