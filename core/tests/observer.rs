//! One-step prediction through an observer ([`rotorid::hover::Observer`]) and the search for
//! its gain ([`rotorid::hover::GainSearch`]).
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use crate::support::flight_log;

use flight_log::flight_log;
use rotorid::hover::{
    flight_sets, Attitude, Controls, GainSearch, HoverSample, HoverState, Observer, RateNoise,
};
use rotorid::{ConfigError, Error, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig};

const TRAINING: u64 = 0x9E37_79B9_7F4A_7C15;
const VERIFICATION: u64 = 0x2545_F491_4F6C_DD1D;

fn trained(log: &[HoverSample<f32>]) -> FlightIdentifier<f32> {
    let mut id = FlightIdentifier::flight(HoverConfig::default(), flight_sets()).unwrap();
    for s in log {
        id.step(s).unwrap();
    }
    id
}

fn bits(s: &HoverState<f32>) -> [u32; 6] {
    s.to_array().map(f32::to_bits)
}

#[test]
fn gain_one_predicts_from_the_measured_state_bit_for_bit() {
    let id = trained(&flight_log(3_000, 0.3, TRAINING));
    let log = flight_log(1_000, 0.3, VERIFICATION);
    let mut observer = Observer::measured();
    let mut before: Option<HoverState<f32>> = None;
    for s in &log {
        let observed = observer.predict(&id, s).unwrap();
        let direct = id.predict_after(before.as_ref(), s).unwrap();
        assert_eq!(bits(&observed), bits(&direct));
        assert_eq!(observer.estimate(), Some(s.state()));
        before = Some(s.state());
    }
}

#[test]
fn gain_zero_is_the_free_run_bit_for_bit() {
    let id = trained(&flight_log(3_000, 0.3, TRAINING));
    let log = flight_log(200, 0.3, VERIFICATION);
    let mut observer = Observer::new([0.0; 6]).unwrap();
    // The model fed its own state, from the first sample's measured one.
    let mut x = log[0].state();
    let mut before: Option<HoverState<f32>> = None;
    for s in &log {
        let observed = observer.predict(&id, s).unwrap();
        let own = HoverSample {
            velocity: x.velocity,
            rates: x.rates,
            ..*s
        };
        let simulated = id.predict_after(before.as_ref(), &own).unwrap();
        assert_eq!(bits(&observed), bits(&simulated));
        before = Some(x);
        x = simulated;
    }
}

#[test]
fn a_refused_sample_or_gain_changes_nothing() {
    let id = trained(&flight_log(1_000, 0.3, TRAINING));
    let log = flight_log(20, 0.3, VERIFICATION);
    let mut observer = Observer::new([0.5; 6]).unwrap();
    let mut search = GainSearch::<f32, 4>::grid();
    for s in &log[..10] {
        observer.predict(&id, s).unwrap();
        search.push(&id, s).unwrap();
    }
    let (kept, kept_search) = (observer, search);
    let next = log[10];
    let mut nan = next;
    nan.rates[1] = f32::NAN;
    let mut late = next;
    late.time_us += 15_000;
    let mut early = next;
    early.time_us = log[9].time_us;
    for (bad, expected) in [
        (nan, "NonFinite"),
        (late, "TimeStep"),
        (early, "NonMonotonicTime"),
    ] {
        let e = observer.predict(&id, &bad).unwrap_err();
        assert!(format!("{e:?}").starts_with(expected), "{e:?}");
        assert!(search.push(&id, &bad).is_err());
        assert_eq!(format!("{observer:?}"), format!("{kept:?}"));
        assert_eq!(format!("{search:?}"), format!("{kept_search:?}"));
    }
    // After a gap the caller restarts: the sample is then taken as measured.
    observer.restart();
    let restarted = observer.predict(&id, &late).unwrap();
    assert_eq!(
        bits(&restarted),
        bits(&id.predict_after(None, &late).unwrap())
    );

    for (gain, index) in [
        ([0.5, 0.5, 0.5, f32::NAN, 0.5, 0.5], 3),
        ([0.5, -0.1, 0.5, 0.5, 0.5, 0.5], 1),
        ([0.5, 0.5, 0.5, 0.5, 0.5, 1.01], 5),
    ] {
        assert_eq!(
            Observer::new(gain).unwrap_err(),
            Error::Config(ConfigError::ObserverGain { index })
        );
    }
    assert_eq!(
        GainSearch::new([0.5f32, f32::INFINITY]).unwrap_err(),
        Error::Config(ConfigError::ObserverGain { index: 1 })
    );
}

