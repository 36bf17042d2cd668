//! Reports of an identification run: metrics as JSON, the Table 4 analogue, and PNG plots in
//! the manner of the paper's Figures 2–5 (actual against estimated, and the errors), plus a
//! free-run figure.

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use rotorid::hover::{HoverSample, HoverState};
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
    /// State names and units, in the order of every array.
    pub states: Vec<String>,
    /// Per variant.
    pub variants: Vec<VariantResult>,
    /// Table 4 analogue (first two variants).
    pub table4: Option<Table4>,
    /// f32 against f64 parameter agreement of the extended structures.
    #[serde(default)]
    pub precision: Vec<crate::precision::PrecisionResult>,
}

/// State labels `name (unit)`.
pub fn state_labels() -> Vec<String> {
    STATE_NAMES
        .iter()
        .zip(STATE_UNITS)
        .map(|(n, u)| format!("{n} ({u})"))
        .collect()
}

/// A per-variant summary table (plain text): hold baseline, frozen one-step, adapting
/// one-step, free run and its hold baseline.
pub fn format_variants(variants: &[VariantResult], window_s: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let labels = state_labels();
    for v in variants {
        let _ = writeln!(s, "{} — {}", v.name, v.description);
        let _ = writeln!(
            s,
            "  {:<12} {:>10} {:>10} {:>10} {:>12} {:>12} {:>16}",
            "state", "hold", "one-step", "adapting", "free run", "hold (run)", "converged (ρ)"
        );
        for (i, label) in labels.iter().enumerate() {
            let t = &v.training;
            let _ = writeln!(
                s,
                "  {:<12} {:>10.4} {:>10.4} {:>10.4} {:>12.4} {:>12.4} {:>16}",
                label,
                v.hold_one_step[i],
                v.one_step[i],
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
    }
    s
}

const COLORS: [RGBColor; 6] = [
    BLACK,
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
];

/// One line of a panel: name, colour index, points (gaps where `None`).
struct Series {
    name: String,
    color: usize,
    points: Vec<Option<(f64, f64)>>,
}

struct Panel {
    ylabel: String,
    series: Vec<Series>,
}

fn plot_panels(path: &Path, title: &str, panels: &[Panel]) -> Result<(), String> {
    let e = |x: &dyn std::fmt::Display| format!("{}: {x}", path.display());
    let height = 260 * u32::try_from(panels.len()).unwrap_or(1) + 40;
    let root = BitMapBackend::new(path, (1400, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(|x| e(&x))?;
    let areas = root.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        let pts = panel
            .series
            .iter()
            .flat_map(|s| s.points.iter().flatten().copied());
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for (x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        // A diverging model would flatten everything else: the y range is at most three times
        // the first series' range (the measurement, or the first variant's errors), centred on
        // it; lines beyond it are clipped.
        if let Some(first) = panel.series.first() {
            let (mut a0, mut a1) = (f64::MAX, f64::MIN);
            for (_, y) in first.points.iter().flatten() {
                a0 = a0.min(*y);
                a1 = a1.max(*y);
            }
            if a0 <= a1 {
                let (mid, half) = ((a0 + a1) / 2.0, ((a1 - a0) / 2.0).max(1e-6));
                y0 = y0.max(mid - 3.0 * half);
                y1 = y1.min(mid + 3.0 * half);
            }
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, -1.0, 1.0);
        }
        let pad = ((y1 - y0) * 0.05).max(1e-6);
        let mut chart = ChartBuilder::on(area)
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1.max(x0 + 1e-6), (y0 - pad)..(y1 + pad))
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc(panel.ylabel.as_str())
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|x| e(&x))?;
        for s in &panel.series {
            let color = COLORS[s.color % COLORS.len()];
            let mut first = true;
            for segment in s.points.split(Option::is_none) {
                if segment.is_empty() {
                    continue;
                }
                let line =
                    LineSeries::new(segment.iter().flatten().copied(), color.stroke_width(1));
                let drawn = chart.draw_series(line).map_err(|x| e(&x))?;
                if first {
                    drawn
                        .label(s.name.as_str())
                        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
                    first = false;
                }
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|x| e(&x))?;
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

fn seconds(samples: &[HoverSample<f32>], k: usize) -> f64 {
    let t0 = samples.first().map_or(0, |s| s.time_us);
    samples
        .get(k)
        .map_or(0.0, |s| (s.time_us.saturating_sub(t0)) as f64 * 1e-6)
}

fn actual(samples: &[HoverSample<f32>], i: usize) -> Series {
    Series {
        name: "actual".into(),
        color: 0,
        points: (0..samples.len())
            .map(|k| {
                Some((
                    seconds(samples, k),
                    f64::from(samples[k].state().to_array()[i]),
                ))
            })
            .collect(),
    }
}

/// Estimates aligned with samples: `est[k]` estimates sample k.
fn estimate(
    samples: &[HoverSample<f32>],
    name: &str,
    color: usize,
    est: &[Option<HoverState<f32>>],
    i: usize,
    error: bool,
) -> Series {
    let points = est
        .iter()
        .enumerate()
        .map(|(k, e)| {
            e.map(|e| {
                let x = f64::from(e.to_array()[i]);
                let y = if error {
                    f64::from(samples[k].state().to_array()[i]) - x
                } else {
                    x
                };
                (seconds(samples, k), y)
            })
        })
        .collect();
    Series {
        name: name.into(),
        color,
        points,
    }
}

/// Writes the figures into `dir`:
///
/// * `fig2_velocity.png`, `fig3_rates.png`: actual against the one-step estimates of the
///   first variant (θ frozen), as the paper's Figures 2 and 3;
/// * `fig4_velocity_error.png`, `fig5_rate_error.png`: actual − estimate of every variant,
///   as Figures 4 and 5;
/// * `fig6_free_run.png`: the rates against the free-run estimates of every variant.
///
/// `span_s` limits the plots to the first seconds of the flight (all of it if `None`).
pub fn write_figures(
    dir: &Path,
    samples: &[HoverSample<f32>],
    variants: &[VariantResult],
    span_s: Option<f64>,
) -> Result<Vec<PathBuf>, String> {
    let n = match span_s {
        Some(s) => samples
            .iter()
            .position(|x| x.time_us.saturating_sub(samples[0].time_us) as f64 * 1e-6 > s)
            .unwrap_or(samples.len()),
        None => samples.len(),
    };
    let samples = &samples[..n];
    // Align: one_step_predictions[k] estimates sample k+1.
    let aligned: Vec<Vec<Option<HoverState<f32>>>> = variants
        .iter()
        .map(|v| {
            let mut a = vec![None];
            a.extend(v.one_step_predictions.iter().copied());
            a.truncate(n);
            a
        })
        .collect();
    let labels = state_labels();
    let mut written = Vec::new();
    let figures: [(&str, &str, std::ops::Range<usize>, bool); 4] = [
        ("fig2_velocity.png", "Fig. 2 analogue: actual and estimated (one-step, θ frozen) velocities, verification flight", 0..3, false),
        ("fig3_rates.png", "Fig. 3 analogue: actual and estimated (one-step, θ frozen) angular velocities, verification flight", 3..6, false),
        ("fig4_velocity_error.png", "Fig. 4 analogue: one-step errors (actual − estimate) of the velocities", 0..3, true),
        ("fig5_rate_error.png", "Fig. 5 analogue: one-step errors (actual − estimate) of the angular velocities", 3..6, true),
    ];
    for (file, title, states, error) in figures {
        let panels: Vec<Panel> = states
            .map(|i| {
                let mut series = Vec::new();
                if !error {
                    series.push(actual(samples, i));
                    if let (Some(v), Some(a)) = (variants.first(), aligned.first()) {
                        series.push(estimate(samples, &v.name, 1, a, i, false));
                    }
                } else {
                    for (j, (v, a)) in variants.iter().zip(&aligned).enumerate() {
                        series.push(estimate(samples, &v.name, j + 1, a, i, true));
                    }
                }
                Panel {
                    ylabel: labels[i].clone(),
                    series,
                }
            })
            .collect();
        let path = dir.join(file);
        plot_panels(&path, title, &panels)?;
        written.push(path);
    }
    let panels: Vec<Panel> = (3..6)
        .map(|i| {
            let mut series = vec![actual(samples, i)];
            for (j, v) in variants.iter().enumerate() {
                let mut tr = v.free_run_trace.clone();
                tr.truncate(n);
                series.push(estimate(
                    samples,
                    &format!("{} (free run)", v.name),
                    j + 1,
                    &tr,
                    i,
                    false,
                ));
            }
            Panel {
                ylabel: labels[i].clone(),
                series,
            }
        })
        .collect();
    let path = dir.join("fig6_free_run.png");
    plot_panels(
        &path,
        "Free run: angular velocities of the frozen models fed their own predictions (restarted every window)",
        &panels,
    )?;
    written.push(path);
    Ok(written)
}

fn row(label: &str, cells: &[String]) -> String {
    format!("| {label} | {} |\n", cells.join(" | "))
}

fn fmt4(x: &[f64; 6]) -> Vec<String> {
    x.iter().map(|v| format!("{v:.4}")).collect()
}

/// The per-variant tables in markdown: hold baseline, one-step (frozen and adapting), free
/// run and its hold baseline, one column per state.
pub fn variants_markdown(m: &Metrics) -> String {
    let mut s = String::new();
    s += &format!("| variant, error | {} |\n", state_labels().join(" | "));
    s += &format!("|---|{}\n", "---:|".repeat(6));
    if let Some(v) = m.variants.first() {
        s += &row("hold `x(k+1) = x(k)`, one step", &fmt4(&v.hold_one_step));
        s += &row(
            &format!("hold window start, {} s", m.window_s),
            &fmt4(&v.hold_free_run),
        );
    }
    for v in &m.variants {
        s += &row(
            &format!("{}, one step (θ frozen)", v.name),
            &fmt4(&v.one_step),
        );
        s += &row(
            &format!("{}, one step (θ adapting)", v.name),
            &fmt4(&v.one_step_adapting),
        );
        s += &row(
            &format!("{}, one step on its training data", v.name),
            &fmt4(&v.training.one_step),
        );
        let rho: Vec<String> = v
            .training
            .convergence_ratio
            .iter()
            .zip(v.training.converged)
            .map(|(r, c)| format!("{r:.3}{}", if c { " (settled)" } else { "" }))
            .collect();
        s += &row(
            &format!("{}, convergence ρ = Σe²/ΣΔy² at end of training", v.name),
            &rho,
        );
        s += &row(
            &format!("{}, free run {} s", v.name, m.window_s),
            &fmt4(&v.free_run),
        );
    }
    s
}

/// Table 4 analogue beside the paper's, in markdown.
pub fn table4_markdown(t: &Table4) -> String {
    let mut s = String::new();
    s += "| state | fuzzy RLS | plain RLS | improvement | paper: fuzzy | paper: plain | paper: improvement |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|\n";
    for (i, label) in state_labels().iter().enumerate() {
        s += &format!(
            "| {} | {:.4} | {:.4} | {:+.1} % | {:.4} | {:.4} | {:.1} % |\n",
            label,
            t.fuzzy[i],
            t.plain[i],
            t.improvement[i],
            t.paper_fuzzy[i],
            t.paper_plain[i],
            t.paper_improvement[i]
        );
    }
    s
}

/// States (by label) where the fuzzy one-step error is below the plain one.
fn better_states(t: &Table4) -> (Vec<String>, Vec<String>) {
    let mut better = Vec::new();
    let mut worse = Vec::new();
    for (i, label) in state_labels().into_iter().enumerate() {
        if t.fuzzy[i] < t.plain[i] {
            better.push(label);
        } else {
            worse.push(label);
        }
    }
    (better, worse)
}

fn list(v: &[String]) -> String {
    if v.is_empty() {
        "none".to_string()
    } else {
        v.join(", ")
    }
}

/// The issue-5 targets, checked on the metrics: the extended structure's free-run error on
/// q, r, p against the paper's (same rule layout: fuzzy with fuzzy, plain with plain), its
/// one-step error against hold on every state, and f32 against f64.
pub fn extended_markdown(m: &Metrics) -> String {
    let find = |name: &str| m.variants.iter().find(|v| v.name == name);
    let mark = |ok: bool| if ok { "✅" } else { "❌" };
    let mut s = String::new();
    s += "Free run over the verification flight, extended against the paper's structure (ratio below 0.5 = at least halved):

";
    s += "| pair | q ratio | r ratio | p ratio |
|---|---:|---:|---:|
";
    for (ext, paper) in [
        ("extended fuzzy", "paper fuzzy"),
        ("extended plain", "paper plain"),
    ] {
        if let (Some(e), Some(p)) = (find(ext), find(paper)) {
            let cells: Vec<String> = (3..6)
                .map(|i| {
                    let r = e.free_run[i] / p.free_run[i];
                    format!("{r:.2} {}", mark(r <= 0.5))
                })
                .collect();
            s += &row(&format!("{ext} / {paper}"), &cells);
        }
    }
    s += "
One-step error (θ frozen) against the hold baseline on every state (ratio below 1 = beats hold):

";
    s += &format!(
        "| variant | {} |
|---|{}
",
        state_labels().join(" | "),
        "---:|".repeat(6)
    );
    for name in [
        "extended fuzzy",
        "extended plain",
        "paper fuzzy",
        "paper plain",
    ] {
        if let Some(v) = find(name) {
            let cells: Vec<String> = (0..6)
                .map(|i| {
                    let r = v.one_step[i] / v.hold_one_step[i];
                    format!("{r:.3} {}", mark(r < 1.0))
                })
                .collect();
            s += &row(name, &cells);
        }
    }
    if !m.precision.is_empty() {
        s += &format!(
            "
f32 against f64 after the identification flight (flight settings: U-D RLS, helicopter scaling), over the well-excited parameters (posterior variance below {:.0e} of the prior, magnitude above {:.0e} of the model's largest):

",
            crate::precision::WELL_EXCITED,
            crate::precision::NEGLIGIBLE
        );
        s += "| variant | parameters | compared | max relative difference | median | target 1e-3 |
|---|---:|---:|---:|---:|---|
";
        for p in &m.precision {
            s += &format!(
                "| {} | {} | {} | {:.2e} | {:.2e} | {} |
",
                p.variant,
                p.parameters,
                p.compared,
                p.max_relative,
                p.median_relative,
                mark(p.max_relative <= 1e-3)
            );
        }
    }
    s
}

/// docs/results.md from the realistic and the clean run. Every number comes from the metrics.
pub fn results_markdown(
    realistic: &Metrics,
    clean: &Metrics,
    envelope: Option<(&Metrics, &std::path::Path)>,
    elapsed_s: Option<f64>,
) -> Result<String, String> {
    let flight = match envelope {
        Some((m, dir)) => crate::flight_report::flight_markdown(realistic, m, dir)?,
        None => "(not run: `rotorid report` was given no `--envelope` metrics)\n".to_string(),
    };
    let t = realistic
        .table4
        .as_ref()
        .ok_or("realistic metrics have no Table 4")?;
    let tc = clean
        .table4
        .as_ref()
        .ok_or("clean metrics have no Table 4")?;
    let (better, worse) = better_states(t);
    let (better_c, worse_c) = better_states(tc);
    let fz = realistic.variants.first().ok_or("no variants")?;
    let pl = realistic.variants.get(1).ok_or("no plain variant")?;
    let mut template = include_str!("report_results.md").to_string();
    let subs: Vec<(&str, String)> = vec![
        ("{{FLIGHT}}", flight),
        ("{{TABLE4}}", table4_markdown(t)),
        ("{{TABLE4_CLEAN}}", table4_markdown(tc)),
        ("{{VARIANTS}}", variants_markdown(realistic)),
        ("{{EXTENDED}}", extended_markdown(realistic)),
        ("{{EXTENDED_CLEAN}}", extended_markdown(clean)),
        ("{{VARIANTS_CLEAN}}", variants_markdown(clean)),
        ("{{BETTER}}", list(&better)),
        ("{{WORSE}}", list(&worse)),
        ("{{BETTER_CLEAN}}", list(&better_c)),
        ("{{WORSE_CLEAN}}", list(&worse_c)),
        ("{{TRAIN_SAMPLES}}", realistic.training_samples.to_string()),
        (
            "{{VERIFY_SAMPLES}}",
            realistic.verification_samples.to_string(),
        ),
        ("{{TRAIN_FILES}}", realistic.training_files.join(", ")),
        ("{{VERIFY_FILE}}", realistic.verification_file.clone()),
        ("{{WINDOW}}", realistic.window_s.to_string()),
        ("{{WINDOWS}}", fz.free_run_windows.to_string()),
        ("{{DIVERGED_FUZZY}}", fz.free_run_diverged.to_string()),
        ("{{DIVERGED_PLAIN}}", pl.free_run_diverged.to_string()),
        (
            "{{DIVERGED_FUZZY_CLEAN}}",
            clean
                .variants
                .first()
                .map_or(0, |v| v.free_run_diverged)
                .to_string(),
        ),
        (
            "{{DIVERGED_PLAIN_CLEAN}}",
            clean
                .variants
                .get(1)
                .map_or(0, |v| v.free_run_diverged)
                .to_string(),
        ),
        (
            "{{ELAPSED}}",
            elapsed_s.map_or("(not measured)".to_string(), |e| format!("{e:.0} s")),
        ),
    ];
    for (k, v) in subs {
        template = template.replace(k, &v);
    }
    Ok(template)
}
