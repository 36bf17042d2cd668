//! Term selection: which optional consequent terms of the flight structure a helicopter's own
//! training data support.
//!
//! The flight structure's terms ([`VelocityStructure::Flight`], [`RateStructure::Flight`])
//! were chosen on the simulators written here; another helicopter needs other terms, and a
//! term the data cannot determine adds variance to every prediction it enters. So, per model
//! (velocity, q̂, r̂, p̂), a backward elimination decides from the data which optional terms to
//! switch off:
//!
//! * The training data are cut into blocks of [`BLOCK_S`]; every third block is held out to
//!   check, the others are learnt (so that each sweep, doublet or operating point of the flight
//!   is in both parts: a split in time would hold out the last manoeuvre only). A log shorter
//!   than `2 FOLDS` blocks (3 min) is cut into `2 FOLDS` shorter blocks, so that each fold still
//!   checks two blocks from different parts of the flight; a block must hold
//!   [`MIN_WINDOWS_PER_BLOCK`] free-run windows, so below `2 FOLDS × 2` windows of training
//!   data (24 s with 2 s windows) there is nothing to check on and every term stays.
//! * A candidate is the flight default with some terms pinned at zero (each rule's prior
//!   variance of the term set to zero, [`pin_to_zero`](super::pin_to_zero): the onboard identifier keeps its fixed
//!   sizes, and the exported state carries the choice, so a warm start flies it). It is learnt
//!   on the learning blocks and scored by its free run ([`SELECTION_WINDOW_S`] windows) on the
//!   check blocks, relative to holding the measured state: the geometric mean of
//!   `free run / hold` over the model's own axes.
//! * Model by model, first the rules: the model with one rule (its three speed rules
//!   replaced by [`unscheduled_sets`], under which the first rule fires alone at every sample:
//!   bit for bit the one-rule model, in the same sizes) replaces the scheduled one if the
//!   score does not get worse. A rule learns only from the part of the flight near its speed,
//!   so three rules hold three times the parameters on the same data: where the dynamics do
//!   not change with the speed, or the flight did not visit the other speeds enough, they add
//!   variance and no fit. Only where the scheduled model's score is below 1 (it beats holding
//!   the measured state): the check blocks revisit the training's operating points, so they
//!   cannot tell how the two forms extrapolate to others, and among models worse than hold
//!   the comparison is mostly noise (the CHANGELOG has what a selection without this guard
//!   did to yaw on plant variations). Then the terms: the term whose removal gives the
//!   lowest score is switched off if the score does not get worse, and the search goes on
//!   until every removal makes it worse (ties go to the simpler model).
//! * With [`select_terms_and_schedules`] (`rotorid identify`'s default), after its
//!   terms: the speed a model's three rules are on. A model that kept its rules and beats
//!   hold on the check blocks moves to the side speed (rate models) or the vertical speed,
//!   its sets at the training data's quantiles of that speed, if that lowers its score by
//!   more than two standard errors of the paired block differences (docs/ab-premises.md).
//! * Last, per rate, the gyro-noise compensation: full ([`GyroCompensation::Full`]) replaces
//!   the default's where it lowers the model's score.
//! * [`select_terms_with`] can ask more of a removal: that it lower the check blocks' free
//!   run by more than their noise (a paired comparison over the blocks), or leave fewer
//!   free-run windows diverging. The product keeps the plain rule: asking two standard
//!   errors keeps the selected model within 3 % of `flight plain` far more often, but keeps
//!   the yaw terms whose removal takes the envelope's yaw free run below holding the measured
//!   rate on most plant variations (docs/ab-removal-evidence.md, `scripts/ab.sh`);
//!   docs/term-evidence.md (`scripts/term-evidence.sh`) has each amount over many seed pairs.
//!
//! The essential terms stay: thrust slope `α1`, weight `α2` and heave damping `d_u`; each
//! rate's control gain `γ` and damping `δ`. The inertia coupling `𝕀` of q̂ and p̂ (Euler's
//! equations of a rigid body) goes only where its removal leaves fewer free-run windows
//! diverging: every helicopter has it, but a training flight that keeps the other two rates
//! small cannot show it, and a flight that does not needs it (docs/term-evidence.md).