#[test]
fn the_search_is_its_candidates_run_one_by_one() {
    let id = trained(&flight_log(2_000, 0.3, TRAINING));
    let log = flight_log(600, 0.3, VERIFICATION);
    let mut search = GainSearch::<f32, 10>::grid();
    assert_eq!(search.best(), None);
    for s in &log {
        search.push(&id, s).unwrap();
    }
    assert_eq!(search.count(), 599);
    let mut least = [(f32::INFINITY, 0.0f32); 6];
    for n in 0..10 {
        let k = search.candidate(n).unwrap();
        assert_eq!(k, (n + 1) as f32 / 10.0);
        let mut alone = Observer::new([k; 6]).unwrap();
        let mut sums = [0.0f32; 6];
        for s in &log {
            if let Some(p) = alone.prediction() {
                for ((sum, y), p) in sums.iter_mut().zip(s.state().to_array()).zip(p.to_array()) {
                    *sum += (y - p) * (y - p);
                }
            }
            alone.predict(&id, s).unwrap();
        }
        let mean = sums.map(|s| s / 599.0);
        assert_eq!(
            search.mean_square(n).unwrap().map(f32::to_bits),
            mean.map(f32::to_bits)
        );
        for (l, &m) in least.iter_mut().zip(&mean) {
            if m < l.0 {
                *l = (m, k);
            }
        }
    }
    assert_eq!(search.best().unwrap().gain(), least.map(|l| l.1));
    assert_eq!(search.candidate(10), None);
}

/// A standard normal deviate (Box-Muller) from a uniform generator on (0, 1).
fn normal(uniform: &mut impl FnMut() -> f64) -> f64 {
    let (a, b) = (uniform(), uniform());
    libm::sqrt(-2.0 * libm::log(a)) * libm::cos(2.0 * core::f64::consts::PI * b)
}

/// The steady-state Kalman gain of `x(k+1) = a x(k) + w`, `y = x + v` (variances `q`, `r`).
fn kalman_gain(a: f64, q: f64, r: f64) -> f64 {
    let b = r * (1.0 - a * a) - q;
    let predicted = (-b + libm::sqrt(b * b + 4.0 * q * r)) / 2.0;
    predicted / (predicted + r)
}

#[test]
fn the_search_finds_the_kalman_gain_of_a_first_order_rate() {
    // The pitch rate of a plain model with only its damping set, q(k+1) = a q(k) + w, measured
    // with white noise: the gain of least one-step error is the steady-state Kalman gain.
    let a = 0.9;
    for (q, r, seed) in [(0.25f64, 1.0f64, 7u64), (4.0, 1.0, 11), (1.0, 0.04, 13)] {
        let mut id =
            ExtendedPlainIdentifier::<f64>::extended_plain(HoverConfig::default()).unwrap();
        let mut snapshot = id.export();
        // Helicopter scaling: the damping term's scale is 10 deg/s, the target's 1 deg/s.
        snapshot.pitch.theta[2] = (a - 1.0) * 10.0;
        id.import(&snapshot).unwrap();

        let mut state = seed;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let mut search = GainSearch::<f64, 10>::grid();
        let mut x = 0.0;
        for k in 0..40_000u64 {
            let sample = HoverSample {
                time_us: k * 20_000,
                attitude: Attitude::default(),
                velocity: [0.0; 3],
                rates: [x + r.sqrt() * normal(&mut uniform), 0.0, 0.0],
                controls: Controls {
                    col: 0.5,
                    ..Controls::default()
                },
            };
            search.push(&id, &sample).unwrap();
            x = a * x + q.sqrt() * normal(&mut uniform);
        }
        let found = search.best().unwrap().gain()[3];
        let expected = kalman_gain(a, q, r);
        // `-- --nocapture` shows them.
        eprintln!("q {q}, r {r}: found {found}, steady-state Kalman gain {expected:.3}");
        assert!(
            (found - expected).abs() < 0.1,
            "q {q}, r {r}: found {found}, Kalman {expected:.3}"
        );
    }
}

#[test]
fn on_noisy_gyros_the_observer_predicts_better_than_the_measured_state() {
    // The flight identifier learns from noisy gyros, is compensated for their noise, and its
    // gain is found on the training flight; on another flight its one-step error on every
    // rate is below that of the prediction from the measured state.
    let training = flight_log(12_000, 0.3, TRAINING);
    let mut id = trained(&training);
    let mut noise = RateNoise::<f32>::new();
    for s in &training {
        noise.push(&s.rates).unwrap();
    }
    id.compensate(&noise.std_dev().unwrap()).unwrap();
    let mut search = GainSearch::<f32, 10>::grid();
    for s in &training {
        search.push(&id, s).unwrap();
    }
    let best = search.best().unwrap();
    let gain = best.gain();
    assert!(gain[3..].iter().all(|&k| k < 1.0), "{gain:?}");

    let verification = flight_log(6_000, 0.3, VERIFICATION);
    let mut errors = [[0.0f64; 3]; 2];
    for (observer, sums) in [best, Observer::measured()].iter_mut().zip(&mut errors) {
        for s in &verification {
            if let Some(p) = observer.prediction() {
                for ((sum, y), p) in sums.iter_mut().zip(s.rates).zip(p.rates) {
                    *sum += f64::from(y - p).powi(2);
                }
            }
            observer.predict(&id, s).unwrap();
        }
    }
    let [observed, measured] = errors;
    for i in 0..3 {
        assert!(
            observed[i] < 0.95 * measured[i],
            "rate {i}: observer {observed:?}, measured state {measured:?}"
        );
    }
}
