//! The rows of a TS update, shared by the global ([`TsRls`](super::TsRls)) and the local
//! ([`LocalTsRls`](super::local::LocalTsRls)) estimator: the scaled consequent terms, the checked
//! prediction `Σ_s Δ̃_s b_s` from the rule-weighted parameters, the regressor
//! `ξ = Δ̃ ⊗ ξ_rules`, and which parameters the fired rules touch.

use crate::error::{Error, Quantity};
use crate::rls::{Run, REGRESSOR_LIMIT, TARGET_LIMIT};
use crate::scalar::{within, Real};

use super::Scaling;

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

/// `Σ_s Δ̃_s b_s` with each `Δ̃_s` checked as [`scaled_terms`] does: [`combine`] of the
/// scaled terms, summed as they are scaled (the same operations in the same order, so the
/// same bits), with no array in between. For the prediction: at opt-level "s" (the C
/// library's) an array returned inside a `Result` is copied twice through `memcpy`. Its
/// per-term check repeats [`scaled_terms`]'s on purpose: one shared per-term helper changed
/// the inlining at "s" and cost the lean C flight firmware 400 B of flash
/// (`scripts/footprint.sh`: 22 974 → 23 378 B).
#[inline(always)]
fn scaled_combine<T: Real, const R: usize, const D: usize>(
    scaling: &Scaling<T, D>,
    terms: &[T; D],
    b: &[T; D],
) -> Result<T, Error> {
    let limit = T::lit(REGRESSOR_LIMIT);
    let mut sum = T::zero();
    for (s, ((&t, &scale), &bs)) in terms
        .iter()
        .zip(scaling.terms.iter())
        .zip(b.iter())
        .enumerate()
    {
        let at = Quantity::Regressor((s * R) as u16);
        if !t.is_finite() {
            return Err(Error::NonFinite(at));
        }
        let d = t / scale;
        if !within(d, limit) {
            return Err(Error::OutOfRange(at));
        }
        sum += d * bs;
    }
    Ok(sum)
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
    if M == 1 {
        // One output: nothing to combine. Its row as the loop below makes it: the scaled
        // terms, or zeros when all are zero (so that a −0 term learns as +0 does there).
        if let (Some(row), Some(t), Some(st), Some(&y)) = (
            rows.first_mut(),
            row_targets.first_mut(),
            all_terms.first(),
            scaled.first(),
        ) {
            if st.iter().any(|&d| d != T::zero()) {
                *row = *st;
            }
            *t = y;
        }
        return finish_rows(strengths, b, scaling, rows, row_targets, 1, innovations);
    }
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
            let norm = g.sum_sq.sqrt_ieee();
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
    finish_rows(strengths, b, scaling, rows, row_targets, count, innovations)
}

/// The end of [`prepare_rows`]: checks the first row's prior error and assembles the update.
#[inline(always)]
fn finish_rows<T: Real, const R: usize, const D: usize, const M: usize>(
    strengths: [T; R],
    b: &[T; D],
    scaling: &Scaling<T, D>,
    rows: [[T; D]; M],
    row_targets: [T; M],
    count: usize,
    innovations: [T; M],
) -> Result<Prepared<T, R, D, M>, Error> {
    let first = match (rows.first(), row_targets.first()) {
        (Some(row), Some(&y)) => y - combine(row, b),
        _ => T::zero(),
    };
    if !within(first, T::lit(TARGET_LIMIT)) {
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
pub(super) fn fired_runs(fired: u32, rules: usize, terms: usize, runs: &mut [Run]) -> usize {
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
pub(super) fn fired_mask<T: Real>(strengths: &[T]) -> u32 {
    let mut mask = 0;
    for (i, &w) in strengths.iter().enumerate().take(32) {
        if w != T::zero() {
            mask |= 1 << i;
        }
    }
    mask
}

/// A checked update of M outputs, ready to [`TsRls::apply`](super::TsRls::apply).
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
    pub(super) first: T,
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
        *o = scaled_combine::<T, R, D>(scaling, t, b)? * scaling.target;
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
pub(super) fn regressor_of<T: Real, const R: usize, const D: usize, const N: usize>(
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
