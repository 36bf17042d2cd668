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
use rotorid_cli::command_line::{parse_rate, IdentifyOptions, Plant, RateArg};
use rotorid_cli::error_chain::Chain;
use rotorid_cli::identify::{self, IdentifyArgs};
use rotorid_cli::import::{self, ImportError};
use rotorid_cli::log::{self, LogError};
use rotorid_cli::simulate;
use rotorid_cli::terminal::Terminal;
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
        /// The pilot's feedback as a multiple of its hover-hold gains (0.05 to 10; 1 as
        /// designed): every stick output of the pilot times this, to see how the closed loop
        /// biases the identification (docs/closed-loop.md). Too weak or too strong a feedback
        /// cannot hold the helicopter; the simulation then says so.
        #[arg(long, default_value_t = 1.0)]
        pilot_gain_scale: f64,
        /// Fly the plant's linearisation about hover instead of the plant: its trim, with
        /// accelerations linear in the deviations from trim (stability and control
        /// derivatives by central differences; exact kinematics). A linear helicopter model
        /// of the kind the identification literature fits in hover.
        #[arg(long)]
        linear: bool,
        /// Sample instants exactly every 20 ms (no ±2 ms jitter); with --clean, data with no
        /// error of any kind.
        #[arg(long)]
        no_jitter: bool,
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
        #[command(flatten)]
        options: IdentifyOptions,
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
    #[error("progress bar")]
    ProgressBar(#[from] indicatif::style::TemplateError),
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
            pilot_gain_scale,
            linear,
            no_jitter,
            output,
        } => run_simulate(
            kind,
            seed,
            duration,
            Sensors { clean, noise_scale },
            (
                plant.into(),
                plant_variation,
                cyclic_power,
                pilot_gain_scale,
                linear,
                no_jitter,
            ),
            &output,
        ),
        Command::Identify { options } => run_identify(&options.into_args()),
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
    (airframe, variation, cyclic_power, pilot_gain_scale, linear, no_jitter): (
        Airframe,
        Option<u64>,
        f64,
        f64,
        bool,
        bool,
    ),
    output: &Path,
) -> Result<(), CliError> {
    let args = simulate::SimulateArgs {
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
        linear,
        no_jitter,
    };
    let samples = simulate::simulate_with_pilot_gain(&args, pilot_gain_scale)?;
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

/// `rotorid identify`: the library's [`identify::identify`], printing as it goes.
fn run_identify(args: &IdentifyArgs) -> Result<(), CliError> {
    let mut terminal = Terminal::new()?;
    identify::identify(args, &mut terminal)?;
    Ok(())
}
