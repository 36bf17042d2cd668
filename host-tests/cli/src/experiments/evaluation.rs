//! Training on identification logs and evaluation on verification logs: one-step and
//! free-run errors, convergence, timing.

use rotorid::convergence::ConvergenceMonitor;
use rotorid::hover::{GyroCompensation, HoverSample, HoverState, Observer, RateNoise};
use serde::{Deserialize, Serialize};

use rotorid_sim::flights::SAMPLE_RATE_HZ;

use super::error::EvaluateError;
use super::regimes::{one_step_bias, RegimeBias};
use super::variants::{Identifier, ModelParameters, ObserverSearch, Variant};

/// Index of the fuzzy (first) and plain (second) Table 4 columns in [`variants`](fn@super::variants).
pub const TABLE4_VARIANTS: (usize, usize) = (0, 1);

/// Mean absolute error per state over `(prediction, actual)` pairs; zeros when empty.
pub fn mean_abs_errors<'a>(
    pairs: impl IntoIterator<Item = (&'a HoverState<f32>, &'a HoverState<f32>)>,
) -> [f64; 6] {
    let mut sum = [0.0f64; 6];
    let mut n = 0usize;
    for (pred, actual) in pairs {
        let (p, x) = (pred.to_array(), actual.to_array());
        for i in 0..6 {
            sum[i] += (f64::from(p[i]) - f64::from(x[i])).abs();
        }
        n += 1;
    }
    if n > 0 {
        sum.iter_mut().for_each(|s| *s /= n as f64);
    }
    sum
}

/// Mean absolute one-step error per state of `predictions` against `actual`, where
/// `predictions[k]` predicts `actual[k + 1]` (`None`, a refused prediction, is skipped).
pub fn one_step_mean_abs_errors(
    predictions: &[Option<HoverState<f32>>],
    actual: &[HoverState<f32>],
) -> [f64; 6] {
    mean_abs_errors(
        predictions
            .iter()
            .zip(actual.iter().skip(1))
            .filter_map(|(p, a)| p.as_ref().map(|p| (p, a))),
    )
}

/// What training on a set of logs did.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingStats {
    /// Samples offered.
    pub samples: usize,
    /// Updates made (samples that followed an accepted sample at the nominal interval).
    pub updates: usize,
    /// Sample chains started (one per log, plus one after each gap or rejection).
    pub chains: usize,
    /// Samples the identifier refused (out of range, numerically unusable).
    pub rejected: usize,
    /// Mean absolute one-step error of the still-adapting predictions over the training data
    /// (each prediction made with θ learnt up to the sample it starts from).
    pub one_step: [f64; 6],
    /// The core's scale-free convergence indicator at the end of training
    /// ([`rotorid::convergence::ConvergenceMonitor`], windows of [`CONVERGENCE_WINDOW`]
    /// samples): ρ = Σe²/ΣΔy² per state over the last window (1 = no better than hold).
    #[serde(default)]
    pub convergence_ratio: [f64; 6],
    /// Whether ρ had settled (changed by at most [`CONVERGENCE_TOLERANCE`] over
    /// [`CONVERGENCE_SETTLE`] consecutive windows) per state.
    #[serde(default)]
    pub converged: [bool; 6],
}

/// Window of the convergence indicator in training reports (samples: 5 s at 50 Hz).
pub const CONVERGENCE_WINDOW: u32 = 250;
/// Relative change of ρ between windows counted as settled.
pub const CONVERGENCE_TOLERANCE: f64 = 0.2;
/// Consecutive settled windows required.
pub const CONVERGENCE_SETTLE: u16 = 3;

