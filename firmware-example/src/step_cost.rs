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

use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample, Observer, Quaternion};
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

/// [`sample`] with its attitude as a quaternion (PX4's form), computed outside the timed
/// step: what a flight stack that holds a quaternion passes.
#[inline(never)]
pub fn quaternion_sample(k: u32) -> HoverSample<f32, Quaternion<f32>> {
    let s = sample(k);
    s.with_attitude(Quaternion::from_euler(&s.attitude))
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

/// How many inputs [`sqrt_hash`] takes.
pub const SQRT_INPUTS: u32 = (0x7f80_0000 >> 12) + 1 + 2 + 256;

/// The bit patterns [`sqrt_hash`] takes the square root of: one in every 4 096 positive `f32`
/// bit patterns from +0 to +∞ (its low 12 bits varied), −0, the largest value, and the 256
/// smallest subnormals ([`SQRT_INPUTS`] in all).
pub fn sqrt_inputs() -> impl Iterator<Item = u32> {
    let spread =
        (0..=(0x7f80_0000u32 >> 12)).map(|i| i << 12 | (i.wrapping_mul(0x9e37_79b9) >> 20));
    spread.chain([0x8000_0000, 0x7f7f_ffff]).chain(1..=256)
}

/// FNV-1a of the bits of [`rotorid::Real::sqrt_ieee`] over [`sqrt_inputs`]. On the
/// Cortex-M4F that is the FPU's `vsqrt.f32`, on x86_64 `libm`'s `sqrtf` (`sqrtss`): a host
/// test compares the two hashes.
pub fn sqrt_hash() -> u32 {
    sqrt_inputs().fold(0x811c_9dc5, |hash, bits| {
        let x = core::hint::black_box(f32::from_bits(bits));
        fnv(hash, rotorid::Real::sqrt_ieee(x).to_bits())
    })
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

/// The running figures of one row: ticks of the measured steps, refusals, hash of the
/// predictions.
struct Tally {
    sum: u64,
    max: u64,
    rejected: u32,
    hash: u32,
}

impl Tally {
    fn new() -> Self {
        Self {
            sum: 0,
            max: 0,
            rejected: 0,
            hash: 0x811c_9dc5,
        }
    }

    /// Step `k` took `ticks` and gave `prediction` (its six states), or was refused.
    fn record(&mut self, k: u32, ticks: u64, prediction: Option<[f32; 6]>) {
        match prediction {
            Some(p) => {
                for x in p {
                    self.hash = fnv(self.hash, x.to_bits());
                }
            }
            None => self.rejected += 1,
        }
        if k >= WARM_UP {
            self.sum += ticks;
            self.max = self.max.max(ticks);
        }
    }

    /// The row of `name` after `steps` steps.
    fn cost(&self, name: &'static str, steps: u32) -> StepCost {
        let steps = steps.saturating_sub(WARM_UP);
        StepCost {
            name,
            mean_ticks: self.sum / u64::from(steps.max(1)),
            max_ticks: self.max,
            steps,
            rejected: self.rejected,
            hash: self.hash,
        }
    }
}

macro_rules! measure {
    ($name:expr, $build:expr, $selection:expr, $timer:expr, $report:expr) => {
        measure!($name, $build, sample, $selection, $timer, $report)
    };
    ($name:expr, $build:expr, $sample:expr, $selection:expr, $timer:expr, $report:expr) => {{
        if $selection.includes($name) {
            let built: Result<_, Error> = $build;
            if let Ok(mut id) = built {
                let mut tally = Tally::new();
                for k in 0..$selection.steps {
                    let s = $sample(k);
                    $timer.restart();
                    let out = id.step(&s);
                    let t = $timer.elapsed();
                    tally.record(k, t, out.ok().map(|o| o.prediction.to_array()));
                }
                $report(&tally.cost($name, $selection.steps));
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
    quaternion_row(c, selection, timer, report);
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
    if selection.includes(FLIGHT_OBSERVER) {
        flight_observer(selection.steps, timer, report);
    }
}

/// The flight identifier with quaternion attitudes ([`FLIGHT_QUATERNION`]), unless the
/// firmware is built with its feature `euler-only` (host-tests includes this file without it).
#[allow(unexpected_cfgs)]
fn quaternion_row(
    c: HoverConfig<f32>,
    selection: Selection<'_>,
    timer: &mut dyn Timer,
    report: &mut dyn FnMut(&StepCost),
) {
    #[cfg(not(feature = "euler-only"))]
    measure!(
        FLIGHT_QUATERNION,
        FlightIdentifier::flight(c, flight_sets()),
        quaternion_sample,
        selection,
        timer,
        report
    );
    let _ = (c, selection, timer, report);
}

/// The name of the flight identifier's row with the attitude as a quaternion
/// ([`quaternion_sample`]): no trigonometry in the step.
pub const FLIGHT_QUATERNION: &str = "FlightIdentifier/quaternion";

/// The name of the observer's row: [`Observer::predict`] beside a learning
/// `FlightIdentifier` (the identifier's own step is not counted).
pub const FLIGHT_OBSERVER: &str = "FlightIdentifier, Observer::predict";

/// [`FLIGHT_OBSERVER`]'s figures: the flight identifier steps through the stream, and after each
/// step an observer (gain 0.5 on every state) predicts the next sample from it; only the
/// observer is timed, and its predictions are hashed.
fn flight_observer(steps: u32, timer: &mut dyn Timer, report: &mut dyn FnMut(&StepCost)) {
    let (Ok(mut id), Ok(mut observer)) = (
        FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()),
        Observer::new([0.5; 6]),
    ) else {
        return;
    };
    let mut tally = Tally::new();
    for k in 0..steps {
        let s = sample(k);
        let learnt = id.step(&s).is_ok();
        timer.restart();
        let out = observer.predict(&id, &s);
        let t = timer.elapsed();
        let prediction = out.ok().filter(|_| learnt).map(|p| p.to_array());
        tally.record(k, t, prediction);
    }
    report(&tally.cost(FLIGHT_OBSERVER, steps));
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
