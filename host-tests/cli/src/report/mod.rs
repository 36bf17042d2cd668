//! Reports of an identification run: metrics as JSON, the Table 4 analogue, and PNG plots in
//! the manner of the paper's Figures 2–5 (actual against estimated, and the errors), plus a
//! free-run figure.

use serde::{Deserialize, Serialize};

use crate::experiments::{
    improvement_percent, VariantResult, PAPER_TABLE4_FUZZY, PAPER_TABLE4_IMPROVEMENT,
    PAPER_TABLE4_PLAIN, STATE_NAMES, STATE_UNITS,
};

/// The Table 4 analogue beside the paper's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Table4 {
    /// Fuzzy variant's frozen one-step mean absolute errors `[v_x v_y v_z]` m/s, `[q r p]` deg/s.
    pub fuzzy: [f64; 6],
    /// Plain variant's.
    pub plain: [f64; 6],
    /// `100 (plain − fuzzy)/plain` (%).
    pub improvement: [f64; 6],
    /// The paper's fuzzy column.
    pub paper_fuzzy: [f64; 6],
    /// The paper's plain column.
    pub paper_plain: [f64; 6],
    /// The paper's improvement column as printed (%).
    pub paper_improvement: [f64; 6],
}

impl Table4 {
    /// From the fuzzy and plain error arrays.
    pub fn new(fuzzy: [f64; 6], plain: [f64; 6]) -> Self {
        Self {
            fuzzy,
            plain,
            improvement: improvement_percent(&fuzzy, &plain),
            paper_fuzzy: PAPER_TABLE4_FUZZY,
            paper_plain: PAPER_TABLE4_PLAIN,
            paper_improvement: PAPER_TABLE4_IMPROVEMENT,
        }
    }
}

/// Everything `rotorid identify` measured (written as `metrics.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Metrics {
    /// Training logs.
    pub training_files: Vec<String>,
    /// Training samples in all.
    pub training_samples: usize,
    /// Verification log.
    pub verification_file: String,
    /// Verification samples.
    pub verification_samples: usize,
    /// Free-run window (s).
    pub window_s: f64,
    /// The gyro noise σ `[q r p]` (deg/s) the free runs' parameters were compensated for
    /// (`None`: not compensated).
    #[serde(default)]
    pub gyro_noise_deg_s: Option<[f32; 3]>,
    /// Which gyro noise the compensation removed: `damping` (the default) or `full`
    /// (`--gyro-compensation`).
    #[serde(default = "damping")]
    pub gyro_compensation: String,
    /// The velocity the free runs fed the models (`model` unless
    /// `--free-run-velocity measured`).
    #[serde(default)]
    pub free_run_velocity: crate::experiments::FreeRunVelocity,
    /// State names and units, in the order of every array.
    pub states: Vec<String>,
    /// Per variant.
    pub variants: Vec<VariantResult>,
    /// Table 4 analogue (first two variants).
    pub table4: Option<Table4>,
    /// f32 against f64 parameter agreement of the extended structures.
    #[serde(default)]
    pub precision: Vec<crate::precision::PrecisionResult>,
    /// The rate the logs were identified at (Hz).
    #[serde(default = "default_rate")]
    pub rate_hz: f64,
    /// How training and verification data were chosen.
    #[serde(default)]
    pub split: String,
    /// What the import did with each log (training logs, then the verification log).
    #[serde(default)]
    pub logs: Vec<LogSummary>,
    /// The decision: the model to fly, per axis, and what the logs could not show.
    #[serde(default)]
    pub verdict: Option<crate::verdict::Verdict>,
    /// The controls' delay applied to the training and verification data, and how each
    /// candidate scored when it was chosen from the data (`null`: none, as for CSV logs).
    #[serde(default)]
    pub control_delay: Option<crate::experiments::DelaySelection>,
    /// Body-axis stability and control derivatives of the training data, per operating
    /// region, with standard errors corrected for coloured residuals
    /// ([`crate::derivatives`]).
    #[serde(default)]
    pub derivatives: Option<crate::derivatives::Derivatives>,
}

