//! Logarithmic frequency-sweep excitation (paper Section 6, Eqs. 31–33, Table 2).
//!
//! `u(t) = A(t) sin f(t)` with
//!
//! ```text
//! K(t) = C2 (exp(C1 t / T_rec) − 1)                                   (31)
//! ν(t) = ω_min + K(t) (ω_max − ω_min)                                 (32)
//! f(t) = ∫₀ᵗ ν dτ = ω_min t + C2 (ω_max − ω_min) [(T_rec/C1)(exp(C1 t/T_rec) − 1) − t]   (33)
//! ```
//!
//! Eq. 33 is printed as a definite integral to `T_rec`; the phase is the running integral
//! (NOTES.md item 4), used here in closed form. Time comes from an integer sample index,
//! `t = k / f_s`, so a long sweep does not drift the way a sum of `dt` does. The sweep is
//! computed in `f64` whatever the estimator's scalar (the phase reaches hundreds of radians,
//! where `f32` would lose the waveform's shape); the result is exact-bit reproducible on every
//! target because `exp` and `sin` come from `libm`.

use crate::error::{ConfigError, Error};

/// C1 of Eq. 31, from the paper (after Tischler).
pub const C1: f64 = 4.0;
/// C2 as printed in the paper: the sweep ends 0.23 % above ω_max (NOTES.md item 5).
pub const C2_PAPER: f64 = 0.0187;
/// C2 = 1/(e^C1 − 1): ν(T_rec) = ω_max exactly.
pub const C2_EXACT: f64 = 0.018_657_360_363_774_05;

/// One of the four controls.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Channel {
    /// Main-rotor collective `u_col`.
    Collective,
    /// Pedal `u_ped`.
    Pedal,
    /// Longitudinal cyclic `u_lon`.
    Longitudinal,
    /// Lateral cyclic `u_lat`.
    Lateral,
}

impl Channel {
    /// Index in `[u_col u_ped u_lon u_lat]`.
    pub const fn index(self) -> usize {
        match self {
            Self::Collective => 0,
            Self::Pedal => 1,
            Self::Longitudinal => 2,
            Self::Lateral => 3,
        }
    }
}

/// One frequency sweep with trim periods before and after.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sweep {
    /// The control it drives.
    pub channel: Channel,
    /// Lowest frequency ω_min (rad/s).
    pub omega_min: f64,
    /// Highest frequency ω_max (rad/s).
    pub omega_max: f64,
    /// Recorded length of the sweep T_rec (s); the paper asks T_rec ≥ 4·2π/ω_min.
    pub duration_s: f64,
    /// Amplitude A at full gain (stick units, added to trim).
    pub amplitude: f64,
    /// C1 of Eq. 31.
    pub c1: f64,
    /// C2 of Eq. 31.
    pub c2: f64,
    /// Gain on A at ω_min (0…1): low frequencies drift the helicopter off hover, so the
    /// paper reduces their amplitude.
    pub low_frequency_gain: f64,
    /// Frequency (rad/s) from which the full amplitude applies; the gain rises linearly in ν
    /// from `low_frequency_gain` at ω_min.
    pub full_amplitude_from: f64,
    /// Time at trim before and after the sweep (s); the paper suggests 3 s.
    pub trim_s: f64,
}

impl Sweep {
    /// Table 2's sweep for a channel with the paper's C1, C2, 3 s trim pads, amplitude A,
    /// half amplitude at ω_min rising to full at 2·ω_min.
    pub fn table2(channel: Channel, amplitude: f64) -> Self {
        let (omega_min, omega_max, duration_s) = match channel {
            Channel::Longitudinal => (1.0, 15.0, 45.0),
            Channel::Lateral => (1.0, 12.0, 31.0),
            Channel::Pedal => (2.0, 23.0, 50.0),
            Channel::Collective => (0.3, 12.0, 105.0),
        };
        Self {
            channel,
            omega_min,
            omega_max,
            duration_s,
            amplitude,
            c1: C1,
            c2: C2_PAPER,
            low_frequency_gain: 0.5,
            full_amplitude_from: 2.0 * omega_min,
            trim_s: 3.0,
        }
    }

    /// Checks the ranges: 0 < ω_min < ω_max, T_rec > 0, C1 > 0, C2 > 0, A finite and ≥ 0,
    /// gain in [0, 1], full-amplitude frequency ≥ ω_min, trim ≥ 0.
    pub fn validate(&self) -> Result<(), Error> {
        let ok = self.omega_min > 0.0
            && self.omega_max > self.omega_min
            && self.omega_max.is_finite()
            && self.duration_s > 0.0
            && self.duration_s <= 1e5
            && self.c1 > 0.0
            && self.c1 <= 50.0
            && self.c2 > 0.0
            && self.c2.is_finite()
            && self.amplitude >= 0.0
            && self.amplitude <= 1.0
            && (0.0..=1.0).contains(&self.low_frequency_gain)
            && self.full_amplitude_from >= self.omega_min
            && self.full_amplitude_from.is_finite()
            && self.trim_s >= 0.0
            && self.trim_s <= 1e4;
        if ok {
            Ok(())
        } else {
            Err(ConfigError::Sweep.into())
        }
    }

