//! The cost of every identifier's step on a stream that fires every rule: the worst case the
//! flight stream cannot show (a hover flight fires 3 of the 27 translational rules).
//!
//! The stream sweeps every premise variable over its whole range within the first seconds
//! (forward speed 0–10 m/s, vertical speed ±1.2 m/s, rates ±30 deg/s), so that every rule of
//! every rule base has fired before the measured steps: from then on every update visits all
//! parameters, and the fuzzy models' longest branches run. The flight identifier's three
//! forward-speed rules all stay above the local-learning threshold around 5 m/s, where the
//! stream spends most of its time. Compiled in this crate, at the opt-level of the onboard
//! identifiers.

use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample};
use rotorid::{
    Error, ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier,
    FlightPlainIdentifier, HoverConfig, PaperFuzzyIdentifier, PaperLocalIdentifier,
    PaperPlainIdentifier,
};

/// Steps per identifier (the table's run).
pub const STEPS: u32 = 400;
/// Steps before measuring (every rule has fired by then).
pub const WARM_UP: u32 = 150;

/// Sample k of the stream (50 Hz). Not inlined, so that its instructions are the same
/// addresses in every loop (`step_profile --identifier` subtracts the stream's).
#[inline(never)]
pub fn sample(k: u32) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    let s = |w: f32, phase: f32| libm::sinf(w * t + phase);
    // Forward speed 5 ± 5 m/s (period ≈ 4 s), heading slowly turning.
    let speed = 5.0 + 5.0 * s(1.6, 0.0);
    let yaw = 0.5 * s(0.3, 0.0);
    HoverSample {
        time_us: 1_000_000 + u64::from(k) * 20_000,
        attitude: Attitude {
            roll: 0.2 * s(0.9, 0.3),
            pitch: -0.05 + 0.15 * s(1.3, 1.0),
            yaw,
        },
        velocity: [
            speed * libm::sinf(yaw) + 1.5 * s(2.1, 0.5),
            1.2 * s(2.9, 0.0),
            -speed * libm::cosf(yaw),
        ],
        rates: [30.0 * s(3.1, 0.0), 30.0 * s(2.3, 1.0), 30.0 * s(3.7, 2.0)],
        controls: Controls {
            col: 0.5 + 0.1 * s(0.7, 0.0),
            ped: 0.2 * s(2.3, 0.0),
            lon: 0.2 * s(1.9, 0.0),
            lat: 0.2 * s(2.9, 0.0),
        },
    }
}

/// One identifier's figures: mean and largest SysTick ticks per step over the measured steps.
pub struct StepCost {
    /// Identifier type.
    pub name: &'static str,
    /// Mean ticks per step.
    pub mean_ticks: u64,
    /// Largest ticks of one step.
    pub max_ticks: u64,
    /// Steps measured.
    pub steps: u32,
    /// Steps the identifier refused (0 expected).
    pub rejected: u32,
    /// FNV-1a hash of the bits of every prediction (all steps): the same on every target, or
    /// the numbers differ (a host test compares the Cortex-M4F's with x86_64's).
    pub hash: u32,
}

/// FNV-1a over 32-bit words.
fn fnv(hash: u32, word: u32) -> u32 {
    word.to_le_bytes()
        .iter()
        .fold(hash, |h, &b| (h ^ u32::from(b)).wrapping_mul(0x0100_0193))
}

/// Which identifiers a run steps, and how far.
#[derive(Copy, Clone)]
pub struct Selection<'a> {
    /// Only the identifier of this name (`None`: every one).
    pub only: Option<&'a str>,
    /// Steps per identifier.
    pub steps: u32,
}

impl Selection<'_> {
    /// The table's run: every identifier, [`STEPS`] steps.
    pub const ALL: Selection<'static> = Selection {
        only: None,
        steps: STEPS,
    };

    fn includes(&self, name: &str) -> bool {
        self.only.is_none_or(|n| n == name)
    }
}

/// The name that selects no identifier but the stream alone: the same loop (samples, stopwatch,
/// hash of six words per step) without a step, which `step_profile --identifier` subtracts.
pub const STREAM_ONLY: &str = "stream";

