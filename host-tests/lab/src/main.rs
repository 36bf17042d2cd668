//! `rotorid-lab`: the studies' command line. `identify` is `rotorid identify` with the full
//! catalogue (the product's variants and the ablations); `report` and `robustness-report`
//! write docs/results.md and docs/robustness.md from the metrics of such runs.
//!
//! ```text
//! rotorid-lab identify --train ident.csv --verify verify.csv --out hover --no-plots
//! rotorid-lab report --realistic hover/metrics.json --clean clean/metrics.json -o results.md
//! ```
//!
//! Flights come from `rotorid simulate` (the product's binary); scripts/results.sh and
//! scripts/robustness.sh run both.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use rotorid_cli::command_line::{IdentifyOptions, Plant};
use rotorid_cli::error_chain::Chain;
use rotorid_cli::identify;
use rotorid_cli::report::Metrics;
use rotorid_cli::terminal::Terminal;
use rotorid_lab::error::ReportError;
use rotorid_lab::flight_report::Condition;
use rotorid_lab::results::SecondPlant;
use rotorid_lab::robustness::PlantRuns;

#[derive(Parser)]
#[command(
    name = "rotorid-lab",
    version,
    about = "The studies behind rotorid's docs: identification with the ablations, and the documents' generators"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// `rotorid identify` with every variant of the studies: the product's and the ablations
    /// of the flight default (their tables, params-*.json and metrics). The same options.
    Identify {
        #[command(flatten)]
        options: IdentifyOptions,
    },
    /// `rotorid identify` with the product's variants and `flight selected 2 SE`, `1 SE` and
    /// `0.5 SE`, the term selections that ask a removal to beat the check blocks' noise (used
    /// by scripts/term-evidence.sh). The same options.
    IdentifyTerms {
        #[command(flatten)]
        options: IdentifyOptions,
    },
    /// Fit the rate models offline by batch least squares, with and without the lagged
    /// control and with each gyro-noise compensation, and score their free runs on a
    /// verification log (JSON; used by scripts/rate-orders.sh).
    RateOrders {
        /// Training log (CSV).
        #[arg(long)]
        train: PathBuf,
        /// Verification log (CSV).
        #[arg(long)]
        verify: PathBuf,
        /// Output JSON file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write docs/results.md from the metrics of a realistic and a clean run (used by
    /// scripts/results.sh).
    Report(ReportArgs),
    /// Write docs/robustness.md from the metrics of plant variations (used by
    /// scripts/robustness.sh).
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

/// The arguments of `rotorid-lab report`.
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
enum LabError {
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
    #[error(transparent)]
    Log(#[from] rotorid_cli::log::LogError),
    #[error(transparent)]
    Core(#[from] rotorid::Error),
    #[error("progress bar")]
    ProgressBar(#[from] rotorid_cli::terminal::TemplateError),
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

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, LabError> {
    let text = std::fs::read_to_string(path).map_err(|source| LabError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| LabError::ParseJson {
        path: path.to_path_buf(),
        source,
    })
}

fn write_text(path: &Path, text: String) -> Result<(), LabError> {
    std::fs::write(path, text).map_err(|source| LabError::Write {
        path: path.to_path_buf(),
        source,
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Identify { options } => run_identify(
            &options.into_args(),
            &rotorid_lab::ablations::full_catalogue(),
        ),
        Command::IdentifyTerms { options } => run_identify(
            &options.into_args(),
            &rotorid_lab::ablations::term_evidence_catalogue(),
        ),
        Command::RateOrders {
            train,
            verify,
            output,
        } => run_rate_orders(&train, &verify, &output),
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

/// `rotorid-lab identify` and `identify-terms`: the library's identification with a study's
/// catalogue, printing as it goes.
fn run_identify(
    args: &identify::IdentifyArgs,
    catalogue: &[rotorid_cli::experiments::Variant],
) -> Result<(), LabError> {
    let mut terminal = Terminal::new()?;
    identify::identify_with(args, catalogue, &mut terminal)?;
    Ok(())
}

/// `rotorid-lab rate-orders`.
fn run_rate_orders(train: &Path, verify: &Path, output: &Path) -> Result<(), LabError> {
    let read = |path: &Path| -> Result<_, LabError> {
        Ok(rotorid_sim::flights::to_hover_samples(
            &rotorid_cli::log::read_log(path)?,
        ))
    };
    let (training, verification) = (read(train)?, read(verify)?);
    let period_s = match (training.first(), training.last()) {
        (Some(a), Some(b)) if training.len() > 1 => {
            (b.time_us - a.time_us) as f64 * 1e-6 / (training.len() - 1) as f64
        }
        _ => 0.02,
    };
    let orders = rotorid_lab::rate_orders::rate_orders(&training, &verification, period_s)?;
    let text = serde_json::to_string_pretty(&orders).map_err(|source| LabError::ParseJson {
        path: output.to_path_buf(),
        source,
    })?;
    write_text(output, text)
}

fn run_robustness_report(runs: &[RunPaths], how: &str, output: &Path) -> Result<(), LabError> {
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
        .collect::<Result<Vec<_>, LabError>>()?;
    write_text(
        output,
        rotorid_lab::robustness::robustness_document(&runs, how),
    )
}

fn run_report(args: &ReportArgs) -> Result<(), LabError> {
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
        .collect::<Result<Vec<_>, LabError>>()?;
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
    let md = rotorid_lab::results::results_markdown(
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
