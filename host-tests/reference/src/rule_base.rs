//! Product t-norm rule base, normalised firing strengths `ξ_i` and the TS regressor (Section 4).

use crate::membership::{MembershipFunction, VariableSpec};

/// Product t-norm rule base over `n` premise variables (Section 4).
///
/// Every combination of one linguistic value per variable is a rule, so there are
/// `R = Π_v (number of sets of v)` rules. Rule order: the first premise variable is the most
/// significant digit, and each variable's sets are in the order left, centre, right; i.e.
/// rule index `i = ((j₁ · n₂ + j₂) · n₃ + j₃) …`.
#[derive(Clone, Debug, PartialEq)]
pub struct RuleBase {
    vars: Vec<Vec<MembershipFunction>>,
}

impl RuleBase {
    /// Rule base over the given variables, each an ordered list of membership functions.
    ///
    /// # Panics
    /// If there is no variable or a variable has no set.
    pub fn new(vars: Vec<Vec<MembershipFunction>>) -> Self {
        assert!(!vars.is_empty(), "a rule base needs a premise variable");
        assert!(
            vars.iter().all(|v| !v.is_empty()),
            "every premise variable needs at least one set"
        );
        Self { vars }
    }

    /// Rule base from Table 3 rows (see [`table3`](crate::table3)).
    pub fn from_specs(specs: &[VariableSpec]) -> Self {
        Self::new(specs.iter().map(VariableSpec::sets).collect())
    }

    /// Number of premise variables `n`.
    pub fn n_vars(&self) -> usize {
        self.vars.len()
    }

    /// Number of rules `R`.
    pub fn n_rules(&self) -> usize {
        self.vars.iter().map(Vec::len).product()
    }

    /// The membership functions of premise variable `v`.
    pub fn sets(&self, v: usize) -> &[MembershipFunction] {
        &self.vars[v]
    }

    /// Per-variable set indices `(j₁, …, j_n)` of rule `i` (first variable most significant).
    pub fn rule_digits(&self, mut i: usize) -> Vec<usize> {
        let mut digits = vec![0; self.vars.len()];
        for (v, sets) in self.vars.iter().enumerate().rev() {
            digits[v] = i % sets.len();
            i /= sets.len();
        }
        digits
    }

    /// Premise degrees `μ_i(x₁, …, x_n) = μ_{F¹}(x₁) · … · μ_{Fⁿ}(x_n)` of all rules (product
    /// inference, Section 4).
    ///
    /// # Panics
    /// If `x.len()` differs from the number of premise variables.
    pub fn firing(&self, x: &[f64]) -> Vec<f64> {
        assert_eq!(x.len(), self.vars.len(), "premise length");
        (0..self.n_rules())
            .map(|i| {
                self.rule_digits(i)
                    .iter()
                    .enumerate()
                    .map(|(v, &j)| self.vars[v][j].eval(x[v]))
                    .product()
            })
            .collect()
    }

    /// Normalised firing strengths `ξ_i = μ_i / Σ_l μ_l` (Section 4); they sum to 1.
    ///
    /// # Panics
    /// If `Σ μ_l` is not positive and finite. With Table 3's sets this cannot happen for finite
    /// inputs: every variable has both shoulders (or a wide centre), so some rule always fires.
    pub fn normalized(&self, x: &[f64]) -> Vec<f64> {
        let mu = self.firing(x);
        let sum: f64 = mu.iter().sum();
        assert!(
            sum > 0.0 && sum.is_finite(),
            "sum of premise degrees is {sum} at x = {x:?}"
        );
        mu.iter().map(|m| m / sum).collect()
    }
}

/// The Takagi-Sugeno regressor of Section 4:
/// `ξᵀ(k) = [Δ₁(k)ξ₁ … Δ₁(k)ξ_R, …, Δ_d(k)ξ₁ … Δ_d(k)ξ_R]`, of length `d·R`, matched to
/// `θᵀ = [α_{1,1} … α_{R,1}, …, α_{1,d} … α_{R,d}]` (parameter-major, rule-minor).
pub fn ts_regressor(xi: &[f64], deltas: &[f64]) -> Vec<f64> {
    deltas
        .iter()
        .flat_map(|&d| xi.iter().map(move |&x| d * x))
        .collect()
}