/// Trains `id` online over `logs` (each its own sample chain: [`DynIdentifier::resume`](rotorid::DynIdentifier::resume) at the
/// start of each log and after a gap or a refused sample). `progress` is called once per
/// sample.
pub fn train(
    id: &mut dyn Identifier,
    logs: &[Vec<HoverSample<f32>>],
    progress: &mut dyn FnMut(),
) -> TrainingStats {
    let mut stats = TrainingStats::default();
    let mut pairs: Vec<(HoverState<f32>, HoverState<f32>)> = Vec::new();
    let mut monitor = ConvergenceMonitor::<f64, 6>::new(
        CONVERGENCE_WINDOW,
        CONVERGENCE_TOLERANCE,
        CONVERGENCE_SETTLE,
    )
    .ok();
    for log in logs {
        let mut pending: Option<HoverState<f32>> = None;
        let mut chained = false;
        let mut previous: Option<HoverSample<f32>> = None;
        for s in log {
            progress();
            stats.samples += 1;
            let result = if chained {
                match id.step(s) {
                    Ok(out) => {
                        stats.updates += 1;
                        if let (Some(m), Some(p), Some(inn)) =
                            (monitor.as_mut(), previous.as_ref(), out.innovation.as_ref())
                        {
                            let (a, b) = (p.state().to_array(), s.state().to_array());
                            let increment: [f64; 6] =
                                core::array::from_fn(|i| f64::from(b[i]) - f64::from(a[i]));
                            let _ = m.observe(&inn.to_array().map(f64::from), &increment);
                        }
                        Ok(out.prediction)
                    }
                    Err(rotorid::Error::TimeStep { .. } | rotorid::Error::NonMonotonicTime) => {
                        stats.chains += 1;
                        pending = None;
                        id.resume(s)
                    }
                    Err(e) => Err(e),
                }
            } else {
                stats.chains += 1;
                id.resume(s)
            };
            match result {
                Ok(pred) => {
                    if let Some(p) = pending {
                        pairs.push((p, s.state()));
                    }
                    pending = Some(pred);
                    chained = true;
                    previous = Some(*s);
                }
                Err(_) => {
                    stats.rejected += 1;
                    pending = None;
                    previous = None;
                }
            }
        }
    }
    stats.one_step = mean_abs_errors(pairs.iter().map(|(p, a)| (p, a)));
    if let Some(m) = monitor {
        stats.convergence_ratio = m.status().ratio;
        stats.converged = m.status().converged;
    }
    stats
}

/// Everything measured for one variant over the verification log.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VariantResult {
    /// [`Variant::name`].
    pub name: String,
    /// [`Variant::description`].
    pub description: String,
    /// Training statistics.
    pub training: TrainingStats,
    /// Hold baseline `x̂(k+1) = x(k)`: mean absolute one-step error per state.
    pub hold_one_step: [f64; 6],
    /// Table 4's definition: θ frozen after training, one-step predictions with `predict`.
    pub one_step: [f64; 6],
    /// θ still adapting during verification (`step`'s predictions).
    pub one_step_adapting: [f64; 6],
    /// Free run: the model fed its own predictions of `v^s` and `ω^b` over windows of
    /// `window_s`, restarted from the measured state at each window, with measured attitude
    /// and controls; mean absolute error over every predicted sample.
    pub free_run: [f64; 6],
    /// The free run of the least-squares parameters the identifier learnt, when
    /// [`free_run`](Self::free_run) is that of the parameters compensated for the gyro noise
    /// (`None`: nothing was compensated, and `free_run` is this).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_run_least_squares: Option<[f64; 6]>,
    /// The rules whose parameters were compensated for the gyro noise before the free run
    /// ([`HoverIdentifier::compensate`](rotorid::HoverIdentifier::compensate)), and those left
    /// as they were.
    #[serde(default)]
    pub compensated_rules: [u16; 2],
    /// The rates `[q r p]` compensated fully ([`GyroCompensation::Full`]: the second-order
    /// term's noise too) rather than the damping term's alone, as the tool was asked or the
    /// variant chose from its training data; all false when nothing was compensated.
    #[serde(default)]
    pub full_compensation: [bool; 3],
    /// The gain `K` per state of the variant's one-step observer
    /// ([`rotorid::hover::Observer`]), found on the training logs ([`observer_gain`]) with the
    /// free run's parameters.
    #[serde(default)]
    pub observer_gain: [f32; 6],
    /// One-step predictions through that observer over the verification log (θ frozen, the
    /// free run's parameters): mean absolute error per state. The variant's one-step
    /// predictor: it predicts from the model's filtered estimate of each sample
    /// (`observer_gain` 1 on every state predicts from the measured state, as
    /// [`one_step`](Self::one_step) with the least-squares parameters).
    #[serde(default)]
    pub one_step_observed: [f64; 6],
    /// The same one-step predictions through an observer of gain 1 on every state (from the
    /// measured state, with the free run's parameters): what
    /// [`one_step_observed`](Self::one_step_observed) must beat on the held-out data for its
    /// gain, found on the training logs, to be worth using.
    #[serde(default)]
    pub one_step_unit_gain: [f64; 6],
    /// Hold baseline of the free run: the window's initial state held for the whole window
    /// (scored over every window sample, whatever the model did).
    pub hold_free_run: [f64; 6],
    /// Free-run windows evaluated.
    pub free_run_windows: usize,
    /// Windows in which the model's own state left the core's sample limits (the rest of that
    /// window is not scored).
    pub free_run_diverged: usize,
    /// Verification samples the frozen model could not predict from (out of range).
    pub rejected_verification: usize,
    /// Frozen one-step bias per flight regime of the verification log ([`one_step_bias`]).
    #[serde(default)]
    pub one_step_bias: Vec<RegimeBias>,
    /// Frozen one-step predictions: `one_step_predictions[k]` predicts sample k+1 (`None`
    /// where refused).
    #[serde(skip)]
    pub one_step_predictions: Vec<Option<HoverState<f32>>>,
    /// Free-run trajectory: `free_run_trace[k]` is the free-run estimate of sample k (`None`
    /// at window starts and after a divergence).
    #[serde(skip)]
    pub free_run_trace: Vec<Option<HoverState<f32>>>,
    /// Trained parameters (warm start).
    #[serde(skip)]
    pub parameters: Vec<ModelParameters>,
    /// The parameters the free run used, when they were compensated for the gyro noise.
    #[serde(skip)]
    pub compensated_parameters: Option<Vec<ModelParameters>>,
    /// The trained identifier in the core's snapshot format (`snapshot-*.ridx`), for a
    /// variant with a kind code.
    #[serde(skip)]
    pub snapshot: Option<Vec<u8>>,
}

