//! Independent `f64` reference of the paper's equations.
//!
//! This module is the yardstick the `rotorid` core is tested against. It is written straight
//! from the paper ("System Identification for a Miniature Helicopter at Hover Using Fuzzy
//! Models", `/work/shared/paper/ts-fuzzy-rls-helicopter-hover.txt`, Sections 4–5, Tables 1
//! and 3) and the reading notes (`NOTES.md`), with plain loops, heap vectors and full
//! (row-major, `n × n`) matrices. It deliberately shares no code with the core and favours
//! transparency over speed: nothing here is meant to match the core bit for bit, only to the
//! accuracy of `f64` arithmetic.
//!
//! Contents:
//!
//! - [`MembershipFunction`]: the three Gaussian shapes of Table 1.
//! - [`table3`]: the centres and spreads of Table 3, with units, in one place.
//! - [`RuleBase`]: product t-norm rule base and normalised firing strengths `ξ_i` (Section 4).
//! - [`ts_regressor`]: the regressor `ξ(k)` of Section 4, `[Δ₁ξ₁ … Δ₁ξ_R, Δ₂ξ₁ … Δ₂ξ_R]`.
//! - [`Rls`]: the full-matrix RLS of Section 4 (optionally with a forgetting factor `λ`).
//! - [`ModelKind`], [`ReferenceModel`]: the four models of Section 5 (Eqs. 27–30) and their
//!   single-rule baselines (Eqs. 19, 26).
//! - [`ReferenceHover`]: all eight models fed one [`HoverSample`] at a time, recording every
//!   step ([`HoverStep`]).
//!
//! # Axes and units (NOTES.md, X-Plane conventions)
//!
//! Inertial frame: `j_s` up, so `v^s = [v_x, v_y, v_z]` has `v_y` up (m/s). Body rates
//! `ω^b = [q, r, p]` (pitch, yaw, roll) in **deg/s**: Table 3's centres and spreads for `q̃, r̃,
//! p̃` are in deg/s and the products `r·p`, `q·p`, `q·r` of Eqs. 28–30 are formed in (deg/s)².
//! Attitude: roll `φ`, pitch `θ`, yaw `ψ` in rad. Controls `u = [u_col, u_ped, u_lon, u_lat]`
//! (normalised; the collective stays clearly positive at hover, see NOTES.md).

use std::fmt;

/// Shape of a Gaussian membership function (Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Left shoulder `μ^l`: `1` for `x ≤ c^l`, Gaussian above.
    Left,
    /// Centre `μ`: Gaussian everywhere.
    Centre,
    /// Right shoulder `μ^r`: `1` for `x ≥ c^r`, Gaussian below.
    Right,
}

/// One Gaussian membership function of Table 1: `exp(−½((x − c)/σ)²)`, saturated at 1 beyond
/// its centre for the shoulders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MembershipFunction {
    /// Left shoulder, centre or right shoulder.
    pub shape: Shape,
    /// Centre `c` (same unit as the premise variable).
    pub c: f64,
    /// Spread `σ > 0` (same unit as the premise variable).
    pub sigma: f64,
}

impl MembershipFunction {
    /// Degree of membership `μ(x) ∈ [0, 1]` (Table 1).
    ///
    /// Left: `1` if `x ≤ c^l`, else `exp(−½((x − c^l)/σ^l)²)`.
    /// Centre: `exp(−½((x − c)/σ)²)`.
    /// Right: `1` if `x ≥ c^r`, else `exp(−½((x − c^r)/σ^r)²)`.
    pub fn eval(&self, x: f64) -> f64 {
        let gauss = || {
            let z = (x - self.c) / self.sigma;
            (-0.5 * z * z).exp()
        };
        match self.shape {
            Shape::Left if x <= self.c => 1.0,
            Shape::Right if x >= self.c => 1.0,
            _ => gauss(),
        }
    }
}

/// Centre and spread of one linguistic value, as printed in Table 3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetSpec {
    /// Centre `c`.
    pub c: f64,
    /// Spread `σ`.
    pub sigma: f64,
}

