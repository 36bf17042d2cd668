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
    /// Identify hover models from flight logs and say which model to fly: per axis, its free
    /// run against holding the measured state and against the linear baseline, and what the
    /// logs could not show (`--full`: every variant's tables). Logs: CSV, PX4 ULog (.ulg),
    /// ArduPilot DataFlash (.bin) or PX4 sdlog2 (.px4log); ground time and implausible
    /// stretches are cut, every usable segment is learnt, and without --verify a part is held
    /// out for verification (--holdout).
    Identify {
        /// Logs to identify from (as --train).
        logs: Vec<PathBuf>,
        /// Training (identification) logs, learnt one after another.
        #[arg(long, num_args = 1..)]
        train: Vec<PathBuf>,
        /// Verification log (θ frozen after training; its longest segment). Without it, part
        /// of the training data is held out (--holdout).
        #[arg(long)]
        verify: Option<PathBuf>,
        /// Fraction of the data held out for verification when --verify is not given (the
        /// later part: a whole segment of about that size, else the end of the longest).
        #[arg(long, default_value_t = 0.3)]
        holdout: f64,
        /// Identification rate (Hz): `auto` takes the fastest of 50, 25, 20, 10, 5 Hz that
        /// every channel of every log is logged at (no invented samples); a number forces it.
        #[arg(long, default_value = "auto", value_parser = parse_rate)]
        rate: RateArg,
        /// Use the logs only from this log time (s, as logged) on; with --to it replaces the
        /// in-air detector.
        #[arg(long)]
        from: Option<f64>,
        /// Use the logs only up to this log time (s).
        #[arg(long)]
        to: Option<f64>,
        /// Print every variant's tables, the Table 4 analogue and every import note, not only
        /// the verdict.
        #[arg(long)]
        full: bool,
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
    /// Convert a PX4 ULog (.ulg), ArduPilot DataFlash (.bin) or PX4 sdlog2 (.px4log) log to
    /// the CSV format (docs/log-format.md): ground time and implausible stretches cut,
    /// resampled at the log's own rate (at most 50 Hz); the longest segment, or every segment
    /// with --all.
    Convert {
        /// Input log (.ulg, .bin, .px4log, or CSV).
        input: PathBuf,
        /// Output CSV file (with --all: OUTPUT-1.csv, OUTPUT-2.csv, … beside it).
        #[arg(short, long)]
        output: PathBuf,
        /// Write every segment, each to its own file.
        #[arg(long)]
        all: bool,
        /// Sample rate of the CSV (Hz): `auto` as `identify --rate`.
        #[arg(long, default_value = "auto", value_parser = parse_rate)]
        rate: RateArg,
        /// Only from this log time (s) on (replaces the in-air detector, as in identify).
        #[arg(long)]
        from: Option<f64>,
        /// Only up to this log time (s).
        #[arg(long)]
        to: Option<f64>,
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
    #[error("no log to identify from: give LOG... (or --train LOG...)")]
    NoLogs,
    #[error(transparent)]
    Split(#[from] rotorid_cli::holdout::SplitError),
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
            logs,
            train,
            verify,
            holdout,
            rate,
            from,
            to,
            full,
            out,
            window,
            plot_span,
            no_plots,
            warm_start,
            gyro_noise,
            free_run_velocity,
            observer_gain,
        } => run_identify(&IdentifyArgs {
            train: logs.into_iter().chain(train).collect(),
            verify,
            holdout,
            options: import::ImportOptions {
                rate_hz: rate.0,
                from_s: from,
                to_s: to,
            },
            full,
            out,
            window,
            plot_span,
            no_plots,
            warm_start,
            gyro_noise,
            free_run_velocity: free_run_velocity.into(),
            observer_gain,
        }),
        Command::Convert {
            input,
            output,
            all,
            rate,
            from,
            to,
        } => run_convert(
            &input,
            &output,
            all,
            &import::ImportOptions {
                rate_hz: rate.0,
                from_s: from,
                to_s: to,
            },
        ),
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

/// Reads a log of any format (CSV, ULog, DataFlash, sdlog2) as `options` say.
fn read(path: &Path, options: &import::ImportOptions) -> Result<import::Imported, CliError> {
    Ok(import::import_with(path, options)?)
}

/// Prints an import's warnings, and its notes (`full`) or a one-line summary of them.
fn report_import(path: &Path, imported: &import::Imported, used: &[&import::Segment], full: bool) {
    let file = path.display().to_string();
    if full || imported.notes.len() <= 2 {
        for n in &imported.notes {
            eprintln!("note: {n}");
        }
    } else {
        eprintln!(
            "note: {file}: {} notes ({} cuts; --full lists them)",
            imported.notes.len(),
            imported.cuts.len()
        );
    }
    for w in &imported.warnings {
        eprintln!("warning: {w}");
    }
    for seg in used {
        for w in log::warnings(&file, seg) {
            eprintln!("warning: {w}");
        }
    }
}

fn run_convert(
    input: &Path,
    output: &Path,
    all: bool,
    options: &import::ImportOptions,
) -> Result<(), CliError> {
    let imported = read(input, options)?;
    let segments: Vec<&import::Segment> = if all {
        imported.segments.iter().collect()
    } else {
        imported.longest().into_iter().collect()
    };
    report_import(input, &imported, &segments, true);
    for (k, seg) in segments.iter().enumerate() {
        let path = if all {
            numbered(output, k + 1)
        } else {
            output.to_path_buf()
        };
        log::write_log(&path, seg)?;
        eprintln!(
            "wrote {} samples ({:.2}–{:.2} s at {} Hz{}) to {}",
            seg.len(),
            seg.first().map_or(0.0, |s| s.t),
            seg.last().map_or(0.0, |s| s.t),
            imported.rate_hz,
            if all {
                String::new()
            } else {
                format!(", the longest of {} segments", imported.segments.len())
            },
            path.display()
        );
    }
    Ok(())
}

/// `out.csv` → `out-3.csv`.
fn numbered(path: &Path, k: usize) -> PathBuf {
    let stem = path.file_stem().map_or_else(
        || "segment".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    let ext = path
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    path.with_file_name(format!("{stem}-{k}{ext}"))
}

/// `--rate`: `auto` (`None`) or a rate in Hz.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RateArg(Option<f64>);

fn parse_rate(text: &str) -> Result<RateArg, String> {
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

/// The arguments of `rotorid identify`, resolved.
struct IdentifyArgs {
    train: Vec<PathBuf>,
    verify: Option<PathBuf>,
    holdout: f64,
    options: import::ImportOptions,
    full: bool,
    out: PathBuf,
    window: f64,
    plot_span: Option<f64>,
    no_plots: bool,
    warm_start: Option<PathBuf>,
    gyro_noise: GyroNoise,
    free_run_velocity: experiments::FreeRunVelocity,
    observer_gain: ObserverGainArg,
}

/// Reads every log at one rate: each at the rate its channels support, then those faster
/// than the slowest again at that (a model is learnt at one sample period).
fn read_all(
    paths: &[&Path],
    options: &import::ImportOptions,
) -> Result<Vec<import::Imported>, CliError> {
    let mut imported = paths
        .iter()
        .map(|p| read(p, options))
        .collect::<Result<Vec<_>, _>>()?;
    let rate = imported
        .iter()
        .map(|i| i.rate_hz)
        .min_by(f64::total_cmp)
        .unwrap_or(import::resample::RATE_HZ);
    for (p, i) in paths.iter().zip(imported.iter_mut()) {
        if i.rate_hz != rate {
            *i = read(
                p,
                &import::ImportOptions {
                    rate_hz: Some(rate),
                    ..*options
                },
            )?;
        }
    }
    Ok(imported)
}

/// The same file given twice (by path or by content).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) if x == y => return true,
        _ => {}
    }
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) if x.len() == y.len() => {
            matches!((std::fs::read(a), std::fs::read(b)), (Ok(x), Ok(y)) if x == y)
        }
        _ => false,
    }
}

