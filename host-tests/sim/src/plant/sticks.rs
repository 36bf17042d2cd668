//! The pilot's commands: a value ([`Sticks`]) on each of the four control channels ([`Channel`]).

use serde::{Deserialize, Serialize};

/// Normalised pilot commands, each in [−1, 1].
///
/// `col`: main collective (hover ≈ +0.5); `ped`: tail pitch, positive = nose right;
/// `lon`: longitudinal cyclic, positive = tip-path plane back, nose up;
/// `lat`: lateral cyclic, positive = tip-path plane right, roll right.
/// See [`StickMap`](super::params::StickMap) for the blade-pitch ranges.
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