macro_rules! measure {
    ($name:expr, $build:expr, $selection:expr, $timer:expr, $report:expr) => {{
        if $selection.includes($name) {
            let built: Result<_, Error> = $build;
            if let Ok(mut id) = built {
                let (mut sum, mut max, mut rejected) = (0u64, 0u64, 0u32);
                let mut hash = 0x811c_9dc5u32;
                for k in 0..$selection.steps {
                    let s = sample(k);
                    $timer.restart();
                    let out = id.step(&s);
                    let t = $timer.elapsed();
                    match out {
                        Ok(o) => {
                            for x in o.prediction.to_array() {
                                hash = fnv(hash, x.to_bits());
                            }
                        }
                        Err(_) => rejected += 1,
                    }
                    if k >= WARM_UP {
                        sum += t;
                        max = max.max(t);
                    }
                }
                let steps = $selection.steps.saturating_sub(WARM_UP);
                $report(&StepCost {
                    name: $name,
                    mean_ticks: sum / u64::from(steps.max(1)),
                    max_ticks: max,
                    steps,
                    rejected,
                    hash,
                });
            }
        }
    }};
}

/// A stopwatch (SysTick or a cycle counter).
pub trait Timer {
    /// Restarts at zero.
    fn restart(&mut self);
    /// Ticks since the restart.
    fn elapsed(&mut self) -> u64;
}

/// Measures every identifier that fits the stack (all but `ExtendedFuzzyIdentifier`, 27 KiB)
/// and reports each.
pub fn run(timer: &mut dyn Timer, report: &mut dyn FnMut(&StepCost)) {
    run_selected(Selection::ALL, timer, report);
}

/// [`run`] for the selected identifiers and step count (`step_profile --identifier` traces
/// one identifier for two step counts).
#[inline(never)]
pub fn run_selected(
    selection: Selection<'_>,
    timer: &mut dyn Timer,
    report: &mut dyn FnMut(&StepCost),
) {
    if selection.only == Some(STREAM_ONLY) {
        stream_only(selection.steps, timer, report);
        return;
    }
    let c = HoverConfig::<f32>::default();
    measure!(
        "FlightIdentifier",
        FlightIdentifier::flight(c, flight_sets()),
        selection,
        timer,
        report
    );
    measure!(
        "FlightPlainIdentifier",
        FlightPlainIdentifier::flight_plain(c),
        selection,
        timer,
        report
    );
    measure!(
        "ExtendedPlainIdentifier",
        ExtendedPlainIdentifier::extended_plain(c),
        selection,
        timer,
        report
    );
    measure!(
        "ExtendedLocalIdentifier",
        ExtendedLocalIdentifier::extended_local(c),
        selection,
        timer,
        report
    );
    measure!(
        "PaperLocalIdentifier",
        PaperLocalIdentifier::paper_local(HoverConfig::paper_robust()),
        selection,
        timer,
        report
    );
    measure!(
        "PaperPlainIdentifier",
        PaperPlainIdentifier::paper_plain(HoverConfig::paper_robust()),
        selection,
        timer,
        report
    );
    measure!(
        "PaperFuzzyIdentifier",
        PaperFuzzyIdentifier::paper_fuzzy(HoverConfig::paper_robust()),
        selection,
        timer,
        report
    );
}

/// The loop of `measure!` without an identifier (see [`STREAM_ONLY`]).
fn stream_only(steps: u32, timer: &mut dyn Timer, report: &mut dyn FnMut(&StepCost)) {
    let mut hash = 0x811c_9dc5u32;
    for k in 0..steps {
        let s = core::hint::black_box(sample(k));
        timer.restart();
        let t = timer.elapsed();
        for x in s.velocity.into_iter().chain(s.rates) {
            hash = fnv(hash, x.to_bits());
        }
        core::hint::black_box(t);
    }
    report(&StepCost {
        name: STREAM_ONLY,
        mean_ticks: 0,
        max_ticks: 0,
        steps,
        rejected: 0,
        hash,
    });
}
