//! The command-line options that `rotorid` and the studies' `rotorid-lab` share: those of
//! `identify` ([`IdentifyOptions`], resolved into the library's [`IdentifyArgs`]), the rate of
//! `convert`, and the simulated plant. Both binaries flatten them into their own commands
//! (clap's derive), so the two `identify` commands take the same options.

use std::path::PathBuf;

use clap::ValueEnum;
use rotorid_sim::plant::Airframe;

use crate::experiments;
use crate::identify::{GyroNoise, IdentifyArgs, ObserverGain};
use crate::import;

/// Which simulated helicopter (`rotorid_sim::plant::Airframe`).
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum Plant {
    /// The MIT X-Cell 60 (published parameters).
    #[default]
    Xcell60,
    /// A flybarless 600-class helicopter (Froude-scaled X-Cell with a flybarless stiff-hub
    /// rotor, higher head speed, larger tail rotor, slimmer canopy).
    Flybarless600,
}

impl From<Plant> for Airframe {
    fn from(p: Plant) -> Self {
        match p {
            Plant::Xcell60 => Airframe::XCell60,
            Plant::Flybarless600 => Airframe::Flybarless600,
        }
    }
}

/// The options of `identify`.
#[derive(Clone, Debug, clap::Args)]
pub struct IdentifyOptions {
    /// Logs to identify from (as --train).
    pub logs: Vec<PathBuf>,
    /// Training (identification) logs, learnt one after another.
    #[arg(long, num_args = 1..)]
    pub train: Vec<PathBuf>,
    /// Verification log (θ frozen after training; its longest segment). Without it, part
    /// of the training data is held out (--holdout).
    #[arg(long)]
    pub verify: Option<PathBuf>,
    /// Fraction of the data held out for verification when --verify is not given (the
    /// later part: a whole segment of about that size, else the end of the longest; another
    /// part where that would take most of a stick's excitation, which the split then says).
    #[arg(long, default_value_t = 0.3)]
    pub holdout: f64,
    /// Identification rate (Hz): `auto` takes the fastest of 50, 25, 20, 10, 5 Hz that
    /// every channel of every log is logged at (no invented samples); a number forces it.
    #[arg(long, default_value = "auto", value_parser = parse_rate)]
    pub rate: RateArg,
    /// Use the logs only from this log time (s, as logged) on; with --to it replaces the
    /// in-air detector.
    #[arg(long)]
    pub from: Option<f64>,
    /// Use the logs only up to this log time (s).
    #[arg(long)]
    pub to: Option<f64>,
    /// How much later than logged the controls act on the airframe (s, 0 to 1): motors,
    /// servos and rotor lag. Default: chosen on the training data of an autopilot's log
    /// (0 to 150 ms, by the flight default's free run; the verdict says which), 0 for CSV.
    #[arg(long, value_parser = parse_control_delay)]
    pub control_delay: Option<f64>,
    /// Print every variant's tables, the Table 4 analogue and every import note, not only
    /// the verdict.
    #[arg(long)]
    pub full: bool,
    /// Directory for metrics.json, params-*.json and the figures.
    #[arg(long, default_value = "rotorid-out")]
    pub out: PathBuf,
    /// Free-run window (s): the model runs on its own predictions, restarted from the
    /// measured state at each window.
    #[arg(long, default_value_t = 2.0)]
    pub window: f64,
    /// Plot only the first seconds of the verification flight (default: all).
    #[arg(long)]
    pub plot_span: Option<f64>,
    /// Do not write the PNG figures.
    #[arg(long)]
    pub no_plots: bool,
    /// Warm start the first variant from a params-*.json or a snapshot-*.ridx (the core's
    /// snapshot of the same variant type) written by an earlier run.
    #[arg(long)]
    pub warm_start: Option<PathBuf>,
    /// White noise σ of the gyro rates (deg/s) that the free run's parameters are
    /// compensated for (`HoverIdentifier::compensate`): `auto` estimates it from the
    /// training logs (`RateNoise`), `none` compensates nothing, one value is every rate's,
    /// three (`Q,R,P`) are each rate's.
    #[arg(long, default_value = "auto", value_parser = parse_gyro_noise)]
    pub gyro_noise: GyroNoise,
    /// Which gyro noise the compensation removes: `damping` (the rate models' `ω(k)` term's,
    /// the default) or `full` (the second-order term `Δω(k−1)`'s too, where the data allow
    /// it and the rate stays stable; elsewhere the damping term's). docs/full-compensation.md
    /// measures both. `flight selected` also chooses `full` per rate where its check blocks
    /// predict better with it (docs/cli.md).
    #[arg(long, value_enum, default_value_t = GyroCompensationArg::Damping)]
    pub gyro_compensation: GyroCompensationArg,
    /// The velocity the free run feeds the models: `model` (their own prediction, the
    /// whole identifier's free run) or `measured` (the measured velocity while the rates
    /// run free: the rate models' free run without the velocity model's error; the
    /// velocities' free-run errors are then zero).
    #[arg(long, value_enum, default_value_t = FreeRunVelocityArg::Model)]
    pub free_run_velocity: FreeRunVelocityArg,
    /// Gain K of every variant's one-step observer (`rotorid::hover::Observer`; 0 to 1,
    /// 1 predicts from the measured state): `auto` finds each variant's on the training
    /// logs (`GainSearch`, 0.1 to 1 in steps of 0.1), one value is every state's, six
    /// (`VX,VY,VZ,Q,R,P`) are each state's.
    #[arg(long, default_value = "auto", value_parser = parse_observer_gain)]
    pub observer_gain: ObserverGain,
    /// Keep every model of `flight selected` on the flight default's speed (forward for the
    /// rates, horizontal for the velocities). By default `flight selected` also chooses, per
    /// model that keeps three rules, the speed they are on: that one, the side speed (rate
    /// models) or the vertical speed, with sets at the training data's quantiles, where the
    /// held-out blocks of the training data show it predicts better by more than their noise
    /// (docs/ab-premises.md).
    #[arg(long)]
    pub no_premise_candidates: bool,
}