/// One row of Table 3: the left, centre and right linguistic values of one premise variable.
/// `None` is Table 3's `(*)`: that linguistic value is not part of the rule base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VariableSpec {
    /// Left shoulder `(c^l, σ^l)`.
    pub left: Option<SetSpec>,
    /// Centre Gaussian `(c, σ)`.
    pub centre: Option<SetSpec>,
    /// Right shoulder `(c^r, σ^r)`.
    pub right: Option<SetSpec>,
}

impl VariableSpec {
    const fn full(cl: f64, sl: f64, c: f64, s: f64, cr: f64, sr: f64) -> Self {
        Self {
            left: Some(SetSpec { c: cl, sigma: sl }),
            centre: Some(SetSpec { c, sigma: s }),
            right: Some(SetSpec { c: cr, sigma: sr }),
        }
    }

    /// The membership functions that take part in the rule base, in the order left, centre,
    /// right, skipping the `(*)` entries.
    pub fn sets(&self) -> Vec<MembershipFunction> {
        [
            (Shape::Left, self.left),
            (Shape::Centre, self.centre),
            (Shape::Right, self.right),
        ]
        .into_iter()
        .filter_map(|(shape, s)| {
            s.map(|s| MembershipFunction {
                shape,
                c: s.c,
                sigma: s.sigma,
            })
        })
        .collect()
    }
}

/// Table 3 of the paper ("Gaussian centers and spreads"), the only place these numbers live in
/// the reference.
///
/// Units: translational velocities `ṽ_x^s, ṽ_y^s, ṽ_z^s` in **m/s** (inertial frame, `y` up);
/// body rates `q̃, r̃, p̃` in **deg/s**. Variables marked `(*)` in Table 3 take no part in that
/// model's rule base and are simply absent from the lists below (NOTES.md item 7).
pub mod table3 {
    use super::{SetSpec, VariableSpec};

    /// `ṽ_x^s` (m/s) for `v̂^s` (Eq. 27): L(−0.5, 0.01), C(0, 1), R(0.5, 0.01).
    pub const VELOCITY_VX: VariableSpec = VariableSpec::full(-0.5, 0.01, 0.0, 1.0, 0.5, 0.01);
    /// `ṽ_y^s` (m/s) for `v̂^s` (Eq. 27): L(−1, 0.03), C(0, 3), R(1, 0.03).
    pub const VELOCITY_VY: VariableSpec = VariableSpec::full(-1.0, 0.03, 0.0, 3.0, 1.0, 0.03);
    /// `ṽ_z^s` (m/s) for `v̂^s` (Eq. 27): L(−1, 0.3), C(0, 0.3), R(1, 0.3).
    pub const VELOCITY_VZ: VariableSpec = VariableSpec::full(-1.0, 0.3, 0.0, 0.3, 1.0, 0.3);

    /// `q̃` (deg/s) for `q̂` (Eq. 28): L(−1.5, 0.01), C(0, 6), R(1.5, 0.01).
    pub const PITCH_Q: VariableSpec = VariableSpec::full(-1.5, 0.01, 0.0, 6.0, 1.5, 0.01);
    /// `r̃` (deg/s) for `q̂` (Eq. 28): L(−4, 0.01), C(0, 8), R(4, 0.01).
    pub const PITCH_R: VariableSpec = VariableSpec::full(-4.0, 0.01, 0.0, 8.0, 4.0, 0.01);
    /// `p̃` (deg/s) for `q̂` (Eq. 28): L(−0.5, 1), centre `(*)`, R(0.5, 1).
    pub const PITCH_P: VariableSpec = VariableSpec {
        left: Some(SetSpec {
            c: -0.5,
            sigma: 1.0,
        }),
        centre: None,
        right: Some(SetSpec { c: 0.5, sigma: 1.0 }),
    };

