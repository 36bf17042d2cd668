//! `rotorid`: simulate X-Cell 60 (or `--plant flybarless600`) flights into the flight-log format, and identify hover
//! models from flight logs (the paper's Table 4 and Figures 2–5 for your own data).
//!
//! ```text
//! rotorid simulate --kind identification --seed 1 -o ident.csv
//! rotorid simulate --kind verification --seed 2 --duration 300 -o verify.csv
//! rotorid identify --train ident.csv --verify verify.csv --out results/
//! rotorid convert flight.ulg -o flight.csv
//! ```
//!
//! The binary of package `rotorid-cli`: argument parsing and printing only; the work is done by
//! its library (`rotorid_cli`) on flights from `rotorid-sim` with the `rotorid` core.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use rotorid_cli::error_chain::Chain;
use rotorid_cli::experiments::{self, EvaluateError, ModelParameters, TABLE4_VARIANTS};
use rotorid_cli::flight_report::Condition;
use rotorid_cli::import::{self, ImportError};
use rotorid_cli::log::{self, LogError};
use rotorid_cli::report::{self, FigureError, Metrics, ReportError, Table4};
use rotorid_cli::results::SecondPlant;
use rotorid_cli::robustness::PlantRuns;
use rotorid_sim::envelope::{self, EnvelopeKind};
use rotorid_sim::flights;
use rotorid_sim::plant::{Airframe, FlightConfig, NoiseStd, PlantError};

#[derive(Parser)]
#[command(
    name = "rotorid",
    version,
    about = "Identify miniature-helicopter hover dynamics (TS fuzzy + RLS) from flight logs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    /// The four Table 2 sweeps (lon, lat, ped, col), 255 s in full.
    Identification,
    /// Doublets and 3-2-1-1 multisteps on all controls between hover periods.
    Verification,
    /// Wide envelope: 12 operating points from hover to 12 m/s forward, ±5 m/s sideways,
    /// ±3 m/s vertical, with doublets and multisteps throughout (300 s).
    Envelope,
    /// The held-out envelope flight: 8 other operating points (200 s); use another seed.
    EnvelopeVerification,
}

