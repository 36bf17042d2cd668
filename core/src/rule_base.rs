//! Takagi-Sugeno rule base: premise variables, fuzzy sets, product t-norm and the normalised
//! firing strengths `ξ_i = μ_i / Σ_j μ_j` of the paper's Section 4.

use heapless::Vec;

use crate::error::{ConfigError, Error, Quantity};
use crate::membership::MembershipFunction;
use crate::scalar::Real;

/// Most fuzzy sets one premise variable can hold (left shoulder, centre, right shoulder).
pub const MAX_SETS: usize = 3;

/// The fuzzy sets (linguistic values) of one premise variable, in rule order.
///
/// An empty variable takes no part in the rule base (the `(*)` rows of the paper's Table 3).
pub type PremiseSets<T> = Vec<MembershipFunction<T>, MAX_SETS, u8>;

/// A rule base over `V` premise variables with `R` rules.
///
/// The rules are every combination of one set per participating variable (the product of the
/// set counts must equal `R`). Rule order: the first variable is the most significant digit,
/// each variable's sets in the order given. With no participating variable the rule base has
/// one rule with ξ = 1: that is the plain (non-fuzzy) RLS model of the paper's Eqs. 19 and 26.
#[derive(Clone, Debug, PartialEq)]
pub struct RuleBase<T, const V: usize, const R: usize> {
    variables: [PremiseSets<T>; V],
}

impl<T: Real, const V: usize, const R: usize> RuleBase<T, V, R> {
    /// Builds a rule base, checking every set and the rule count.
    pub fn new(variables: [PremiseSets<T>; V]) -> Result<Self, Error> {
        let mut rules: u32 = 1;
        for (v, sets) in variables.iter().enumerate() {
            for (s, mf) in sets.iter().enumerate() {
                if !mf.is_valid() {
                    return Err(ConfigError::MembershipFunction {
                        variable: v as u8,
                        set: s as u8,
                    }
                    .into());
                }
            }
            if !sets.is_empty() {
                rules = rules.saturating_mul(sets.len() as u32);
            }
        }
        if rules as usize != R || R > usize::from(u16::MAX) {
            return Err(ConfigError::RuleCount {
                expected: R.min(usize::from(u16::MAX)) as u16,
                found: rules,
            }
            .into());
        }
        Ok(Self { variables })
    }

    /// The single-rule base of the plain RLS baseline (no premise variable takes part).
    pub fn single_rule() -> Result<Self, Error> {
        Self::new(core::array::from_fn(|_| Vec::new()))
    }

    /// The sets of each premise variable.
    pub fn variables(&self) -> &[PremiseSets<T>; V] {
        &self.variables
    }

    /// Whether `sets` are this rule base's sets, bit for bit: then a rule base over `sets`
    /// has the same rules and the same firing strengths at every premise.
    pub fn has_sets(&self, sets: &[PremiseSets<T>]) -> bool {
        same_sets(&self.variables, sets)
    }

    /// Checks that every premise value that takes part is finite.
    pub fn check_premise(&self, x: &[T; V]) -> Result<(), Error> {
        for (v, (sets, xv)) in self.variables.iter().zip(x.iter()).enumerate() {
            if !sets.is_empty() && !xv.is_finite() {
                return Err(Error::NonFinite(Quantity::Premise(v as u8)));
            }
        }
        Ok(())
    }

    /// Normalised firing strengths `ξ_i` (each in [0, 1], summing to 1 up to rounding).
    ///
    /// The premise of rule i is the product of its sets' degrees (product t-norm), multiplied
    /// in variable order. When the sum of all rule premises is below the smallest normal
    /// number (every rule far outside its sets), the strengths are computed from the
    /// exponents instead: `ξ_i = exp(l_i − max_j l_j) / Σ_k exp(l_k − max_j l_j)` with
    /// `l_i = Σ log μ`, which is the same quantity without underflow. The result is never NaN
    /// for a finite premise.
    pub fn firing_strengths(&self, x: &[T; V]) -> Result<[T; R], Error> {
        self.check_premise(x)?;
        let mut xi = [T::zero(); R];
        strengths(&self.variables, x, &mut xi);
        Ok(xi)
    }

    /// The rules in order, each as the set index of every variable (0 for variables that
    /// take no part).
    pub fn rules(&self) -> Rules<'_, T, V> {
        Rules {
            variables: &self.variables,
            digits: [0; V],
            remaining: R,
        }
    }
}