use rotorid::hover::{GyroCompensation, HoverSample};
use rotorid::DynIdentifier;
use serde::{Deserialize, Serialize};

use super::evaluation::{free_run, gyro_noise_of, train, FreeRunVelocity};
use super::mask::{Schedule, ScheduledOn, SelectedFlight, TermMask};
use super::variants::Identifier;

/// Length of the blocks the training data are cut into (s), when the data hold `2 FOLDS` of
/// them.
pub const BLOCK_S: f64 = 30.0;
/// Free-run window of the selection's score (s), the tool's default verification window.
pub const SELECTION_WINDOW_S: f64 = 2.0;
/// Folds of the cross-validation: block `i` is held out in fold `i mod FOLDS`.
pub const FOLDS: usize = 3;
/// Fewest free-run windows a block must hold to be checked on; with shorter blocks the
/// selection keeps every term. One window is a single draw of the run's error; two from
/// different manoeuvres are the least that compares candidates on more than one instant.
pub const MIN_WINDOWS_PER_BLOCK: usize = 2;

/// The terms the selection may switch off, per model (indices into θ of one rule).
const OPTIONAL: [&[usize]; 4] = [
    &[2, 3, 5, 6, 7],
    &[0, 3, 4, 5],
    &[0, 3, 4, 5],
    &[0, 3, 4, 5],
];

/// Per model, the optional term that is rigid-body dynamics rather than aerodynamics: the
/// inertia coupling `𝕀` of q̂ and p̂ (Euler's equations: `(I_zz − I_xx)/I_yy · r p` and
/// `(I_yy − I_zz)/I_xx · q r`), which every helicopter has. The check blocks of a flight that
/// keeps the other two rates small cannot tell it from noise, and a flight that does not
/// needs it, so it is switched off only where its removal leaves fewer free-run windows
/// diverging (the yaw model's first term, `𝕀 |v|`, is aerodynamic and selected as the rest).
const RIGID_BODY: [Option<usize>; 4] = [None, Some(0), None, Some(0)];

/// Axes (indices of `[v_x v_y v_z q r p]`) each model predicts.
const AXES: [&[usize]; 4] = [&[0, 1, 2], &[3], &[4], &[5]];

/// What the selection found.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TermSelection {
    /// The terms switched off.
    pub mask: TermMask,
    /// Free run / hold per state `[v_x v_y v_z q r p]` on the check blocks with every term.
    pub full: [f64; 6],
    /// The same with the selected terms.
    pub selected: [f64; 6],
    /// Candidates learnt and scored.
    pub candidates: usize,
    /// Samples learnt and held out to check.
    pub samples: (usize, usize),
}

/// The training data cut into learning chains and held-out check blocks (see the module
/// docs).
pub(super) struct Split {
    learn: Vec<Vec<HoverSample<f32>>>,
    check: Vec<Vec<HoverSample<f32>>>,
}

pub(super) fn split(training: &[Vec<HoverSample<f32>>], block: usize, fold: usize) -> Split {
    let mut learn: Vec<Vec<HoverSample<f32>>> = Vec::new();
    let mut check = Vec::new();
    let mut index = 0usize;
    for log in training {
        // Consecutive learning blocks of one log stay one chain.
        let mut chain: Vec<HoverSample<f32>> = Vec::new();
        for part in log.chunks(block.max(1)) {
            if index % FOLDS == fold {
                if !chain.is_empty() {
                    learn.push(std::mem::take(&mut chain));
                }
                check.push(part.to_vec());
            } else {
                chain.extend_from_slice(part);
            }
            index += 1;
        }
        if !chain.is_empty() {
            learn.push(chain);
        }
    }
    Split { learn, check }
}

