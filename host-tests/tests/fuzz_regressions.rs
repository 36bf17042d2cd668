//! Inputs the fuzzers (`scripts/fuzz.sh`) found, kept as regression tests.

use rotorid::hover::{Attitude, Controls, HoverSample, HoverSnapshot};
use rotorid::{ExtendedPlainIdentifier, HoverConfig};
use rotorid_link::msg::read_rls_state;
use rotorid_link::Reader;

/// `parameter_import`: an exported state with parameters near 1e38 was imported, and the next
/// step returned `Ok` with a non-finite prediction. Parameters beyond `PARAMETER_LIMIT` are
/// refused at import now, and no prediction comes out of an `Ok` unless it is finite.
#[test]
fn absurd_imported_parameters_never_give_a_non_finite_prediction() {
    let data = include_bytes!("data/fuzz_parameter_import.bin");
    let mut id = ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()).unwrap();
    let mut r = Reader::new(data);
    let snapshot = HoverSnapshot {
        velocity: read_rls_state::<7, 28>(&mut r).unwrap(),
        pitch: read_rls_state::<5, 15>(&mut r).unwrap(),
        yaw: read_rls_state::<5, 15>(&mut r).unwrap(),
        roll: read_rls_state::<5, 15>(&mut r).unwrap(),
    };
    let before = id.clone();
    if id.import(&snapshot).is_err() {
        assert_eq!(id, before);
        return;
    }
    for k in 0..50u64 {
        let t = k as f32 * 0.02;
        let s = HoverSample {
            time_us: k * 20_000,
            attitude: Attitude {
                roll: 0.02,
                pitch: -0.01,
                yaw: 0.1 * t,
            },
            velocity: [0.1, 0.0, -0.1],
            rates: [1.0, -0.5, 0.3],
            controls: Controls {
                col: 0.5,
                ped: 0.02,
                lon: 0.01,
                lat: -0.01,
            },
        };
        if let Ok(out) = id.step(&s) {
            assert!(out.prediction.to_array().iter().all(|x| x.is_finite()));
        }
    }
}
