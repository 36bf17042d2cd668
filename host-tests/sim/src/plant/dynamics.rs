//! Nonlinear 6-DOF X-Cell 60 model: forces, moments, state derivative and RK4 step.
//!
//! Frames: body forward-right-down (FRD) at the CG, inertial north-east-down (NED). Attitude is
//! a unit quaternion (body → NED); roll/pitch/yaw are the ZYX Euler angles. Body rates
//! `p, q, r` (rad/s) are right-handed about the FRD axes (roll right, pitch up, yaw right).
//!
//! The main rotor turns clockwise seen from above (as the X-Cell's): its reaction torque yaws
//! the nose left (`N = −Q`), and the tail rotor pushes the tail to the left (thrust along −y at
//! the tail hub), which yaws the nose right (`N = l_tr T_tr`).
//!
//! Sign conventions of the flapping angles (Gavrilets): `a1 > 0` tilts the tip-path plane back
//! (force `X = −T a1`, moment `M = (K_β + T h_mr) a1` nose up); `b1 > 0` tilts it right
//! (`Y = T b1`, `L = (K_β + T h_mr) b1` roll right).

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use super::params::Helicopter;
use super::rotor::{solve_rotor, RotorSolution};
use super::sticks::Sticks;

/// Blade pitch commands (rad) produced from the sticks by [`Helicopter::blade_pitch`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BladePitch {
    /// Main-rotor collective pitch `θ0` (rad).
    pub theta0: f64,
    /// Tail-rotor blade pitch `θ_tr` (rad), offset included.
    pub theta_tr: f64,
    /// Longitudinal cyclic `δ_lon` (rad).
    pub delta_lon: f64,
    /// Lateral cyclic `δ_lat` (rad).
    pub delta_lat: f64,
}

impl Helicopter {
    /// Maps sticks (clamped to [−1, 1] first) to blade pitch with [`Helicopter::sticks`].
    pub fn blade_pitch(&self, sticks: &Sticks) -> BladePitch {
        let s = sticks.clamped();
        let m = &self.sticks;
        BladePitch {
            theta0: m.col_offset + m.col_gain * s.col,
            theta_tr: self.tail_pitch_offset + m.ped_gain * s.ped,
            delta_lon: m.lon_gain * s.lon,
            delta_lat: m.lat_gain * s.lat,
        }
    }
}

/// Full plant state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Position of the CG in NED (m).
    pub pos_ned: Vector3<f64>,
    /// CG velocity relative to the ground in body FRD axes, `[u, v, w]` (m/s).
    pub vel_body: Vector3<f64>,
    /// Attitude, body → NED.
    pub att: UnitQuaternion<f64>,
    /// Body rates `[p, q, r]` (rad/s).
    pub omega: Vector3<f64>,
    /// Longitudinal tip-path-plane flapping `a1` (rad).
    pub a1: f64,
    /// Lateral tip-path-plane flapping `b1` (rad).
    pub b1: f64,
}

impl State {
    /// State at rest at the origin with attitude from ZYX Euler angles (rad) and flapping
    /// `a1`, `b1` (rad).
    pub fn at_rest(roll: f64, pitch: f64, yaw: f64, a1: f64, b1: f64) -> Self {
        Self {
            pos_ned: Vector3::zeros(),
            vel_body: Vector3::zeros(),
            att: UnitQuaternion::from_euler_angles(roll, pitch, yaw),
            omega: Vector3::zeros(),
            a1,
            b1,
        }
    }

    /// ZYX Euler angles `(roll φ, pitch θ, yaw ψ)` (rad); yaw in (−π, π].
    pub fn euler(&self) -> (f64, f64, f64) {
        self.att.euler_angles()
    }

    /// CG velocity in NED `[v_n, v_e, v_d]` (m/s).
    pub fn vel_ned(&self) -> Vector3<f64> {
        self.att * self.vel_body
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.pos_ned.iter().all(|x| x.is_finite())
            && self.vel_body.iter().all(|x| x.is_finite())
            && self.att.coords.iter().all(|x| x.is_finite())
            && self.omega.iter().all(|x| x.is_finite())
            && self.a1.is_finite()
            && self.b1.is_finite()
    }

    fn add_scaled(&self, d: &StateDot, h: f64) -> Self {
        Self {
            pos_ned: self.pos_ned + d.pos_ned * h,
            vel_body: self.vel_body + d.vel_body * h,
            att: UnitQuaternion::new_normalize(self.att.into_inner() + d.att * h),
            omega: self.omega + d.omega * h,
            a1: self.a1 + d.a1 * h,
            b1: self.b1 + d.b1 * h,
        }
    }
}