/// Free run / hold per state of `mask`'s flight identifier, learnt on each fold's learning
/// chains and run free on its check blocks, summed over the folds.
pub(super) fn score(
    mask: TermMask,
    folds: &[Split],
    period_us: u32,
    window: usize,
    gyro_noise: Option<[f32; 3]>,
) -> Result<Score, rotorid::Error> {
    let (mut error, mut hold) = ([0.0f64; 6], [0.0f64; 6]);
    let mut diverged = 0;
    let mut blocks = Vec::new();
    for split in folds {
        // The model the product flies for this mask (`flight selected`'s).
        let mut id = SelectedFlight::new(mask, period_us)?;
        train(&mut id, &split.learn, &mut || {});
        if let Some(sigma) = gyro_noise {
            // As the tool's verification does (with its default): the free run flies the
            // parameters compensated for the gyro noise, on each rate as the mask says; a
            // refused compensation leaves the least-squares ones.
            let _ = id.compensate_each(&sigma, id.compensation(GyroCompensation::Damping));
        }
        for block in &split.check {
            let run = free_run(&id, block, window, FreeRunVelocity::Model);
            diverged += run.diverged;
            let weight = block.len().saturating_sub(1) as f64;
            for i in 0..6 {
                error[i] += run.error[i] * weight;
                hold[i] += run.hold[i] * weight;
            }
            blocks.push(run.error);
        }
    }
    let ratios = core::array::from_fn(|i| {
        if hold[i] > 0.0 {
            error[i] / hold[i]
        } else {
            1.0
        }
    });
    Ok(Score {
        diverged,
        ratios,
        blocks,
    })
}

/// A candidate's free run on the check blocks.
#[derive(Clone, Debug)]
pub(super) struct Score {
    /// Windows whose state left the core's sample limits (the run stops there).
    pub(super) diverged: usize,
    /// Free run / hold per state `[v_x v_y v_z q r p]` over the steps run.
    pub(super) ratios: [f64; 6],
    /// Free-run mean absolute error per state on each check block, fold after fold: the
    /// same blocks, in the same order, for every candidate.
    pub(super) blocks: Vec<[f64; 6]>,
}

impl Score {
    /// The order of candidates for model `m`: fewer diverged windows first (a window that
    /// diverged stopped early, so its error covers only the steps before and would flatter
    /// the candidate), then the lower [`model_score`].
    fn key(&self, m: usize) -> (usize, f64) {
        (self.diverged, model_score(&self.ratios, m))
    }
}

/// Whether `candidate` predicts model `m`'s axes better than `current` by more than
/// `evidence` standard errors of the check blocks: per block the log of the error ratio
/// (candidate over current, mean over the axes), whose mean over the blocks must lie below
/// `-evidence · s/√n`. The blocks are paired (the same data for both), so what differs
/// between them is the candidate alone. With `evidence` 0 only the sign of the mean counts;
/// fewer than two blocks, or a non-finite ratio, are no evidence.
fn better_beyond_noise(candidate: &Score, current: &Score, m: usize, evidence: f64) -> bool {
    let axes = AXES[m];
    let d: Vec<f64> = candidate
        .blocks
        .iter()
        .zip(&current.blocks)
        .map(|(c, b)| axes.iter().map(|&i| (c[i] / b[i]).ln()).sum::<f64>() / axes.len() as f64)
        .collect();
    if d.len() < 2 || d.iter().any(|x| !x.is_finite()) {
        return false;
    }
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let variance = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    mean < -evidence * (variance / n).sqrt()
}

/// Whether `candidate`'s change of model `m` is supported by `evidence` standard errors:
/// fewer free-run windows diverging, or as many and [`better_beyond_noise`].
fn convinces(candidate: &Score, current: &Score, m: usize, evidence: f64) -> bool {
    match candidate.diverged.cmp(&current.diverged) {
        core::cmp::Ordering::Less => true,
        core::cmp::Ordering::Equal => better_beyond_noise(candidate, current, m, evidence),
        core::cmp::Ordering::Greater => false,
    }
}

