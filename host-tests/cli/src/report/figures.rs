//! The PNG figures of a run, in the manner of the paper's Figures 2–5, and the free-run figure.

use std::path::{Path, PathBuf};

use plotters::drawing::DrawingAreaErrorKind;
use plotters::prelude::*;
use rotorid::hover::{HoverSample, HoverState};

use crate::experiments::*;

const COLORS: [RGBColor; 6] = [
    BLACK,
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
];

/// Width of the legend beside each panel (px).
const LEGEND_WIDTH: u32 = 260;

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

/// What plotters reports when drawing on a PNG fails.
pub type DrawError =
    DrawingAreaErrorKind<<BitMapBackend<'static> as plotters::backend::DrawingBackend>::ErrorType>;

/// Why a figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FigureError {
    /// Plotters failed on the figure (drawing, or writing the PNG).
    #[error("{}: cannot draw the figure", path.display())]
    Draw {
        /// The figure's file.
        path: PathBuf,
        /// Plotters' reason.
        #[source]
        source: DrawError,
    },
}

fn plot_panels(path: &Path, title: &str, panels: &[Panel]) -> Result<(), FigureError> {
    let e = |source| FigureError::Draw {
        path: path.to_path_buf(),
        source,
    };
    let height = 260 * u32::try_from(panels.len()).unwrap_or(1) + 40;
    let root = BitMapBackend::new(path, (1400, height)).into_drawing_area();
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(e)?;
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
        // The legend beside the chart, never over the data.
        let (plot, legend) = area.split_horizontally(1400 - LEGEND_WIDTH);
        let mut chart = ChartBuilder::on(&plot)
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1.max(x0 + 1e-6), (y0 - pad)..(y1 + pad))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc(panel.ylabel.as_str())
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(e)?;
        for (k, s) in panel.series.iter().enumerate() {
            let color = COLORS[s.color % COLORS.len()];
            for segment in s.points.split(Option::is_none) {
                if segment.is_empty() {
                    continue;
                }
                let line =
                    LineSeries::new(segment.iter().flatten().copied(), color.stroke_width(2));
                chart.draw_series(line).map_err(e)?;
            }
            let y = 24 + 22 * i32::try_from(k).unwrap_or(0);
            legend
                .draw(&PathElement::new([(8, y), (36, y)], color.stroke_width(3)))
                .map_err(e)?;
            legend
                .draw(&Text::new(
                    s.name.as_str(),
                    (44, y - 8),
                    ("sans-serif", 15).into_font().color(&BLACK),
                ))
                .map_err(e)?;
        }
    }
    root.present().map_err(e)?;
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

/// Writes the figures into `dir`, each line one of the `shown` variants (by name, in that
/// order; the first variant when none is found), so that a panel holds a few lines:
///
/// * `fig2_velocity.png`, `fig3_rates.png`: actual against the one-step estimates of the
///   first shown variant (θ frozen), as the paper's Figures 2 and 3;
/// * `fig4_velocity_error.png`, `fig5_rate_error.png`: actual − estimate of each shown
///   variant, as Figures 4 and 5;
/// * `fig6_free_run.png`: the rates against the free-run estimates of each shown variant.
///
/// `span_s` limits the plots to the first seconds of the flight (all of it if `None`).
pub fn write_figures(
    dir: &Path,
    samples: &[HoverSample<f32>],
    all: &[VariantResult],
    shown: &[&str],
    span_s: Option<f64>,
) -> Result<Vec<PathBuf>, FigureError> {
    let mut variants: Vec<VariantResult> = shown
        .iter()
        .filter_map(|n| all.iter().find(|v| v.name == *n).cloned())
        .collect();
    if variants.is_empty() {
        variants.extend(all.first().cloned());
    }
    let variants = variants.as_slice();
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
    // The paper's axes named in the autopilot's terms (x east, y up, z south).
    let labels = [
        "east velocity v_x (m/s)",
        "up velocity v_y (m/s)",
        "south velocity v_z (m/s)",
        "pitch rate q (deg/s)",
        "yaw rate r (deg/s)",
        "roll rate p (deg/s)",
    ];
    let mut written = Vec::new();
    let figures: [(&str, &str, std::ops::Range<usize>, bool); 4] = [
        ("fig2_velocity.png", "Fig. 2 analogue: actual and estimated (one-step, θ frozen) velocities, verification data", 0..3, false),
        ("fig3_rates.png", "Fig. 3 analogue: actual and estimated (one-step, θ frozen) angular velocities, verification data", 3..6, false),
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
                    ylabel: labels[i].to_string(),
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
                ylabel: labels[i].to_string(),
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
