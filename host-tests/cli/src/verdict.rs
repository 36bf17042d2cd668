//! The decision `rotorid identify` prints by default: which model to fly and why, per axis in
//! the autopilot's frame against holding the measured state and against the linear baseline,
//! and what the log could not show.
//!
//! The candidates are the models a flight computer would run: the flight default
//! (`FlightIdentifier`), its one-rule counterpart (`flight plain`) and the linear baseline
//! (`extended plain`). Each is scored by its free run (the model fed its own predictions over
//! windows, restarted from the measured state) against the hold predictor (the window's first
//! state held): a model that cannot beat holding the state has learnt nothing usable for
//! prediction on that axis.

use serde::{Deserialize, Serialize};

use crate::derivatives::Region;
use crate::experiments::{FreeRunVelocity, TermMask, VariantResult, MODELS};
use rotorid_sim::plant::SensorSample;

/// The candidates, in order of preference when their scores tie.
pub const CANDIDATES: [&str; 4] = [
    "flight",
    "flight selected",
    "flight plain",
    "extended plain",
];

/// The linear baseline the models are compared with.
pub const BASELINE: &str = "extended plain";

/// The axes in the autopilot's frame, in the order of the metrics' state arrays
/// (`[v_x v_y v_z q r p]` in the paper's axes: x east, y up, z south; q pitch, r yaw, p
/// roll), with their units. Errors are magnitudes, so east/up/south errors are the
/// east/down/north velocities' errors.
pub const AXES: [(&str, &str); 6] = [
    ("east velocity", "m/s"),
    ("down velocity", "m/s"),
    ("north velocity", "m/s"),
    ("pitch rate q", "deg/s"),
    ("yaw rate r", "deg/s"),
    ("roll rate p", "deg/s"),
];

/// The order the verdict lists the axes in: north, east, down, roll, pitch, yaw.
pub const DISPLAY_ORDER: [usize; 6] = [2, 0, 1, 5, 3, 4];

/// The axes a free run scores, in [`DISPLAY_ORDER`]: every axis when the models run on their
/// own velocity, the rates only when they are fed the measured one (the velocities' free-run
/// errors are then zero by construction, not a prediction).
pub fn scored_axes(velocity: FreeRunVelocity) -> &'static [usize] {
    match velocity {
        FreeRunVelocity::Model => &DISPLAY_ORDER,
        FreeRunVelocity::Measured => &[5, 3, 4],
    }
}

/// Stick standard deviation (normalised units) from which a stick counts as clearly moved:
/// the built-in hold-out keeps such a stick's excitation in the training data
/// ([`crate::holdout`]), and where the body-axis derivatives could not be fitted at all, a
/// stick below it gets the "hardly moved" caveat (with the derivatives, their standard error
/// decides instead: a few doublets between hovers can determine a control power at a smaller
/// deviation).
pub const MIN_STICK_STD: f64 = 0.02;

/// Stick standard deviation (normalised units) below which a stick did not move at all: one
/// step of a 1000-step PWM range (1 µs of 1000 µs). With every stick below it there is no input
/// to identify a response to, and no model to fly. (Not [`MIN_STICK_STD`]: a multicopter's
/// rate-controller outputs in a position hold vary by about 1 % and still drive its motion.)
pub const STILL_STICK_STD: f64 = 0.001;

/// Fewest free-run windows of held-out data for a model to be recommended: one window is a
/// single draw of the run's error (the term selection asks as much of each block it checks
/// on, [`MIN_WINDOWS_PER_BLOCK`](crate::experiments::MIN_WINDOWS_PER_BLOCK)).
pub const MIN_VERIFICATION_WINDOWS: usize = crate::experiments::MIN_WINDOWS_PER_BLOCK;

/// Fewest training samples for which the verdict does not warn (60 s at 50 Hz).
pub const MIN_TRAINING_SAMPLES: usize = 3000;

/// Forward-speed centres of the flight default's rules (m/s) and their spread: a rule has
/// fired when enough samples lie within one spread of its centre.
const RULE_CENTRES_MPS: [f64; 3] = [0.0, 5.0, 10.0];
const RULE_SPREAD_MPS: f64 = 2.5;
/// Flight time within a rule's spread for it to count as learnt (s): in seconds, not samples,
/// so that a 10 Hz log is held to the same two seconds of flight as a 50 Hz one.
const MIN_RULE_S: f64 = 2.0;