/// Geometric mean of `ratios` over model `m`'s axes (non-finite: infinitely bad).
fn model_score(ratios: &[f64; 6], m: usize) -> f64 {
    geometric_mean(ratios, AXES[m])
}

/// Geometric mean of `ratios` over `axes` (a NaN or a non-finite mean: infinitely bad).
pub(super) fn geometric_mean(ratios: &[f64; 6], axes: &[usize]) -> f64 {
    let log_sum: f64 = axes
        .iter()
        .map(|&i| match ratios[i] {
            r if r.is_nan() => f64::INFINITY,
            r => r.max(1e-12).ln(),
        })
        .sum();
    let s = (log_sum / axes.len() as f64).exp();
    if s.is_finite() {
        s
    } else {
        f64::INFINITY
    }
}

/// Samples per block for `samples` of training data: [`BLOCK_S`], or `2 FOLDS` equal blocks
/// when the data are shorter than that many; `None` when such a block would hold fewer than
/// [`MIN_WINDOWS_PER_BLOCK`] windows of `window` samples.
pub(super) fn block_length(samples: usize, rate_hz: f64, window: usize) -> Option<usize> {
    let full = (BLOCK_S * rate_hz).round().max(1.0) as usize;
    let block = full.min(samples / (2 * FOLDS));
    (block >= MIN_WINDOWS_PER_BLOCK * window).then_some(block)
}

/// Whether `samples` of training data at `rate_hz` are enough for [`select_terms`] to check
/// candidates on (see [`MIN_WINDOWS_PER_BLOCK`]); with fewer it keeps every term.
pub fn selects_from(samples: usize, rate_hz: f64) -> bool {
    block_length(samples, rate_hz, window_samples(rate_hz)).is_some()
}

/// Samples in one [`SELECTION_WINDOW_S`] free-run window at `rate_hz`.
pub(super) fn window_samples(rate_hz: f64) -> usize {
    (SELECTION_WINDOW_S * rate_hz).round().max(1.0) as usize
}

/// Selects the flight default's terms from `training` at `period_us` (see the module docs).
/// With too little data to check on ([`MIN_WINDOWS_PER_BLOCK`]), every term stays.
pub fn select_terms(
    training: &[Vec<HoverSample<f32>>],
    period_us: u32,
) -> Result<TermSelection, rotorid::Error> {
    select_terms_with(training, period_us, None)
}

/// [`select_terms`], where with `evidence` = `Some(k)` a term is switched off only if, beyond
/// not making the score worse, its removal lowers the model's free run on the check blocks
/// by more than `k` standard errors of the paired block differences (`k` = 2: the partial-F
/// ≥ 4 of stepwise regression, asked of the removal), or leaves fewer free-run windows
/// diverging (such a window's error covers only the steps before it left the limits, so the
/// paired errors cannot show it). The rules' and the compensation's choices are the same as
/// [`select_terms`]'.
pub fn select_terms_with(
    training: &[Vec<HoverSample<f32>>],
    period_us: u32,
    evidence: Option<f64>,
) -> Result<TermSelection, rotorid::Error> {
    select(training, period_us, evidence, false)
}

/// [`select_terms`] with the premise candidates as well (`rotorid identify`'s `flight
/// selected`): after its terms, a model that keeps three rules and beats hold on
/// the check blocks may have them on the side speed (rate models) or the vertical speed
/// instead of the flight default's speed, with three sets at the training data's quantiles
/// ([`rotorid::premise::quantile_sets`]); such a change must lower the model's free run on
/// the check blocks by more than two standard errors of the paired block differences (it
/// moves the operating regions, which the check blocks revisit but a later flight need not:
/// without these guards the yaw model's envelope free run got worse, docs/ab-premises.md).
pub fn select_terms_and_schedules(
    training: &[Vec<HoverSample<f32>>],
    period_us: u32,
) -> Result<TermSelection, rotorid::Error> {
    select(training, period_us, None, true)
}