/// Whether two rule bases' sets (one list per premise variable) are the same, bit for bit.
pub fn same_sets<T: Real>(a: &[PremiseSets<T>], b: &[PremiseSets<T>]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.len() == y.len() && x.iter().zip(y.iter()).all(|(f, g)| f.same_bits(g)))
}

/// The firing strengths of a rule base with sets `variables` at premise `x` (checked finite)
/// into `xi` (one entry per rule), as [`RuleBase::firing_strengths`] documents.
///
/// Generic over the scalar only, with the sizes as slice lengths: one copy of this code serves
/// every rule base of a firmware (it would otherwise carry one per rule count).
#[inline(never)]
fn strengths<T: Real>(variables: &[PremiseSets<T>], x: &[T], xi: &mut [T]) {
    // Rule premises μ_i, built one variable at a time: after a variable with k sets, entry
    // `i·k + s` is entry i of the previous variables times that variable's degree in set s.
    // This is the rule order (first variable most significant) and multiplies each μ_i in
    // variable order, starting from 1.
    let len = expand(
        variables,
        x,
        xi,
        T::one(),
        MembershipFunction::degree,
        |p, d| p * d,
    );
    let mu = xi.get_mut(..len).unwrap_or(&mut []);
    let mut sum = T::zero();
    for &m in mu.iter() {
        sum += m;
    }
    if sum >= T::MIN_POSITIVE {
        for m in mu.iter_mut() {
            *m /= sum;
        }
        return;
    }
    // Every premise underflowed: the same quantity from the exponents,
    // `ξ_i = exp(l_i − max_j l_j) / Σ_k exp(l_k − max_j l_j)` with `l_i = Σ log μ`.
    let len = expand(
        variables,
        x,
        xi,
        T::zero(),
        MembershipFunction::log_degree,
        |p, l| p + l,
    );
    let logs = xi.get_mut(..len).unwrap_or(&mut []);
    let mut max = logs.first().copied().unwrap_or_else(T::zero);
    for &l in logs.iter() {
        if l > max {
            max = l;
        }
    }
    let mut sum = T::zero();
    for l in logs.iter_mut() {
        *l = (*l - max).exp();
        sum += *l;
    }
    // sum >= 1: the largest term is exp(0).
    for l in logs.iter_mut() {
        *l /= sum;
    }
}

/// Fills `out` with `combine` folded over the participating variables' `degree`s in rule
/// order (see [`strengths`]), starting from `init`; each degree is evaluated once. Returns the
/// number of rules written.
#[inline(always)]
fn expand<T: Real>(
    variables: &[PremiseSets<T>],
    x: &[T],
    out: &mut [T],
    init: T,
    degree: impl Fn(&MembershipFunction<T>, T) -> T,
    combine: impl Fn(T, T) -> T,
) -> usize {
    let Some(first) = out.first_mut() else {
        return 0;
    };
    *first = init;
    let mut len = 1;
    for (sets, &xv) in variables.iter().zip(x.iter()) {
        let k = sets.len();
        if k == 0 || len * k > out.len() {
            continue;
        }
        let mut degrees = [T::zero(); MAX_SETS];
        for (d, mf) in degrees.iter_mut().zip(sets.iter()) {
            *d = degree(mf, xv);
        }
        // Backwards, so that entry i is read before the entries i·k.. that replace it.
        for i in (0..len).rev() {
            let Some(&prefix) = out.get(i) else {
                continue;
            };
            if let Some(block) = out.get_mut(i * k..(i + 1) * k) {
                for (o, &d) in block.iter_mut().zip(degrees.iter()) {
                    *o = combine(prefix, d);
                }
            }
        }
        len *= k;
    }
    len
}

/// Iterator over the rules of a [`RuleBase`]: for each rule, the set index of every variable.
#[derive(Clone, Debug)]
pub struct Rules<'a, T, const V: usize> {
    variables: &'a [PremiseSets<T>; V],
    digits: [usize; V],
    remaining: usize,
}

impl<T, const V: usize> Iterator for Rules<'_, T, V> {
    type Item = [usize; V];

    fn next(&mut self) -> Option<[usize; V]> {
        if self.remaining == 0 {
            return None;
        }
        self.remaining -= 1;
        let current = self.digits;
        // Mixed-radix increment, last variable fastest.
        for (d, sets) in self.digits.iter_mut().zip(self.variables.iter()).rev() {
            if sets.is_empty() {
                continue;
            }
            *d += 1;
            if *d < sets.len() {
                break;
            }
            *d = 0;
        }
        Some(current)
    }
}