/// Horizontal-speed bands of the operating regions the verification is compared on (m/s):
/// near hover below 3 (the body-axis derivatives' hover region, and about where a rotor's
/// translational lift sets in), transition up to 7, forward flight beyond.
const HORIZONTAL_BANDS_MPS: [f64; 2] = [3.0, 7.0];
/// Vertical speed beyond which a region is a climb or a descent (m/s): about a third of a
/// miniature helicopter's hover induced velocity `√(T/2ρA)` (≈ 4 m/s for the X-Cell's 8 kg on
/// a 1.55 m rotor), beyond which the rotor's inflow, hence its thrust per collective and its
/// torque, differ from hover's, and a descent nears the rotor's own wake.
const VERTICAL_BAND_MPS: f64 = 1.5;
/// Share of the verification data an operating region must hold to be named.
const MIN_REGION_SHARE: f64 = 0.05;

/// The operating region of a sample: (horizontal band 0..=2, vertical band 0 descent, 1
/// level, 2 climb).
fn region_of(s: &SensorSample) -> (usize, usize) {
    let horizontal = s.v_north.hypot(s.v_east);
    let up = -s.v_down;
    let h = HORIZONTAL_BANDS_MPS
        .iter()
        .filter(|&&b| horizontal >= b)
        .count();
    let v = if up < -VERTICAL_BAND_MPS {
        0
    } else if up > VERTICAL_BAND_MPS {
        2
    } else {
        1
    };
    (h, v)
}

/// Seconds in each operating region ([`region_of`]) of `samples` at `rate_hz`.
fn region_seconds<'a>(
    samples: impl Iterator<Item = &'a SensorSample>,
    rate_hz: f64,
) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for s in samples {
        let (h, v) = region_of(s);
        out[h][v] += 1.0 / rate_hz;
    }
    out
}

/// The operating regions the verification data fly in (at least [`MIN_REGION_SHARE`] of
/// them and [`MIN_RULE_S`]) that the training data hardly flew (under [`MIN_RULE_S`]): there
/// every model extrapolates, whatever its rules, so a free run worse than hold may say more
/// about the training flight than about the model. Regions of horizontal speed
/// ([`HORIZONTAL_BANDS_MPS`]) and vertical speed ([`VERTICAL_BAND_MPS`]), together: a
/// helicopter that climbed only in forward flight has not shown how it climbs in hover.
/// `None` when every region the verification flies was trained on.
fn regime_caveat(
    training: &[Vec<SensorSample>],
    verification: &[SensorSample],
    rate_hz: f64,
) -> Option<String> {
    let trained = region_seconds(training.iter().flatten(), rate_hz);
    let verified = region_seconds(verification.iter(), rate_hz);
    let total: f64 = verified.iter().flatten().sum();
    let horizontal = [
        "under 3 m/s horizontally",
        "at 3–7 m/s horizontally",
        "above 7 m/s horizontally",
    ];
    let vertical = [
        "descent faster than 1.5 m/s",
        "level flight (within ±1.5 m/s vertically)",
        "climb faster than 1.5 m/s",
    ];
    let mut unseen = Vec::new();
    for h in 0..3 {
        for v in 0..3 {
            let held = verified[h][v];
            if held >= MIN_RULE_S && held >= MIN_REGION_SHARE * total && trained[h][v] < MIN_RULE_S
            {
                unseen.push(format!(
                    "{} {}, {held:.0} s verified and {:.0} s trained",
                    vertical[v], horizontal[h], trained[h][v]
                ));
            }
        }
    }
    (!unseen.is_empty()).then(|| {
        format!(
            "the verification data fly where the training data hardly did (every model extrapolates there, and the axes worse than hold may come from it; fly those conditions in the training data too): {}",
            unseen.join("; ")
        )
    })
}

/// One axis of the chosen model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisVerdict {
    /// Axis in the autopilot's frame (`"north velocity"`, `"roll rate p"`, …).
    pub axis: String,
    /// Unit of the errors.
    pub unit: String,
    /// The chosen model's free-run mean absolute error.
    pub free_run: f64,
    /// Holding the window's first state.
    pub hold: f64,
    /// The linear baseline's free run.
    pub baseline: f64,
    /// `free_run / hold` (below 1: better than hold).
    pub vs_hold: f64,
    /// `free_run / baseline`.
    pub vs_baseline: f64,
}

