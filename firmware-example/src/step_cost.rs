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

/// Steps per identifier.
pub const STEPS: u32 = 400;
/// Steps before measuring (every rule has fired by then).
pub const WARM_UP: u32 = 150;

/// Sample k of the stream (50 Hz).
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

macro_rules! measure {
    ($name:expr, $build:expr, $timer:expr, $report:expr) => {{
        let built: Result<_, Error> = $build;
        if let Ok(mut id) = built {
            let (mut sum, mut max, mut rejected) = (0u64, 0u64, 0u32);
            let mut hash = 0x811c_9dc5u32;
            for k in 0..STEPS {
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
            let steps = STEPS - WARM_UP;
            $report(&StepCost {
                name: $name,
                mean_ticks: sum / u64::from(steps),
                max_ticks: max,
                steps,
                rejected,
                hash,
            });
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
#[inline(never)]
pub fn run(timer: &mut dyn Timer, report: &mut dyn FnMut(&StepCost)) {
    let c = HoverConfig::<f32>::default();
    measure!(
        "FlightIdentifier",
        FlightIdentifier::flight(c, flight_sets()),
        timer,
        report
    );
    measure!(
        "FlightPlainIdentifier",
        FlightPlainIdentifier::flight_plain(c),
        timer,
        report
    );
    measure!(
        "ExtendedPlainIdentifier",
        ExtendedPlainIdentifier::extended_plain(c),
        timer,
        report
    );
    measure!(
        "ExtendedLocalIdentifier",
        ExtendedLocalIdentifier::extended_local(c),
        timer,
        report
    );
    measure!(
        "PaperLocalIdentifier",
        PaperLocalIdentifier::paper_local(HoverConfig::paper_robust()),
        timer,
        report
    );
    measure!(
        "PaperPlainIdentifier",
        PaperPlainIdentifier::paper_plain(HoverConfig::paper_robust()),
        timer,
        report
    );
    measure!(
        "PaperFuzzyIdentifier",
        PaperFuzzyIdentifier::paper_fuzzy(HoverConfig::paper_robust()),
        timer,
        report
    );
}
