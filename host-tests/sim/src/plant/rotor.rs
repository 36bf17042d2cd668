//! Blade-element thrust with uniform inflow from momentum theory (main and tail rotor).
//!
//! `C_T = (a σ/2) [θ0 (1/3 + μ²/2) + (μ_z − λ0)/2]`, limited to `±C_T,max`;
//! `λ0 = C_T / (2 η_w sqrt(μ² + (λ0 − μ_z)²))`;
//! `C_Q = C_T (λ0 − μ_z) + (C_D0 σ/8)(1 + 7μ²/3)`.
//!
//! The inflow equation is solved with a bracketed (safeguarded) Newton iteration from a fixed
//! starting point, so the result depends on the inputs only: no warm start, no hidden state.

use super::params::RotorBlades;

/// Most iterations of the inflow solver. Newton converges in ≈ 5; bisection fallback needs
/// ≈ 55 to reach f64 resolution on the initial bracket, so this is never the binding limit
/// in practice.
const MAX_INFLOW_ITERATIONS: usize = 80;

/// Initial inflow bracket `[−2, 2]`: `h(λ) = 2 η_w λ S − C_T` is negative at the lower end and
/// positive at the upper end for any |μ_z| < 1 and |C_T| ≤ 0.1 (far outside the flight regime).
const INFLOW_BRACKET: f64 = 2.0;

/// Converged rotor state for one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorSolution {
    /// Thrust coefficient `C_T` (–), after the `C_T,max` limit.
    pub c_t: f64,
    /// Uniform inflow ratio `λ0` (–), positive for flow through the disc along the thrust.
    pub lambda0: f64,
    /// Torque coefficient `C_Q` (–).
    pub c_q: f64,
    /// Thrust `T = C_T ρ (ΩR)² π R²` (N).
    pub thrust: f64,
    /// Shaft torque `Q = C_Q ρ (ΩR)² π R³` (N·m).
    pub torque: f64,
    /// Induced velocity `v_i = λ0 Ω R` (m/s).
    pub induced_velocity: f64,
    /// Whether the `C_T,max` limit was active.
    pub saturated: bool,
}

/// Solves the rotor for collective blade pitch `theta0` (rad), rotor speed `omega` (rad/s),
/// in-plane airspeed `v_inplane` (m/s, ≥ 0) and airspeed along the shaft opposite to the
/// thrust `v_axial` (m/s; positive = air coming in from the thrust side, as in a descent for
/// the main rotor). Air density `rho` (kg/m³).
pub fn solve_rotor(
    blades: &RotorBlades,
    rho: f64,
    omega: f64,
    theta0: f64,
    v_inplane: f64,
    v_axial: f64,
) -> RotorSolution {
    let tip_speed = omega * blades.radius;
    let mu = v_inplane / tip_speed;
    let mu_z = v_axial / tip_speed;
    let sigma = blades.solidity();
    let k = 0.5 * blades.lift_slope * sigma;
    let eta = blades.eta_w;
    let ct_max = blades.ct_max;

    // Blade-element C_T as a function of λ, with the limit, and its slope in λ.
    let ct_of = |lambda: f64| -> (f64, f64, bool) {
        let raw = k * (theta0 * (1.0 / 3.0 + 0.5 * mu * mu) + 0.5 * (mu_z - lambda));
        if raw > ct_max {
            (ct_max, 0.0, true)
        } else if raw < -ct_max {
            (-ct_max, 0.0, true)
        } else {
            (raw, -0.5 * k, false)
        }
    };
    // Residual h(λ) = 2 η λ S(λ) − C_T(λ), increasing through its root; h'(λ).
    let residual = |lambda: f64| -> (f64, f64) {
        let d = lambda - mu_z;
        let s = (mu * mu + d * d).sqrt();
        let (ct, dct, _) = ct_of(lambda);
        let ds = if s > 1e-12 { d / s } else { 0.0 };
        (
            2.0 * eta * lambda * s - ct,
            2.0 * eta * (s + lambda * ds) - dct,
        )
    };

    // Fixed start: the hover solution for the blade-element C_T at λ = μ_z.
    let (c0, _, _) = ct_of(mu_z);
    let mut lambda = mu_z + c0.signum() * (c0.abs() / (2.0 * eta)).sqrt();
    let mut lo = -INFLOW_BRACKET;
    let mut hi = INFLOW_BRACKET;
    if !(lambda > lo && lambda < hi) {
        lambda = 0.0;
    }
    for _ in 0..MAX_INFLOW_ITERATIONS {
        let (h, dh) = residual(lambda);
        if h == 0.0 {
            break;
        }
        if h < 0.0 {
            lo = lambda;
        } else {
            hi = lambda;
        }
        let newton = lambda - h / dh;
        let next = if dh > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - lambda).abs();
        lambda = next;
        if step <= 1e-15 * (1.0 + lambda.abs()) {
            break;
        }
    }

    let (c_t, _, saturated) = ct_of(lambda);
    let c_q = c_t * (lambda - mu_z) + blades.cd0 * sigma / 8.0 * (1.0 + 7.0 * mu * mu / 3.0);
    let q_dyn = rho * tip_speed * tip_speed * blades.disc_area();
    RotorSolution {
        c_t,
        lambda0: lambda,
        c_q,
        thrust: c_t * q_dyn,
        torque: c_q * q_dyn * blades.radius,
        induced_velocity: lambda * tip_speed,
        saturated,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::params::XCell60;

    #[test]
    fn inflow_satisfies_momentum_equation() {
        let p = XCell60::default();
        for &(theta, vin, vax) in &[
            (0.1, 0.0, 0.0),
            (0.1, 5.0, 1.0),
            (0.05, 12.0, -3.0),
            (0.15, 0.0, 4.0),
            (-0.1, 3.0, 0.0),
            (0.0, 0.0, 0.0),
        ] {
            let s = solve_rotor(&p.main, p.rho, p.omega, theta, vin, vax);
            let tip = p.omega * p.main.radius;
            let mu = vin / tip;
            let mu_z = vax / tip;
            let rhs = s.c_t
                / (2.0 * p.main.eta_w * (mu * mu + (s.lambda0 - mu_z).powi(2)).sqrt().max(1e-300));
            if s.c_t != 0.0 {
                assert!(
                    (s.lambda0 - rhs).abs() < 1e-12,
                    "{theta} {vin} {vax}: {s:?}"
                );
            }
        }
    }
}