/// Time derivative of [`State`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateDot {
    /// NED velocity (m/s).
    pub pos_ned: Vector3<f64>,
    /// Body-axis acceleration `[u̇, v̇, ẇ]` (m/s²).
    pub vel_body: Vector3<f64>,
    /// Quaternion rate `q̇ = ½ q ⊗ (0, ω)` (1/s).
    pub att: Quaternion<f64>,
    /// Angular acceleration `[ṗ, q̇, ṙ]` (rad/s²).
    pub omega: Vector3<f64>,
    /// `ȧ1` (rad/s).
    pub a1: f64,
    /// `ḃ1` (rad/s).
    pub b1: f64,
}

impl StateDot {
    /// The accelerations `[u̇ v̇ ẇ ṗ q̇ ṙ ȧ1 ḃ1]`: what the trim zeroes (the first six) and what
    /// a linearisation is linear in.
    pub fn accelerations(&self) -> nalgebra::SVector<f64, 8> {
        nalgebra::SVector::<f64, 8>::from_column_slice(&[
            self.vel_body.x,
            self.vel_body.y,
            self.vel_body.z,
            self.omega.x,
            self.omega.y,
            self.omega.z,
            self.a1,
            self.b1,
        ])
    }
}

/// Forces, moments and rotor solutions of one evaluation (for trim, tests and diagnostics).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aero {
    /// Main rotor solution (`thrust` N, `torque` N·m, `c_t`, `lambda0`, …).
    pub main: RotorSolution,
    /// Tail rotor solution.
    pub tail: RotorSolution,
    /// Blade pitch used.
    pub pitch: BladePitch,
    /// Total external force in body axes, gravity included (N).
    pub force_body: Vector3<f64>,
    /// Total external moment about the CG in body axes (N·m).
    pub moment_body: Vector3<f64>,
}

/// Lift-plus-stalled-drag force of a small fin on its normal velocity `v_n` (m/s) with
/// in-plane speed `v_t` (m/s): `−½ ρ S (C_Lα |v_t| + |v_n|) v_n`. This is Gavrilets' vertical-fin
/// form; it is used for the horizontal fin too instead of a stall switch, so the force stays
/// continuous in the state (smooth Jacobian for trim, no chattering).
fn fin_force(rho: f64, area: f64, lift_slope: f64, v_t: f64, v_n: f64) -> f64 {
    -0.5 * rho * area * (lift_slope * v_t.abs() + v_n.abs()) * v_n
}