fn run_identify(args: &IdentifyArgs) -> Result<(), CliError> {
    let window = args.window;
    if !(window.is_finite() && window > 0.0 && window <= 3600.0) {
        return Err(CliError::Window(window));
    }
    if args.train.is_empty() {
        return Err(CliError::NoLogs);
    }
    let mut paths: Vec<&Path> = args.train.iter().map(PathBuf::as_path).collect();
    if let Some(v) = &args.verify {
        paths.push(v);
    }
    let imported = read_all(&paths, &args.options)?;
    let rate_hz = imported
        .first()
        .map_or(import::resample::RATE_HZ, |i| i.rate_hz);
    let mut labelled = Vec::new();
    for (path, im) in args.train.iter().zip(&imported) {
        let used = import::segments_for_identify(im, true);
        report_import(path, im, &used, args.full);
        for (k, seg) in im.segments.iter().enumerate() {
            if used.iter().any(|u| std::ptr::eq(*u, seg)) {
                labelled.push(rotorid_cli::holdout::Labelled {
                    file: path.display().to_string(),
                    segment: k + 1,
                    samples: seg.clone(),
                });
            }
        }
    }
    let split = match (&args.verify, imported.last()) {
        (Some(v), Some(im)) => {
            let longest = im
                .longest()
                .ok_or_else(|| CliError::NoSamples(v.to_path_buf()))?;
            report_import(v, im, &[longest], args.full);
            if args.train.iter().any(|t| same_file(t, v)) {
                eprintln!(
                    "warning: {} is also a training log: the scores measure how well the models fit it, not how they predict; leave out --verify to hold part of the data out",
                    v.display()
                );
            }
            rotorid_cli::holdout::Split {
                training: labelled.into_iter().map(|l| l.samples).collect(),
                verification: longest.clone(),
                how: format!("verified on {} (its longest segment)", v.display()),
            }
        }
        _ => rotorid_cli::holdout::split(
            labelled,
            args.holdout,
            import::min_useful_samples(rate_hz),
        )?,
    };
    let verify_name = args
        .verify
        .as_ref()
        .map_or_else(|| "held-out data".to_string(), |v| v.display().to_string());
    if split.verification.len() < 2 {
        return Err(CliError::TooFewSamples(PathBuf::from(&verify_name)));
    }
    let training: Vec<Vec<rotorid::hover::HoverSample<f32>>> = split
        .training
        .iter()
        .map(|s| flights::to_hover_samples(s))
        .collect();
    let verification = flights::to_hover_samples(&split.verification);
    let warm: Option<Vec<ModelParameters>> =
        args.warm_start.as_deref().map(read_json).transpose()?;
    let out = args.out.as_path();
    std::fs::create_dir_all(out).map_err(|source| CliError::CreateDir {
        path: out.to_path_buf(),
        source,
    })?;

    let gyro_noise = match args.gyro_noise {
        // RateNoise's third differences are noise only when the rates are sampled well above
        // the body dynamics (50 Hz for a helicopter); at a log's lower rate they are mostly
        // motion, and compensating for that would spoil the free run.
        GyroNoise::Auto if rate_hz >= import::resample::RATE_HZ => {
            experiments::gyro_noise_of(&training)
        }
        GyroNoise::Auto => {
            eprintln!(
                "note: at {rate_hz} Hz the rates' differences are mostly motion, not gyro noise: the free runs are not compensated for it (give --gyro-noise with the gyro's data-sheet σ)"
            );
            None
        }
        GyroNoise::None => None,
        GyroNoise::Given(sigma) => Some(sigma),
    };
    let n_train: usize = training.iter().map(Vec::len).sum();
    eprintln!(
        "identifying at {rate_hz} Hz: {:.1} s of training data in {} segment(s), {:.1} s to verify; {}",
        n_train as f64 / rate_hz,
        training.len(),
        verification.len() as f64 / rate_hz,
        split.how
    );
    if args.full {
        if let Some([q, r, p]) = gyro_noise {
            eprintln!(
                "free runs compensated for gyro noise σ = {q:.3}, {r:.3}, {p:.3} deg/s (q, r, p)"
            );
        }
    }
    if args.free_run_velocity == experiments::FreeRunVelocity::Measured {
        eprintln!("free runs on the measured velocity: the rates run free, the velocities do not");
    }
    let variants = experiments::variants();
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
            velocity: args.free_run_velocity,
            observer_gain: match args.observer_gain {
                ObserverGainArg::Auto => None,
                ObserverGainArg::Given(gain) => Some(gain),
            },
            rate_hz,
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
    if args.full {
        println!(
            "Table 4 analogue: mean absolute one-step error over {verify_name} (θ frozen after training on {n_train} samples)\n"
        );
        if let Some(t) = &table4 {
            print!("{}", experiments::format_table4(&t.fuzzy, &t.plain));
        }
        println!();
        print!("{}", report::format_variants(&results, window));
    }

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
    if args.full {
        for p in &precision {
            println!(
                "{}: f32 vs f64, {} of {} parameters well excited, relative difference max {:.2e}, median {:.2e}",
                p.variant, p.compared, p.parameters, p.max_relative, p.median_relative
            );
        }
    }
    let verdict = rotorid_cli::verdict::verdict(&results, &split.training, rate_hz);
    match &verdict {
        Some(v) => print!("{}", rotorid_cli::verdict::format_verdict(v, window)),
        None => println!(
            "No verdict: no candidate model could be scored against hold (each left the sample limits in a free-run window, or a state never moved); see metrics.json, or --full"
        ),
    }
    let segments: Vec<&[rotorid_sim::plant::SensorSample]> =
        split.training.iter().map(Vec::as_slice).collect();
    let derivatives = rotorid_cli::derivatives::derivatives(&segments, rate_hz);
    let text = rotorid_cli::derivatives::format_derivatives(&derivatives);
    println!("{}", text.trim_end());
    let metrics = Metrics {
        precision,
        training_files: args.train.iter().map(|p| p.display().to_string()).collect(),
        training_samples: n_train,
        verification_file: verify_name,
        verification_samples: verification.len(),
        window_s: window,
        gyro_noise_deg_s: gyro_noise,
        free_run_velocity: args.free_run_velocity,
        states: report::state_labels(),
        variants: results,
        table4,
        rate_hz,
        split: split.how.clone(),
        logs: paths
            .iter()
            .zip(&imported)
            .map(|(p, im)| report::LogSummary::of(&p.display().to_string(), im))
            .collect(),
        verdict,
        derivatives: Some(derivatives),
    };
    write_json(&out.join("metrics.json"), &metrics)?;
    let mut figures = 0;
    if !args.no_plots {
        // The model to fly and the linear baseline; every variant with --full.
        let mut shown: Vec<&str> = metrics
            .verdict
            .as_ref()
            .map(|v| v.model.as_str())
            .into_iter()
            .chain([rotorid_cli::verdict::BASELINE])
            .collect();
        shown.dedup();
        if args.full {
            shown = metrics
                .variants
                .iter()
                .map(|v| v.name.as_str())
                .take(5)
                .collect();
        }
        figures = report::write_figures(
            out,
            &verification,
            &metrics.variants,
            &shown,
            args.plot_span,
        )?
        .len();
    }
    println!(
        "Files: {}: metrics.json (every variant, the import's cuts and rates), params-*.json{}",
        out.display(),
        if figures > 0 {
            format!(", {figures} figures")
        } else {
            String::new()
        }
    );
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