/// The decision.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// The model to fly (a variant name), or the closest candidate when [`fly`](Self::fly) is
    /// false.
    pub model: String,
    /// Whether the log identifies a model to fly: the chosen model beats holding the measured
    /// state overall, on at least [`MIN_VERIFICATION_WINDOWS`] held-out windows, with at least
    /// one stick moved ([`STILL_STICK_STD`]) in the training data. `why` says which failed.
    #[serde(default)]
    pub fly: bool,
    /// Why, in a sentence.
    pub why: String,
    /// Per axis, north, east, down, roll, pitch, yaw.
    pub axes: Vec<AxisVerdict>,
    /// Each candidate's score: the geometric mean over the axes of free run / hold.
    pub scores: Vec<(String, f64)>,
    /// What the log could not show, and why.
    pub caveats: Vec<String>,
    /// The flight default's optional terms that the term selection switched off (`"r: κ"`,
    /// …), and the models it left with one rule (`"r: rules"`; see
    /// [`select_terms`](crate::experiments::select_terms)): the candidate `flight
    /// selected`, whether or not it is the model chosen.
    #[serde(default)]
    pub terms_off: Vec<String>,
    /// Whether the training data were long enough for the term selection to check
    /// candidates on ([`selects_from`](crate::experiments::selects_from)); when false,
    /// `flight selected` keeps every term because nothing could be checked, not because the
    /// data support them all.
    #[serde(default)]
    pub terms_checked: bool,
    /// The rates (`"q"`, `"r"`, `"p"`) whose parameters `flight selected` flies compensated
    /// fully for the gyro noise (the second-order term's too), chosen on the same check
    /// blocks as its terms (or asked for with `--gyro-compensation full`); the others get the
    /// damping term's compensation.
    #[serde(default)]
    pub full_compensation: Vec<String>,
}

/// Geometric mean of free run / hold over the `scored` axes; `None` if any is not finite or
/// the model left the sample limits in any window.
fn score(v: &VariantResult, scored: &[usize]) -> Option<f64> {
    if v.free_run_diverged > 0 || scored.is_empty() {
        return None;
    }
    let mut log_sum = 0.0;
    for &i in scored {
        // A state that never moved (held exactly) is predicted exactly by any model that
        // keeps it: even.
        let r = if v.free_run[i] == 0.0 && v.hold_free_run[i] == 0.0 {
            1.0
        } else {
            v.free_run[i] / v.hold_free_run[i]
        };
        if !(r.is_finite() && r > 0.0) {
            return None;
        }
        log_sum += r.ln();
    }
    Some((log_sum / scored.len() as f64).exp())
}

