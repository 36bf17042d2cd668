//! A plant's linearisation about hover: a linear helicopter model that nobody tuned rotorid on.
//!
//! The identification-model literature fits helicopters in hover with linear state-space
//! models (stability and control derivatives, flapping as states; Mettler's X-Cell model is
//! one). [`LinearHover`] is that kind of plant, made from the nonlinear one by central
//! differences at the hover trim: the accelerations `[u̇ v̇ ẇ ṗ q̇ ṙ ȧ1 ḃ1]` are the trim's
//! plus a constant Jacobian times the deviation of `[u v w φ θ p q r a1 b1]` from trim and of
//! the blade pitch `[θ0 θ_tr δ_lon δ_lat]` from its trim (gravity's tilt, rotor, fins and
//! fuselage all linear; the heading does not enter). The kinematics stay exact (position from
//! the body velocity, attitude from the body rates), so the logs look like any other flight's.
//! A gust enters as the air's velocity does: minus the wind in body axes on `[u v w]`.

use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};

use super::dynamics::{derivative, BladePitch, State, StateDot};
use super::params::Helicopter;
use super::trim::HoverTrim;

/// Deviations the dynamics are linear in: `[u v w φ θ p q r a1 b1]`.
const STATES: usize = 10;
/// Blade-pitch deviations: `[θ0 θ_tr δ_lon δ_lat]`.
const INPUTS: usize = 4;
/// Central-difference step (m/s, rad, rad/s).
const STEP: f64 = 1e-6;

/// The linear hover model of a plant (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearHover {
    trim: State,
    pitch: BladePitch,
    /// Accelerations at trim (zero to the trim's tolerance).
    at_trim: SVector<f64, 8>,
    /// `∂[u̇ v̇ ẇ ṗ q̇ ṙ ȧ1 ḃ1] / ∂[u v w φ θ p q r a1 b1]`.
    a: SMatrix<f64, 8, STATES>,
    /// `∂[u̇ v̇ ẇ ṗ q̇ ṙ ȧ1 ḃ1] / ∂[θ0 θ_tr δ_lon δ_lat]`.
    b: SMatrix<f64, 8, INPUTS>,
}

/// Blade pitch as a vector `[θ0 θ_tr δ_lon δ_lat]`.
fn pitch_vector(p: &BladePitch) -> SVector<f64, INPUTS> {
    SVector::<f64, INPUTS>::new(p.theta0, p.theta_tr, p.delta_lon, p.delta_lat)
}

impl LinearHover {
    /// Linearises `p` about its hover trim `trim`.
    pub fn new(p: &Helicopter, trim: &HoverTrim) -> Self {
        let base = trim.state;
        let pitch = trim.blade_pitch;
        let still = Vector3::zeros();
        let f = |x: &SVector<f64, STATES>, u: &SVector<f64, INPUTS>| {
            let s = Self::state_at(&base, trim.yaw, x);
            let bp = BladePitch {
                theta0: pitch.theta0 + u[0],
                theta_tr: pitch.theta_tr + u[1],
                delta_lon: pitch.delta_lon + u[2],
                delta_lat: pitch.delta_lat + u[3],
            };
            derivative(p, &s, &bp, &still).0.accelerations()
        };
        let (x0, u0) = (SVector::zeros(), SVector::zeros());
        let mut a = SMatrix::<f64, 8, STATES>::zeros();
        for j in 0..STATES {
            let mut e = SVector::<f64, STATES>::zeros();
            e[j] = STEP;
            a.set_column(j, &((f(&e, &u0) - f(&-e, &u0)) / (2.0 * STEP)));
        }
        let mut b = SMatrix::<f64, 8, INPUTS>::zeros();
        for j in 0..INPUTS {
            let mut e = SVector::<f64, INPUTS>::zeros();
            e[j] = STEP;
            b.set_column(j, &((f(&x0, &e) - f(&x0, &-e)) / (2.0 * STEP)));
        }
        Self {
            trim: base,
            pitch,
            at_trim: f(&x0, &u0),
            a,
            b,
        }
    }

