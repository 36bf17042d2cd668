//! Compensating the rate models for the gyros' white noise
//! ([`HoverIdentifier::compensate`](rotorid::HoverIdentifier::compensate)).
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use crate::support::flight_log;

use flight_log::flight_log;
use rotorid::hover::{flight_sets, GyroCompensation, HoverSample, RateNoise};
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

/// The bits of θ and of the factor of every rule of one model's export.
fn bits<const N: usize, const NP: usize>(rules: &[rotorid::rls::RlsState<f32, N, NP>]) -> Vec<u32> {
    rules
        .iter()
        .flat_map(|r| r.theta.iter().chain(&r.factor))
        .map(|x| x.to_bits())
        .collect()
}

#[test]
fn each_rate_takes_the_compensation_chosen_for_it() {
    use GyroCompensation::{Damping, Full};
    let noisy = trained(&flight_log(12_000, 0.3, SEED));
    let sigma = [0.3; 3];
    let with = |how: [GyroCompensation; 3]| {
        let mut id = noisy.clone();
        id.compensate_each(&sigma, how).unwrap();
        id.export()
    };
    let (damping, full, mixed) = (
        with([Damping; 3]),
        with([Full; 3]),
        with([Full, Damping, Damping]),
    );
    // The two compensations differ on pitch and roll (else this test could not fail; on
    // yaw this flight's rules fall back to the damping term's)...
    assert_ne!(bits(&full.pitch), bits(&damping.pitch));
    assert_ne!(bits(&full.roll), bits(&damping.roll));
    // ...and each rate of the mixed choice is bit for bit its own choice's.
    assert_eq!(bits(&mixed.pitch), bits(&full.pitch));
    assert_eq!(bits(&mixed.yaw), bits(&damping.yaw));
    assert_eq!(bits(&mixed.roll), bits(&damping.roll));
    assert_eq!(bits(&mixed.velocity), bits(&noisy.export().velocity));
    // compensate_with is the same choice on every rate.
    let mut uniform = noisy.clone();
    uniform.compensate_with(&sigma, Full).unwrap();
    assert_eq!(bits(&uniform.export().roll), bits(&full.roll));
}
