//! Hover trim: sticks and roll/pitch attitude that zero all forces and moments at rest.

use nalgebra::{SMatrix, SVector, Vector3};

use super::dynamics::{derivative, BladePitch, State};
use super::error::PlantError;
use super::params::Helicopter;
use super::sticks::Sticks;

/// Newton iterations allowed; the residual is smooth near hover and converges in ≈ 5.
const MAX_TRIM_ITERATIONS: usize = 50;
/// Convergence threshold on the largest residual (m/s² and rad/s²).
const TRIM_TOLERANCE: f64 = 1e-11;
/// Central-difference step on the unknowns (stick units and rad).
const JACOBIAN_STEP: f64 = 1e-6;

/// Hover trim at zero velocity and zero body rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoverTrim {
    /// Trim sticks (normalised, inside [−1, 1]).
    pub sticks: Sticks,
    /// Roll attitude `φ` (rad).
    pub roll: f64,
    /// Pitch attitude `θ` (rad).
    pub pitch: f64,
    /// Heading `ψ` (rad), as requested.
    pub yaw: f64,
    /// Steady longitudinal flapping `a1` (rad).
    pub a1: f64,
    /// Steady lateral flapping `b1` (rad).
    pub b1: f64,
    /// Blade pitch at trim (rad).
    pub blade_pitch: BladePitch,
    /// Main-rotor thrust `T` (N).
    pub thrust: f64,
    /// Main-rotor thrust coefficient `C_T` (–).
    pub c_t: f64,
    /// Main-rotor inflow ratio `λ0` (–).
    pub lambda0: f64,
    /// Main-rotor collective blade pitch `θ0` (rad).
    pub collective_pitch: f64,
    /// Main-rotor torque `Q` (N·m).
    pub main_torque: f64,
    /// Main-rotor power `P = Q Ω` (W).
    pub main_power: f64,
    /// Tail-rotor thrust `T_tr` (N).
    pub tail_thrust: f64,
    /// Tail-rotor blade pitch `θ_tr` (rad).
    pub tail_pitch: f64,
    /// The trimmed plant state (at the origin).
    pub state: State,
}

fn trim_state(p: &Helicopter, x: &SVector<f64, 6>, yaw: f64) -> (Sticks, BladePitch, State) {
    let sticks = Sticks {
        col: x[0],
        ped: x[1],
        lon: x[2],
        lat: x[3],
    };
    let bp = p.blade_pitch(&sticks);
    // At zero speed and rates the flapping settles at a1 = A_lon δ_lon, b1 = B_lat δ_lat.
    let state = State::at_rest(
        x[4],
        x[5],
        yaw,
        p.a_lon * bp.delta_lon,
        p.b_lat * bp.delta_lat,
    );
    (sticks, bp, state)
}

fn residual(p: &Helicopter, x: &SVector<f64, 6>, yaw: f64) -> SVector<f64, 6> {
    let (_, bp, state) = trim_state(p, x, yaw);
    let (d, _) = derivative(p, &state, &bp, &Vector3::zeros());
    d.accelerations().fixed_rows::<6>(0).into_owned()
}

/// Solves the hover trim at heading `yaw` (rad) by Newton iteration on
/// `(u_col, u_ped, u_lon, u_lat, φ, θ)` with a central-difference Jacobian.
pub fn trim_hover(p: &Helicopter, yaw: f64) -> Result<HoverTrim, PlantError> {
    // Start: hover collective and pedal near their design points, level attitude.
    let mut x = SVector::<f64, 6>::new(0.5, 0.4, 0.0, 0.0, 0.0, 0.0);
    let mut converged = false;
    let mut worst = f64::INFINITY;
    for _ in 0..MAX_TRIM_ITERATIONS {
        let r = residual(p, &x, yaw);
        worst = r.amax();
        if !worst.is_finite() {
            break;
        }
        if worst < TRIM_TOLERANCE {
            converged = true;
            break;
        }
        let mut jac = SMatrix::<f64, 6, 6>::zeros();
        for j in 0..6 {
            let mut xp = x;
            let mut xm = x;
            xp[j] += JACOBIAN_STEP;
            xm[j] -= JACOBIAN_STEP;
            let col = (residual(p, &xp, yaw) - residual(p, &xm, yaw)) / (2.0 * JACOBIAN_STEP);
            jac.set_column(j, &col);
        }
        let Some(step) = jac.lu().solve(&r) else {
            break;
        };
        x -= step;
    }
    if !converged {
        return Err(PlantError::TrimFailed { residual: worst });
    }
    if x.iter().take(4).any(|u| u.abs() >= 1.0) {
        return Err(PlantError::TrimOutOfRange {
            col: x[0],
            ped: x[1],
            lon: x[2],
            lat: x[3],
        });
    }
    let (sticks, bp, state) = trim_state(p, &x, yaw);
    let (_, aero) = derivative(p, &state, &bp, &Vector3::zeros());
    Ok(HoverTrim {
        sticks,
        roll: x[4],
        pitch: x[5],
        yaw,
        a1: state.a1,
        b1: state.b1,
        blade_pitch: bp,
        thrust: aero.main.thrust,
        c_t: aero.main.c_t,
        lambda0: aero.main.lambda0,
        collective_pitch: bp.theta0,
        main_torque: aero.main.torque,
        main_power: aero.main.torque * p.omega,
        tail_thrust: aero.tail.thrust,
        tail_pitch: bp.theta_tr,
        state,
    })
}