fn default_rate() -> f64 {
    50.0
}

/// One log's import, for metrics.json: its format, each channel's native rate, the
/// segments used and what was cut.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LogSummary {
    /// The file.
    pub file: String,
    /// `ULog`, `DataFlash`, `Csv`, ….
    pub format: String,
    /// Native rate of each channel (Hz); absent for a CSV log taken as it is.
    pub native_rates: Option<crate::import::NativeRates>,
    /// The rate it was resampled at (Hz).
    pub rate_hz: f64,
    /// Seconds in its segments.
    pub duration_s: f64,
    /// Segments.
    pub segments: usize,
    /// Each cut: `(from, to)` log time (s; `null` for an open end) and why.
    pub cuts: Vec<(Option<f64>, Option<f64>, String)>,
    /// Where the ground time came from (`Autopilot`, `Data`), if it was looked for.
    pub in_air: Option<String>,
    /// The import's notes.
    pub notes: Vec<String>,
    /// The import's warnings.
    pub warnings: Vec<String>,
}

impl LogSummary {
    /// The summary of `imported`, read from `file`.
    pub fn of(file: &str, imported: &crate::import::Imported) -> Self {
        let finite = |x: f64| x.is_finite().then_some(x);
        Self {
            file: file.to_string(),
            format: format!("{:?}", imported.format),
            native_rates: imported.native_rates,
            rate_hz: imported.rate_hz,
            duration_s: imported.duration_s(),
            segments: imported.segments.len(),
            cuts: imported
                .cuts
                .iter()
                .map(|c| (finite(c.from_s), finite(c.to_s), c.reason.clone()))
                .collect(),
            in_air: imported.in_air.map(|s| format!("{s:?}")),
            notes: imported.notes.clone(),
            warnings: imported.warnings.clone(),
        }
    }
}

/// State labels `name (unit)`.
pub fn state_labels() -> Vec<String> {
    STATE_NAMES
        .iter()
        .zip(STATE_UNITS)
        .map(|(n, u)| format!("{n} ({u})"))
        .collect()
}

/// A per-variant summary table (plain text): hold baseline, frozen one-step from the measured
/// state and through the observer, adapting one-step, free run and its hold baseline.
pub fn format_variants(variants: &[VariantResult], window_s: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let labels = state_labels();
    for v in variants {
        let _ = writeln!(s, "{} — {}", v.name, v.description);
        let _ = writeln!(
            s,
            "  {:<12} {:>10} {:>10} {:>10} {:>10} {:>12} {:>12} {:>16}",
            "state",
            "hold",
            "one-step",
            "observed",
            "adapting",
            "free run",
            "hold (run)",
            "converged (ρ)"
        );
        for (i, label) in labels.iter().enumerate() {
            let t = &v.training;
            let _ = writeln!(
                s,
                "  {:<12} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>12.4} {:>12.4} {:>16}",
                label,
                v.hold_one_step[i],
                v.one_step[i],
                v.one_step_observed[i],
                v.one_step_adapting[i],
                v.free_run[i],
                v.hold_free_run[i],
                format!(
                    "{} ({:.3})",
                    if t.converged[i] { "yes" } else { "no" },
                    t.convergence_ratio[i]
                )
            );
        }
        let _ = writeln!(
            s,
            "  free run: {} windows of {window_s} s, {} left the sample limits",
            v.free_run_windows, v.free_run_diverged
        );
        let gain: Vec<String> = v.observer_gain.iter().map(|k| format!("{k:.1}")).collect();
        let _ = writeln!(
            s,
            "  observed: one step through the observer of gain K = {} (v_x v_y v_z q r p)",
            gain.join(", ")
        );
    }
    s
}

#[cfg(feature = "figures")]
mod figures;
#[cfg(not(feature = "figures"))]
mod no_figures;

#[cfg(feature = "figures")]
pub use figures::{write_figures, DrawError, FigureError};
#[cfg(not(feature = "figures"))]
pub use no_figures::{write_figures, FigureError};

/// [`Metrics::gyro_compensation`] of metrics written before it was recorded.
fn damping() -> String {
    "damping".to_string()
}
