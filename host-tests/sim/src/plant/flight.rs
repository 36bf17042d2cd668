//! Flight runner: trimmed start, pilot at the sample rate, RK4 physics, recorded samples.

use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::airframe::{Airframe, StickScale};
use super::dynamics::{rk4_step, rk4_with, State};
use super::error::PlantError;
use super::linear::LinearHover;
use super::params::{Helicopter, XCell60};
use super::pilot::{HoverPilot, PilotGains};
use super::sensors::{jitter_steps, measure, Gust, NoiseStd, SensorSample, Turbulence};
use super::sticks::{Channel, Sticks};
use super::trim::{trim_hover, HoverTrim};

/// ChaCha stream numbers: each random source has its own stream of the seed, so turning one
/// option on or off does not change the others' draws.
const STREAM_JITTER: u64 = 1;
const STREAM_NOISE: u64 = 2;
const STREAM_TURBULENCE: u64 = 3;
const STREAM_VERIFICATION: u64 = 4;

/// What the excitation closure asks for at one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Excitation {
    /// The driven channel, or `None` for pilot-only hover.
    pub channel: Option<Channel>,
    /// Offset from the trim value of that channel (stick units); ignored when `channel` is
    /// `None`.
    pub value: f64,
}

impl Excitation {
    /// No excitation: the pilot flies all four channels.
    pub fn none() -> Self {
        Self::default()
    }

    /// Drive `channel` at `trim + value`.
    pub fn on(channel: Channel, value: f64) -> Self {
        Self {
            channel: Some(channel),
            value,
        }
    }
}

/// Envelope beyond which a flight stops with [`PlantError::Diverged`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Largest allowed |p|, |q|, |r| (rad/s). Default 10.
    pub max_rate: f64,
    /// Largest allowed ground speed |v| (m/s). Default 30.
    pub max_speed: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_rate: 10.0,
            max_speed: 30.0,
        }
    }
}

/// Configuration of one flight.
///
/// [`Default`] is paper-like: 50 Hz with ±2 ms sample jitter ("variable with an average of
/// 50 Hz"), no measurement noise, still air, RK4 at 1 kHz, 60 s, seed 0.
/// [`FlightConfig::realistic`] adds the default noise and turbulence.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlightConfig {
    /// Vehicle parameters.
    pub params: Helicopter,
    /// Pilot gains, as designed on the X-Cell 60; the pilot flies them scaled by
    /// `stick_scale` ([`FlightConfig::pilot_gains`]).
    pub gains: PilotGains,
    /// Stick scaling of the pilot and of the excitation for `params` relative to the X-Cell 60
    /// ([`Airframe::stick_scale`]); all ones by default.
    pub stick_scale: StickScale,
    /// Seed of every random source.
    pub seed: u64,
    /// Flight length (s); `floor(duration · sample_rate)` samples are recorded.
    pub duration: f64,
    /// Nominal sample rate (Hz). `1 / (sample_rate · dt)` must be a whole number ≥ 2.
    pub sample_rate: f64,
    /// Integration step (s).
    pub dt: f64,
    /// Largest sample-time jitter (s), uniform in `[−jitter, jitter]`, rounded to the
    /// integration grid; must be below half a sample period. Jitter moves each instant about
    /// its nominal time `k / sample_rate` (it does not accumulate), so the mean rate is exact.
    pub jitter: f64,
    /// Measurement noise, if any.
    pub noise: Option<NoiseStd>,
    /// Turbulence, if any.
    pub turbulence: Option<Turbulence>,
    /// Initial heading (rad).
    pub initial_yaw: f64,
    /// Divergence limits.
    pub limits: Limits,
    /// Fly the plant's linearisation about its hover trim ([`LinearHover`]) instead of the
    /// plant: a linear helicopter model with the same trim and derivatives there.
    #[serde(default)]
    pub linear: bool,
}

impl Default for FlightConfig {
    fn default() -> Self {
        Self {
            params: Helicopter::default(),
            gains: PilotGains::default(),
            stick_scale: StickScale::default(),
            seed: 0,
            duration: 60.0,
            sample_rate: 50.0,
            dt: 0.001,
            jitter: 0.002,
            noise: None,
            turbulence: None,
            initial_yaw: 0.0,
            limits: Limits::default(),
            linear: false,
        }
    }
}

impl FlightConfig {
    /// Default flight with measurement noise and turbulence at their default levels.
    pub fn realistic(seed: u64, duration: f64) -> Self {
        Self {
            seed,
            duration,
            noise: Some(NoiseStd::default()),
            turbulence: Some(Turbulence::default()),
            ..Self::default()
        }
    }