    /// `r̃` (deg/s) for `r̂` (Eq. 29): L(−0.5, 0.01), C(0, 8), R(0.5, 0.01). (`q̃` is `(*)`.)
    pub const YAW_R: VariableSpec = VariableSpec::full(-0.5, 0.01, 0.0, 8.0, 0.5, 0.01);
    /// `p̃` (deg/s) for `r̂` (Eq. 29): L(−1.5, 0.03), C(0, 6), R(1.5, 0.03).
    pub const YAW_P: VariableSpec = VariableSpec::full(-1.5, 0.03, 0.0, 6.0, 1.5, 0.03);

    /// `q̃` (deg/s) for `p̂` (Eq. 30): L(−2, 0.03), C(0, 6), R(2, 0.03). (`p̃` is `(*)`.)
    pub const ROLL_Q: VariableSpec = VariableSpec::full(-2.0, 0.03, 0.0, 6.0, 2.0, 0.03);
    /// `r̃` (deg/s) for `p̂` (Eq. 30): L(−0.5, 0.01), C(0, 8), R(0.5, 0.01).
    pub const ROLL_R: VariableSpec = VariableSpec::full(-0.5, 0.01, 0.0, 8.0, 0.5, 0.01);

    /// Premise variables of `v̂^s` (Eq. 27), in order `(ṽ_x, ṽ_y, ṽ_z)`: 3·3·3 = 27 rules.
    pub const VELOCITY: [VariableSpec; 3] = [VELOCITY_VX, VELOCITY_VY, VELOCITY_VZ];
    /// Premise variables of `q̂` (Eq. 28), in order `(q̃, r̃, p̃)`: 3·3·2 = 18 rules.
    pub const PITCH_RATE: [VariableSpec; 3] = [PITCH_Q, PITCH_R, PITCH_P];
    /// Premise variables of `r̂` (Eq. 29), in order `(r̃, p̃)`: 3·3 = 9 rules.
    pub const YAW_RATE: [VariableSpec; 2] = [YAW_R, YAW_P];
    /// Premise variables of `p̂` (Eq. 30), in order `(q̃, r̃)`: 3·3 = 9 rules.
    pub const ROLL_RATE: [VariableSpec; 2] = [ROLL_Q, ROLL_R];
}

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

    /// Rule base from Table 3 rows (see [`table3`]).
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

/// Full-matrix recursive least squares, exactly as Section 4 prints it, optionally with an
/// exponential forgetting factor `λ`:
///
/// ```text
/// Kw(k+1)   = P(k) ξ(k) [ξᵀ(k) P(k) ξ(k) + λ]⁻¹
/// P(k+1)    = [I − Kw(k+1) ξᵀ(k)] P(k) / λ
/// θ̂(k+1)    = θ̂(k) + Kw(k+1) [y(k+1) − ξᵀ(k) θ̂(k)]
/// ```
///
/// with `P(0) = α I`, `θ̂(0) = 0` (or given). The paper uses `λ = 1` (NOTES.md item 8).
///
/// `P` is stored as a full row-major `n × n` matrix. `[I − Kξᵀ] P` is evaluated as
/// `P − K (ξᵀP)`, which is the same product re-associated (`(Kξᵀ)P = K(ξᵀP)`); no symmetry of
/// `P` is assumed and `P` is never symmetrised, so any asymmetry from rounding is visible.
#[derive(Clone, Debug, PartialEq)]
pub struct Rls {
    n: usize,
    theta: Vec<f64>,
    p: Vec<f64>,
    lambda: f64,
}

impl Rls {
    /// `n` parameters, `P(0) = α I`, `θ̂(0) = 0`, no forgetting (`λ = 1`), as in the paper.
    pub fn new(n: usize, alpha: f64) -> Self {
        Self::with_forgetting(n, alpha, 1.0)
    }

