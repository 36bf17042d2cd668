//! Sensor samples, measurement noise and turbulence.

use nalgebra::Vector3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use super::dynamics::State;
use super::sticks::Sticks;

/// One recorded sample (nominally 50 Hz).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SensorSample {
    /// Sample time (s), on the integration grid.
    pub t: f64,
    /// Commands applied during the interval that starts at `t` (zero-order hold).
    pub sticks: Sticks,
    /// Roll `φ` (rad), ZYX Euler.
    pub roll: f64,
    /// Pitch `θ` (rad).
    pub pitch: f64,
    /// Yaw `ψ` (rad), wrapped to (−π, π].
    pub yaw: f64,
    /// North velocity (m/s).
    pub v_north: f64,
    /// East velocity (m/s).
    pub v_east: f64,
    /// Down velocity (m/s).
    pub v_down: f64,
    /// Body roll rate `p` (rad/s), FRD.
    pub p: f64,
    /// Body pitch rate `q` (rad/s).
    pub q: f64,
    /// Body yaw rate `r` (rad/s).
    pub r: f64,
}

/// Standard deviations of the white Gaussian measurement noise. The defaults are typical of a
/// small-helicopter GPS/INS: 0.02 m/s on velocity, 0.3 deg/s on rates, 0.2 deg on attitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NoiseStd {
    /// Velocity noise (m/s), each NED axis.
    pub velocity: f64,
    /// Rate noise (rad/s), each body axis.
    pub rate: f64,
    /// Attitude noise (rad), each Euler angle.
    pub angle: f64,
}

impl Default for NoiseStd {
    fn default() -> Self {
        Self {
            velocity: 0.02,
            rate: 0.3_f64.to_radians(),
            angle: 0.2_f64.to_radians(),
        }
    }
}

/// Light turbulence: each NED gust component is an independent first-order Gauss-Markov
/// (filtered white noise, the first-order Dryden form) process, exactly discretised on the
/// integration step: `g ← e^(−dt/τ) g + σ sqrt(1 − e^(−2dt/τ)) n`, `n ~ N(0, 1)`. It starts
/// from a draw of its stationary distribution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Turbulence {
    /// RMS of the horizontal (north and east) gust components (m/s). Default 0.3.
    pub sigma_horizontal: f64,
    /// RMS of the vertical gust component (m/s). Default 0.15 (near the ground vertical gusts
    /// are weaker).
    pub sigma_vertical: f64,
    /// Correlation time `τ` (s). Default 2 s (a ≈ 10 m length scale drifting past at a few
    /// m/s of wind; at hover the Dryden `L/V` form needs a wind speed, so τ is given directly).
    pub tau: f64,
}

impl Default for Turbulence {
    fn default() -> Self {
        Self {
            sigma_horizontal: 0.3,
            sigma_vertical: 0.15,
            tau: 2.0,
        }
    }
}

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

/// State of the gust process.
#[derive(Debug, Clone)]
pub(crate) struct Gust {
    cfg: Turbulence,
    decay: f64,
    wind: Vector3<f64>,
}

impl Gust {
    pub(crate) fn new(cfg: Turbulence, dt: f64, rng: &mut ChaCha8Rng) -> Self {
        let wind = Vector3::new(
            cfg.sigma_horizontal * normal(rng),
            cfg.sigma_horizontal * normal(rng),
            cfg.sigma_vertical * normal(rng),
        );
        Self {
            cfg,
            decay: (-dt / cfg.tau).exp(),
            wind,
        }
    }

    /// Wind to use over the next step (m/s, NED).
    pub(crate) fn wind(&self) -> Vector3<f64> {
        self.wind
    }

    /// Advances one integration step.
    pub(crate) fn step(&mut self, rng: &mut ChaCha8Rng) {
        let a = self.decay;
        let b = (1.0 - a * a).sqrt();
        self.wind.x = a * self.wind.x + b * self.cfg.sigma_horizontal * normal(rng);
        self.wind.y = a * self.wind.y + b * self.cfg.sigma_horizontal * normal(rng);
        self.wind.z = a * self.wind.z + b * self.cfg.sigma_vertical * normal(rng);
    }
}

/// Measures `state` at time `t` (s) with the commands `sticks`; adds noise if `noise` is given
/// (draws in the fixed order roll, pitch, yaw, v_n, v_e, v_d, p, q, r).
pub(crate) fn measure(
    t: f64,
    state: &State,
    sticks: Sticks,
    noise: Option<(&NoiseStd, &mut ChaCha8Rng)>,
) -> SensorSample {
    let (roll, pitch, yaw) = state.euler();
    let v = state.vel_ned();
    let w = state.omega;
    let mut s = SensorSample {
        t,
        sticks,
        roll,
        pitch,
        yaw,
        v_north: v.x,
        v_east: v.y,
        v_down: v.z,
        p: w.x,
        q: w.y,
        r: w.z,
    };
    if let Some((n, rng)) = noise {
        s.roll += n.angle * normal(rng);
        s.pitch += n.angle * normal(rng);
        s.yaw = super::pilot::wrap_pi(s.yaw + n.angle * normal(rng));
        s.v_north += n.velocity * normal(rng);
        s.v_east += n.velocity * normal(rng);
        s.v_down += n.velocity * normal(rng);
        s.p += n.rate * normal(rng);
        s.q += n.rate * normal(rng);
        s.r += n.rate * normal(rng);
    }
    s
}

/// Uniform integer jitter in `[−max_steps, max_steps]` grid steps.
pub(crate) fn jitter_steps(max_steps: i64, rng: &mut ChaCha8Rng) -> i64 {
    if max_steps == 0 {
        0
    } else {
        rng.random_range(-max_steps..=max_steps)
    }
}