    /// The trim state moved by the deviations `x` (roll and pitch about the trim's, heading
    /// `yaw`).
    fn state_at(base: &State, yaw: f64, x: &SVector<f64, STATES>) -> State {
        let (roll, pitch, _) = base.euler();
        State {
            vel_body: base.vel_body + Vector3::new(x[0], x[1], x[2]),
            att: UnitQuaternion::from_euler_angles(roll + x[3], pitch + x[4], yaw),
            omega: base.omega + Vector3::new(x[5], x[6], x[7]),
            a1: base.a1 + x[8],
            b1: base.b1 + x[9],
            ..*base
        }
    }

    /// The derivative of `s` under blade pitch `pitch` and wind `wind_ned` (m/s, NED): linear
    /// dynamics, exact kinematics.
    pub fn derivative(&self, s: &State, pitch: &BladePitch, wind_ned: &Vector3<f64>) -> StateDot {
        let (roll, tilt, _) = s.euler();
        let (roll0, tilt0, _) = self.trim.euler();
        let wind = s.att.inverse_transform_vector(wind_ned);
        let dv = s.vel_body - self.trim.vel_body - wind;
        let dw = s.omega - self.trim.omega;
        let x = SVector::<f64, STATES>::from_column_slice(&[
            dv.x,
            dv.y,
            dv.z,
            wrap(roll - roll0),
            wrap(tilt - tilt0),
            dw.x,
            dw.y,
            dw.z,
            s.a1 - self.trim.a1,
            s.b1 - self.trim.b1,
        ]);
        let u = pitch_vector(pitch) - pitch_vector(&self.pitch);
        let acc = self.at_trim + self.a * x + self.b * u;
        StateDot {
            pos_ned: s.att * s.vel_body,
            vel_body: Vector3::new(acc[0], acc[1], acc[2]),
            att: s.att.into_inner() * nalgebra::Quaternion::from_imag(s.omega) * 0.5,
            omega: Vector3::new(acc[3], acc[4], acc[5]),
            a1: acc[6],
            b1: acc[7],
        }
    }
}

/// An angle difference in (−π, π].
fn wrap(a: f64) -> f64 {
    let two_pi = 2.0 * core::f64::consts::PI;
    a - two_pi * ((a + core::f64::consts::PI) / two_pi).floor()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::trim::trim_hover;
    use crate::plant::XCell60;

    /// At trim the linear model is at rest, and for a small deviation its accelerations are
    /// close to the nonlinear model's (not to second order: the fins' and the rotor's in-plane
    /// speed enter through magnitudes, `|v|`, which no linear model follows at hover).
    #[test]
    fn the_linearisation_matches_the_plant_near_hover() {
        let p = XCell60::default();
        let trim = trim_hover(&p, 0.3).unwrap();
        let lin = LinearHover::new(&p, &trim);
        let still = Vector3::zeros();
        let at_rest = lin.derivative(&trim.state, &trim.blade_pitch, &still);
        assert!(at_rest.accelerations().amax() < 1e-8, "{at_rest:?}");
        let mut s = trim.state;
        s.vel_body += Vector3::new(0.01, -0.01, 0.005);
        s.omega += Vector3::new(0.002, -0.001, 0.003);
        s.a1 += 1e-4;
        let mut bp = trim.blade_pitch;
        bp.delta_lon += 1e-3;
        let exact = derivative(&p, &s, &bp, &still).0.accelerations();
        let linear = lin.derivative(&s, &bp, &still).accelerations();
        let change = (exact
            - derivative(&p, &trim.state, &trim.blade_pitch, &still)
                .0
                .accelerations())
        .amax();
        assert!(change > 1e-3, "the deviation moves the plant: {change}");
        assert!(
            (exact - linear).amax() < 0.15 * change,
            "exact {exact:?} linear {linear:?}"
        );
    }
}
