//! Hover-hold pilot: flies the channels that are not excited so each manoeuvre stays near
//! hover (Section 6 of the paper), while the excited channel gets `trim + excitation`.
//!
//! Structure (all around the trim values):
//! * cyclic: PD on attitude with a velocity hold in the heading frame. Forward ground speed
//!   raises the pitch reference (nose up brakes), rightward speed lowers the roll reference.
//! * collective: vertical-speed hold plus a weak altitude hold.
//! * pedal: a weak heading hold (rate damping plus a small heading term), since the airframe
//!   has no yaw damper. While the pedal is excited the pilot leaves it alone and the heading
//!   reference follows the aircraft, so on release it holds the new heading instead of
//!   swinging back; the altitude reference does the same while the collective is excited.
//!
//! The pilot reads the true state (it stands for a human or autopilot with good sensing);
//! its commands are what the flight records.

use serde::{Deserialize, Serialize};

use super::dynamics::State;
use super::sticks::{Channel, Sticks};
use super::trim::HoverTrim;

/// Feedback gains of [`HoverPilot`]. Stick units are normalised (–).
///
/// Design notes (linearised hover model of the default parameters, checked numerically):
/// one unit of cyclic gives ≈ 1.75 rad/s of flapping rate, i.e. ≈ 45 rad/s² of pitch or
/// ≈ 85 rad/s² of roll acceleration once the flapping settles, and the rotor damps the rates
/// strongly; the coupled body-flap modes sit at ≈ −4.2 ± 14j (pitch) and −4.2 ± 20j (roll).
/// Attitude gains of 1.5–2 /rad place the slow attitude pole near 3–4 rad/s without eroding
/// the damping of those modes, which the 50 Hz zero-order hold would otherwise destabilise.
/// The velocity loop is kept ≈ 5× slower than the attitude loop. One unit of collective gives
/// ≈ 27 m/s² of vertical acceleration against ≈ 0.8 /s natural heave damping; one unit of pedal
/// ≈ 39 rad/s² of yaw acceleration against ≈ 1.1 /s natural yaw damping. The heading hold
/// (≈ 2.4 rad/s, damping ≈ 0.8) is far below the pedal sweep band but holds the heading
/// against the main-rotor torque change with speed (≈ 10 % of hover torque at 5–10 m/s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PilotGains {
    /// Longitudinal cyclic per pitch-attitude error (1/rad).
    pub pitch_att: f64,
    /// Longitudinal cyclic per pitch rate (s/rad).
    pub pitch_rate: f64,
    /// Lateral cyclic per roll-attitude error (1/rad).
    pub roll_att: f64,
    /// Lateral cyclic per roll rate (s/rad).
    pub roll_rate: f64,
    /// Attitude reference per horizontal ground speed (rad per m/s).
    pub velocity: f64,
    /// Limit of the velocity loop's attitude offset from trim (rad).
    pub max_tilt: f64,
    /// Collective per down velocity (s/m).
    pub vertical_speed: f64,
    /// Collective per metre below the altitude reference (1/m).
    pub altitude: f64,
    /// Pedal per yaw rate (s/rad).
    pub yaw_rate: f64,
    /// Pedal per heading error (1/rad).
    pub heading: f64,
}

impl Default for PilotGains {
    fn default() -> Self {
        Self {
            pitch_att: 2.0,
            pitch_rate: 0.05,
            roll_att: 1.5,
            roll_rate: 0.03,
            velocity: 0.06,
            max_tilt: 0.2,
            vertical_speed: 0.1,
            altitude: 0.04,
            yaw_rate: 0.07,
            heading: 0.15,
        }
    }
}

/// The hover-hold pilot. Create it at the trimmed state with [`HoverPilot::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct HoverPilot {
    /// Gains in use.
    pub gains: PilotGains,
    /// Heading reference (rad).
    heading_ref: f64,
    /// Altitude reference as NED down position (m).
    down_ref: f64,
    /// Velocity set-point in the heading frame `[forward, right, down]` (m/s); zero holds
    /// hover. A non-zero down speed lets the altitude reference follow the aircraft.
    pub velocity_ref: [f64; 3],
    /// Trim offsets found by an outer loop (e.g. [`crate::envelope`]'s integrators) for flight
    /// away from hover: `[pitch (rad), roll (rad), collective (stick)]`, zero at hover.
    pub offsets: [f64; 3],
}

/// Wraps an angle to (−π, π].
pub(crate) fn wrap_pi(a: f64) -> f64 {
    let two_pi = 2.0 * core::f64::consts::PI;
    let w = a - two_pi * (a / two_pi).round();
    if w <= -core::f64::consts::PI {
        w + two_pi
    } else {
        w
    }
}

impl HoverPilot {
    /// A pilot holding the heading and altitude of `state`.
    pub fn new(gains: PilotGains, state: &State) -> Self {
        let (_, _, yaw) = state.euler();
        Self {
            gains,
            heading_ref: yaw,
            down_ref: state.pos_ned.z,
            velocity_ref: [0.0; 3],
            offsets: [0.0; 3],
        }
    }

    /// Sticks for the current state: the excited channel (if any) gets
    /// `trim + excitation`, the others the pilot's feedback around trim. All clamped to
    /// [−1, 1].
    pub fn command(
        &mut self,
        state: &State,
        trim: &HoverTrim,
        excited: Option<Channel>,
        excitation: f64,
    ) -> Sticks {
        let g = &self.gains;
        let (roll, pitch, yaw) = state.euler();
        let v = state.vel_ned();
        let w = state.omega;
        let (sy, cy) = yaw.sin_cos();
        let v_fwd = cy * v.x + sy * v.y - self.velocity_ref[0];
        let v_right = -sy * v.x + cy * v.y - self.velocity_ref[1];
        let v_down = v.z - self.velocity_ref[2];

        if excited == Some(Channel::Ped) {
            self.heading_ref = yaw;
        }
        if excited == Some(Channel::Col) || self.velocity_ref[2] != 0.0 {
            self.down_ref = state.pos_ned.z;
        }

        let [pitch_offset, roll_offset, col_offset] = self.offsets;
        let pitch_ref =
            trim.pitch + pitch_offset + (g.velocity * v_fwd).clamp(-g.max_tilt, g.max_tilt);
        let roll_ref =
            trim.roll + roll_offset - (g.velocity * v_right).clamp(-g.max_tilt, g.max_tilt);
        let t = &trim.sticks;
        let mut out = Sticks {
            col: t.col
                + col_offset
                + g.vertical_speed * v_down
                + g.altitude * (state.pos_ned.z - self.down_ref),
            ped: t.ped - g.yaw_rate * w.z - g.heading * wrap_pi(yaw - self.heading_ref),
            lon: t.lon - g.pitch_att * (pitch - pitch_ref) - g.pitch_rate * w.y,
            lat: t.lat - g.roll_att * (roll - roll_ref) - g.roll_rate * w.x,
        };
        if let Some(ch) = excited {
            out.set(ch, t.get(ch) + excitation);
        }
        out.clamped()
    }
}

#[cfg(test)]
mod tests {
    use super::wrap_pi;

    #[test]
    fn wrap() {
        assert!((wrap_pi(3.0 * core::f64::consts::PI) - core::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_pi(-0.5) + 0.5).abs() < 1e-15);
        assert!((wrap_pi(7.0) - (7.0 - 2.0 * core::f64::consts::PI)).abs() < 1e-12);
    }
}