/// The verdict on `results` (every variant evaluated on `verification`, their free runs fed
/// `velocity`), with caveats from the training and the verification data, the training
/// data's body-axis `derivatives` (their `all` region) and the import (`warnings`, printed
/// already, counted here).
pub fn verdict(
    results: &[VariantResult],
    training: &[Vec<SensorSample>],
    verification: &[SensorSample],
    derivatives: Option<&Region>,
    rate_hz: f64,
    velocity: FreeRunVelocity,
) -> Option<Verdict> {
    let find = |name: &str| results.iter().find(|v| v.name == name);
    let baseline = find(BASELINE)?;
    let scored = scored_axes(velocity);
    let n_axes = scored.len();
    let scores: Vec<(String, f64)> = CANDIDATES
        .iter()
        .filter_map(|n| Some((n.to_string(), score(find(n)?, scored)?)))
        .collect();
    let (model, best) = scores
        .iter()
        .fold(None::<(&str, f64)>, |acc, (n, s)| match acc {
            Some((_, b)) if b <= *s * 1.02 => acc,
            _ => Some((n.as_str(), *s)),
        })?;
    let chosen = find(model)?;
    let axes: Vec<AxisVerdict> = scored
        .iter()
        .map(|&i| AxisVerdict {
            axis: AXES[i].0.to_string(),
            unit: AXES[i].1.to_string(),
            free_run: chosen.free_run[i],
            hold: chosen.hold_free_run[i],
            baseline: baseline.free_run[i],
            vs_hold: chosen.free_run[i] / chosen.hold_free_run[i],
            vs_baseline: chosen.free_run[i] / baseline.free_run[i],
        })
        .collect();
    let beats_hold = axes.iter().filter(|a| a.vs_hold < 1.0).count();
    let beats_baseline = axes.iter().filter(|a| a.vs_baseline < 1.0).count();
    let stds = stick_stds(training.iter().flatten());
    let why_not = no_model(best, &stds, chosen.free_run_windows);
    let fly = why_not.is_none();
    let why = match why_not {
        Some(NoModel::NoneBeatsHold) => format!(
            "no model beats holding the measured state overall (the best, {model}, is {best:.2} of hold, geometric mean over the axes): this log does not identify a model to fly; it beats hold on {beats_hold} of {n_axes} axes"
        ),
        Some(NoModel::NoStickMoved) => format!(
            "no stick moved in the training data (every σ below {} % of travel): the log shows drift, not the response to the controls, so it identifies no model to fly (the closest, {model}, is {best:.2} of hold)",
            STILL_STICK_STD * 100.0
        ),
        Some(NoModel::TooFewWindows(windows)) => format!(
            "the held-out part holds {windows} free-run window(s), fewer than {MIN_VERIFICATION_WINDOWS}: one window is a single draw of the error, too little to tell a model from holding the state (the closest, {model}, is {best:.2} of hold); fly longer or give --verify"
        ),
        None => format!(
            "the lowest free-run error relative to holding the measured state ({best:.2} of hold, geometric mean over the axes); it beats hold on {beats_hold} of {n_axes} axes and the linear baseline on {beats_baseline} of {n_axes}"
        ),
    };
    let mut caveats = Vec::new();
    if velocity == FreeRunVelocity::Measured {
        caveats.push(
            "the free runs were fed the measured velocity (--free-run-velocity measured): only the rates are scored, and a model flown on its own velocity may do worse".to_string(),
        );
    }
    // One line for every axis worse than hold: the verdict must fit a screen.
    let worse: Vec<String> = axes
        .iter()
        .filter(|a| a.vs_hold >= 1.0)
        .map(|a| format!("{} ({:.2}×)", a.axis, a.vs_hold))
        .collect();
    if !worse.is_empty() {
        let (these, models) = if worse.len() == 1 {
            ("this axis's", "model")
        } else {
            ("these axes'", "models")
        };
        caveats.push(format!(
            "the free run is worse than holding the measured value on {}: do not use {these} {models} to predict beyond one step",
            worse.join(", ")
        ));
    }
    if model != CANDIDATES[0] {
        if let Some(default) = find(CANDIDATES[0]) {
            let worse: Vec<String> = scored
                .iter()
                .filter(|&&i| default.free_run[i] >= default.hold_free_run[i])
                .map(|&i| {
                    format!(
                        "{} ({:.2}×)",
                        AXES[i].0,
                        default.free_run[i] / default.hold_free_run[i]
                    )
                })
                .collect();
            if !worse.is_empty() {
                caveats.push(format!(
                    "the flight default (FlightIdentifier) is worse than hold on {}",
                    worse.join(", ")
                ));
            }
        }
    }
    caveats.extend(regime_caveat(training, verification, rate_hz));
    caveats.extend(observer_caveat(
        &chosen.observer_gain,
        &chosen.one_step_observed,
        &chosen.one_step_unit_gain,
    ));
    caveats.extend(stick_caveats(&stds, derivatives));
    if model == "flight" || model == "flight selected" {
        caveats.extend(rule_caveats(training, rate_hz));
    }
    if rate_hz < 50.0 {
        caveats.push(format!(
            "identified at {rate_hz} Hz, the rate the log's slowest channel supports: dynamics faster than about {:.1} Hz are not resolved and the one-step scores are per {:.0} ms step; log faster (see the warning)",
            rate_hz / 4.0,
            1000.0 / rate_hz
        ));
    }
    let n: usize = training.iter().map(Vec::len).sum();
    let terms_checked = crate::experiments::selects_from(n, rate_hz);
    let min = (MIN_TRAINING_SAMPLES as f64 * rate_hz / 50.0) as usize;
    if n < min {
        let selection = if terms_checked {
            ""
        } else {
            "; too little to choose the flight default's terms from the data (`flight selected` keeps every term)"
        };
        caveats.push(format!(
            "only {:.0} s of training data: a minute or more of excited flight identifies the models reliably{selection}",
            n as f64 / rate_hz
        ));
    }
    // The terms the flight default's selection switched off, whichever model is chosen: what
    // the training data did not support.
    let terms_off = find("flight selected")
        .map(|v| TermMask::of_parameters(&v.parameters).describe())
        .unwrap_or_default();
    let full_compensation: Vec<String> = find("flight selected")
        .map(|v| {
            // The rate models, in `full_compensation`'s order.
            MODELS[1..]
                .iter()
                .zip(v.full_compensation)
                .filter(|(_, full)| *full)
                .map(|(axis, _)| axis.to_string())
                .collect()
        })
        .unwrap_or_default();
    let why = if model == "flight selected" {
        let off = if terms_off.is_empty() {
            "none".to_string()
        } else {
            terms_off.join(", ")
        };
        let full = if full_compensation.is_empty() {
            String::new()
        } else {
            format!(
                "; {} flown with the gyro noise compensated fully (the second-order term's too: where it predicted the held-out blocks better, or as --gyro-compensation asked)",
                full_compensation.join(", ")
            )
        };
        // The premise candidates may have moved some model's rules to another speed.
        let (moved, legend) = if terms_off.iter().any(|t| t.contains(": rules on the ")) {
            (
                ", or its rules scheduled on another speed where the data predict better so",
                "; `rules on the …`: its three rules are on that speed",
            )
        } else {
            ("", "")
        };
        format!("{why}; the flight default's rules and terms that the training data did not support are switched off{moved} ({off}; `rules`: that model has one rule, not scheduled on the speed{legend}){full}")
    } else {
        why
    };
    Some(Verdict {
        model: model.to_string(),
        fly,
        why,
        terms_off,
        terms_checked,
        full_compensation,
        axes,
        scores,
        caveats,
    })
}

