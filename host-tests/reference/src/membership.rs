//! Membership functions of Table 1 and the centres and spreads of Table 3.

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
