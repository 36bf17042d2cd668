//! Compensating the rate models for the gyros' white noise
//! ([`HoverIdentifier::compensate`](rotorid::HoverIdentifier::compensate)).
use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample, RateNoise};
use rotorid::{Error, FlightIdentifier, HoverConfig, PaperFuzzyIdentifier};

/// A manoeuvring helicopter whose rates follow second-order dynamics driven by the sticks,
/// flying forward at up to 10 m/s and back (every forward-speed rule fires), and its gyros
/// measured with uniform white noise of standard deviation `sigma` (deg/s).
fn flight_log(samples: u64, sigma: f64) -> Vec<HoverSample<f32>> {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let (mut stick, mut target) = (0.0f64, 0.0f64);
    let (mut w, mut w_before) = ([0.0f64; 3], [0.0f64; 3]);
    let mut log = Vec::new();
    for k in 0..samples {
        let t = k as f64 * 0.02;
        // A pilot's stick: smooth at the sample scale (a first-order lag of random steps).
        if k % 20 == 0 {
            target = 0.1 * uniform();
        }
        stick += 0.1 * (target - stick);
        // ω(k+1) = ω(k) + a (ω(k) − ω(k−1)) − d ω(k) + g u: a lightly damped rotor lag.
        let next = [0, 1, 2].map(|i| {
            let (a, d, g) = [(0.5, 0.08, 40.0), (0.3, 0.05, 60.0), (0.6, 0.1, 50.0)][i];
            w[i] + a * (w[i] - w_before[i]) - d * w[i] + g * stick * (1.0 + 0.1 * i as f64)
        });
        let speed = 5.0 - 5.0 * (0.05 * t).cos();
        let noisy = w.map(|x| (x + sigma * 3f64.sqrt() * uniform()) as f32);
        log.push(HoverSample {
            time_us: 1_000_000 + k * 20_000,
            attitude: Attitude {
                roll: (0.05 * (0.7 * t).sin()) as f32,
                pitch: (-0.03 + 0.04 * (1.3 * t).cos()) as f32,
                yaw: 0.0,
            },
            velocity: [0.0, (0.3 * (0.9 * t).cos()) as f32, -speed as f32],
            rates: noisy,
            controls: Controls {
                col: (0.5 + 0.05 * (0.3 * t).sin()) as f32,
                ped: stick as f32,
                lon: (stick * 1.1) as f32,
                lat: (stick * 1.2) as f32,
            },
        });
        (w_before, w) = (w, next);
    }
    log
}

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
    let clean = rate_terms(&trained(&flight_log(12_000, 0.0)));
    let noisy_log = flight_log(12_000, sigma);
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
    let id = trained(&flight_log(2_000, 0.3));
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
    for s in &flight_log(500, 0.3) {
        paper.step(s).unwrap();
    }
    let before = paper.clone();
    let outcome = paper.compensate(&[0.3; 3]).unwrap();
    assert_eq!((outcome.compensated, outcome.refused), (0, 0));
    assert_eq!(paper, before);
}
