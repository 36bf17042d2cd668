//! Conversion between the flight-computer convention and the paper's axes.
//!
//! Flight computers (PX4, ArduPilot) give velocity in north-east-down (NED) and body rates
//! about forward-right-down (FRD) axes in rad/s. The paper uses X-Plane's axes (NOTES.md):
//! body `i_b` right, `j_b` up, `k_b` back; inertial x east, y up, z south; rates in deg/s.
//! With M the map FRD/NED → paper (`i = +y, j = −z, k = −x`):
//!
//! * velocity: `v^s = [v_e, −v_d, −v_n]`;
//! * attitude: the usual ZYX roll φ, pitch θ, yaw ψ are kept as they are; with them the
//!   paper's `R e2` equals `M R_nb Mᵀ e2` (tested in `hover::models::rotor_axis`);
//! * rates: `[q r p]` are the conventional pitch, yaw and roll rates (nose up, nose right,
//!   right wing down positive, as X-Plane's Q, R, P outputs and the paper's kinematics
//!   `Ψ(Θ)` have them), converted to deg/s.
//!
//! The paper's text also says the rates follow the right-hand rule about `i_b, j_b, k_b`,
//! which would flip the signs of r and p. The identification does not depend on the choice:
//! Table 3's sets are symmetric and the per-rule parameters absorb the sign. This crate uses
//! the conventional signs throughout.
//!
//! ```
//! use nalgebra::Vector3;
//! use rotorid::frames::NedFrdSample;
//! use rotorid::hover::{Attitude, Controls};
//!
//! // 1 m/s north, 2 m/s east, 0.5 m/s down; rolling right at 0.1 rad/s.
//! let px4 = NedFrdSample::<f32> {
//!     time_us: 20_000,
//!     attitude: Attitude { roll: 0.05, pitch: -0.02, yaw: 1.0 },
//!     velocity_ned: Vector3::new(1.0, 2.0, 0.5),
//!     rates_frd: Vector3::new(0.1, 0.0, 0.0),
//!     controls: Controls { col: 0.5, ped: 0.0, lon: 0.0, lat: 0.0 },
//! };
//! let s = px4.to_paper();
//! assert_eq!(s.velocity, [2.0, -0.5, -1.0]); // [v_e, −v_d, −v_n]
//! assert!((s.rates[2] - 5.729578).abs() < 1e-5); // p in deg/s, last of [q r p]
//! ```

use nalgebra::Vector3;

use crate::hover::{Attitude, Controls};
use crate::hover::{HoverSample, HoverState};
use crate::scalar::Real;

const DEG_PER_RAD: f64 = 57.295_779_513_082_32;
const RAD_PER_DEG: f64 = 0.017_453_292_519_943_295;

/// A sample in the flight computer's convention.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct NedFrdSample<T: nalgebra::Scalar> {
    /// Time stamp (µs).
    pub time_us: u64,
    /// ZYX Euler angles (rad).
    pub attitude: Attitude<T>,
    /// Velocity `[v_n v_e v_d]` (m/s).
    pub velocity_ned: Vector3<T>,
    /// Body rates `[p q r]` about forward, right, down (rad/s).
    pub rates_frd: Vector3<T>,
    /// Normalised controls.
    pub controls: Controls<T>,
}

/// NED velocity (m/s) → paper inertial velocity `[v_x v_y v_z]` (m/s).
pub fn velocity_ned_to_paper<T: Real>(v: &Vector3<T>) -> [T; 3] {
    [v.y, -v.z, -v.x]
}

/// Paper inertial velocity (m/s) → NED (m/s).
pub fn velocity_paper_to_ned<T: Real>(v: &[T; 3]) -> Vector3<T> {
    let [x, y, z] = *v;
    Vector3::new(-z, x, -y)
}

/// FRD body rates `[p q r]` (rad/s) → paper `[q r p]` (deg/s).
pub fn rates_frd_to_paper<T: Real>(w: &Vector3<T>) -> [T; 3] {
    let k = T::lit(DEG_PER_RAD);
    [w.y * k, w.z * k, w.x * k]
}

/// Paper `[q r p]` (deg/s) → FRD `[p q r]` (rad/s).
pub fn rates_paper_to_frd<T: Real>(w: &[T; 3]) -> Vector3<T> {
    let k = T::lit(RAD_PER_DEG);
    let [q, r, p] = *w;
    Vector3::new(p * k, q * k, r * k)
}

impl<T: Real> NedFrdSample<T> {
    /// In the paper's axes and units.
    pub fn to_paper(&self) -> HoverSample<T> {
        HoverSample {
            time_us: self.time_us,
            attitude: self.attitude,
            velocity: velocity_ned_to_paper(&self.velocity_ned),
            rates: rates_frd_to_paper(&self.rates_frd),
            controls: self.controls,
        }
    }

    /// From the paper's axes and units.
    pub fn from_paper(s: &HoverSample<T>) -> Self {
        Self {
            time_us: s.time_us,
            attitude: s.attitude,
            velocity_ned: velocity_paper_to_ned(&s.velocity),
            rates_frd: rates_paper_to_frd(&s.rates),
            controls: s.controls,
        }
    }
}

/// A predicted state in NED (m/s) and FRD `[p q r]` (rad/s).
pub fn state_to_ned_frd<T: Real>(s: &HoverState<T>) -> (Vector3<T>, Vector3<T>) {
    (
        velocity_paper_to_ned(&s.velocity),
        rates_paper_to_frd(&s.rates),
    )
}