    /// K(t) of Eq. 31 (t in s from the sweep's start).
    pub fn k(&self, t: f64) -> f64 {
        self.c2 * (libm::exp(self.c1 * t / self.duration_s) - 1.0)
    }

    /// Instantaneous frequency ν(t) (rad/s), Eq. 32.
    pub fn frequency(&self, t: f64) -> f64 {
        self.omega_min + self.k(t) * (self.omega_max - self.omega_min)
    }

    /// Phase f(t) (rad), Eq. 33 in closed form.
    pub fn phase(&self, t: f64) -> f64 {
        let tr = self.duration_s;
        let bracket = (tr / self.c1) * (libm::exp(self.c1 * t / tr) - 1.0) - t;
        self.omega_min * t + self.c2 * (self.omega_max - self.omega_min) * bracket
    }

    /// Amplitude A(t) with the low-frequency reduction.
    pub fn amplitude_at(&self, t: f64) -> f64 {
        let span = self.full_amplitude_from - self.omega_min;
        let ramp = if span > 0.0 {
            ((self.frequency(t) - self.omega_min) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.amplitude * (self.low_frequency_gain + (1.0 - self.low_frequency_gain) * ramp)
    }

    /// Total length with both trim pads (s).
    pub fn total_s(&self) -> f64 {
        self.trim_s + self.duration_s + self.trim_s
    }

    /// Offset from trim at time `t` since the start of the leading trim pad: 0 in the pads,
    /// `A(t) sin f(t)` during the sweep.
    pub fn offset(&self, t: f64) -> f64 {
        let ts = t - self.trim_s;
        if !(0.0..=self.duration_s).contains(&ts) {
            return 0.0;
        }
        self.amplitude_at(ts) * libm::sin(self.phase(ts))
    }

    /// Number of samples at `rate_hz` covering [`total_s`](Self::total_s).
    pub fn samples(&self, rate_hz: u32) -> u32 {
        let n = libm::ceil(self.total_s() * f64::from(rate_hz));
        if n >= 0.0 && n < f64::from(u32::MAX) {
            n as u32
        } else {
            0
        }
    }
}

/// Sweeps played one after another (each with its own trim pads), as in the paper where
/// several manoeuvres are concatenated.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SweepSchedule<const S: usize> {
    sweeps: [Sweep; S],
    rate_hz: u32,
}

/// What the schedule commands at one sample.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Excitation {
    /// The channel being swept (the others hold hover).
    pub channel: Channel,
    /// Offset from trim on that channel (stick units).
    pub offset: f64,
}

impl SweepSchedule<4> {
    /// Table 2's four sweeps in the order lon, lat, ped, col, with per-channel amplitudes
    /// `[col, ped, lon, lat]` (stick units).
    pub fn table2(amplitudes: [f64; 4], rate_hz: u32) -> Result<Self, Error> {
        let [col, ped, lon, lat] = amplitudes;
        Self::new(
            [
                Sweep::table2(Channel::Longitudinal, lon),
                Sweep::table2(Channel::Lateral, lat),
                Sweep::table2(Channel::Pedal, ped),
                Sweep::table2(Channel::Collective, col),
            ],
            rate_hz,
        )
    }
}

impl<const S: usize> SweepSchedule<S> {
    /// A schedule of sweeps sampled at `rate_hz` (1…10 000 Hz).
    pub fn new(sweeps: [Sweep; S], rate_hz: u32) -> Result<Self, Error> {
        if rate_hz == 0 || rate_hz > 10_000 {
            return Err(ConfigError::Sweep.into());
        }
        for s in &sweeps {
            s.validate()?;
        }
        Ok(Self { sweeps, rate_hz })
    }

    /// The sweeps.
    pub fn sweeps(&self) -> &[Sweep; S] {
        &self.sweeps
    }

    /// Sample rate (Hz).
    pub fn rate_hz(&self) -> u32 {
        self.rate_hz
    }

    /// Total number of samples.
    pub fn len(&self) -> u32 {
        self.sweeps
            .iter()
            .fold(0u32, |n, s| n.saturating_add(s.samples(self.rate_hz)))
    }

    /// Whether the schedule has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The command at sample index k (time `k / f_s` from the schedule's start), or `None`
    /// past the end.
    pub fn at(&self, k: u32) -> Option<Excitation> {
        let mut start = 0u32;
        for s in &self.sweeps {
            let n = s.samples(self.rate_hz);
            if k < start.saturating_add(n) {
                let t = f64::from(k - start) / f64::from(self.rate_hz);
                return Some(Excitation {
                    channel: s.channel,
                    offset: s.offset(t),
                });
            }
            start = start.saturating_add(n);
        }
        None
    }
}
