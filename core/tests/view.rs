//! The size-erased views ([`RlsView`], `HoverIdentifier::for_each_rls`) show exactly what the
//! identifier exports, and the diagonal and trace through a view are the estimator's own bits.

use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample, ModelId};
use rotorid::rls::{Algorithm, RlsState};
use rotorid::rls::{Rls, RlsConfig};
use rotorid::{FlightIdentifier, HoverConfig, PaperFuzzyIdentifier};

fn sample(k: u64) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    HoverSample {
        time_us: 20_000 * k,
        attitude: Attitude {
            roll: 0.05 * (1.3 * t).sin(),
            pitch: 0.04 * (0.9 * t).sin(),
            yaw: 0.3,
        },
        velocity: [
            0.4 * (0.5 * t).sin(),
            0.2 * (0.7 * t).cos(),
            -3.0 - 3.0 * (0.2 * t).sin(),
        ],
        rates: [
            10.0 * (1.1 * t).sin(),
            8.0 * (1.7 * t).cos(),
            12.0 * (0.8 * t).sin(),
        ],
        controls: Controls {
            col: 0.5 + 0.05 * (2.1 * t).sin(),
            ped: 0.1 * (1.9 * t).sin(),
            lon: 0.1 * (0.6 * t).cos(),
            lat: 0.1 * (1.4 * t).sin(),
        },
    }
}

fn flat<const N: usize, const NP: usize>(s: &RlsState<f32, N, NP>) -> (u8, u32, Vec<u32>) {
    let bits = s
        .theta
        .iter()
        .chain(&s.factor)
        .map(|x| x.to_bits())
        .collect();
    (s.algorithm.code(), s.updates, bits)
}

#[test]
fn views_show_the_export_in_its_order() {
    let mut id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
    for k in 0..300 {
        id.step(&sample(k)).unwrap();
    }
    let mut seen = Vec::new();
    id.for_each_rls(|model, index, v| {
        let bits = v
            .parameters()
            .iter()
            .chain(v.packed_factor())
            .map(|x| x.to_bits())
            .collect();
        seen.push((
            model,
            index,
            (v.algorithm().code(), v.counters().updates, bits),
        ));
    });
    let snapshot = id.export();
    let mut expected = Vec::new();
    for (i, s) in snapshot.velocity.iter().enumerate() {
        expected.push((ModelId::Velocity, i, flat(s)));
    }
    for (i, s) in snapshot.pitch.iter().enumerate() {
        expected.push((ModelId::Pitch, i, flat(s)));
    }
    for (i, s) in snapshot.yaw.iter().enumerate() {
        expected.push((ModelId::Yaw, i, flat(s)));
    }
    for (i, s) in snapshot.roll.iter().enumerate() {
        expected.push((ModelId::Roll, i, flat(s)));
    }
    assert_eq!(seen.len(), 12, "3 rules × 4 models");
    assert_eq!(seen, expected);

    // A global identifier: one estimator per model.
    let mut paper = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).unwrap();
    for k in 0..50 {
        paper.step(&sample(k)).unwrap();
    }
    let mut sizes = Vec::new();
    paper.for_each_rls(|m, i, v| sizes.push((m, i, v.len(), v.packed_factor().len())));
    assert_eq!(
        sizes,
        [
            (ModelId::Velocity, 0, 54, 1485),
            (ModelId::Pitch, 0, 36, 666),
            (ModelId::Yaw, 0, 18, 171),
            (ModelId::Roll, 0, 18, 171)
        ]
    );
}

#[test]
fn diagonal_and_trace_through_a_view_are_the_estimators_bits() {
    for config in [RlsConfig::<f32>::paper(1e6), RlsConfig::robust(1e6)] {
        let mut rls = Rls::<f32, 5, 15>::new(config).unwrap();
        for k in 0..40 {
            let x = k as f32;
            let xi = [
                1.0,
                (0.3 * x).sin(),
                (0.7 * x).cos(),
                0.01 * x,
                (1.1 * x).sin(),
            ];
            rls.update(&xi, 2.0 * xi[1] - xi[2] + 0.5).unwrap();
        }
        let v = rls.view();
        let diag: Vec<u32> = v.covariance_diagonal().map(f32::to_bits).collect();
        let own: Vec<u32> = rls
            .covariance_diagonal()
            .iter()
            .map(|x| x.to_bits())
            .collect();
        assert_eq!(diag, own);
        assert_eq!(v.trace().to_bits(), rls.trace().to_bits());
        // Against the definition, entry by entry.
        for i in 0..5 {
            let p = rls.covariance(i, i).unwrap();
            assert!((v.covariance_diagonal_entry(i).unwrap() - p).abs() <= 1e-6 * p.abs().max(1.0));
        }
        assert_eq!(v.covariance_diagonal_entry(5), None);
    }
    assert_eq!(
        Algorithm::from_code(Algorithm::UdFactor.code()),
        Some(Algorithm::UdFactor)
    );
    assert_eq!(
        Algorithm::from_code(Algorithm::Covariance.code()),
        Some(Algorithm::Covariance)
    );
    assert_eq!(Algorithm::from_code(2), None);
}

#[test]
fn models_report_their_premise_and_sets() {
    use rotorid::hover::{Premise, StateModel};
    let sets = flight_sets::<f32>();
    let id = FlightIdentifier::<f32>::flight(HoverConfig::default(), sets.clone()).unwrap();
    let (premise, variables) = id.velocity_model().premise_sets();
    assert_eq!(premise, Premise::HorizontalSpeed);
    assert_eq!(variables[0], sets, "horizontal speed");
    assert!(variables[1].is_empty() && variables[2].is_empty());
    let (premise, variables) = id.roll_model().premise_sets();
    assert_eq!((premise, &variables[0]), (Premise::HeadingVelocity, &sets));
    let paper = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).unwrap();
    let (premise, variables) = paper.pitch_model().premise_sets();
    assert_eq!(premise, Premise::Rates);
    assert_eq!(
        variables.iter().map(|v| v.len()).product::<usize>(),
        18,
        "18 rules"
    );
}
