//! The four models of Section 5 (Eqs. 27–30), their single-rule baselines (Eqs. 19, 26) and
//! all eight fed one sample at a time.

use std::fmt;

use crate::membership::{table3, VariableSpec};
use crate::rls::Rls;
use crate::rule_base::{ts_regressor, RuleBase};

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
