//! X-Cell 60 plant simulator.
//!
//! A nonlinear six-degree-of-freedom model of a miniature helicopter after Gavrilets, Mettler
//! and Feron (AIAA 2001-4333), as specified in `shared/plant/xcell60.md`:
//!
//! * [`airframe`]: the airframes ([`Airframe`]) and the stick scaling between them;
//! * [`params`]: the published parameters ([`Helicopter`], the X-Cell 60 by default, and the second airframe) and the stick map ([`StickMap`]);
//! * [`rotor`]: blade-element thrust with momentum inflow (main and tail rotor);
//! * [`dynamics`]: forces, moments, the state derivative and an RK4 step;
//! * [`trim`]: the hover trim solver ([`trim_hover`]);
//! * [`pilot`]: the hover-hold pilot flying the channels that are not excited;
//! * [`sensors`]: 50 Hz samples with jitter, noise and turbulence options;
//! * [`flight`]: the flight runner [`simulate`] and verification manoeuvres;
//! * [`variation`]: other helicopters of the same kind, drawn around an airframe
//!   ([`Helicopter::varied`]).
//!
//! Frames and units: body forward-right-down, inertial north-east-down, SI, angles in rad,
//! rates in rad/s. Conversion to the paper's X-Plane axes is left to the experiment layer
//! (see `shared/paper/NOTES.md`).
//!
//! Everything random comes from a `u64` seed through `rand_chacha::ChaCha8Rng`, with separate
//! streams for jitter, measurement noise and turbulence, so the same seed gives the same
//! samples bit for bit.

pub mod airframe;
pub mod dynamics;
pub mod flight;
pub mod params;
pub mod pilot;
pub mod rotor;
pub mod sensors;
pub mod trim;
pub mod variation;

use serde::{Deserialize, Serialize};

pub use airframe::{
    heave_and_yaw_at_hover, steady_response_per_stick, Airframe, HeaveYawDerivatives, StickScale,
};
pub use dynamics::{derivative, rk4_step, Aero, BladePitch, State, StateDot};
pub use flight::{
    simulate, verification_excitation, verification_excitation_scaled, Excitation, Flight,
    FlightConfig, Limits,
};
pub use params::{Helicopter, RotorBlades, StickMap, XCell60};
pub use pilot::{HoverPilot, PilotGains};
pub use rotor::{solve_rotor, RotorSolution};
pub use sensors::{NoiseStd, SensorSample, Turbulence};
pub use trim::{trim_hover, HoverTrim};

/// Normalised pilot commands, each in [−1, 1].
///
/// `col`: main collective (hover ≈ +0.5); `ped`: tail pitch, positive = nose right;
/// `lon`: longitudinal cyclic, positive = tip-path plane back, nose up;
/// `lat`: lateral cyclic, positive = tip-path plane right, roll right.
/// See [`StickMap`] for the blade-pitch ranges.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Sticks {
    /// Collective `u_col` (–).
    pub col: f64,
    /// Pedal `u_ped` (–).
    pub ped: f64,
    /// Longitudinal cyclic `u_lon` (–).
    pub lon: f64,
    /// Lateral cyclic `u_lat` (–).
    pub lat: f64,
}

impl Sticks {
    /// Each command clamped to [−1, 1] (NaN becomes 0 so it cannot reach the dynamics).
    pub fn clamped(&self) -> Self {
        let c = |x: f64| if x.is_nan() { 0.0 } else { x.clamp(-1.0, 1.0) };
        Self {
            col: c(self.col),
            ped: c(self.ped),
            lon: c(self.lon),
            lat: c(self.lat),
        }
    }

    /// The command of one channel.
    pub fn get(&self, ch: Channel) -> f64 {
        match ch {
            Channel::Col => self.col,
            Channel::Ped => self.ped,
            Channel::Lon => self.lon,
            Channel::Lat => self.lat,
        }
    }

    /// Sets the command of one channel.
    pub fn set(&mut self, ch: Channel, value: f64) {
        match ch {
            Channel::Col => self.col = value,
            Channel::Ped => self.ped = value,
            Channel::Lon => self.lon = value,
            Channel::Lat => self.lat = value,
        }
    }
}

/// One of the four control channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Channel {
    /// Main collective.
    Col,
    /// Pedal (tail collective).
    Ped,
    /// Longitudinal cyclic.
    Lon,
    /// Lateral cyclic.
    Lat,
}

impl Channel {
    /// All channels in the order `col, ped, lon, lat`.
    pub const ALL: [Channel; 4] = [Channel::Col, Channel::Ped, Channel::Lon, Channel::Lat];
}

/// Errors of the plant simulator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlantError {
    /// The trim Newton iteration did not converge.
    #[error("hover trim did not converge (largest residual {residual:e})")]
    TrimFailed {
        /// Largest remaining residual (m/s² or rad/s²).
        residual: f64,
    },
    /// Trim needs a stick outside [−1, 1] (the stick map cannot fly this configuration).
    #[error("hover trim needs sticks outside [-1, 1]: col {col}, ped {ped}, lon {lon}, lat {lat}")]
    TrimOutOfRange {
        /// Collective.
        col: f64,
        /// Pedal.
        ped: f64,
        /// Longitudinal cyclic.
        lon: f64,
        /// Lateral cyclic.
        lat: f64,
    },
    /// The flight configuration is not usable.
    #[error("invalid flight configuration: {0}")]
    InvalidConfig(String),
    /// The vehicle left the flight envelope (or the state stopped being finite).
    #[error("vehicle diverged at t = {t:.3} s: {quantity} = {value}")]
    Diverged {
        /// Simulation time (s).
        t: f64,
        /// Which quantity crossed its limit.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
}