/// Result of [`free_run`].
#[derive(Debug, Clone, Default)]
pub struct FreeRun {
    /// `trace[k]`: free-run estimate of sample k (`None` at window starts, after divergence).
    pub trace: Vec<Option<HoverState<f32>>>,
    /// Mean absolute error per state over every predicted sample.
    pub error: [f64; 6],
    /// The same for holding each window's initial state.
    pub hold: [f64; 6],
    /// Windows run.
    pub windows: usize,
    /// Windows in which the model's state left the core's sample limits.
    pub diverged: usize,
}

/// Which velocity a free run feeds the models (`rotorid identify --free-run-velocity`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FreeRunVelocity {
    /// The velocity model's own prediction `v̂^s` (the free run of the whole identifier).
    #[default]
    Model,
    /// The measured `v^s` of each sample, while the rates run free: the rate models' free
    /// run without the velocity model's error (a diagnostic: the rate models of
    /// [`RateStructure::Flight`](rotorid::hover::RateStructure::Flight) read the speed). The
    /// velocity states' free-run errors are then zero.
    Measured,
}

/// Free-run simulation of a frozen model over `samples` in windows of `window` steps: each
/// window starts from the measured state, then the model is fed its own predicted `ω^b` and,
/// with [`FreeRunVelocity::Model`], its own `v^s`, with the measured attitude and controls.
pub fn free_run(
    id: &dyn Identifier,
    samples: &[HoverSample<f32>],
    window: usize,
    velocity: FreeRunVelocity,
) -> FreeRun {
    let window = window.max(1);
    let mut trace = vec![None; samples.len()];
    let mut pairs = Vec::new();
    let mut hold_pairs = Vec::new();
    let (mut windows, mut diverged) = (0, 0);
    let mut start = 0;
    while start + 1 < samples.len() {
        windows += 1;
        let end = (start + window).min(samples.len() - 1);
        let x0 = samples[start].state();
        let mut x = x0;
        // The state before the window's first sample is measured; later, the model's own.
        let mut before = start.checked_sub(1).map(|i| samples[i].state());
        for j in start..end {
            hold_pairs.push((x0, samples[j + 1].state()));
        }
        for j in start..end {
            let mut s = samples[j];
            if velocity == FreeRunVelocity::Model {
                s.velocity = x.velocity;
            }
            s.rates = x.rates;
            match id.predict_after(before.as_ref(), &s) {
                Ok(mut next) => {
                    if velocity == FreeRunVelocity::Measured {
                        next.velocity = samples[j + 1].velocity;
                    }
                    before = Some(x);
                    x = next;
                    trace[j + 1] = Some(next);
                    pairs.push((next, samples[j + 1].state()));
                }
                Err(_) => {
                    diverged += 1;
                    break;
                }
            }
        }
        start = end;
    }
    FreeRun {
        trace,
        error: mean_abs_errors(pairs.iter().map(|(p, a)| (p, a))),
        hold: mean_abs_errors(hold_pairs.iter().map(|(p, a)| (p, a))),
        windows,
        diverged,
    }
}