/// Which simulated helicopter (`rotorid_sim::plant::Airframe`).
#[derive(Clone, Copy, Default, ValueEnum)]
enum Plant {
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

#[derive(Subcommand)]
enum Command {
    /// Fly the helicopter simulator (X-Cell 60 by default) and write the flight log (CSV,
    /// docs/log-format.md).
    Simulate {
        /// Flight kind.
        #[arg(long, value_enum)]
        kind: Kind,
        /// Seed of noise, turbulence, jitter and (verification) manoeuvres.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Duration (s). Identification: at most the 255 s of the sweeps (default all);
        /// verification: default 120 s.
        #[arg(long)]
        duration: Option<f64>,
        /// No measurement noise and no turbulence (jitter stays).
        #[arg(long)]
        clean: bool,
        /// Measurement noise as a multiple of the default (GPS/INS-like: 0.02 m/s, 0.3 deg/s,
        /// 0.2 deg): a noisier or cleaner sensor set on the same flight. Ignored with --clean.
        #[arg(long, default_value_t = 1.0)]
        noise_scale: f64,
        /// Simulated helicopter; the pilot and the inputs are scaled to it.
        #[arg(long, value_enum, default_value_t = Plant::Xcell60)]
        plant: Plant,
        /// Fly another helicopter of the plant's kind instead: its parameters each varied by a
        /// random factor drawn from this seed (mass ±15 %, inertias, hub, flapping, tail, fins
        /// and fuselage up to 1.6× either way, head speed ±10 %; docs/robustness.md). Some
        /// variations cannot hover; the simulation then says so.
        #[arg(long, value_name = "SEED")]
        plant_variation: Option<u64>,
        /// Output CSV file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Train the fuzzy and plain identifiers on logs, verify on another log, print Table 4.
    /// Logs: CSV, PX4 ULog (.ulg) or ArduPilot DataFlash (.bin); a log split at gaps trains on
    /// each segment and verifies on the longest.
    Identify {
        /// Training (identification) logs, learnt one after another.
        #[arg(long, required = true, num_args = 1..)]
        train: Vec<PathBuf>,
        /// Verification log (θ frozen after training).
        #[arg(long)]
        verify: PathBuf,
        /// Directory for metrics.json, params-*.json and the figures.
        #[arg(long, default_value = "rotorid-out")]
        out: PathBuf,
        /// Free-run window (s): the model runs on its own predictions, restarted from the
        /// measured state at each window.
        #[arg(long, default_value_t = 2.0)]
        window: f64,
        /// Plot only the first seconds of the verification flight (default: all).
        #[arg(long)]
        plot_span: Option<f64>,
        /// Do not write the PNG figures.
        #[arg(long)]
        no_plots: bool,
        /// Warm start the first variant from a params-*.json written by an earlier run.
        #[arg(long)]
        warm_start: Option<PathBuf>,
        /// White noise σ of the gyro rates (deg/s) that the free run's parameters are
        /// compensated for (`HoverIdentifier::compensate`): `auto` estimates it from the
        /// training logs (`RateNoise`), `none` compensates nothing, one value is every rate's,
        /// three (`Q,R,P`) are each rate's.
        #[arg(long, default_value = "auto", value_parser = parse_gyro_noise)]
        gyro_noise: GyroNoise,
        /// The velocity the free run feeds the models: `model` (their own prediction, the
        /// whole identifier's free run) or `measured` (the measured velocity while the rates
        /// run free: the rate models' free run without the velocity model's error; the
        /// velocities' free-run errors are then zero).
        #[arg(long, value_enum, default_value_t = FreeRunVelocityArg::Model)]
        free_run_velocity: FreeRunVelocityArg,
        /// Gain K of every variant's one-step observer (`rotorid::hover::Observer`; 0 to 1,
        /// 1 predicts from the measured state): `auto` finds each variant's on the training
        /// logs (`GainSearch`, 0.1 to 1 in steps of 0.1), one value is every state's, six
        /// (`VX,VY,VZ,Q,R,P`) are each state's.
        #[arg(long, default_value = "auto", value_parser = parse_observer_gain)]
        observer_gain: ObserverGainArg,
    },
    /// Convert a PX4 ULog (.ulg) or ArduPilot DataFlash (.bin) log to the CSV format
    /// (docs/log-format.md): resampled at 50 Hz; the longest gap-free segment.
    Convert {
        /// Input log (.ulg, .bin, or CSV).
        input: PathBuf,
        /// Output CSV file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write docs/results.md from the metrics of a realistic and a clean run (used by
    /// scripts/results.sh).
    #[command(hide = true)]
    Report(ReportArgs),
    /// Write docs/robustness.md from the metrics of plant variations (used by
    /// scripts/robustness.sh).
    #[command(hide = true)]
    RobustnessReport {
        /// One plant's runs as `FAMILY|LABEL|HOVER_METRICS|ENVELOPE_METRICS[|MEASURED]`: the
        /// table it goes in, its row's label, the metrics.json of its hover and envelope pairs,
        /// and optionally that of the envelope pair run with `identify --free-run-velocity
        /// measured`. Repeatable; tables and rows keep the order given.
        #[arg(
            long = "run",
            value_name = "FAMILY|LABEL|HOVER|ENVELOPE[|MEASURED]",
            value_parser = parse_run
        )]
        runs: Vec<RunPaths>,
        /// The command lines that made the runs (quoted in the document).
        #[arg(long)]
        how: String,
        /// Output markdown file.
        #[arg(short, long)]
        output: PathBuf,
    },
}

/// The arguments of `rotorid report`.
#[derive(clap::Args)]
struct ReportArgs {
    /// metrics.json of the realistic (noisy, turbulent) run.
    #[arg(long)]
    realistic: PathBuf,
    /// metrics.json of the clean (no noise, still air) run.
    #[arg(long)]
    clean: PathBuf,
    /// metrics.json of the envelope run (its directory also holds params-flight.json).
    #[arg(long)]
    envelope: Option<PathBuf>,
    /// The second plant whose runs `--second-hover` and `--second-envelope` are.
    #[arg(long, value_enum, default_value_t = Plant::Flybarless600)]
    second_plant: Plant,
    /// metrics.json of the second plant's hover run.
    #[arg(long, requires = "second_envelope")]
    second_hover: Option<PathBuf>,
    /// metrics.json of the second plant's envelope run (its directory also holds
    /// params-flight.json).
    #[arg(long, requires = "second_hover")]
    second_envelope: Option<PathBuf>,
    /// metrics.json of the hover run with noisier sensors (`simulate --noise-scale 3`).
    #[arg(long)]
    noisy_hover: Option<PathBuf>,
    /// A run for the section "What limits the flight default", as `GROUP|LABEL|METRICS`:
    /// the table it goes in, its row's label, and its metrics.json (whose directory also
    /// holds params-flight.json and params-extended-plain.json). Repeatable; tables and rows
    /// keep the order given.
    #[arg(long = "condition", value_name = "GROUP|LABEL|METRICS", value_parser = parse_condition)]
    conditions: Vec<(String, String, PathBuf)>,
    /// Seconds the results script took to simulate and identify (for the doc).
    #[arg(long)]
    elapsed: Option<f64>,
    /// Output markdown file.
    #[arg(short, long)]
    output: PathBuf,
}

/// What went wrong in a command; `main` prints it with its causes ([`Chain`]).
#[derive(Debug, thiserror::Error)]
enum CliError {
    #[error("--duration must be in (0, 36000] s, got {0}")]
    Duration(f64),
    #[error("--noise-scale must be in [0, 100], got {0}")]
    NoiseScale(f64),
    #[error(
        "--duration {given} s: the identification flight (the four Table 2 sweeps) lasts {full} s; \
         give at most that, or fly a verification flight for longer"
    )]
    LongerThanSweeps { given: f64, full: f64 },
    #[error("--duration does not apply to envelope flights (their length is their schedule's)")]
    EnvelopeDuration,
    #[error("--window must be in (0, 3600] s, got {0}")]
    Window(f64),
    #[error("plant {airframe}")]
    Airframe {
        airframe: &'static str,
        source: PlantError,
    },
    #[error("plant {airframe}, variation {seed}: this variation cannot hover (try another seed)")]
    Variation {
        airframe: &'static str,
        seed: u64,
        source: PlantError,
    },
    #[error("simulation")]
    Simulation(#[source] PlantError),
    #[error(transparent)]
    Log(#[from] LogError),
    #[error(transparent)]
    Import(#[from] ImportError),
    #[error("{}: no samples", .0.display())]
    NoSamples(PathBuf),
    #[error("{}: needs at least 2 samples", .0.display())]
    TooFewSamples(PathBuf),
    #[error("{}: cannot read", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: cannot write", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: cannot create the directory", path.display())]
    CreateDir {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not the expected JSON", path.display())]
    ParseJson {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("{}: cannot encode as JSON", path.display())]
    ToJson {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("progress bar")]
    ProgressBar(#[from] indicatif::style::TemplateError),
    #[error(transparent)]
    Evaluate(#[from] EvaluateError),
    #[error("comparing f32 with f64")]
    Precision(#[source] rotorid::Error),
    #[error(transparent)]
    Figure(#[from] FigureError),
    #[error(transparent)]
    Report(#[from] ReportError),
}

/// `FAMILY|LABEL|HOVER|ENVELOPE[|MEASURED]` of `robustness-report --run`.
#[derive(Clone, Debug)]
struct RunPaths {
    family: String,
    label: String,
    hover: PathBuf,
    envelope: PathBuf,
    envelope_measured_velocity: Option<PathBuf>,
}

fn parse_run(s: &str) -> Result<RunPaths, String> {
    match s.split('|').collect::<Vec<_>>()[..] {
        [family, label, hover, envelope, ref measured @ ..]
            if !hover.is_empty() && !envelope.is_empty() && measured.len() <= 1 =>
        {
            Ok(RunPaths {
                family: family.to_string(),
                label: label.to_string(),
                hover: hover.into(),
                envelope: envelope.into(),
                envelope_measured_velocity: measured
                    .first()
                    .filter(|m| !m.is_empty())
                    .map(PathBuf::from),
            })
        }
        _ => Err(format!(
            "expected FAMILY|LABEL|HOVER|ENVELOPE or FAMILY|LABEL|HOVER|ENVELOPE|MEASURED, got {s:?}"
        )),
    }
}

/// `GROUP|LABEL|METRICS` of `report --condition`.
fn parse_condition(s: &str) -> Result<(String, String, PathBuf), String> {
    match s.split('|').collect::<Vec<_>>()[..] {
        [group, label, metrics]
            if !group.is_empty() && !label.is_empty() && !metrics.is_empty() =>
        {
            Ok((group.to_string(), label.to_string(), PathBuf::from(metrics)))
        }
        _ => Err(format!("expected GROUP|LABEL|METRICS, got {s:?}")),
    }
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, CliError> {
    let text = std::fs::read_to_string(path).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| CliError::ParseJson {
        path: path.to_path_buf(),
        source,
    })
}

fn write_text(path: &Path, text: String) -> Result<(), CliError> {
    std::fs::write(path, text).map_err(|source| CliError::Write {
        path: path.to_path_buf(),
        source,
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate {
            kind,
            seed,
            duration,
            clean,
            noise_scale,
            plant,
            plant_variation,
            output,
        } => run_simulate(
            kind,
            seed,
            duration,
            Sensors { clean, noise_scale },
            (plant.into(), plant_variation),
            &output,
        ),
        Command::Identify {
            train,
            verify,
            out,
            window,
            plot_span,
            no_plots,
            warm_start,
            gyro_noise,
            free_run_velocity,
            observer_gain,
        } => run_identify(
            &train,
            &verify,
            &out,
            window,
            plot_span,
            no_plots,
            warm_start.as_deref(),
            gyro_noise,
            free_run_velocity.into(),
            observer_gain,
        ),
        Command::Convert { input, output } => run_convert(&input, &output),
        Command::Report(args) => run_report(&args),
        Command::RobustnessReport { runs, how, output } => {
            run_robustness_report(&runs, &how, &output)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", Chain(&e));
            ExitCode::FAILURE
        }
    }
}

/// The simulated sensors: none (`clean`, still air too), or the default noise times
/// `noise_scale`.
struct Sensors {
    clean: bool,
    noise_scale: f64,
}

fn run_simulate(
    kind: Kind,
    seed: u64,
    duration: Option<f64>,
    sensors: Sensors,
    (airframe, variation): (Airframe, Option<u64>),
    output: &Path,
) -> Result<(), CliError> {
    let scale = sensors.noise_scale;
    if !(scale.is_finite() && (0.0..=100.0).contains(&scale)) {
        return Err(CliError::NoiseScale(scale));
    }
    if let Some(d) = duration {
        if !(d.is_finite() && d > 0.0 && d <= 36_000.0) {
            return Err(CliError::Duration(d));
        }
    }
    if let (Kind::Identification, Some(d)) = (kind, duration) {
        let full = flights::identification_duration_s();
        if d > full {
            return Err(CliError::LongerThanSweeps { given: d, full });
        }
    }
    let sensors = if sensors.clean {
        FlightConfig::default()
    } else {
        let realistic = FlightConfig::realistic(seed, 0.0);
        FlightConfig {
            noise: realistic.noise.map(|n| NoiseStd {
                velocity: n.velocity * scale,
                rate: n.rate * scale,
                angle: n.angle * scale,
            }),
            ..realistic
        }
    };
    let config = FlightConfig { seed, ..sensors }
        .for_airframe(airframe)
        .map_err(|source| CliError::Airframe {
            airframe: airframe.name(),
            source,
        })?;
    let config = match variation {
        Some(seed) => config.varied(seed).map_err(|source| CliError::Variation {
            airframe: airframe.name(),
            seed,
            source,
        })?,
        None => config,
    };
    let samples = match kind {
        Kind::Identification => {
            flights::identification_flight_with(&config, duration.unwrap_or(f64::INFINITY))
        }
        Kind::Verification => flights::verification_flight_with(&FlightConfig {
            duration: duration.unwrap_or(120.0),
            ..config
        }),
        Kind::Envelope | Kind::EnvelopeVerification => {
            let kind = match kind {
                Kind::Envelope => EnvelopeKind::Identification,
                _ => EnvelopeKind::Verification,
            };
            if duration.is_some() {
                return Err(CliError::EnvelopeDuration);
            }
            envelope::envelope_flight_with(&config, kind)
        }
    }
    .map_err(CliError::Simulation)?;
    log::write_log(output, &samples)?;
    eprintln!(
        "wrote {} samples ({:.1} s) to {}",
        samples.len(),
        samples.len() as f64 / f64::from(flights::SAMPLE_RATE_HZ),
        output.display()
    );
    Ok(())
}

/// Reads a log of any format (CSV, ULog, DataFlash) and prints its notes and warnings; `all`:
/// every usable segment (training), else the longest (verification).
fn read(path: &Path, all: bool) -> Result<Vec<Vec<rotorid::hover::HoverSample<f32>>>, CliError> {
    let imported = import::import(path)?;
    let segments = import::segments_for_identify(&imported, all);
    report_import(path, &imported, &segments);
    Ok(segments
        .iter()
        .map(|s| flights::to_hover_samples(s))
        .collect())
}

/// Prints an import's notes and the warnings on the segments used.
fn report_import(path: &Path, imported: &import::Imported, used: &[&import::Segment]) {
    for n in &imported.notes {
        eprintln!("note: {n}");
    }
    for seg in used {
        for w in log::warnings(&path.display().to_string(), seg) {
            eprintln!("warning: {w}");
        }
    }
}

fn run_convert(input: &Path, output: &Path) -> Result<(), CliError> {
    let imported = import::import(input)?;
    let seg = imported
        .longest()
        .ok_or_else(|| CliError::NoSamples(input.to_path_buf()))?;
    report_import(input, &imported, &[seg]);
    log::write_log(output, seg)?;
    eprintln!(
        "wrote {} samples ({:.2}–{:.2} s, the longest of {} segments) to {}",
        seg.len(),
        seg.first().map_or(0.0, |s| s.t),
        seg.last().map_or(0.0, |s| s.t),
        imported.segments.len(),
        output.display()
    );
    Ok(())
}

fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value).map_err(|source| CliError::ToJson {
        path: path.to_path_buf(),
        source,
    })?;
    write_text(path, text + "\n")
}

/// `--free-run-velocity` ([`experiments::FreeRunVelocity`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum FreeRunVelocityArg {
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

/// `--gyro-noise`: what the free run's parameters are compensated for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum GyroNoise {
    /// Estimated from the training logs.
    Auto,
    /// Not compensated.
    None,
    /// σ of `[q r p]` (deg/s).
    Given([f32; 3]),
}

fn parse_gyro_noise(text: &str) -> Result<GyroNoise, String> {
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

/// `--observer-gain`: the one-step observer's gain.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ObserverGainArg {
    /// Found on the training logs, per variant.
    Auto,
    /// K of `[v_x v_y v_z q r p]`.
    Given([f32; 6]),
}

fn parse_observer_gain(text: &str) -> Result<ObserverGainArg, String> {
    if text == "auto" {
        return Ok(ObserverGainArg::Auto);
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
        [k] => Ok(ObserverGainArg::Given([k; 6])),
        [a, b, c, q, r, p] => Ok(ObserverGainArg::Given([a, b, c, q, r, p])),
        _ => Err(format!(
            "`{text}`: one observer gain or six (VX,VY,VZ,Q,R,P) expected, or auto"
        )),
    }
}

#[allow(clippy::too_many_arguments)]
fn run_identify(
    train: &[PathBuf],
    verify: &Path,
    out: &Path,
    window: f64,
    plot_span: Option<f64>,
    no_plots: bool,
    warm_start: Option<&Path>,
    gyro_noise: GyroNoise,
    free_run_velocity: experiments::FreeRunVelocity,
    observer_gain: ObserverGainArg,
) -> Result<(), CliError> {
    if !(window.is_finite() && window > 0.0 && window <= 3600.0) {
        return Err(CliError::Window(window));
    }
    let mut training = Vec::new();
    for p in train {
        training.extend(read(p, true)?);
    }
    let verification = read(verify, false)?
        .into_iter()
        .next()
        .ok_or_else(|| CliError::NoSamples(verify.to_path_buf()))?;
    if verification.len() < 2 {
        return Err(CliError::TooFewSamples(verify.to_path_buf()));
    }
    let warm: Option<Vec<ModelParameters>> = warm_start.map(read_json).transpose()?;
    std::fs::create_dir_all(out).map_err(|source| CliError::CreateDir {
        path: out.to_path_buf(),
        source,
    })?;

    let gyro_noise = match gyro_noise {
        GyroNoise::Auto => experiments::gyro_noise_of(&training),
        GyroNoise::None => None,
        GyroNoise::Given(sigma) => Some(sigma),
    };
    if let Some([q, r, p]) = gyro_noise {
        eprintln!(
            "free runs compensated for gyro noise σ = {q:.3}, {r:.3}, {p:.3} deg/s (q, r, p)"
        );
    }
    if free_run_velocity == experiments::FreeRunVelocity::Measured {
        eprintln!("free runs on the measured velocity: the rates run free, the velocities do not");
    }
    let variants = experiments::variants();
    let n_train: usize = training.iter().map(Vec::len).sum();
    let total = (n_train + verification.len()) * variants.len();
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} samples ({eta})")?
            .progress_chars("=> "),
    );
    let mut results = Vec::new();
    for (i, v) in variants.iter().enumerate() {
        bar.set_message(v.name);
        let warm = if i == 0 { warm.as_deref() } else { None };
        let mut tick = || bar.inc(1);
        let settings = experiments::EvaluationSettings {
            window_s: window,
            gyro_noise,
            velocity: free_run_velocity,
            observer_gain: match observer_gain {
                ObserverGainArg::Auto => None,
                ObserverGainArg::Given(gain) => Some(gain),
            },
        };
        results.push(experiments::evaluate(
            v,
            &training,
            &verification,
            settings,
            warm,
            &mut tick,
        )?);
    }
    bar.finish_and_clear();

    let table4 = match (
        results.get(TABLE4_VARIANTS.0),
        results.get(TABLE4_VARIANTS.1),
    ) {
        (Some(f), Some(p)) => Some(Table4::new(f.one_step, p.one_step)),
        _ => None,
    };
    println!(
        "Table 4 analogue: mean absolute one-step error over {} (θ frozen after training on {} samples)\n",
        verify.display(),
        n_train
    );
    if let Some(t) = &table4 {
        print!("{}", experiments::format_table4(&t.fuzzy, &t.plain));
    }
    println!();
    print!("{}", report::format_variants(&results, window));

    for r in &results {
        let name = r.name.replace(' ', "-");
        write_json(&out.join(format!("params-{name}.json")), &r.parameters)?;
        if let Some(p) = &r.compensated_parameters {
            write_json(&out.join(format!("params-{name}-compensated.json")), p)?;
        }
    }
    // f32 against f64 for the extended structures (issue 5): same logs, same settings.
    let precision =
        rotorid_cli::precision::extended_f32_vs_f64(&training).map_err(CliError::Precision)?;
    for p in &precision {
        println!(
            "{}: f32 vs f64, {} of {} parameters well excited, relative difference max {:.2e}, median {:.2e}",
            p.variant, p.compared, p.parameters, p.max_relative, p.median_relative
        );
    }
    let metrics = Metrics {
        precision,
        training_files: train.iter().map(|p| p.display().to_string()).collect(),
        training_samples: n_train,
        verification_file: verify.display().to_string(),
        verification_samples: verification.len(),
        window_s: window,
        gyro_noise_deg_s: gyro_noise,
        free_run_velocity,
        states: report::state_labels(),
        variants: results,
        table4,
    };
    write_json(&out.join("metrics.json"), &metrics)?;
    if !no_plots {
        let figs = report::write_figures(out, &verification, &metrics.variants, plot_span)?;
        eprintln!("wrote {} figures to {}", figs.len(), out.display());
    }
    eprintln!("wrote metrics.json and params-*.json to {}", out.display());
    Ok(())
}

fn run_robustness_report(runs: &[RunPaths], how: &str, output: &Path) -> Result<(), CliError> {
    let runs = runs
        .iter()
        .map(|r| {
            Ok(PlantRuns {
                family: r.family.clone(),
                label: r.label.clone(),
                hover: read_json(&r.hover)?,
                envelope: read_json(&r.envelope)?,
                envelope_measured_velocity: r
                    .envelope_measured_velocity
                    .as_deref()
                    .map(read_json)
                    .transpose()?,
            })
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    write_text(
        output,
        rotorid_cli::robustness::robustness_document(&runs, how),
    )
}

fn run_report(args: &ReportArgs) -> Result<(), CliError> {
    let load = read_json::<Metrics>;
    let dir_of = |p: &Path| p.parent().unwrap_or(Path::new(".")).to_path_buf();
    let conditions = args
        .conditions
        .iter()
        .map(|(group, label, metrics)| {
            Ok(Condition {
                group: group.clone(),
                label: label.clone(),
                metrics: load(metrics)?,
                params: read_json(&dir_of(metrics).join("params-flight.json"))?,
                compensated_params: {
                    let path = dir_of(metrics).join("params-flight-compensated.json");
                    path.exists().then(|| read_json(&path)).transpose()?
                },
                baseline_params: read_json(&dir_of(metrics).join("params-extended-plain.json"))?,
            })
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    let envelope = match &args.envelope {
        Some(p) => Some((load(p)?, dir_of(p))),
        None => None,
    };
    let second = match (&args.second_hover, &args.second_envelope) {
        (Some(hover), Some(envelope)) => Some((load(hover)?, load(envelope)?, dir_of(envelope))),
        _ => None,
    };
    let second = second.as_ref().map(|(hover, envelope, dir)| SecondPlant {
        airframe: args.second_plant.into(),
        hover,
        envelope,
        envelope_dir: dir,
    });
    let md = rotorid_cli::results::results_markdown(
        &load(&args.realistic)?,
        &load(&args.clean)?,
        envelope.as_ref().map(|(m, d)| (m, d.as_path())),
        second.as_ref(),
        args.noisy_hover.as_deref().map(load).transpose()?.as_ref(),
        &conditions,
        args.elapsed,
    )?;
    write_text(&args.output, md)
}
