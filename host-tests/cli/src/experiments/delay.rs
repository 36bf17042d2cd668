//! The controls' delay: how long after a logged command the airframe responds to it, chosen
//! from the training data.
//!
//! An autopilot logs each command when its controller computes it; the ESCs and motors (tens
//! of milliseconds to spin up), or the servos and the rotor's flapping, act on the airframe
//! later. The identifier learns `x(k+1)` from `u(k)`, so a command that acts a step late reads
//! as a weak, noisy control power and drives a free run out of phase. Tried at fixed delays on
//! the logs committed here (`rotorid identify LOG --control-delay 0.1`), the best delay differs
//! by vehicle, and a wrong one costs more than none: 100 ms helped every PX4 multicopter and
//! made the flight default's free run on ArduPilot's SITL helicopter diverge. A one-step
//! least-squares fit does not find
//! it (in closed loop the controller's output tracks the rates it reacts to, and the fits were
//! best at no delay on the multicopters whose free runs improved most with one), so the delay
//! is chosen the way [`select_terms`](super::select_terms) chooses terms: by the free run.
//!
//! [`select_delay`] cuts the training data into the same learning and check blocks, and for
//! each candidate of [`candidates`] learns the flight default on the learning blocks with the
//! controls delayed ([`delayed`]) and runs it free on the check blocks. The delay with the
//! lowest geometric mean of `free run / hold` over the six states is chosen (fewer diverged
//! windows first; ties go to the shorter delay).

use rotorid::hover::HoverSample;
use rotorid_sim::plant::SensorSample;
use serde::{Deserialize, Serialize};

use super::evaluation::gyro_noise_of;
use super::mask::TermMask;
use super::selection::{block_length, geometric_mean, score, split, window_samples, Split, FOLDS};

/// Longest delay tried (s): a slow helicopter servo and the rotor's flapping lag together; a
/// multicopter's motors are well within it.
pub const MAX_CONTROL_DELAY_S: f64 = 0.15;

/// Finest spacing of the candidates (s): at 50 Hz one sample step, above it a whole number
/// of steps at least this long.
pub const DELAY_SPACING_S: f64 = 0.02;

/// What the delay selection found.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DelaySelection {
    /// The delay applied (s): a whole number of sample steps.
    pub delay_s: f64,
    /// Each candidate's score, shortest delay first; empty when the delay was given
    /// (`--control-delay`).
    pub scores: Vec<DelayScore>,
}

/// One candidate delay's free run on the check blocks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DelayScore {
    /// The delay (s).
    pub delay_s: f64,
    /// The geometric mean over the six states of `free run / hold` (`None`: not finite).
    pub score: Option<f64>,
    /// Free-run windows that left the core's sample limits (they count first: a diverged
    /// window stops early, and its error would flatter the candidate).
    pub diverged: usize,
}

/// The candidate delays at `rate_hz`, in whole sample steps (a delay within a step would
/// have to be interpolated, which smooths the controls as well as delaying them): 0 up to
/// [`MAX_CONTROL_DELAY_S`], one step apart or more to keep them [`DELAY_SPACING_S`] apart.
/// At 10 Hz that is 0 and 100 ms; at 25 Hz 0, 40, 80, 120 ms; at 50 Hz 0 to 140 ms.
pub fn candidates(rate_hz: f64) -> Vec<usize> {
    let step_s = 1.0 / rate_hz;
    let spacing = (DELAY_SPACING_S / step_s).ceil().max(1.0) as usize;
    let last = (MAX_CONTROL_DELAY_S / step_s + 1e-9).floor() as usize;
    (0..=last).step_by(spacing).collect()
}

/// `samples` with each sample's sticks those of `steps` samples earlier; the first `steps`
/// samples, whose delayed sticks are not in the log, are dropped.
pub fn delayed(samples: &[SensorSample], steps: usize) -> Vec<SensorSample> {
    samples
        .iter()
        .skip(steps)
        .zip(samples)
        .map(|(s, earlier)| SensorSample {
            sticks: earlier.sticks,
            ..*s
        })
        .collect()
}