/// Why a log identifies no model to fly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NoModel {
    /// The best candidate's free run is no better than holding the measured state.
    NoneBeatsHold,
    /// Every stick's σ over the training data is below [`STILL_STICK_STD`]: with no control
    /// moved the log shows drift and noise, not the response to a control, and a model that
    /// beats hold there predicts nothing a controller could use.
    NoStickMoved,
    /// Fewer than [`MIN_VERIFICATION_WINDOWS`] held-out windows (how many there were).
    TooFewWindows(usize),
}

/// Whether the best candidate (score `best`, free run / hold) is a model to fly, given the
/// sticks' σ over the training data (`stds`, empty when unknown) and the held-out windows.
fn no_model(best: f64, stds: &[f64], windows: usize) -> Option<NoModel> {
    if best >= 1.0 {
        Some(NoModel::NoneBeatsHold)
    } else if !stds.is_empty() && stds.iter().all(|&s| s < STILL_STICK_STD) {
        Some(NoModel::NoStickMoved)
    } else if windows < MIN_VERIFICATION_WINDOWS {
        Some(NoModel::TooFewWindows(windows))
    } else {
        None
    }
}

/// The axes on which the chosen model's one-step observer, its gain `K` searched on the
/// training logs, predicts the held-out data worse than from the measured state (`K` = 1):
/// a gain that does not carry over from the training data (`gain`, `observed` and
/// `unit_gain` per state in the metrics' order).
fn observer_caveat(gain: &[f32; 6], observed: &[f64; 6], unit_gain: &[f64; 6]) -> Option<String> {
    let worse: Vec<String> = DISPLAY_ORDER
        .iter()
        .filter(|&&i| gain[i] != 1.0 && observed[i] > unit_gain[i])
        .map(|&i| {
            format!(
                "{} (K = {}: {:.3} against {:.3} {})",
                AXES[i].0, gain[i], observed[i], unit_gain[i], AXES[i].1
            )
        })
        .collect();
    (!worse.is_empty()).then(|| {
        format!(
            "the one-step observer's gain, searched on the training data, predicts the held-out data worse than the measured state (K = 1) on {}: use K = 1 there",
            worse.join(", ")
        )
    })
}

/// The sticks as the verdict and the hold-out name them, in the order of [`stick_stds`].
pub(crate) const STICK_NAMES: [&str; 4] = [
    "collective",
    "pedal",
    "longitudinal cyclic",
    "lateral cyclic",
];

/// Standard deviation of each stick over `samples` (collective, pedal, longitudinal,
/// lateral; normalised units; two passes: the mean, then the deviations); empty with fewer
/// than two samples.
pub(crate) fn stick_stds<'a>(samples: impl Iterator<Item = &'a SensorSample> + Clone) -> Vec<f64> {
    let value = |s: &SensorSample, k: usize| match k {
        0 => s.sticks.col,
        1 => s.sticks.ped,
        2 => s.sticks.lon,
        _ => s.sticks.lat,
    };
    let count = samples.clone().count();
    if count < 2 {
        return Vec::new();
    }
    let n = count as f64;
    (0..4)
        .map(|k| {
            let mean = samples.clone().map(|s| value(s, k)).sum::<f64>() / n;
            let var = samples
                .clone()
                .map(|s| (value(s, k) - mean).powi(2))
                .sum::<f64>()
                / n;
            var.sqrt()
        })
        .collect()
}

/// The sticks whose control derivative the training data do not determine. With the
/// body-axis derivatives of the training data (`fitted`, their `all` region), the
/// derivative's own standard error decides (`|value| ≥ 2 SE`, `Derivative::determined`):
/// a stick's deviation alone (`stds`, from [`stick_stds`]) understates a few doublets
/// between long hovers, and the information grows with the samples too. Where the
/// derivative was not fitted at all (too few samples, a failed fit), a deviation below
/// [`MIN_STICK_STD`].
fn stick_caveats(stds: &[f64], fitted: Option<&Region>) -> Vec<String> {
    let derivatives = [
        ("vertical (Z_col) and yaw-torque terms", "Z_col"),
        ("yaw control power (N_ped)", "N_ped"),
        ("pitch control power (M_lon)", "M_lon"),
        ("roll control power (L_lat)", "L_lat"),
    ];
    STICK_NAMES
        .iter()
        .zip(derivatives)
        .zip(stds)
        .filter_map(|((name, (what, symbol)), &std)| {
            let moved = format!("σ = {:.1} % of travel", std * 100.0);
            let derivative = fitted
                .and_then(|r| r.derivative(symbol))
                .filter(|d| d.value.is_some());
            match derivative {
                Some(d) if d.determined => None,
                Some(d) => Some(format!(
                    "{what} not determined by the log ({symbol} = {:.3} ± {:.3} {}, within two standard errors of zero; the {name} moved {moved}): fly a doublet or sweep on it",
                    d.value.unwrap_or(f64::NAN),
                    d.se.unwrap_or(f64::NAN),
                    d.unit
                )),
                None if std < MIN_STICK_STD => Some(format!(
                    "the {name} was hardly moved ({moved}): {what} not determined; fly a doublet or sweep on it"
                )),
                None => None,
            }
        })
        .collect()
}