/// Runs `step` on `state` for each sample of a chain of samples; where the chain breaks (a gap
/// in time, a refused sample), `restart`s it and goes on from that sample as the first of a
/// new chain.
fn chained<S, E>(
    state: &mut S,
    samples: &[HoverSample<f32>],
    step: impl Fn(&mut S, &HoverSample<f32>) -> Result<E, rotorid::Error>,
    restart: impl Fn(&mut S),
) -> Vec<Option<E>> {
    samples
        .iter()
        .map(|s| match step(state, s) {
            Ok(x) => Some(x),
            Err(rotorid::Error::TimeStep { .. } | rotorid::Error::NonMonotonicTime) => {
                restart(state);
                step(state, s).ok()
            }
            Err(_) => {
                restart(state);
                None
            }
        })
        .collect()
}

/// The observer of `id` whose gain gives the least one-step squared error over the training
/// logs, per state, among [`ObserverSearch`]'s candidates (each log a chain of its own);
/// `None` when no prediction could be scored.
pub fn observer_gain(
    id: &dyn Identifier,
    training: &[Vec<HoverSample<f32>>],
) -> Option<Observer<f32>> {
    let mut search = ObserverSearch::grid();
    for log in training {
        search.restart();
        chained(
            &mut search,
            log,
            |search, s| id.search_gain(search, s),
            ObserverSearch::restart,
        );
    }
    search.best()
}

/// One-step predictions of `id` through `observer` over `samples` (restarting after a gap):
/// `observed[k]` predicts sample k+1 (`None` where refused).
pub fn observed_one_step(
    id: &dyn Identifier,
    samples: &[HoverSample<f32>],
    mut observer: Observer<f32>,
) -> Vec<Option<HoverState<f32>>> {
    let mut observed = chained(
        &mut observer,
        samples,
        |observer, s| id.observe(observer, s),
        Observer::restart,
    );
    observed.pop();
    observed
}

/// σ̂ of the white noise of each gyro rate `[q r p]` (deg/s) in the training logs
/// ([`RateNoise`], each log a chain of its own); `None` for logs too short.
pub fn gyro_noise_of(training: &[Vec<HoverSample<f32>>]) -> Option<[f32; 3]> {
    let mut noise = RateNoise::<f32>::new();
    for log in training {
        noise.restart();
        for s in log {
            // A rate the core refuses does not count (the identifier refuses it too).
            let _ = noise.push(&s.rates);
        }
    }
    noise.std_dev()
}

/// A warm start whose one-step error on the training log exceeds the hold predictor's by
/// more than this factor (on any state, with a floor of [`WARM_START_FLOOR`]) is refused: a
/// model learnt on this helicopter is within a small factor of hold even when poor; one
/// thousand times worse is a damaged or foreign file.
pub const WARM_START_MAX_RATIO: f64 = 100.0;

/// Error below which a warm start is never called absurd (m/s, deg/s): hold errors of a
/// still log are near zero.
pub const WARM_START_FLOOR: f64 = 1.0;

/// Samples of the first training log a warm start is checked on.
const WARM_START_PROBE: usize = 500;

