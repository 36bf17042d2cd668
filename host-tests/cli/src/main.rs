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
use rotorid_cli::experiments;
use rotorid_cli::flight_report::Condition;
use rotorid_cli::identify::{self, GyroNoise, IdentifyArgs, ObserverGain};
use rotorid_cli::import::{self, ImportError};
use rotorid_cli::log::{self, LogError};
use rotorid_cli::report::{Metrics, ReportError};
use rotorid_cli::results::SecondPlant;
use rotorid_cli::robustness::PlantRuns;
use rotorid_cli::simulate;
use rotorid_sim::flights;
use rotorid_sim::plant::Airframe;

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
        /// Cyclic control power as a fraction of the plant's (0.1 to 2): both
        /// cyclic-to-flapping gains (A_lon, B_lat) times this, the pilot's stick scaling left
        /// as for the undamaged plant (a worn or damaged rotor; docs/python.md's fleet example).
        #[arg(long, default_value_t = 1.0)]
        cyclic_power: f64,
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
        observer_gain: ObserverGain,
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
    #[error(transparent)]
    Simulate(#[from] simulate::SimulateError),
    #[error(transparent)]
    Log(#[from] LogError),
    #[error(transparent)]
    Import(#[from] ImportError),
    #[error(transparent)]
    Identify(#[from] identify::IdentifyError),
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
    #[error("{}: not the expected JSON", path.display())]
    ParseJson {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("progress bar")]
    ProgressBar(#[from] indicatif::style::TemplateError),
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
            cyclic_power,
            output,
        } => run_simulate(
            kind,
            seed,
            duration,
            Sensors { clean, noise_scale },
            (plant.into(), plant_variation, cyclic_power),
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
            out: Some(out),
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
    (airframe, variation, cyclic_power): (Airframe, Option<u64>, f64),
    output: &Path,
) -> Result<(), CliError> {
    let samples = simulate::simulate(&simulate::SimulateArgs {
        kind: match kind {
            Kind::Identification => simulate::FlightKind::Identification,
            Kind::Verification => simulate::FlightKind::Verification,
            Kind::Envelope => simulate::FlightKind::Envelope,
            Kind::EnvelopeVerification => simulate::FlightKind::EnvelopeVerification,
        },
        seed,
        duration,
        clean: sensors.clean,
        noise_scale: sensors.noise_scale,
        airframe,
        variation,
        cyclic_power,
    })?;
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
    for line in identify::import_notes(path, imported, used, full) {
        eprintln!("{line}");
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

fn parse_observer_gain(text: &str) -> Result<ObserverGain, String> {
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

/// `rotorid identify`: the library's [`identify::identify`], printing as it goes.
fn run_identify(args: &IdentifyArgs) -> Result<(), CliError> {
    let mut terminal = Terminal::new()?;
    identify::identify(args, &mut terminal)?;
    Ok(())
}

/// Prints an identification's notes to stderr and its text to stdout, with a progress bar.
struct Terminal {
    style: ProgressStyle,
    bar: Option<ProgressBar>,
}

impl Terminal {
    fn new() -> Result<Self, CliError> {
        Ok(Self {
            style: ProgressStyle::with_template(
                "{msg:>12} [{bar:40}] {pos}/{len} samples ({eta})",
            )?
            .progress_chars("=> "),
            bar: None,
        })
    }
}

impl identify::Progress for Terminal {
    fn note(&mut self, line: &str) {
        eprintln!("{line}");
    }
    fn print(&mut self, text: &str) {
        print!("{text}");
    }
    fn start(&mut self, total: u64) {
        let bar = ProgressBar::new(total);
        bar.set_style(self.style.clone());
        self.bar = Some(bar);
    }
    fn variant(&mut self, name: &'static str) {
        if let Some(bar) = &self.bar {
            bar.set_message(name);
        }
    }
    fn tick(&mut self) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }
    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
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