impl IdentifyOptions {
    /// The library's arguments: `logs` and `--train` together, the import's cuts and rate.
    pub fn into_args(self) -> IdentifyArgs {
        IdentifyArgs {
            train: self.logs.into_iter().chain(self.train).collect(),
            verify: self.verify,
            holdout: self.holdout,
            options: import::ImportOptions {
                rate_hz: self.rate.0,
                from_s: self.from,
                to_s: self.to,
            },
            control_delay_s: self.control_delay,
            full: self.full,
            out: Some(self.out),
            window: self.window,
            plot_span: self.plot_span,
            no_plots: self.no_plots,
            warm_start: self.warm_start,
            gyro_noise: self.gyro_noise,
            gyro_compensation: self.gyro_compensation.into(),
            free_run_velocity: self.free_run_velocity.into(),
            observer_gain: self.observer_gain,
            premise_candidates: !self.no_premise_candidates,
        }
    }
}

/// `--rate`: `auto` (`None`) or a rate in Hz.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateArg(
    /// The rate (Hz); `None` for `auto`.
    pub Option<f64>,
);

/// Parses `--rate`.
pub fn parse_rate(text: &str) -> Result<RateArg, String> {
    if text == "auto" {
        return Ok(RateArg(None));
    }
    match text.parse::<f64>() {
        Ok(r) if r.is_finite() && (1.0..=1000.0).contains(&r) && (1e6 / r).fract() == 0.0 => {
            Ok(RateArg(Some(r)))
        }
        _ => Err(format!(
            "`{text}` is not an identification rate: auto, or Hz from 1 to 1000 whose period is a whole number of µs (50, 25, 20, 10, …)"
        )),
    }
}

/// Parses `--control-delay`: seconds from 0 to 1.
pub fn parse_control_delay(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(d) if (0.0..=1.0).contains(&d) => Ok(d),
        _ => Err(format!(
            "`{text}` is not a control delay: seconds from 0 to 1 (0.04 for 40 ms)"
        )),
    }
}

/// `--free-run-velocity` ([`experiments::FreeRunVelocity`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FreeRunVelocityArg {
    /// The velocity model's own prediction.
    Model,
    /// The measured velocity.
    Measured,
}

impl From<FreeRunVelocityArg> for experiments::FreeRunVelocity {
    fn from(v: FreeRunVelocityArg) -> Self {
        match v {
            FreeRunVelocityArg::Model => Self::Model,
            FreeRunVelocityArg::Measured => Self::Measured,
        }
    }
}

/// `--gyro-noise`: `auto`, `none`, one σ (deg/s) or three (`Q,R,P`).
/// `--gyro-compensation`'s values ([`rotorid::hover::GyroCompensation`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GyroCompensationArg {
    /// The damping term's noise.
    Damping,
    /// The damping and the second-order terms' noise.
    Full,
}

impl From<GyroCompensationArg> for rotorid::hover::GyroCompensation {
    fn from(arg: GyroCompensationArg) -> Self {
        match arg {
            GyroCompensationArg::Damping => Self::Damping,
            GyroCompensationArg::Full => Self::Full,
        }
    }
}

pub fn parse_gyro_noise(text: &str) -> Result<GyroNoise, String> {
    match text {
        "auto" => return Ok(GyroNoise::Auto),
        "none" => return Ok(GyroNoise::None),
        _ => {}
    }
    let values = text
        .split(',')
        .map(|v| match v.trim().parse::<f32>() {
            Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
            _ => Err(format!(
                "`{v}` is not a noise σ (deg/s, finite, ≥ 0); expected auto, none, SIGMA or Q,R,P"
            )),
        })
        .collect::<Result<Vec<f32>, String>>()?;
    match values[..] {
        [x] => Ok(GyroNoise::Given([x; 3])),
        [q, r, p] => Ok(GyroNoise::Given([q, r, p])),
        _ => Err(format!(
            "`{text}`: one value or three (Q,R,P) expected, or auto, none"
        )),
    }
}

/// `--observer-gain`: `auto`, one gain K (0 to 1) or six (`VX,VY,VZ,Q,R,P`).
pub fn parse_observer_gain(text: &str) -> Result<ObserverGain, String> {
    if text == "auto" {
        return Ok(ObserverGain::Auto);
    }
    let values = text
        .split(',')
        .map(|v| match v.trim().parse::<f32>() {
            Ok(k) if (0.0..=1.0).contains(&k) => Ok(k),
            _ => Err(format!(
                "`{v}` is not an observer gain (0 to 1); expected auto, K or VX,VY,VZ,Q,R,P"
            )),
        })
        .collect::<Result<Vec<f32>, String>>()?;
    match values[..] {
        [k] => Ok(ObserverGain::Given([k; 6])),
        [a, b, c, q, r, p] => Ok(ObserverGain::Given([a, b, c, q, r, p])),
        _ => Err(format!(
            "`{text}`: one observer gain or six (VX,VY,VZ,Q,R,P) expected, or auto"
        )),
    }
}