/// The flight default's rules that the training data never reached: its rate models' on the
/// forward speed, its translational model's on the horizontal speed in any direction.
fn rule_caveats(training: &[Vec<SensorSample>], rate_hz: f64) -> Vec<String> {
    let min_samples = (MIN_RULE_S * rate_hz).ceil() as usize;
    let unlearnt = |speed: &dyn Fn(&SensorSample) -> f64| -> Vec<String> {
        RULE_CENTRES_MPS
            .iter()
            .filter(|c| {
                training
                    .iter()
                    .flatten()
                    .filter(|s| (speed(s) - **c).abs() < RULE_SPREAD_MPS)
                    .count()
                    < min_samples
            })
            .map(|c| format!("{c:.0}"))
            .collect()
    };
    let forward = unlearnt(&|s| s.v_north * s.yaw.cos() + s.v_east * s.yaw.sin());
    let horizontal = unlearnt(&|s| s.v_north.hypot(s.v_east));
    let speeds = |unlearnt: &[String]| match unlearnt {
        [] => None,
        [one] => Some((format!("rule at {one} m/s"), "was")),
        [first @ .., last] => Some((
            format!("rules at {} and {last} m/s", first.join(", ")),
            "were",
        )),
    };
    let prior = format!(
        "hardly reached (under {MIN_RULE_S} s of flight within {RULE_SPREAD_MPS} m/s): its models there are the prior, not the log's"
    );
    if forward == horizontal {
        return speeds(&forward)
            .map(|(rules, were)| {
                format!("the flight default's {rules} (the rates' forward speed, the velocity's horizontal speed) {were} {prior}")
            })
            .into_iter()
            .collect();
    }
    // One line, as the verdict must fit a screen.
    let parts: Vec<(String, &str)> = [
        speeds(&forward)
            .map(|(rules, were)| (format!("forward-speed {rules} (its rate models)"), were)),
        speeds(&horizontal).map(|(rules, were)| {
            (
                format!("horizontal-speed {rules} (its velocity model)"),
                were,
            )
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    let were = match parts.as_slice() {
        [] => return Vec::new(),
        [(_, were)] => *were,
        _ => "were",
    };
    let rules: Vec<&str> = parts.iter().map(|(r, _)| r.as_str()).collect();
    vec![format!(
        "the flight default's {} {were} {prior}",
        rules.join(" and its ")
    )]
}

/// The verdict as text (at most about 20 lines).
pub fn format_verdict(v: &Verdict, window_s: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    if v.fly {
        let _ = writeln!(s, "Model to fly: {}", v.model);
    } else {
        let _ = writeln!(s, "No model to fly from this log (closest: {})", v.model);
    }
    let _ = writeln!(s, "  why: {}", v.why);
    let _ = writeln!(
        s,
        "  {:<28} {:>15} {:>9} {:>9} {:>8} {:>9}",
        format!("{window_s} s free run, mean |error|"),
        v.model,
        "hold",
        "linear",
        "vs hold",
        "vs linear"
    );
    for a in &v.axes {
        let _ = writeln!(
            s,
            "  {:<28} {:>15.3} {:>9.3} {:>9.3} {:>6.0} % {:>7.0} %",
            format!("{} ({})", a.axis, a.unit),
            a.free_run,
            a.hold,
            a.baseline,
            100.0 * (a.vs_hold - 1.0),
            100.0 * (a.vs_baseline - 1.0)
        );
    }
    let others: Vec<String> = v
        .scores
        .iter()
        .map(|(n, x)| format!("{n} {x:.2}"))
        .collect();
    let _ = writeln!(
        s,
        "  free run / hold, geometric mean (lower is better): {}",
        others.join(", ")
    );
    if !v.terms_off.is_empty() && v.model != "flight selected" {
        let _ = writeln!(
            s,
            "  rules and terms the training data did not support (flight selected): {}",
            v.terms_off.join(", ")
        );
    }
    if !v.caveats.is_empty() {
        let _ = writeln!(s, "What the log could not show:");
        for c in &v.caveats {
            let _ = writeln!(s, "  - {c}");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{
        no_model, observer_caveat, regime_caveat, rule_caveats, stick_caveats, NoModel,
        MIN_VERIFICATION_WINDOWS, STILL_STICK_STD,
    };
    use crate::derivatives::{AxisFit, Derivative, Region};
    use rotorid_sim::plant::SensorSample;

    /// `seconds` of flight at 10 Hz with the given north and east speeds (m/s), heading north.
    fn flight(seconds: usize, speeds: impl Fn(f64) -> (f64, f64)) -> Vec<SensorSample> {
        (0..seconds * 10)
            .map(|k| {
                let t = k as f64 / 10.0;
                let (v_north, v_east) = speeds(t / seconds as f64);
                SensorSample {
                    t,
                    v_north,
                    v_east,
                    ..SensorSample::default()
                }
            })
            .collect()
    }

    /// The rules a log never reached are named once when the rate models' forward speed and
    /// the velocity model's horizontal speed miss the same ones, per model when they differ,
    /// in one line either way.
    #[test]
    fn unreached_rules_are_named_per_premise_when_the_premises_differ() {
        // Forward from hover to 12 m/s: every rule reached.
        let sweep = flight(60, |x| (12.0 * x, 0.0));
        assert!(rule_caveats(&[sweep], 10.0).is_empty());
        // Hover: both premises miss 5 and 10 m/s, one line.
        let hover = rule_caveats(&[flight(60, |_| (0.0, 0.0))], 10.0);
        assert_eq!(hover.len(), 1, "{hover:?}");
        assert!(
            hover[0].contains("rules at 5 and 10 m/s (the rates' forward speed, the velocity's horizontal speed) were"),
            "{hover:?}"
        );
        // Sideways at 5 m/s, heading north: the forward speed stays at 0 (5 and 10 missed),
        // the horizontal speed at 5 (0 and 10 missed).
        let sideways = rule_caveats(&[flight(60, |_| (0.0, 5.0))], 10.0);
        assert_eq!(sideways.len(), 1, "{sideways:?}");
        assert!(
            sideways[0].contains("forward-speed rules at 5 and 10 m/s (its rate models) and its horizontal-speed rules at 0 and 10 m/s (its velocity model) were hardly reached"),
            "{sideways:?}"
        );
    }

    /// `seconds` of flight at 10 Hz at a horizontal (north) and an up speed (m/s).
    fn flying(seconds: usize, north: f64, up: f64) -> Vec<SensorSample> {
        (0..seconds * 10)
            .map(|k| SensorSample {
                t: k as f64 / 10.0,
                v_north: north,
                v_down: -up,
                ..SensorSample::default()
            })
            .collect()
    }

    /// Only regions the verification flies for a while and the training hardly flew are
    /// named, by horizontal and vertical speed together: climbs in forward flight do not
    /// train a climb in hover.
    #[test]
    fn the_regime_caveat_names_what_the_verification_flies_and_the_training_did_not() {
        let training = [
            flying(60, 0.0, 0.0),
            flying(20, 10.0, 3.0),
            flying(20, 10.0, -3.0),
        ];
        // Within the training's regions: nothing to say.
        let seen = [flying(30, 0.0, 0.5), flying(10, 9.0, 2.0)].concat();
        assert_eq!(regime_caveat(&training, &seen, 10.0), None);
        // A climb in hover (20 s) and a moment of descent in hover (1 s, under 2 s): the
        // climb alone is named, with its seconds.
        let unseen = [
            flying(30, 0.0, 0.0),
            flying(20, 0.5, 2.5),
            flying(1, 0.0, -2.0),
        ]
        .concat();
        let caveat = regime_caveat(&training, &unseen, 10.0).expect("a caveat");
        assert!(
            caveat.contains(
                "climb faster than 1.5 m/s under 3 m/s horizontally, 20 s verified and 0 s trained"
            ),
            "{caveat}"
        );
        assert!(!caveat.contains("descent"), "{caveat}");
    }

    /// A region whose only fitted equation holds `(symbol, value, se)` derivatives.
    fn region(derivatives: &[(&str, f64, f64)]) -> Region {
        let derivatives = derivatives
            .iter()
            .map(|&(symbol, value, se)| Derivative {
                symbol: symbol.to_string(),
                unit: "rad/s² per unit stick".to_string(),
                value: Some(value),
                se: Some(se),
                se_ols: Some(se),
                determined: value.abs() >= 2.0 * se,
                note: None,
            })
            .collect();
        Region {
            name: "all".to_string(),
            definition: String::new(),
            samples: 1000,
            fitted: true,
            reason: None,
            excitation: Vec::new(),
            axes: vec![AxisFit {
                axis: "p".to_string(),
                equation: String::new(),
                samples: 1000,
                fitted: true,
                reason: None,
                derivatives,
                r_squared: None,
                residual_rms: None,
                lags: None,
            }],
            rate_axes: Vec::new(),
        }
    }

    /// Whether a stick's control derivative is determined is the fit's standard error's to
    /// say, not the stick's deviation: small doublets can determine it, a larger deviation
    /// may not. Without a fitted derivative the deviation decides.
    #[test]
    fn stick_caveats_follow_the_derivatives_standard_errors() {
        // Every stick at σ = 0.5 % of travel.
        let small = [0.005; 4];
        let fitted = region(&[
            ("Z_col", -20.0, 1.0),
            ("L_lat", 8.0, 0.5),
            ("M_lon", 1.0, 2.0),
        ]);
        let caveats = stick_caveats(&small, Some(&fitted));
        assert_eq!(caveats.len(), 2, "{caveats:?}");
        // M_lon within two SE of zero: named with its value and SE.
        assert!(caveats.iter().any(|c| c.starts_with("pitch control power (M_lon) not determined by the log (M_lon = 1.000 ± 2.000 rad/s² per unit stick")), "{caveats:?}");
        // N_ped not fitted: the deviation decides.
        assert!(
            caveats
                .iter()
                .any(|c| c.starts_with("the pedal was hardly moved (σ = 0.5 % of travel)")),
            "{caveats:?}"
        );
        // Determined (Z_col, L_lat): nothing, though their sticks moved as little.
        assert!(
            !caveats
                .iter()
                .any(|c| c.contains("Z_col") || c.contains("L_lat")),
            "{caveats:?}"
        );
        // Without derivatives, a 5 % deviation is enough and 0.5 % is not.
        assert!(stick_caveats(&[0.05; 4], None).is_empty());
        assert_eq!(stick_caveats(&small, None).len(), 4);
    }

    /// A model is to fly only when it beats hold, a stick moved at all and the held-out part
    /// holds at least two windows; each failure is named, the first in that order.
    #[test]
    fn a_model_is_to_fly_only_when_it_beats_hold_on_excited_data_and_enough_windows() {
        let moved = [0.0, 0.0, STILL_STICK_STD, 0.0];
        let still = [STILL_STICK_STD * 0.99; 4];
        let enough = MIN_VERIFICATION_WINDOWS;
        assert_eq!(no_model(0.8, &moved, enough), None);
        assert_eq!(no_model(1.0, &moved, enough), Some(NoModel::NoneBeatsHold));
        assert_eq!(no_model(1.2, &still, 0), Some(NoModel::NoneBeatsHold));
        assert_eq!(no_model(0.8, &still, enough), Some(NoModel::NoStickMoved));
        assert_eq!(
            no_model(0.8, &moved, enough - 1),
            Some(NoModel::TooFewWindows(enough - 1))
        );
        // Sticks unknown (fewer than two training samples): not held against the model.
        assert_eq!(no_model(0.8, &[], enough), None);
    }

    /// Only axes whose searched gain is not 1 and loses to the measured state on the held-out
    /// data are named, in the verdict's order (roll before pitch).
    #[test]
    fn the_observer_caveat_names_the_axes_whose_gain_did_not_carry_over() {
        let gain = [1.0, 0.5, 1.0, 0.9, 0.5, 0.8];
        let unit = [0.1, 0.1, 0.1, 3.0, 1.0, 2.0];
        // v_y and r: the gain helps; q and p: it loses; v_x and v_z: gain 1 (no search gain).
        let observed = [0.2, 0.05, 0.2, 3.5, 0.9, 2.5];
        let line = observer_caveat(&gain, &observed, &unit).unwrap();
        assert!(
            line.contains("pitch rate q (K = 0.9: 3.500 against 3.000 deg/s)"),
            "{line}"
        );
        assert!(line.contains("roll rate p (K = 0.8"), "{line}");
        assert!(
            line.find("roll rate p") < line.find("pitch rate q"),
            "{line}"
        );
        for axis in [
            "east velocity",
            "down velocity",
            "north velocity",
            "yaw rate r",
        ] {
            assert!(!line.contains(axis), "{axis} in {line}");
        }
        assert_eq!(observer_caveat(&gain, &unit, &unit), None);
        assert_eq!(observer_caveat(&[1.0; 6], &observed, &unit), None);
    }
}
