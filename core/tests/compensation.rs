//! Compensating the rate models for the gyros' white noise
//! ([`HoverIdentifier::compensate`](rotorid::HoverIdentifier::compensate)).
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use crate::support::flight_log;

use flight_log::flight_log;
use rotorid::hover::{flight_sets, HoverSample, RateNoise};
use rotorid::{Error, FlightIdentifier, HoverConfig, PaperFuzzyIdentifier};

/// The noise generator's seed of every log here.
const SEED: u64 = 0x9E37_79B9_7F4A_7C15;

fn trained(log: &[HoverSample<f32>]) -> FlightIdentifier<f32> {
    let mut id = FlightIdentifier::flight(HoverConfig::default(), flight_sets()).unwrap();
    for s in log {
        id.step(s).unwrap();
    }
    id
}

/// Damping δ and second-order term η of each rate model's rules (physical units).
fn rate_terms(id: &FlightIdentifier<f32>) -> Vec<f32> {
    let mut terms = Vec::new();
    for rule in 0..3 {
        for term in [2, 6] {
            let ts = [
                id.pitch_model().ts(),
                id.yaw_model().ts(),
                id.roll_model().ts(),
            ];
            terms.extend(ts.iter().map(|t| t.physical_parameter(rule, term).unwrap()));
        }
    }
    terms
}

#[test]
fn compensation_brings_the_rate_terms_back_towards_the_noise_free_estimate() {
    let sigma = 0.3;
    let clean = rate_terms(&trained(&flight_log(12_000, 0.0, SEED)));
    let noisy_log = flight_log(12_000, sigma, SEED);
    let noisy = trained(&noisy_log);
    // The rates are smooth at the sample scale: σ̂ is within a tenth.
    let mut estimate = RateNoise::<f32>::new();
    for s in &noisy_log {
        estimate.push(&s.rates).unwrap();
    }
    for s in estimate.std_dev().unwrap() {
        assert!((f64::from(s) - sigma).abs() < 0.1 * sigma, "σ̂ {s}");
    }
    let gyro_noise = [sigma as f32; 3];
    let mut compensated = noisy.clone();
    let outcome = compensated.compensate(&gyro_noise).unwrap();
    assert_eq!(
        (outcome.compensated, outcome.refused),
        (9, 0),
        "{outcome:?}"
    );
    let (before, after) = (rate_terms(&noisy), rate_terms(&compensated));
    let distance =
        |terms: &[f32]| -> f32 { terms.iter().zip(&clean).map(|(a, b)| (a - b).abs()).sum() };
    assert!(
        distance(&after) < 0.7 * distance(&before),
        "noise-free {clean:?}\nleast squares {before:?}\ncompensated {after:?}"
    );
}

#[test]
fn no_noise_compensates_to_the_same_bits_and_bad_noise_changes_nothing() {
    let id = trained(&flight_log(2_000, 0.3, SEED));
    let mut same = id.clone();
    same.compensate(&[0.0; 3]).unwrap();
    assert_eq!(same, id);
    for bad in [[f32::NAN, 0.3, 0.3], [0.3, -0.1, 0.3], [0.3, 0.3, 2001.0]] {
        let mut refused = id.clone();
        assert!(matches!(
            refused.compensate(&bad),
            Err(Error::NonFinite(_) | Error::OutOfRange(_))
        ));
        assert_eq!(refused, id);
    }
}

#[test]
fn only_the_flight_rate_structure_is_compensated() {
    let mut paper = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).unwrap();
    for s in &flight_log(500, 0.3, SEED) {
        paper.step(s).unwrap();
    }
    let before = paper.clone();
    let outcome = paper.compensate(&[0.3; 3]).unwrap();
    assert_eq!((outcome.compensated, outcome.refused), (0, 0));
    assert_eq!(paper, before);
}