    /// As [`Rls::new`] with a forgetting factor `λ ∈ (0, 1]`.
    ///
    /// # Panics
    /// If `n == 0`, `α ≤ 0` or `λ ∉ (0, 1]`.
    pub fn with_forgetting(n: usize, alpha: f64, lambda: f64) -> Self {
        assert!(n > 0, "RLS needs at least one parameter");
        assert!(alpha > 0.0, "P(0) = alpha I needs alpha > 0");
        assert!(lambda > 0.0 && lambda <= 1.0, "lambda must be in (0, 1]");
        let mut p = vec![0.0; n * n];
        for i in 0..n {
            p[i * n + i] = alpha;
        }
        Self {
            n,
            theta: vec![0.0; n],
            p,
            lambda,
        }
    }

    /// Replace `θ̂` (e.g. a "good initial guess", Section 4).
    ///
    /// # Panics
    /// If the length is not `n`.
    pub fn set_theta(&mut self, theta: &[f64]) {
        assert_eq!(theta.len(), self.n, "theta length");
        self.theta.copy_from_slice(theta);
    }

    /// Number of parameters `n = d·R`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Forgetting factor `λ`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// Current estimate `θ̂`.
    pub fn theta(&self) -> &[f64] {
        &self.theta
    }

    /// Current covariance `P`, full row-major `n × n` (`P[i][j]` at `i·n + j`).
    pub fn p(&self) -> &[f64] {
        &self.p
    }

    /// Element `P[i][j]`.
    pub fn p_at(&self, i: usize, j: usize) -> f64 {
        self.p[i * self.n + j]
    }

    /// Output `ξᵀ θ̂`.
    pub fn predict(&self, xi: &[f64]) -> f64 {
        assert_eq!(xi.len(), self.n, "regressor length");
        xi.iter().zip(&self.theta).map(|(a, b)| a * b).sum()
    }

    /// One RLS step with regressor `ξ(k)` and target `y(k+1)`. Returns the a-priori innovation
    /// `y(k+1) − ξᵀ(k) θ̂(k)`.
    ///
    /// Order of computation as in the paper: `P(k) → Kw(k+1) → P(k+1) → θ̂(k+1)`.
    // Index loops on purpose: they read like the matrix formulas they implement.
    pub fn update(&mut self, xi: &[f64], y: f64) -> f64 {
        self.update_with_forgetting(xi, y, self.lambda)
    }

    /// [`Rls::update`] with forgetting factor `lambda` for this step only. A sample with
    /// several outputs forgets once: `λ = 1` for all but its last measurement.
    #[allow(clippy::needless_range_loop)]
    pub fn update_with_forgetting(&mut self, xi: &[f64], y: f64, lambda: f64) -> f64 {
        let n = self.n;
        assert_eq!(xi.len(), n, "regressor length");
        let innovation = y - self.predict(xi);

        // P ξ (column) and ξᵀ P (row).
        let mut p_xi = vec![0.0; n];
        let mut xi_p = vec![0.0; n];
        for i in 0..n {
            for j in 0..n {
                p_xi[i] += self.p[i * n + j] * xi[j];
                xi_p[j] += xi[i] * self.p[i * n + j];
            }
        }
        // ξᵀ P ξ + λ.
        let denom: f64 = lambda + xi.iter().zip(&p_xi).map(|(a, b)| a * b).sum::<f64>();
        let k: Vec<f64> = p_xi.iter().map(|v| v / denom).collect();

        // P ← [I − K ξᵀ] P / λ = (P − K (ξᵀ P)) / λ.
        for i in 0..n {
            for j in 0..n {
                let v = self.p[i * n + j] - k[i] * xi_p[j];
                self.p[i * n + j] = v / lambda;
            }
        }
        // θ̂ ← θ̂ + K e.
        for i in 0..n {
            self.theta[i] += k[i] * innovation;
        }
        innovation
    }
}

/// Lower Cholesky factor `L` (`A = L Lᵀ`) of a full row-major `n × n` matrix, or `None` if a
/// pivot is not strictly positive (or not finite): a positive-definiteness check. Reads the
/// lower triangle only; check symmetry separately.
pub fn cholesky_lower(a: &[f64], n: usize) -> Option<Vec<f64>> {
    assert_eq!(a.len(), n * n, "matrix size");
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let d = d.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    Some(l)
}