/// State derivative of the nonlinear model for blade pitch `pitch` held over the step and a
/// wind (gust) velocity `wind_ned` (m/s, NED, air motion over the ground).
pub fn derivative(
    p: &Helicopter,
    s: &State,
    pitch: &BladePitch,
    wind_ned: &Vector3<f64>,
) -> (StateDot, Aero) {
    let rot = s.att.to_rotation_matrix();
    let w = s.omega;
    // Airspeed of the CG in body axes.
    let air = s.vel_body - rot.inverse_transform_vector(wind_ned);

    // ---- Main rotor ------------------------------------------------------------------
    let omega = p.omega;
    let tip = omega * p.main.radius;
    let inplane = (air.x * air.x + air.y * air.y).sqrt();
    let main = solve_rotor(&p.main, p.rho, omega, pitch.theta0, inplane, air.z);
    let thrust = main.thrust;
    let r_mr = Vector3::new(0.0, 0.0, -p.h_mr);
    let f_mr = Vector3::new(-thrust * s.a1, thrust * s.b1, -thrust);
    // Hub spring K_β on the flapping, thrust lever arm via r × F, reaction torque −Q.
    let m_mr = Vector3::new(p.k_beta * s.b1, p.k_beta * s.a1, -main.torque) + r_mr.cross(&f_mr);

    // ---- Flapping (first-order tip-path plane, Gavrilets) ----------------------------
    let tau = p.tau_e();
    let mu_x = air.x / tip;
    let mu_y = air.y / tip;
    let mu_z = air.z / tip;
    let mu = inplane / tip;
    let a_sigma = p.main.lift_slope * p.main.solidity();
    // ∂a1/∂μ = 2 K_μ (4 θ0/3 − λ0): blow-back with speed; ∂b1/∂μ_v = −∂a1/∂μ.
    let da1_dmu = 2.0 * p.k_mu * (4.0 * pitch.theta0 / 3.0 - main.lambda0);
    // ∂a1/∂μ_z = K_μ 16 μ² sign(μ_x) / ((1 − μ²/2)(8|μ| + a σ)).
    let da1_dmuz =
        p.k_mu * 16.0 * mu * mu * mu_x.signum() / ((1.0 - 0.5 * mu * mu) * (8.0 * mu + a_sigma));
    let a1_dot = -w.y - s.a1 / tau
        + (da1_dmu * mu_x + da1_dmuz * mu_z) / tau
        + p.a_lon / tau * pitch.delta_lon;
    let b1_dot = -w.x - s.b1 / tau - da1_dmu * mu_y / tau + p.b_lat / tau * pitch.delta_lat;

    // ---- Tail rotor and vertical fin (both at the tail hub) --------------------------
    let r_tr = Vector3::new(-p.l_tr, 0.0, -p.h_tr);
    let air_tr = air + w.cross(&r_tr);
    let inplane_tr = (air_tr.x * air_tr.x + air_tr.z * air_tr.z).sqrt();
    // Thrust acts along −y; air coming in from the +y side raises its blade angle of attack.
    let tail = solve_rotor(
        &p.tail,
        p.rho,
        p.omega_tr(),
        pitch.theta_tr,
        inplane_tr,
        air_tr.y,
    );
    let f_tr = Vector3::new(0.0, -tail.thrust, 0.0);
    // The tail wash moves air toward +y past the part ε_vf of the fin inside it.
    let v_vf = air_tr.y - p.vfin_wash_fraction * tail.induced_velocity;
    let f_vf = Vector3::new(
        0.0,
        fin_force(p.rho, p.vfin_area, p.vfin_lift_slope, inplane_tr, v_vf),
        0.0,
    );

    // ---- Horizontal fin (inside the rotor radius: full main-rotor downwash) ----------
    let r_ht = Vector3::new(-p.l_ht, 0.0, 0.0);
    let air_ht = air + w.cross(&r_ht);
    let w_ht = air_ht.z - main.induced_velocity;
    let f_ht = Vector3::new(
        0.0,
        0.0,
        fin_force(p.rho, p.hfin_area, p.hfin_lift_slope, air_ht.x, w_ht),
    );

    // ---- Fuselage drag in the downwash (acts at the CG, no moment) -------------------
    let w_fus = air.z - main.induced_velocity;
    let v_inf = (air.x * air.x + air.y * air.y + w_fus * w_fus).sqrt();
    let f_fus =
        -0.5 * p.rho * v_inf * Vector3::new(p.fus_sx * air.x, p.fus_sy * air.y, p.fus_sz * w_fus);

    // ---- Totals ------------------------------------------------------------------------
    let gravity = rot.inverse_transform_vector(&Vector3::new(0.0, 0.0, p.mass * p.g));
    let force = f_mr + f_tr + f_vf + f_ht + f_fus + gravity;
    let moment = m_mr + r_tr.cross(&(f_tr + f_vf)) + r_ht.cross(&f_ht);

    // ---- Rigid body (Newton-Euler in body axes) ----------------------------------------
    let inertia = Matrix3::from_diagonal(&Vector3::new(p.ixx, p.iyy, p.izz));
    let vel_dot = force / p.mass - w.cross(&s.vel_body);
    let h = inertia * w;
    let torque = moment - w.cross(&h);
    let omega_dot = Vector3::new(torque.x / p.ixx, torque.y / p.iyy, torque.z / p.izz);
    let att_dot = s.att.into_inner() * Quaternion::from_imag(w) * 0.5;

    (
        StateDot {
            pos_ned: rot * s.vel_body,
            vel_body: vel_dot,
            att: att_dot,
            omega: omega_dot,
            a1: a1_dot,
            b1: b1_dot,
        },
        Aero {
            main,
            tail,
            pitch: *pitch,
            force_body: force,
            moment_body: moment,
        },
    )
}

/// One classical RK4 step of length `dt` (s) with blade pitch and wind held over the step.
/// The quaternion is renormalised at every stage and at the end.
pub fn rk4_step(
    p: &Helicopter,
    s: &State,
    pitch: &BladePitch,
    wind_ned: &Vector3<f64>,
    dt: f64,
) -> State {
    rk4_with(s, dt, |x| derivative(p, x, pitch, wind_ned).0)
}

/// One classical RK4 step of length `dt` (s) of the derivative `f` (the plant's, or its
/// linearisation's, with the controls and wind held over the step).
pub fn rk4_with(s: &State, dt: f64, f: impl Fn(&State) -> StateDot) -> State {
    let k1 = f(s);
    let k2 = f(&s.add_scaled(&k1, 0.5 * dt));
    let k3 = f(&s.add_scaled(&k2, 0.5 * dt));
    let k4 = f(&s.add_scaled(&k3, dt));
    let sixth = dt / 6.0;
    let sum = StateDot {
        pos_ned: k1.pos_ned + 2.0 * k2.pos_ned + 2.0 * k3.pos_ned + k4.pos_ned,
        vel_body: k1.vel_body + 2.0 * k2.vel_body + 2.0 * k3.vel_body + k4.vel_body,
        att: k1.att + k2.att * 2.0 + k3.att * 2.0 + k4.att,
        omega: k1.omega + 2.0 * k2.omega + 2.0 * k3.omega + k4.omega,
        a1: k1.a1 + 2.0 * k2.a1 + 2.0 * k3.a1 + k4.a1,
        b1: k1.b1 + 2.0 * k2.b1 + 2.0 * k3.b1 + k4.b1,
    };
    s.add_scaled(&sum, sixth)
}