    /// Noise-free, jitter-free, still-air flight (exact 50 Hz).
    pub fn ideal(duration: f64) -> Self {
        Self {
            duration,
            jitter: 0.0,
            ..Self::default()
        }
    }

    /// This configuration flying `airframe`: its parameters and stick scaling.
    pub fn for_airframe(self, airframe: Airframe) -> Result<Self, PlantError> {
        Ok(Self {
            params: airframe.params(),
            stick_scale: airframe.stick_scale()?,
            ..self
        })
    }

    /// This configuration flying a variation of its helicopter ([`Helicopter::varied`]), with
    /// the stick scaling between the X-Cell 60 and the varied plant (the flight's inputs are
    /// designed on the X-Cell). Fails if the variation cannot hover.
    pub fn varied(self, seed: u64) -> Result<Self, PlantError> {
        let params = self.params.varied(seed);
        Ok(Self {
            params,
            stick_scale: StickScale::between(&XCell60::default(), &params)?,
            ..self
        })
    }

    /// The gains the pilot flies: [`FlightConfig::gains`] scaled by
    /// [`FlightConfig::stick_scale`].
    pub fn pilot_gains(&self) -> PilotGains {
        self.gains.scaled(&self.stick_scale)
    }

    /// Checks the configuration; returns `(steps per sample, jitter steps, samples)`.
    fn grid(&self) -> Result<(i64, i64, u64), PlantError> {
        let bad = |m: &str| Err(PlantError::InvalidConfig(m.to_string()));
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return bad("dt must be finite and positive");
        }
        if !(self.sample_rate.is_finite() && self.sample_rate > 0.0) {
            return bad("sample_rate must be finite and positive");
        }
        if !(self.duration.is_finite() && self.duration >= 0.0) {
            return bad("duration must be finite and non-negative");
        }
        if !(self.jitter.is_finite() && self.jitter >= 0.0) {
            return bad("jitter must be finite and non-negative");
        }
        let ratio = 1.0 / (self.sample_rate * self.dt);
        let steps = ratio.round();
        if (ratio - steps).abs() > 1e-6 || !(2.0..=1e9).contains(&steps) {
            return bad("1/(sample_rate*dt) must be a whole number of at least 2");
        }
        let jitter = (self.jitter / self.dt).round();
        if 2.0 * jitter >= steps {
            return bad("jitter must be below half the sample period");
        }
        if let Some(n) = &self.noise {
            if ![n.velocity, n.rate, n.angle]
                .iter()
                .all(|s| s.is_finite() && *s >= 0.0)
            {
                return bad("noise standard deviations must be finite and non-negative");
            }
        }
        if let Some(t) = &self.turbulence {
            let ok = [t.sigma_horizontal, t.sigma_vertical]
                .iter()
                .all(|s| s.is_finite() && *s >= 0.0)
                && t.tau.is_finite()
                && t.tau > 0.0;
            if !ok {
                return bad("turbulence needs finite sigmas >= 0 and tau > 0");
            }
        }
        let samples = (self.duration * self.sample_rate + 1e-9).floor();
        if samples > 1e9 {
            return bad("too many samples");
        }
        // All three are whole numbers of modest size here, so the casts are exact.
        Ok((steps as i64, jitter as i64, samples as u64))
    }
}

fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(stream);
    r
}

/// A flight in progress, for callers that choose the sticks themselves (for example a
/// controller in the loop). [`simulate`] is a loop over [`Flight::step`].
///
/// Each step records the sample at the current instant, holds the sticks, and integrates to
/// the next (jittered) instant.
#[derive(Debug, Clone)]
pub struct Flight {
    config: FlightConfig,
    trim: HoverTrim,
    state: State,
    pilot: HoverPilot,
    period: i64,
    max_jitter: i64,
    /// Index of the next sample.
    k: u64,
    /// Integration-grid index of `state`.
    grid_step: i64,
    rng_jitter: ChaCha8Rng,
    rng_noise: ChaCha8Rng,
    rng_turb: ChaCha8Rng,
    gust: Option<Gust>,
    linear: Option<LinearHover>,
}

impl Flight {
    /// Trims at hover and places the helicopter there at t = 0.
    pub fn new(config: &FlightConfig) -> Result<Self, PlantError> {
        let (period, max_jitter, _) = config.grid()?;
        let trim = trim_hover(&config.params, config.initial_yaw)?;
        let mut rng_turb = rng(config.seed, STREAM_TURBULENCE);
        let gust = config
            .turbulence
            .map(|cfg| Gust::new(cfg, config.dt, &mut rng_turb));
        Ok(Self {
            config: *config,
            trim,
            state: trim.state,
            pilot: HoverPilot::new(config.pilot_gains(), &trim.state),
            period,
            max_jitter,
            k: 0,
            grid_step: 0,
            rng_jitter: rng(config.seed, STREAM_JITTER),
            rng_noise: rng(config.seed, STREAM_NOISE),
            rng_turb,
            gust,
            linear: config
                .linear
                .then(|| LinearHover::new(&config.params, &trim)),
        })
    }