/// One telemetry sample in the paper's axes and units (NOTES.md).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HoverSample {
    /// Roll `φ` (rad).
    pub roll: f64,
    /// Pitch `θ` (rad).
    pub pitch: f64,
    /// Yaw `ψ` (rad).
    pub yaw: f64,
    /// Inertial velocity `v^s = [v_x, v_y, v_z]` (m/s), `v_y` up.
    pub v: [f64; 3],
    /// Body rates `ω^b = [q, r, p]` (deg/s): pitch, yaw, roll.
    pub omega: [f64; 3],
    /// Controls `u = [u_col, u_ped, u_lon, u_lat]` (normalised).
    pub u: [f64; 4],
}

impl HoverSample {
    /// Pitch rate `q` (deg/s).
    pub fn q(&self) -> f64 {
        self.omega[0]
    }
    /// Yaw rate `r` (deg/s).
    pub fn r(&self) -> f64 {
        self.omega[1]
    }
    /// Roll rate `p` (deg/s).
    pub fn p(&self) -> f64 {
        self.omega[2]
    }
    /// Collective `u_col`.
    pub fn u_col(&self) -> f64 {
        self.u[0]
    }
    /// Pedal `u_ped`.
    pub fn u_ped(&self) -> f64 {
        self.u[1]
    }
    /// Longitudinal cyclic `u_lon`.
    pub fn u_lon(&self) -> f64 {
        self.u[2]
    }
    /// Lateral cyclic `u_lat`.
    pub fn u_lat(&self) -> f64 {
        self.u[3]
    }
}

/// `R e₂`: the body "up" axis `j_b` in the inertial frame (the column Eq. 27 uses, NOTES.md
/// item 1): `[sφcψ − cφsθsψ, cφcθ, sφsψ + cφsθcψ]`.
pub fn body_up_in_inertial(roll: f64, pitch: f64, yaw: f64) -> [f64; 3] {
    let (sf, cf) = roll.sin_cos();
    let (st, ct) = pitch.sin_cos();
    let (sp, cp) = yaw.sin_cos();
    [sf * cp - cf * st * sp, cf * ct, sf * sp + cf * st * cp]
}

/// The four identified models of Section 5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModelKind {
    /// `v̂^s` (Eq. 27; baseline Eq. 19): premise `(v_x, v_y, v_z)`, 27 rules, three outputs
    /// sharing `θ = [α₁¹ … α₁²⁷, α₂¹ … α₂²⁷]` (54 parameters).
    Velocity,
    /// `q̂` (Eq. 28; baseline Eq. 26): premise `(q, r, p)` with `p` left/right only, 18 rules,
    /// `Δ = [r·p, u_lon·u_col]`, `θ = [𝕀₁ⁱ…, γ₁ⁱ…]` (36 parameters).
    PitchRate,
    /// `r̂` (Eq. 29; baseline Eq. 26): premise `(r, p)`, 9 rules, `Δ = [q·p, u_ped]`,
    /// `θ = [𝕀₂ⁱ…, γ₂ⁱ…]` (18 parameters).
    YawRate,
    /// `p̂` (Eq. 30; baseline Eq. 26): premise `(q, r)`, 9 rules, `Δ = [q·r, u_lat·u_col]`,
    /// `θ = [𝕀₃ⁱ…, γ₃ⁱ…]` (18 parameters).
    RollRate,
}

impl ModelKind {
    /// All four, in the order used by [`ReferenceHover`] and [`HoverStep`].
    pub const ALL: [ModelKind; 4] = [
        ModelKind::Velocity,
        ModelKind::PitchRate,
        ModelKind::YawRate,
        ModelKind::RollRate,
    ];

    /// Number of consequent parameters per rule, `d = 2` for every model.
    pub const D: usize = 2;

