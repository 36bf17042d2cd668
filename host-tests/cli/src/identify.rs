//! `rotorid identify` as a library call: read the logs, split off the verification data,
//! evaluate every identifier variant of a catalogue (the product's, or a study's with
//! [`identify_with`]), give the verdict and the derivatives, and (optionally) write
//! metrics.json, params-*.json and the figures.
//!
//! The command-line tool and the Python package both call [`identify`]; what the tool prints
//! goes through a [`Progress`] (stderr notes, stdout text, the progress bar), so that a caller
//! without a terminal collects it instead, and the returned [`Outcome`] holds the metrics as
//! values ([`Outcome::metrics_json`] is metrics.json byte for byte).

use std::path::{Path, PathBuf};

use crate::experiments::{self, ModelParameters, TABLE4_VARIANTS};
use crate::import;
use crate::report::{self, Metrics, Table4};
use rotorid_sim::flights;

mod error;

pub use error::IdentifyError;
use error::{json_text, read_json, write_json};

/// What the free run's parameters are compensated for (`--gyro-noise`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GyroNoise {
    /// Estimated from the training logs.
    Auto,
    /// Not compensated.
    None,
    /// σ of `[q r p]` (deg/s).
    Given([f32; 3]),
}

/// The one-step observer's gain (`--observer-gain`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ObserverGain {
    /// Found on the training logs, per variant.
    Auto,
    /// K of `[v_x v_y v_z q r p]` (0 to 1).
    Given([f32; 6]),
}

/// The arguments of an identification (those of `rotorid identify`, resolved).
#[derive(Clone, Debug)]
pub struct IdentifyArgs {
    /// Training logs, learnt one after another.
    pub train: Vec<PathBuf>,
    /// Verification log (its longest segment); `None` holds out part of the training data.
    pub verify: Option<PathBuf>,
    /// Fraction held out for verification when `verify` is `None`.
    pub holdout: f64,
    /// Rate and time cuts of the import.
    pub options: import::ImportOptions,
    /// Print every variant's tables and every import note, not only the verdict.
    pub full: bool,
    /// Directory for metrics.json, params-*.json and the figures; `None` writes no file.
    pub out: Option<PathBuf>,
    /// Free-run window (s).
    pub window: f64,
    /// Plot only the first seconds of the verification flight.
    pub plot_span: Option<f64>,
    /// Do not write the PNG figures.
    pub no_plots: bool,
    /// A params-*.json to warm start the first variant from.
    pub warm_start: Option<PathBuf>,
    /// What the free run's parameters are compensated for.
    pub gyro_noise: GyroNoise,
    /// Which gyro noise the compensation removes.
    pub gyro_compensation: rotorid::hover::GyroCompensation,
    /// The velocity the free run feeds the models.
    pub free_run_velocity: experiments::FreeRunVelocity,
    /// The one-step observer's gain.
    pub observer_gain: ObserverGain,
    /// How much later than logged the controls act (s); `None`: chosen on the training data
    /// when every log is an autopilot's ([`experiments::select_delay`]), 0 for CSV logs.
    pub control_delay_s: Option<f64>,
    /// Whether `flight selected` also chooses the speed each model's rules are on
    /// ([`experiments::variants_with`]; `true` by default, `--no-premise-candidates`).
    pub premise_candidates: bool,
}

impl IdentifyArgs {
    /// The defaults of `rotorid identify` for these training logs, writing no file.
    pub fn new(train: Vec<PathBuf>) -> Self {
        Self {
            train,
            verify: None,
            holdout: 0.3,
            options: import::ImportOptions::default(),
            full: false,
            out: None,
            window: 2.0,
            plot_span: None,
            no_plots: false,
            warm_start: None,
            gyro_noise: GyroNoise::Auto,
            gyro_compensation: rotorid::hover::GyroCompensation::Damping,
            free_run_velocity: experiments::FreeRunVelocity::Model,
            observer_gain: ObserverGain::Auto,
            control_delay_s: None,
            premise_candidates: true,
        }
    }
}