/// Chooses the controls' delay from `training` at `period_us` (see the module docs); `None`
/// when the data are too short to check candidates on (as for the term selection).
pub fn select_delay(
    training: &[Vec<SensorSample>],
    period_us: u32,
) -> Result<Option<DelaySelection>, rotorid::Error> {
    let rate_hz = 1e6 / f64::from(period_us.max(1));
    let window = window_samples(rate_hz);
    let samples: usize = training.iter().map(Vec::len).sum();
    let Some(block) = block_length(samples, rate_hz, window) else {
        return Ok(None);
    };
    let candidates = candidates(rate_hz);
    let longest = candidates.iter().copied().max().unwrap_or(0);
    // Every candidate on the same samples: those after the longest delay.
    let shifted = |steps: usize| -> Vec<Vec<HoverSample<f32>>> {
        training
            .iter()
            .map(|log| {
                let log = delayed(log, steps);
                rotorid_sim::flights::to_hover_samples(
                    log.get(longest - steps..).unwrap_or_default(),
                )
            })
            .collect()
    };
    // The gyro noise of the rates (over all the training data), which no delay changes.
    let all: Vec<Vec<HoverSample<f32>>> = training
        .iter()
        .map(|log| rotorid_sim::flights::to_hover_samples(log))
        .collect();
    let gyro_noise = gyro_noise_of(&all);
    let mut best: Option<(f64, (usize, f64))> = None;
    let mut scores = Vec::new();
    for steps in candidates {
        let data = shifted(steps);
        let folds: Vec<Split> = (0..FOLDS).map(|f| split(&data, block, f)).collect();
        let s = score(TermMask::default(), &folds, period_us, window, gyro_noise)?;
        let mean = Some(geometric_mean(&s.ratios, &[0, 1, 2, 3, 4, 5])).filter(|m| m.is_finite());
        let delay_s = steps as f64 / rate_hz;
        scores.push(DelayScore {
            delay_s,
            score: mean,
            diverged: s.diverged,
        });
        let key = (s.diverged, mean.unwrap_or(f64::INFINITY));
        if best.is_none_or(|(_, b)| key < b) {
            best = Some((delay_s, key));
        }
    }
    Ok(best.map(|(delay_s, _)| DelaySelection { delay_s, scores }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_are_whole_steps_up_to_150_ms() {
        assert_eq!(candidates(10.0), [0, 1]);
        assert_eq!(candidates(25.0), [0, 1, 2, 3]);
        assert_eq!(candidates(50.0), [0, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(candidates(100.0), [0, 2, 4, 6, 8, 10, 12, 14]);
    }

    #[test]
    fn a_delayed_log_reads_the_sticks_of_earlier_samples() {
        let samples = rotorid_sim::flights::identification_flight_for(1, 2.0).unwrap();
        assert_eq!(delayed(&samples, 0), samples);
        let two = delayed(&samples, 2);
        assert_eq!(two.len(), samples.len() - 2);
        for (k, s) in two.iter().enumerate() {
            assert_eq!(s.t, samples[k + 2].t);
            assert_eq!(s.q, samples[k + 2].q);
            assert_eq!(s.sticks, samples[k].sticks);
        }
        assert!(delayed(&samples[..3], 5).is_empty());
    }

    /// On a simulated flight whose sticks act when they are logged the selection keeps no
    /// delay; with the same flight logged 40 ms early (each row's sticks those that act two
    /// samples later, as an autopilot logs a command its motors take that long to follow)
    /// it finds the 40 ms.
    #[test]
    fn the_selection_finds_the_delay_a_log_was_given() {
        let flight = rotorid_sim::flights::identification_flight_for(2, 60.0).unwrap();
        let period = super::super::period_us(50.0);
        let none = select_delay(std::slice::from_ref(&flight), period)
            .unwrap()
            .expect("60 s is enough to choose on");
        assert_eq!(none.delay_s, 0.0, "{:?}", none.scores);
        let early: Vec<SensorSample> = flight
            .iter()
            .zip(flight.iter().skip(2))
            .map(|(s, later)| SensorSample {
                sticks: later.sticks,
                ..*s
            })
            .collect();
        let found = select_delay(&[early], period).unwrap().unwrap();
        assert_eq!(found.delay_s, 0.04, "{:?}", found.scores);
        assert_eq!(found.scores.len(), candidates(50.0).len());
    }
}