/// Standard errors a premise candidate must beat the current model's check-block free run by.
const SCHEDULE_EVIDENCE: f64 = 2.0;

fn select(
    training: &[Vec<HoverSample<f32>>],
    period_us: u32,
    evidence: Option<f64>,
    schedules: bool,
) -> Result<TermSelection, rotorid::Error> {
    let rate_hz = 1e6 / f64::from(period_us.max(1));
    let window = window_samples(rate_hz);
    let samples: usize = training.iter().map(Vec::len).sum();
    let Some(block) = block_length(samples, rate_hz, window) else {
        return Ok(TermSelection::default());
    };
    let folds: Vec<Split> = (0..FOLDS).map(|f| split(training, block, f)).collect();
    let check_samples: usize = folds.iter().flat_map(|f| &f.check).map(Vec::len).sum();
    let learn_samples: usize = folds.iter().flat_map(|f| &f.learn).map(Vec::len).sum();
    let mut selection = TermSelection {
        samples: (learn_samples, check_samples),
        ..TermSelection::default()
    };
    let gyro_noise = gyro_noise_of(training);
    // The candidates' sets, once: the vertical speed is the same variable of the velocity's
    // and the rates' premises (the paper axes' `y`), the side speed the rates' alone.
    let side = schedules
        .then(|| quantile_schedule(training, 1, ScheduledOn::SideSpeed))
        .flatten();
    let vertical = schedules
        .then(|| quantile_schedule(training, 0, ScheduledOn::VerticalSpeed))
        .flatten();
    let mut mask = TermMask::default();
    let mut current = score(mask, &folds, period_us, window, gyro_noise)?;
    selection.full = current.ratios;
    selection.candidates = 1;
    for (m, optional) in OPTIONAL.iter().enumerate() {
        // The rules first, with every term (see the module docs); ties go to one rule. Only
        // where the scheduled model beats holding the measured state on the check blocks: a
        // model worse than hold there is limited by something else (excitation, feedback,
        // turbulence), and the check blocks, which revisit the training's operating points,
        // cannot tell how the two forms extrapolate to others.
        if current.key(m).1 < 1.0 {
            let candidate = mask.with_one_rule(m);
            let one_rule = score(candidate, &folds, period_us, window, gyro_noise)?;
            selection.candidates += 1;
            if one_rule.key(m).1.is_finite() && one_rule.key(m) <= current.key(m) {
                mask = candidate;
                current = one_rule;
            }
        }
        loop {
            let mut best: Option<(TermMask, Score)> = None;
            for &t in optional.iter().filter(|&&t| !mask.is_off(m, t)) {
                // Euler's coupling goes only to stop a diverging window (see `RIGID_BODY`).
                let rigid = RIGID_BODY[m] == Some(t);
                if rigid && current.diverged == 0 {
                    continue;
                }
                let candidate = mask.without(m, t);
                let score = score(candidate, &folds, period_us, window, gyro_noise)?;
                selection.candidates += 1;
                if rigid && score.diverged >= current.diverged {
                    continue;
                }
                if best.as_ref().is_none_or(|(_, b)| score.key(m) < b.key(m)) {
                    best = Some((candidate, score));
                }
            }
            match best {
                // Ties go to the simpler model; a model that could not be scored at all
                // (no finite score) replaces nothing.
                Some((candidate, score))
                    if score.key(m).1.is_finite()
                        && score.key(m) <= current.key(m)
                        && evidence.is_none_or(|k| convinces(&score, &current, m, k)) =>
                {
                    mask = candidate;
                    current = score;
                }
                _ => break,
            }
        }
        // Then the speed its rules are on (only with `schedules`; see
        // `select_terms_and_schedules`), with the terms chosen.
        if schedules && !mask.has_one_rule(m) && current.key(m).1 < 1.0 {
            let candidates = if m == 0 {
                [None, vertical.map(|s| (ScheduledOn::VerticalSpeed, s))]
            } else {
                [
                    side.map(|s| (ScheduledOn::SideSpeed, s)),
                    vertical.map(|s| (ScheduledOn::VerticalSpeed, s)),
                ]
            };
            for (on, sets) in candidates.into_iter().flatten() {
                let candidate = mask.scheduled(m, Schedule { on, sets });
                let score = score(candidate, &folds, period_us, window, gyro_noise)?;
                selection.candidates += 1;
                if score.key(m).1.is_finite()
                    && score.key(m) < current.key(m)
                    && convinces(&score, &current, m, SCHEDULE_EVIDENCE)
                {
                    mask = candidate;
                    current = score;
                }
            }
        }
        // Then a rate's compensation, after its terms: it changes what the second-order
        // term's estimate means. Full replaces the damping term's only if it predicts
        // better (ties go to the default).
        if m > 0 && gyro_noise.is_some() {
            let candidate = mask.with_full_compensation(m);
            let full = score(candidate, &folds, period_us, window, gyro_noise)?;
            selection.candidates += 1;
            if full.key(m).1.is_finite() && full.key(m) < current.key(m) {
                mask = candidate;
                current = full;
            }
        }
    }
    selection.mask = mask;
    selection.selected = current.ratios;
    Ok(selection)
}