    /// Table 3's premise variables of this model.
    pub fn premise_specs(self) -> &'static [VariableSpec] {
        match self {
            ModelKind::Velocity => &table3::VELOCITY,
            ModelKind::PitchRate => &table3::PITCH_RATE,
            ModelKind::YawRate => &table3::YAW_RATE,
            ModelKind::RollRate => &table3::ROLL_RATE,
        }
    }

    /// The fuzzy rule base of this model (Table 3).
    pub fn rule_base(self) -> RuleBase {
        RuleBase::from_specs(self.premise_specs())
    }

    /// Premise values `(x₁, …, x_n)` of a sample: `(v_x, v_y, v_z)` m/s, `(q, r, p)`, `(r, p)`,
    /// `(q, r)` deg/s.
    pub fn premise(self, s: &HoverSample) -> Vec<f64> {
        match self {
            ModelKind::Velocity => s.v.to_vec(),
            ModelKind::PitchRate => vec![s.q(), s.r(), s.p()],
            ModelKind::YawRate => vec![s.r(), s.p()],
            ModelKind::RollRate => vec![s.q(), s.r()],
        }
    }

    /// Number of outputs: 3 (`v_x, v_y, v_z`) for [`ModelKind::Velocity`], else 1.
    pub fn n_outputs(self) -> usize {
        match self {
            ModelKind::Velocity => 3,
            _ => 1,
        }
    }

    /// The modelled state `y_j(k)` of output `j`: `v_j` (m/s) or the rate (deg/s).
    pub fn state(self, s: &HoverSample, j: usize) -> f64 {
        match self {
            ModelKind::Velocity => s.v[j],
            ModelKind::PitchRate => s.q(),
            ModelKind::YawRate => s.r(),
            ModelKind::RollRate => s.p(),
        }
    }

    /// Consequent functions `[Δ₁(k), Δ₂(k)]` of output `j` from sample `k`:
    ///
    /// - Velocity (Eq. 27), with `e = R e₂` ([`body_up_in_inertial`]):
    ///   `v_x: [e_x u_col, 0]`, `v_y: [e_y u_col, 1]`, `v_z: [e_z u_col, 0]`.
    /// - `q̂` (Eq. 28): `[r·p, u_lon·u_col]`.
    /// - `r̂` (Eq. 29): `[q·p, u_ped]`.
    /// - `p̂` (Eq. 30): `[q·r, u_lat·u_col]`.
    pub fn deltas(self, s: &HoverSample, j: usize) -> [f64; 2] {
        match self {
            ModelKind::Velocity => {
                let e = body_up_in_inertial(s.roll, s.pitch, s.yaw);
                let a2 = if j == 1 { 1.0 } else { 0.0 };
                [e[j] * s.u_col(), a2]
            }
            ModelKind::PitchRate => [s.r() * s.p(), s.u_lon() * s.u_col()],
            ModelKind::YawRate => [s.q() * s.p(), s.u_ped()],
            ModelKind::RollRate => [s.q() * s.r(), s.u_lat() * s.u_col()],
        }
    }
}

impl fmt::Display for ModelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ModelKind::Velocity => "velocity",
            ModelKind::PitchRate => "q",
            ModelKind::YawRate => "r",
            ModelKind::RollRate => "p",
        })
    }
}

/// One identified model: the Takagi-Sugeno form (Eqs. 27–30, Table 3) or its single-rule
/// baseline (Eqs. 19, 26, `ξ = 1`), with its own [`Rls`].
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceModel {
    kind: ModelKind,
    rules: Option<RuleBase>,
    rls: Rls,
}

impl ReferenceModel {
    /// Takagi-Sugeno model with Table 3's rule base, `P(0) = α I`, `θ̂(0) = 0`, forgetting `λ`.
    pub fn fuzzy(kind: ModelKind, alpha: f64, lambda: f64) -> Self {
        let rules = kind.rule_base();
        let n = ModelKind::D * rules.n_rules();
        Self {
            kind,
            rules: Some(rules),
            rls: Rls::with_forgetting(n, alpha, lambda),
        }
    }