    /// The hover trim the flight started from.
    pub fn trim(&self) -> &HoverTrim {
        &self.trim
    }

    /// The true (noise-free) plant state at the current instant.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.grid_step as f64 * self.config.dt
    }

    /// Index of the sample the next step records.
    pub fn sample_index(&self) -> u64 {
        self.k
    }

    /// Records the current instant with the pilot's sticks (the excited channel, if any, at
    /// `trim + excitation.value`), then flies to the next instant.
    pub fn step(&mut self, excitation: Excitation) -> Result<SensorSample, PlantError> {
        let value = if excitation.value.is_finite() {
            excitation.value
        } else {
            0.0
        };
        let sticks = self
            .pilot
            .command(&self.state, &self.trim, excitation.channel, value);
        self.step_with_sticks(sticks)
    }

    /// Records the current instant with `sticks` (clamped to [−1, 1]), then flies to the next
    /// instant with them held. The pilot is bypassed.
    pub fn step_with_sticks(&mut self, sticks: Sticks) -> Result<SensorSample, PlantError> {
        let sticks = sticks.clamped();
        let dt = self.config.dt;
        let now = self.time();
        let rng_noise = &mut self.rng_noise;
        let noise = self.config.noise.as_ref().map(|n| (n, rng_noise));
        let sample = measure(now, &self.state, sticks, noise);
        self.k += 1;
        // Next instant: nominal grid point plus jitter, so the mean rate stays exact. The
        // product stays far inside i64 for any flight that could run.
        let target =
            self.k as i64 * self.period + jitter_steps(self.max_jitter, &mut self.rng_jitter);
        let p = &self.config.params;
        let pitch = p.blade_pitch(&sticks);
        while self.grid_step < target {
            let wind = self.gust.as_ref().map_or_else(Vector3::zeros, Gust::wind);
            self.state = match &self.linear {
                Some(l) => rk4_with(&self.state, dt, |x| l.derivative(x, &pitch, &wind)),
                None => rk4_step(p, &self.state, &pitch, &wind, dt),
            };
            if let Some(g) = self.gust.as_mut() {
                g.step(&mut self.rng_turb);
            }
            self.grid_step += 1;
            check_envelope(&self.state, &self.config.limits, self.time())?;
        }
        Ok(sample)
    }
}

/// Flies one flight: starts trimmed at hover, runs the pilot at each sample instant (sticks
/// held until the next), integrates with RK4 on the `dt` grid and records a [`SensorSample`]
/// at each instant. `excitation(k, t)` is called once per sample, in order, with the sample
/// index and time (s).
///
/// Stops with [`PlantError::Diverged`] when a body rate or the ground speed leaves
/// [`FlightConfig::limits`] or the state stops being finite.
pub fn simulate(
    config: &FlightConfig,
    excitation: &mut dyn FnMut(u64, f64) -> Excitation,
) -> Result<Vec<SensorSample>, PlantError> {
    let (_, _, n_samples) = config.grid()?;
    let mut flight = Flight::new(config)?;
    let mut out = Vec::with_capacity(usize::try_from(n_samples).unwrap_or(0));
    for k in 0..n_samples {
        let e = excitation(k, flight.time());
        out.push(flight.step(e)?);
    }
    Ok(out)
}

fn check_envelope(state: &State, limits: &Limits, t: f64) -> Result<(), PlantError> {
    if !state.is_finite() {
        return Err(PlantError::Diverged {
            t,
            quantity: "state (non-finite)",
            value: f64::NAN,
        });
    }
    let names = ["p", "q", "r"];
    for (i, name) in names.iter().enumerate() {
        let w = state.omega[i];
        if w.abs() > limits.max_rate {
            return Err(PlantError::Diverged {
                t,
                quantity: name,
                value: w,
            });
        }
    }
    let speed = state.vel_body.norm();
    if speed > limits.max_speed {
        return Err(PlantError::Diverged {
            t,
            quantity: "ground speed",
            value: speed,
        });
    }
    Ok(())
}

/// Shape of a verification manoeuvre.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// `+1` for `w`, `−1` for `w`.
    Doublet,
    /// `+1, −1, +1, −1` for `3u, 2u, u, u`.
    Multistep3211,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Manoeuvre {
    start: f64,
    channel: Channel,
    shape: Shape,
    /// Doublet half-width or 3-2-1-1 unit (s).
    unit: f64,
    /// Signed amplitude (stick units).
    amplitude: f64,
}