/// Refuses warm-start parameters whose predictions on the first training log are absurd
/// ([`WARM_START_MAX_RATIO`]).
fn check_warm_start(
    id: &dyn Identifier,
    log: &[HoverSample<f32>],
    variant: &'static str,
) -> Result<(), EvaluateError> {
    let n = log.len().min(WARM_START_PROBE);
    let mut preds = Vec::with_capacity(n);
    let mut refused = 0usize;
    for k in 0..n.saturating_sub(1) {
        let before = k
            .checked_sub(1)
            .and_then(|i| log.get(i))
            .map(HoverSample::state);
        let p = log
            .get(k)
            .and_then(|s| id.predict_after(before.as_ref(), s).ok());
        refused += usize::from(p.is_none());
        preds.push(p);
    }
    let actual: Vec<HoverState<f32>> = log[..n].iter().map(HoverSample::state).collect();
    let error = one_step_mean_abs_errors(&preds, &actual);
    let hold = mean_abs_errors(actual.iter().zip(actual.iter().skip(1)));
    let labels = [
        "v_x (m/s)",
        "v_y (m/s)",
        "v_z (m/s)",
        "q (deg/s)",
        "r (deg/s)",
        "p (deg/s)",
    ];
    for i in 0..6 {
        let limit = (WARM_START_MAX_RATIO * hold[i]).max(WARM_START_FLOOR);
        // Half the predictions refused or more: the model leaves the core's limits at once.
        let all_refused = refused > 0 && 2 * refused + 1 >= n;
        if !(error[i].is_finite() && error[i] <= limit) || all_refused {
            return Err(EvaluateError::WarmStartAbsurd {
                variant,
                state: labels[i],
                error: if all_refused { f64::INFINITY } else { error[i] },
                hold: hold[i],
                ratio: WARM_START_MAX_RATIO,
            });
        }
    }
    Ok(())
}

/// How [`evaluate`] runs its free runs and its observer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvaluationSettings {
    /// Free-run window (s): each window restarts from the measured state.
    pub window_s: f64,
    /// σ of the gyro noise `[q r p]` (deg/s) the free run's and the observer's parameters are
    /// compensated for (`None`: the least-squares parameters).
    pub gyro_noise: Option<[f32; 3]>,
    /// Which gyro noise the compensation removes.
    pub gyro_compensation: GyroCompensation,
    /// The velocity the free runs feed the models.
    pub velocity: FreeRunVelocity,
    /// The one-step observer's gain per state `[v_x v_y v_z q r p]` (`None`: each variant's
    /// own, found on the training logs by [`observer_gain`]).
    pub observer_gain: Option<[f32; 6]>,
    /// The rate the logs are sampled at and the identifiers run at (Hz): 50 for the
    /// simulator's flights, a real log's own rate when it is logged slower.
    pub rate_hz: f64,
}

impl EvaluationSettings {
    /// The identifiers' sample period (µs) at [`rate_hz`](Self::rate_hz).
    pub fn period_us(&self) -> u32 {
        period_us(self.rate_hz)
    }
}

/// The identifiers' sample period (µs) at `rate_hz` (Hz); 50 Hz's when the rate is not a
/// usable number.
pub fn period_us(rate_hz: f64) -> u32 {
    let us = (1e6 / rate_hz).round();
    if us.is_finite() && us >= 1.0 && us <= f64::from(u32::MAX) {
        us as u32
    } else {
        1_000_000 / SAMPLE_RATE_HZ
    }
}