    /// Plain RLS baseline (Eq. 19 or 26): one rule, `ξ = 1`, 2 parameters.
    pub fn plain(kind: ModelKind, alpha: f64, lambda: f64) -> Self {
        Self {
            kind,
            rules: None,
            rls: Rls::with_forgetting(ModelKind::D, alpha, lambda),
        }
    }

    /// Which model this is.
    pub fn kind(&self) -> ModelKind {
        self.kind
    }

    /// `true` for the Takagi-Sugeno form, `false` for the single-rule baseline.
    pub fn is_fuzzy(&self) -> bool {
        self.rules.is_some()
    }

    /// The rule base (`None` for the baseline).
    pub fn rule_base(&self) -> Option<&RuleBase> {
        self.rules.as_ref()
    }

    /// Number of rules `R` (1 for the baseline).
    pub fn n_rules(&self) -> usize {
        self.rules.as_ref().map_or(1, RuleBase::n_rules)
    }

    /// The estimator.
    pub fn rls(&self) -> &Rls {
        &self.rls
    }

    /// Mutable estimator (e.g. to set `θ̂(0)`).
    pub fn rls_mut(&mut self) -> &mut Rls {
        &mut self.rls
    }

    /// Normalised firing strengths `ξ_i` at sample `s` (`[1]` for the baseline).
    pub fn strengths(&self, s: &HoverSample) -> Vec<f64> {
        match &self.rules {
            Some(rb) => rb.normalized(&self.kind.premise(s)),
            None => vec![1.0],
        }
    }

    /// Regressor `ξ(k)` of every output, built from sample `k` ([`ts_regressor`]).
    pub fn regressors(&self, s: &HoverSample) -> Vec<Vec<f64>> {
        let xi = self.strengths(s);
        (0..self.kind.n_outputs())
            .map(|j| ts_regressor(&xi, &self.kind.deltas(s, j)))
            .collect()
    }

    /// Regression targets `y_j(k+1) − y_j(k)` (the coefficient of the state is fixed at 1).
    pub fn targets(&self, s_k: &HoverSample, s_k1: &HoverSample) -> Vec<f64> {
        (0..self.kind.n_outputs())
            .map(|j| self.kind.state(s_k1, j) - self.kind.state(s_k, j))
            .collect()
    }

    /// Update with the pair `(k, k+1)`: regressors from `s_k`, targets `y(k+1) − y(k)`. For the
    /// velocity model the three outputs share `θ` and are processed as three sequential scalar
    /// RLS updates in the order `x, y, z`, each with its own regressor, straight from Eq. 27
    /// (the core combines the parallel `x` and `z` rows into one; the results agree to
    /// rounding, `tests/reference_agreement.rs`). With `λ < 1` the sample forgets once, after
    /// its last update.
    ///
    /// Returns the a-priori innovations `target_j − ξ_jᵀ θ̂`, all computed with `θ̂` from before
    /// the first of the updates.
    pub fn update(&mut self, s_k: &HoverSample, s_k1: &HoverSample) -> Vec<f64> {
        let regs = self.regressors(s_k);
        let targets = self.targets(s_k, s_k1);
        let innovations: Vec<f64> = regs
            .iter()
            .zip(&targets)
            .map(|(xi, y)| y - self.rls.predict(xi))
            .collect();
        // One forgetting per sample, after its last output (as the core does).
        let last = regs.len().saturating_sub(1);
        for (m, (xi, y)) in regs.iter().zip(&targets).enumerate() {
            let lambda = if m == last { self.rls.lambda() } else { 1.0 };
            self.rls.update_with_forgetting(xi, *y, lambda);
        }
        innovations
    }

    /// One-step predictions `ŷ_j(k+1) = y_j(k) + ξ_jᵀ(k) θ̂` from sample `k`.
    pub fn predict(&self, s: &HoverSample) -> Vec<f64> {
        self.regressors(s)
            .iter()
            .enumerate()
            .map(|(j, xi)| self.kind.state(s, j) + self.rls.predict(xi))
            .collect()
    }
}