impl Manoeuvre {
    fn length(&self) -> f64 {
        match self.shape {
            Shape::Doublet => 2.0 * self.unit,
            Shape::Multistep3211 => 7.0 * self.unit,
        }
    }

    /// Offset at time `t` (s); zero outside.
    fn value(&self, t: f64) -> f64 {
        let x = (t - self.start) / self.unit;
        if x < 0.0 {
            return 0.0;
        }
        let sign = match self.shape {
            Shape::Doublet if x < 1.0 => 1.0,
            Shape::Doublet if x < 2.0 => -1.0,
            Shape::Multistep3211 if x < 3.0 => 1.0,
            Shape::Multistep3211 if x < 5.0 => -1.0,
            Shape::Multistep3211 if x < 6.0 => 1.0,
            Shape::Multistep3211 if x < 7.0 => -1.0,
            _ => return 0.0,
        };
        sign * self.amplitude
    }
}

/// Seeded ranges of one channel's verification manoeuvres, each `(min, max)`.
struct ManoeuvreRanges {
    /// Normal amplitude (stick units).
    normal: (f64, f64),
    /// Large-excursion amplitude (stick units).
    large: (f64, f64),
    /// Doublet half-width (s).
    doublet: (f64, f64),
    /// 3-2-1-1 unit (s).
    unit_3211: (f64, f64),
}

/// The yaw axis has no damper and the collective is powerful (≈ 27 m/s² per unit), so they
/// get smaller amplitudes than the cyclic (≈ 1.75 rad/s of steady rate per unit).
fn ranges(ch: Channel) -> ManoeuvreRanges {
    let (normal, large, doublet, unit_3211) = match ch {
        Channel::Col => ((0.03, 0.08), (0.12, 0.18), (0.3, 0.8), (0.2, 0.4)),
        Channel::Ped => ((0.03, 0.07), (0.10, 0.14), (0.3, 0.6), (0.15, 0.3)),
        Channel::Lon | Channel::Lat => ((0.08, 0.2), (0.35, 0.5), (0.2, 0.5), (0.1, 0.25)),
    };
    ManoeuvreRanges {
        normal,
        large,
        doublet,
        unit_3211,
    }
}

/// Verification-flight inputs: after 3 s of hover, doublets and 3-2-1-1 multisteps on all
/// four channels (each round visits every channel once, in a seeded random order), with
/// seeded amplitudes (one in four is a large excursion), signs and widths, separated by
/// 2.5–5 s of pilot-held hover so the helicopter settles into a new hover state, as in the
/// paper's verification flight. Nothing starts that would not finish 2 s before `duration`.
pub fn verification_excitation(seed: u64, duration: f64) -> impl FnMut(u64, f64) -> Excitation {
    verification_excitation_scaled(seed, duration, StickScale::default())
}

/// [`verification_excitation`] for another airframe: each manoeuvre's amplitude multiplied by
/// its channel's factor in `scale` (the plan, widths and timing are the same).
pub fn verification_excitation_scaled(
    seed: u64,
    duration: f64,
    scale: StickScale,
) -> impl FnMut(u64, f64) -> Excitation {
    let mut rng = rng(seed, STREAM_VERIFICATION);
    let mut plan: Vec<Manoeuvre> = Vec::new();
    let mut t = 3.0;
    'rounds: loop {
        let mut order = Channel::ALL;
        // Fisher-Yates with the seeded stream.
        for i in (1..order.len()).rev() {
            let j = rng.random_range(0..=i);
            order.swap(i, j);
        }
        for ch in order {
            let r = ranges(ch);
            let shape = if rng.random_bool(0.5) {
                Shape::Doublet
            } else {
                Shape::Multistep3211
            };
            let (lo, hi) = if rng.random_bool(0.25) {
                r.large
            } else {
                r.normal
            };
            let magnitude = rng.random_range(lo..=hi);
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let (wlo, whi) = match shape {
                Shape::Doublet => r.doublet,
                Shape::Multistep3211 => r.unit_3211,
            };
            let m = Manoeuvre {
                start: t,
                channel: ch,
                shape,
                unit: rng.random_range(wlo..=whi),
                amplitude: sign * magnitude * scale.get(ch),
            };
            if !(duration.is_finite() && m.start + m.length() + 2.0 <= duration) {
                break 'rounds;
            }
            t = m.start + m.length() + rng.random_range(2.5..=5.0);
            plan.push(m);
        }
    }
    move |_k, t| {
        plan.iter()
            .find(|m| t >= m.start && t < m.start + m.length())
            .map_or_else(Excitation::none, |m| Excitation::on(m.channel, m.value(t)))
    }
}