/// Three sets for model `m`'s rules on `on`'s speed at the training data's quantiles
/// ([`rotorid::premise::quantile_sets`], the noise floor the median over the logs of
/// [`rotorid::premise::noise_std`]); `None` when the data give none.
fn quantile_schedule(
    training: &[Vec<HoverSample<f32>>],
    m: usize,
    on: ScheduledOn,
) -> Option<[(f32, f32); 3]> {
    use rotorid::hover::{BodyFrame, Premise};
    let premise = if m == 0 {
        Premise::HorizontalSpeed
    } else {
        Premise::HeadingVelocity
    };
    let variable = on.scheduling().variable(m > 0)?;
    let mut values = Vec::new();
    let mut noise = Vec::new();
    for log in training {
        let x: Vec<f32> = log
            .iter()
            .filter_map(|s| {
                let frame = BodyFrame::of(&s.attitude);
                premise.of(s, &frame).get(variable).copied()
            })
            .collect();
        let mut scratch = vec![0.0f32; x.len()];
        noise.extend(rotorid::premise::noise_std(&x, &mut scratch));
        values.extend(x);
    }
    noise.sort_by(f32::total_cmp);
    let floor = *noise.get(noise.len() / 2)?;
    let sets = rotorid::premise::quantile_sets(&mut values, 3, floor).ok()?;
    let set = |i: usize| sets.get(i).map(|mf| mf.parameters());
    Some([set(0)?, set(1)?, set(2)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A removal counts as better beyond noise only when the paired block differences say so:
    /// a consistent 10 % gain passes at two standard errors; a larger mean gain that swings
    /// between −30 % and +10 % block to block does not (it passes on the sign alone); a loss
    /// never passes, and one block is no evidence.
    #[test]
    fn a_removal_must_beat_the_paired_blocks_noise() {
        let run = |blocks: Vec<[f64; 6]>| Score {
            diverged: 0,
            ratios: [1.0; 6],
            blocks,
        };
        let current = run(vec![[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]; 8]);
        let scaled = |f: &dyn Fn(usize) -> f64| {
            run((0..8)
                .map(|b| core::array::from_fn(|i| current.blocks[b][i] * f(b)))
                .collect())
        };
        let consistent = scaled(&|b| if b % 2 == 0 { 0.89 } else { 0.91 });
        assert!(better_beyond_noise(&consistent, &current, 3, 2.0));
        assert!(better_beyond_noise(&consistent, &current, 0, 2.0));
        let noisy = scaled(&|b| if b % 2 == 0 { 0.7 } else { 1.1 });
        assert!(!better_beyond_noise(&noisy, &current, 3, 2.0));
        assert!(better_beyond_noise(&noisy, &current, 3, 0.0));
        let worse = scaled(&|_| 1.05);
        assert!(!better_beyond_noise(&worse, &current, 3, 0.0));
        let one = run(vec![[0.5; 6]]);
        assert!(!better_beyond_noise(&one, &run(vec![[1.0; 6]]), 3, 0.0));
        // A change that stops a window diverging convinces whatever its blocks' errors (a
        // diverged window's error covers only the steps before it left the limits); one that
        // makes a window diverge never does.
        let diverging = Score {
            diverged: 1,
            ..current.clone()
        };
        assert!(convinces(&worse, &diverging, 3, 2.0));
        assert!(!convinces(&diverging, &worse, 3, 0.0));
        assert!(convinces(&consistent, &current, 3, 2.0));
        assert!(!convinces(&noisy, &current, 3, 2.0));
    }

    /// A premise candidate's sets sit at the training data's quantiles of its speed: the
    /// middle one at the median of the vertical speed (the paper axes' `y`, up); the
    /// translational model has no side speed to be scheduled on.
    #[test]
    fn premise_candidates_sit_at_the_training_datas_quantiles() {
        let log = rotorid_sim::flights::identification_flight_for(1, 40.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let training = vec![samples.clone()];
        let [l, c, r] = quantile_schedule(&training, 0, ScheduledOn::VerticalSpeed).unwrap();
        let mut up: Vec<f32> = samples.iter().map(|s| s.velocity[1]).collect();
        up.sort_by(f32::total_cmp);
        let median = up[((up.len() - 1) as f64 * 0.5 + 0.5) as usize];
        assert_eq!(c.0.to_bits(), median.to_bits());
        assert!(l.0 < c.0 && c.0 < r.0, "{l:?} {c:?} {r:?}");
        assert!([l, c, r].iter().all(|s| s.1 > 0.0));
        // The rate models' up speed is the same variable of their own premise.
        let rate = quantile_schedule(&training, 1, ScheduledOn::VerticalSpeed).unwrap();
        assert_eq!(rate[1].0.to_bits(), median.to_bits());
        assert!(quantile_schedule(&training, 1, ScheduledOn::SideSpeed).is_some());
        assert!(quantile_schedule(&training, 0, ScheduledOn::SideSpeed).is_none());
    }

    #[test]
    fn every_third_block_is_held_out_and_nothing_is_lost() {
        let log = rotorid_sim::flights::identification_flight_for(1, 40.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let s = split(std::slice::from_ref(&samples), 500, 2);
        let learnt: usize = s.learn.iter().map(Vec::len).sum();
        let held: usize = s.check.iter().map(Vec::len).sum();
        assert_eq!(learnt + held, samples.len());
        assert!(s.check.iter().all(|b| b.len() <= 500));
        // 2 000 samples: blocks 0 1 | 2 | 3: learn 0-999, check 1000-1499, learn 1500-.
        assert_eq!(s.check.len(), 1);
        assert_eq!(s.check[0][0].time_us, samples[1000].time_us);
    }

    /// The velocity model is selected first and nothing selected later enters its free run
    /// (the rates' models do not feed it), so its cross-validated score can only improve. A
    /// rate flown with the full compensation predicts its check blocks strictly better than
    /// with the damping term's alone, the rest of the choice unchanged.
    #[test]
    fn the_selection_never_worsens_the_velocity_models_cross_validated_score() {
        let log = rotorid_sim::flights::identification_flight_for(3, 75.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let training = [samples];
        let selection = select_terms(&training, 20_000).unwrap();
        assert!(selection.candidates > 1, "{selection:?}");
        assert!(
            model_score(&selection.selected, 0) <= model_score(&selection.full, 0),
            "{selection:?}"
        );
        // Every held-out sample was checked once: the folds cover the data.
        assert_eq!(selection.samples.1, 75 * 50);
        let mask = selection.mask;
        assert!(
            !mask.full_compensation[0],
            "the velocity model has no gyro noise"
        );
        // On this flight the choice is made (q's, at this commit): the check below has
        // something to check.
        assert!(mask.full_compensation.contains(&true), "{selection:?}");
        let window = window_samples(50.0);
        let block = block_length(75 * 50, 50.0, window).unwrap();
        let folds: Vec<Split> = (0..FOLDS).map(|f| split(&training, block, f)).collect();
        let noise = gyro_noise_of(&training);
        let chosen = score(mask, &folds, 20_000, window, noise).unwrap();
        for m in (1..4).filter(|&m| mask.full_compensation[m]) {
            let mut damping = mask;
            damping.full_compensation[m] = false;
            let without = score(damping, &folds, 20_000, window, noise).unwrap();
            assert!(chosen.key(m) < without.key(m), "{m}: {selection:?}");
        }
    }

    /// Euler's coupling of q̂ and p̂ stays where no free-run window diverges, whatever the
    /// check blocks say of it; the other optional terms are still selected on.
    #[test]
    fn the_inertia_coupling_stays_unless_it_stops_a_divergence() {
        let log = rotorid_sim::flights::identification_flight_for(3, 75.0).unwrap();
        let training = [rotorid_sim::flights::to_hover_samples(&log)];
        let selection = select_terms(&training, 20_000).unwrap();
        let window = window_samples(50.0);
        let block = block_length(75 * 50, 50.0, window).unwrap();
        let folds: Vec<Split> = (0..FOLDS).map(|f| split(&training, block, f)).collect();
        let full = score(
            TermMask::default(),
            &folds,
            20_000,
            window,
            gyro_noise_of(&training),
        );
        assert_eq!(full.unwrap().diverged, 0);
        for m in [1, 3] {
            assert_eq!(RIGID_BODY[m], Some(0));
            assert!(!selection.mask.is_off(m, 0), "{m}: {selection:?}");
        }
        let mut optional = (0..4).flat_map(|m| OPTIONAL[m].iter().map(move |&t| (m, t)));
        assert!(
            optional.any(|(m, t)| selection.mask.is_off(m, t)),
            "{selection:?}"
        );
    }

    #[test]
    fn too_little_data_keeps_every_term() {
        // 20 s: six blocks of 3.3 s hold one 2 s window each.
        let log = rotorid_sim::flights::identification_flight_for(1, 20.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let selection = select_terms(&[samples], 20_000).unwrap();
        assert_eq!(selection.mask, TermMask::default());
        assert_eq!(selection.candidates, 0);
    }

    #[test]
    fn short_logs_are_cut_into_six_blocks_of_at_least_two_windows() {
        // 50 Hz, 2 s windows (100 samples).
        assert_eq!(block_length(20_000, 50.0, 100), Some(1500));
        assert_eq!(block_length(9_000, 50.0, 100), Some(1500));
        assert_eq!(block_length(3_000, 50.0, 100), Some(500));
        assert_eq!(block_length(1_200, 50.0, 100), Some(200));
        assert_eq!(block_length(1_199, 50.0, 100), None);
        // 10 Hz (a real log's rate): 34 s of training make blocks of 5.6 s.
        assert_eq!(block_length(344, 10.0, 20), Some(57));
        assert_eq!(block_length(80, 10.0, 20), None);
        assert!(selects_from(1_200, 50.0) && !selects_from(1_199, 50.0));
        assert!(selects_from(240, 10.0) && !selects_from(239, 10.0));
    }

    /// A 40 s flight (too short for 30 s blocks) is still selected on, with every sample
    /// checked once over the folds.
    #[test]
    fn a_short_flight_is_selected_on() {
        let log = rotorid_sim::flights::identification_flight_for(3, 40.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let selection = select_terms(&[samples], 20_000).unwrap();
        assert!(selection.candidates > 1, "{selection:?}");
        assert_eq!(selection.samples.1, 40 * 50);
        assert!(model_score(&selection.selected, 0) <= model_score(&selection.full, 0));
    }
}