/// Where an identification reports while it runs. Every method does nothing by default.
pub trait Progress {
    /// One line for the user beside the results (the tool's stderr: notes, warnings).
    fn note(&mut self, _line: &str) {}
    /// Result text (the tool's stdout: the verdict, the derivatives, `--full` tables).
    fn print(&mut self, _text: &str) {}
    /// Evaluation starts: `total` samples to go through.
    fn start(&mut self, _total: u64) {}
    /// The variant now evaluated.
    fn variant(&mut self, _name: &'static str) {}
    /// One sample done.
    fn tick(&mut self) {}
    /// Evaluation done.
    fn finish(&mut self) {}
}

/// A [`Progress`] that collects the notes and the printed text (for callers without a
/// terminal, such as the Python package).
#[derive(Clone, Debug, Default)]
pub struct Collect {
    /// Every note, in order.
    pub notes: Vec<String>,
    /// Everything printed, concatenated.
    pub text: String,
}

impl Progress for Collect {
    fn note(&mut self, line: &str) {
        self.notes.push(line.to_string());
    }
    fn print(&mut self, text: &str) {
        self.text.push_str(text);
    }
}

/// What an identification gives back.
#[derive(Debug)]
#[non_exhaustive]
pub struct Outcome {
    /// Everything metrics.json holds (the verdict, every variant, the derivatives).
    pub metrics: Metrics,
    /// The verification samples the scores were computed on.
    pub verification: Vec<rotorid::hover::HoverSample<f32>>,
    /// Figures written (0 without `out` or with `no_plots`).
    pub figures: usize,
}

impl Outcome {
    /// metrics.json's text, byte for byte what [`identify`] writes.
    ///
    /// # Errors
    /// [`IdentifyError::ToJson`] when a value cannot be encoded.
    pub fn metrics_json(&self) -> Result<String, IdentifyError> {
        json_text(Path::new("metrics.json"), &self.metrics)
    }
}

/// The warm-start parameters in a snapshot file (`snapshot-*.ridx`, the core's format: the C
/// interface's export): read into a fresh identifier of the first variant, whose kind, length,
/// CRC and values it must match.
fn warm_from_snapshot(
    path: &Path,
    first: Option<&experiments::Variant>,
    training: &[Vec<rotorid::hover::HoverSample<f32>>],
    period_us: u32,
) -> Result<Vec<ModelParameters>, IdentifyError> {
    let bytes = std::fs::read(path).map_err(|source| IdentifyError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let refused = |source| IdentifyError::Snapshot {
        path: path.to_path_buf(),
        source,
    };
    let Some((first, kind)) = first.and_then(|v| Some((v, v.kind?))) else {
        return Err(refused(rotorid::Error::Incompatible));
    };
    let mut id = (first.build)(training, period_us).map_err(refused)?;
    id.read_snapshot(kind, &bytes).map_err(refused)?;
    Ok(id.parameters())
}

/// Reads a log of any format (CSV, ULog, DataFlash, sdlog2) as `options` say.
fn read(path: &Path, options: &import::ImportOptions) -> Result<import::Imported, IdentifyError> {
    Ok(import::import_with(path, options)?)
}

/// The import's warnings, and its notes (`full`) or a one-line summary of them, as lines.
pub fn import_notes(
    path: &Path,
    imported: &import::Imported,
    used: &[&import::Segment],
    full: bool,
) -> Vec<String> {
    let file = path.display().to_string();
    let mut lines = Vec::new();
    if full || imported.notes.len() <= 2 {
        for n in &imported.notes {
            lines.push(format!("note: {n}"));
        }
    } else {
        lines.push(format!(
            "note: {file}: {} notes ({} cuts; --full lists them)",
            imported.notes.len(),
            imported.cuts.len()
        ));
    }
    for w in &imported.warnings {
        lines.push(format!("warning: {w}"));
    }
    let segments: Vec<&[rotorid_sim::plant::SensorSample]> =
        used.iter().map(|seg| seg.as_slice()).collect();
    if let Some(w) = crate::log::short_warning(&file, &segments) {
        lines.push(format!("warning: {w}"));
    }
    for seg in &segments {
        for w in crate::log::doubtful_data(&file, seg) {
            lines.push(format!("warning: {w}"));
        }
    }
    lines
}

fn report_import(
    progress: &mut dyn Progress,
    path: &Path,
    imported: &import::Imported,
    used: &[&import::Segment],
    full: bool,
) {
    for line in import_notes(path, imported, used, full) {
        progress.note(&line);
    }
}

/// Reads every log at one rate: each at the rate its channels support, then those faster
/// than the slowest again at that (a model is learnt at one sample period).
fn read_all(
    paths: &[&Path],
    options: &import::ImportOptions,
) -> Result<Vec<import::Imported>, IdentifyError> {
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

/// The controls' delay ([`experiments::select_delay`]): `--control-delay`'s, or chosen on the
/// training data when every log is an autopilot's (a CSV's sticks act at their time stamps,
/// as the simulators' do); applied to the training and the verification data, and said in a
/// note.
fn control_delay(
    args: &IdentifyArgs,
    imported: &[import::Imported],
    split: &mut crate::holdout::Split,
    rate_hz: f64,
    progress: &mut dyn Progress,
) -> Result<Option<experiments::DelaySelection>, IdentifyError> {
    let autopilot = imported
        .iter()
        .all(|im| im.format != import::LogFormat::Csv);
    let chosen = match args.control_delay_s {
        // A whole number of steps, as the chosen delays are.
        Some(given) => Some(experiments::DelaySelection {
            delay_s: (given * rate_hz).round() / rate_hz,
            scores: Vec::new(),
        }),
        None if autopilot => {
            let period = experiments::period_us(rate_hz);
            let chosen =
                experiments::select_delay(&split.training, period).map_err(IdentifyError::Delay)?;
            if chosen.is_none() {
                progress.note(
                    "note: too little training data to choose the controls' delay: taken as 0 (--control-delay sets it)",
                );
            }
            chosen
        }
        None => None,
    };
    let Some(d) = &chosen else {
        return Ok(None);
    };
    let steps = (d.delay_s * rate_hz).round() as usize;
    for log in &mut split.training {
        *log = experiments::delayed(log, steps);
    }
    split.verification = experiments::delayed(&split.verification, steps);
    let none = d.scores.first().and_then(|s| s.score);
    let best = d
        .scores
        .iter()
        .find(|s| s.delay_s == d.delay_s)
        .and_then(|s| s.score);
    progress.note(&match (d.scores.is_empty(), none, best) {
        (true, ..) => format!(
            "controls delayed by {:.0} ms (--control-delay, in whole {:.0} ms steps)",
            d.delay_s * 1e3,
            1e3 / rate_hz
        ),
        (false, Some(none), Some(best)) => format!(
            "controls delayed by {:.0} ms, chosen on the training data by the flight default's free run ({best:.2} of hold against {none:.2} with none; 0 to {:.0} ms tried; --control-delay sets it)",
            d.delay_s * 1e3,
            experiments::MAX_CONTROL_DELAY_S * 1e3
        ),
        (false, ..) => format!(
            "controls delayed by {:.0} ms, chosen on the training data by the flight default's free run (--control-delay sets it)",
            d.delay_s * 1e3
        ),
    });
    Ok(chosen)
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

/// Identifies hover models from the logs of `args` with the product's catalogue
/// ([`experiments::variants`]): what `rotorid identify` does.
///
/// # Errors
/// [`IdentifyError`]: bad arguments, a log that cannot be imported or split, a failed
/// evaluation, a file that cannot be written.
pub fn identify(
    args: &IdentifyArgs,
    progress: &mut dyn Progress,
) -> Result<Outcome, IdentifyError> {
    identify_with(
        args,
        &experiments::variants_with(args.premise_candidates),
        progress,
    )
}

/// [`identify`] with the variants given, in their order (a study's catalogue, such as
/// `rotorid-lab`'s with the ablations). The verdict picks among those of its candidates
/// (`verdict::CANDIDATES`) that `variants` holds; Table 4 reads the first two.
///
/// # Errors
/// As [`identify`].
pub fn identify_with(
    args: &IdentifyArgs,
    variants: &[experiments::Variant],
    progress: &mut dyn Progress,
) -> Result<Outcome, IdentifyError> {
    let window = args.window;
    if !(window.is_finite() && window > 0.0 && window <= 3600.0) {
        return Err(IdentifyError::Window(window));
    }
    if args.train.is_empty() {
        return Err(IdentifyError::NoLogs);
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
        report_import(progress, path, im, &used, args.full);
        for (k, seg) in im.segments.iter().enumerate() {
            if used.iter().any(|u| std::ptr::eq(*u, seg)) {
                labelled.push(crate::holdout::Labelled {
                    file: path.display().to_string(),
                    segment: k + 1,
                    samples: seg.clone(),
                });
            }
        }
    }
    let mut split = match (&args.verify, imported.last()) {
        (Some(v), Some(im)) => {
            let longest = im
                .longest()
                .ok_or_else(|| IdentifyError::NoSamples(v.to_path_buf()))?;
            report_import(progress, v, im, &[longest], args.full);
            if args.train.iter().any(|t| same_file(t, v)) {
                progress.note(&format!(
                    "warning: {} is also a training log: the scores measure how well the models fit it, not how they predict; leave out --verify to hold part of the data out",
                    v.display()
                ));
            }
            crate::holdout::Split {
                training: labelled.into_iter().map(|l| l.samples).collect(),
                verification: longest.clone(),
                how: format!("verified on {} (its longest segment)", v.display()),
            }
        }
        _ => crate::holdout::split(labelled, args.holdout, import::min_useful_samples(rate_hz))?,
    };
    let verify_name = args
        .verify
        .as_ref()
        .map_or_else(|| "held-out data".to_string(), |v| v.display().to_string());
    let control_delay = control_delay(args, &imported, &mut split, rate_hz, progress)?;
    if split.verification.len() < 2 {
        return Err(IdentifyError::TooFewSamples(PathBuf::from(&verify_name)));
    }
    let training: Vec<Vec<rotorid::hover::HoverSample<f32>>> = split
        .training
        .iter()
        .map(|s| flights::to_hover_samples(s))
        .collect();
    let verification = flights::to_hover_samples(&split.verification);
    let warm: Option<Vec<ModelParameters>> = match args.warm_start.as_deref() {
        None => None,
        Some(path) if path.extension().is_some_and(|e| e == "ridx") => Some(warm_from_snapshot(
            path,
            variants.first(),
            &training,
            experiments::period_us(rate_hz),
        )?),
        Some(path) => Some(read_json(path)?),
    };
    let out = args.out.as_deref();
    if let Some(out) = out {
        std::fs::create_dir_all(out).map_err(|source| IdentifyError::CreateDir {
            path: out.to_path_buf(),
            source,
        })?;
    }

    let gyro_noise = match args.gyro_noise {
        // RateNoise's third differences are noise only when the rates are sampled well above
        // the body dynamics (50 Hz for a helicopter); at a log's lower rate they are mostly
        // motion, and compensating for that would spoil the free run.
        GyroNoise::Auto if rate_hz >= import::resample::RATE_HZ => {
            experiments::gyro_noise_of(&training)
        }
        GyroNoise::Auto => {
            progress.note(&format!(
                "note: at {rate_hz} Hz the rates' differences are mostly motion, not gyro noise: the free runs are not compensated for it (give --gyro-noise with the gyro's data-sheet σ)"
            ));
            None
        }
        GyroNoise::None => None,
        GyroNoise::Given(sigma) => Some(sigma),
    };
    let n_train: usize = training.iter().map(Vec::len).sum();
    progress.note(&format!(
        "identifying at {rate_hz} Hz: {:.1} s of training data in {} segment(s), {:.1} s to verify; {}",
        n_train as f64 / rate_hz,
        training.len(),
        verification.len() as f64 / rate_hz,
        split.how
    ));
    if args.full {
        if let Some([q, r, p]) = gyro_noise {
            progress.note(&format!(
                "free runs compensated for gyro noise σ = {q:.3}, {r:.3}, {p:.3} deg/s (q, r, p)"
            ));
        }
    }
    if args.free_run_velocity == experiments::FreeRunVelocity::Measured {
        progress
            .note("free runs on the measured velocity: the rates run free, the velocities do not");
    }
    let total = (n_train + verification.len()) * variants.len();
    progress.start(total as u64);
    let mut results = Vec::new();
    for (i, v) in variants.iter().enumerate() {
        progress.variant(v.name);
        let warm = if i == 0 { warm.as_deref() } else { None };
        let mut tick = || progress.tick();
        let settings = experiments::EvaluationSettings {
            window_s: window,
            gyro_noise,
            gyro_compensation: args.gyro_compensation,
            velocity: args.free_run_velocity,
            observer_gain: match args.observer_gain {
                ObserverGain::Auto => None,
                ObserverGain::Given(gain) => Some(gain),
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
    progress.finish();

    let table4 = match (
        results.get(TABLE4_VARIANTS.0),
        results.get(TABLE4_VARIANTS.1),
    ) {
        (Some(f), Some(p)) => Some(Table4::new(f.one_step, p.one_step)),
        _ => None,
    };
    if args.full {
        progress.print(&format!(
            "Table 4 analogue: mean absolute one-step error over {verify_name} (θ frozen after training on {n_train} samples)\n\n"
        ));
        if let Some(t) = &table4 {
            progress.print(&experiments::format_table4(&t.fuzzy, &t.plain));
        }
        progress.print("\n");
        progress.print(&report::format_variants(&results, window));
    }

    if let Some(out) = out {
        for r in &results {
            let name = r.name.replace(' ', "-");
            write_json(&out.join(format!("params-{name}.json")), &r.parameters)?;
            if let Some(snapshot) = &r.snapshot {
                let path = out.join(format!("snapshot-{name}.ridx"));
                std::fs::write(&path, snapshot)
                    .map_err(|source| IdentifyError::Write { path, source })?;
            }
            if let Some(p) = &r.compensated_parameters {
                write_json(&out.join(format!("params-{name}-compensated.json")), p)?;
            }
        }
    }
    // f32 against f64 for the extended structures (issue 5): same logs, same settings.
    let precision =
        crate::precision::extended_f32_vs_f64(&training).map_err(IdentifyError::Precision)?;
    if args.full {
        for p in &precision {
            progress.print(&format!(
                "{}: f32 vs f64, {} of {} parameters well excited, relative difference max {:.2e}, median {:.2e}\n",
                p.variant, p.compared, p.parameters, p.max_relative, p.median_relative
            ));
        }
    }
    let segments: Vec<&[rotorid_sim::plant::SensorSample]> =
        split.training.iter().map(Vec::as_slice).collect();
    let derivatives = crate::derivatives::derivatives(&segments, rate_hz);
    let mut verdict = crate::verdict::verdict(
        &results,
        &split.training,
        &split.verification,
        derivatives.regions.iter().find(|r| r.name == "all"),
        rate_hz,
        args.free_run_velocity,
    );
    if let (Some(v), Some(d)) = (&mut verdict, &control_delay) {
        if d.delay_s > 0.0 {
            v.caveats.push(format!(
                "the controls act {:.0} ms after they are logged ({}): the models were learnt with them delayed so, and a model flown onboard must be fed them as late",
                d.delay_s * 1e3,
                if d.scores.is_empty() { "--control-delay" } else { "chosen on the training data" }
            ));
        }
    }
    match &verdict {
        Some(v) => progress.print(&crate::verdict::format_verdict(v, window)),
        None => progress.print(
            "No verdict: no candidate model could be scored against hold (each left the sample limits in a free-run window, or a state never moved); see metrics.json, or --full\n",
        ),
    }
    let text = crate::derivatives::format_derivatives(&derivatives);
    progress.print(&format!("{}\n", text.trim_end()));
    let metrics = Metrics {
        precision,
        training_files: args.train.iter().map(|p| p.display().to_string()).collect(),
        training_samples: n_train,
        verification_file: verify_name,
        verification_samples: verification.len(),
        window_s: window,
        gyro_noise_deg_s: gyro_noise,
        gyro_compensation: match args.gyro_compensation {
            rotorid::hover::GyroCompensation::Full => "full",
            _ => "damping",
        }
        .to_string(),
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
        control_delay,
    };
    let mut figures = 0;
    if let Some(out) = out {
        write_json(&out.join("metrics.json"), &metrics)?;
        if !args.no_plots {
            // The model to fly and the linear baseline; every variant with --full.
            let mut shown: Vec<&str> = metrics
                .verdict
                .as_ref()
                .map(|v| v.model.as_str())
                .into_iter()
                .chain([crate::verdict::BASELINE])
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
        progress.print(&format!(
            "Files: {}: metrics.json (every variant, the import's cuts and rates), params-*.json{}\n",
            out.display(),
            if figures > 0 {
                format!(", {figures} figures")
            } else {
                String::new()
            }
        ));
    }
    Ok(Outcome {
        metrics,
        verification,
        figures,
    })
}