/// What one model did at one step of [`ReferenceHover::push`].
#[derive(Clone, Debug, PartialEq)]
pub struct ModelStep {
    /// Which model.
    pub kind: ModelKind,
    /// A-priori innovations `(y_j(k+1) − y_j(k)) − ξ_jᵀ(k) θ̂` (one per output), with `θ̂` from
    /// before this step's update(s).
    pub innovations: Vec<f64>,
    /// Predictions `ŷ_j(k+2) = y_j(k+1) + ξ_jᵀ(k+1) θ̂` with the updated `θ̂`.
    pub predictions: Vec<f64>,
    /// `θ̂` after the update.
    pub theta: Vec<f64>,
    /// `P` after the update, full row-major `n × n`.
    pub p: Vec<f64>,
}

/// Everything recorded at one sample by [`ReferenceHover::push`].
#[derive(Clone, Debug, PartialEq)]
pub struct HoverStep {
    /// Index `k+1` of the sample just pushed (the first sample is index 0 and yields no step).
    pub index: usize,
    /// Takagi-Sugeno models, in [`ModelKind::ALL`] order.
    pub fuzzy: [ModelStep; 4],
    /// Single-rule baselines, in [`ModelKind::ALL`] order.
    pub plain: [ModelStep; 4],
}

/// All eight models (four Takagi-Sugeno, four baselines) fed one sample at a time.
///
/// At sample `k+1` every model is updated with the regressor built from sample `k` and the
/// target `y(k+1) − y(k)`, then predicts `y(k+2) = y(k+1) + ξᵀ(k+1) θ̂`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceHover {
    fuzzy: [ReferenceModel; 4],
    plain: [ReferenceModel; 4],
    prev: Option<HoverSample>,
    count: usize,
}

impl ReferenceHover {
    /// The paper's setting: `P(0) = α I`, `θ̂(0) = 0`, no forgetting.
    pub fn new(alpha: f64) -> Self {
        Self::with_forgetting(alpha, 1.0)
    }

    /// As [`ReferenceHover::new`] with a forgetting factor `λ` for every model.
    pub fn with_forgetting(alpha: f64, lambda: f64) -> Self {
        Self {
            fuzzy: ModelKind::ALL.map(|k| ReferenceModel::fuzzy(k, alpha, lambda)),
            plain: ModelKind::ALL.map(|k| ReferenceModel::plain(k, alpha, lambda)),
            prev: None,
            count: 0,
        }
    }

    /// Takagi-Sugeno models in [`ModelKind::ALL`] order.
    pub fn fuzzy(&self) -> &[ReferenceModel; 4] {
        &self.fuzzy
    }

    /// Mutable Takagi-Sugeno models (e.g. to set `θ̂(0)` before the first sample).
    pub fn fuzzy_mut(&mut self) -> &mut [ReferenceModel; 4] {
        &mut self.fuzzy
    }

    /// Baselines in [`ModelKind::ALL`] order.
    pub fn plain(&self) -> &[ReferenceModel; 4] {
        &self.plain
    }

    /// Mutable baselines.
    pub fn plain_mut(&mut self) -> &mut [ReferenceModel; 4] {
        &mut self.plain
    }

    /// Number of samples pushed so far.
    pub fn samples(&self) -> usize {
        self.count
    }

    /// Feed the next sample. The first sample only primes the history and returns `None`.
    pub fn push(&mut self, s: HoverSample) -> Option<HoverStep> {
        let prev = self.prev.replace(s);
        let index = self.count;
        self.count += 1;
        let prev = prev?;
        let step = |m: &mut ReferenceModel| {
            let innovations = m.update(&prev, &s);
            ModelStep {
                kind: m.kind(),
                innovations,
                predictions: m.predict(&s),
                theta: m.rls().theta().to_vec(),
                p: m.rls().p().to_vec(),
            }
        };
        let fuzzy = self.fuzzy.each_mut().map(step);
        let plain = self.plain.each_mut().map(step);
        Some(HoverStep {
            index,
            fuzzy,
            plain,
        })
    }
}