/// Trains a fresh `variant` on `training` logs, freezes θ and verifies on `verification`:
/// hold baseline, frozen one-step (Table 4), one-step through the observer, still-adapting
/// one-step, and free run as `settings` say: with a gyro noise, the free run and the observer
/// use the parameters compensated for it (the least-squares parameters' free run is kept
/// beside it). `progress` is called once per training sample and once per verification
/// sample.
pub fn evaluate(
    variant: &Variant,
    training: &[Vec<HoverSample<f32>>],
    verification: &[HoverSample<f32>],
    settings: EvaluationSettings,
    warm_start: Option<&[ModelParameters]>,
    progress: &mut dyn FnMut(),
) -> Result<VariantResult, EvaluateError> {
    let mut id =
        (variant.build)(training, settings.period_us()).map_err(|source| EvaluateError::Build {
            variant: variant.name,
            source,
        })?;
    if let Some(p) = warm_start {
        id.load(p).map_err(|source| EvaluateError::WarmStart {
            variant: variant.name,
            source,
        })?;
        if let Some(log) = training.first() {
            check_warm_start(id.as_ref(), log, variant.name)?;
        }
    }
    let training_stats = train(id.as_mut(), training, progress);

    // Frozen one-step predictions (Table 4).
    let mut preds = Vec::with_capacity(verification.len());
    let mut rejected = 0;
    for (k, s) in verification
        .iter()
        .take(verification.len().saturating_sub(1))
        .enumerate()
    {
        progress();
        let before = k.checked_sub(1).map(|i| verification[i].state());
        let p = id.predict_after(before.as_ref(), s).ok();
        if p.is_none() {
            rejected += 1;
        }
        preds.push(p);
    }
    let actual: Vec<HoverState<f32>> = verification.iter().map(HoverSample::state).collect();
    let one_step = one_step_mean_abs_errors(&preds, &actual);
    let hold_one_step = mean_abs_errors(actual.iter().zip(actual.iter().skip(1)));

    // Still adapting: a copy of the trained identifier keeps learning on the verification log.
    let mut adapting = id.boxed_clone();
    let stats = train(adapting.as_mut(), &[verification.to_vec()], &mut || {});

    let window = (settings.window_s * settings.rate_hz).round();
    let window = if window.is_finite() && window >= 1.0 {
        window as usize
    } else {
        1
    };
    let least_squares = free_run(id.as_ref(), verification, window, settings.velocity);
    // The parameters compensated for the gyro noise, where any rule was: the free run's and
    // the observer's.
    let mut compensated_rules = [0; 2];
    let mut compensated = None;
    let mut full_compensation = [false; 3];
    if let Some(sigma) = settings.gyro_noise {
        let how = id.compensation(settings.gyro_compensation);
        full_compensation = how.map(|h| h == GyroCompensation::Full);
        let mut simulated = id.boxed_clone();
        let c =
            simulated
                .compensate_each(&sigma, how)
                .map_err(|source| EvaluateError::Compensate {
                    variant: variant.name,
                    source,
                })?;
        compensated_rules = [c.compensated, c.refused];
        if c.compensated > 0 {
            compensated = Some(simulated);
        }
    }
    let (free, free_run_least_squares) = match &compensated {
        Some(simulated) => (
            free_run(simulated.as_ref(), verification, window, settings.velocity),
            Some(least_squares.error),
        ),
        None => (least_squares, None),
    };
    let flown = compensated.as_deref().unwrap_or(id.as_ref());
    let observer = match settings.observer_gain {
        Some(gain) => Observer::new(gain).map_err(|source| EvaluateError::Observer {
            variant: variant.name,
            source,
        })?,
        None => observer_gain(flown, training).unwrap_or_else(Observer::measured),
    };
    let observed = observed_one_step(flown, verification, observer);
    let one_step_observed = one_step_mean_abs_errors(&observed, &actual);
    let one_step_unit_gain = if observer.gain() == Observer::<f32>::measured().gain() {
        one_step_observed
    } else {
        let unit = observed_one_step(flown, verification, Observer::measured());
        one_step_mean_abs_errors(&unit, &actual)
    };

    Ok(VariantResult {
        name: variant.name.to_string(),
        description: variant.description.to_string(),
        training: training_stats,
        hold_one_step,
        one_step,
        one_step_adapting: stats.one_step,
        free_run: free.error,
        free_run_least_squares,
        compensated_rules,
        full_compensation,
        observer_gain: observer.gain(),
        one_step_observed,
        one_step_unit_gain,
        hold_free_run: free.hold,
        free_run_windows: free.windows,
        free_run_diverged: free.diverged,
        rejected_verification: rejected,
        one_step_bias: one_step_bias(verification, &preds, 1.0 / settings.rate_hz),
        one_step_predictions: preds,
        free_run_trace: free.trace,
        parameters: id.parameters(),
        compensated_parameters: compensated.map(|c| c.parameters()),
        // The core's snapshot under the variant's kind code (`DynIdentifier::snapshot_vec`
        // sizes the buffer from the identifier: the core's identifiers cannot fail it).
        snapshot: variant
            .kind
            .map(|kind| id.snapshot_vec(kind).unwrap_or_default()),
    })
}
