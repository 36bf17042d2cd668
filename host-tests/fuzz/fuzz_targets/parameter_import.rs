//! Arbitrary exported states into `import`: a refused state changes nothing; an accepted one
//! keeps the identifier's predictions finite on a regular stream.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid::hover::{Attitude, Controls, HoverSample};
use rotorid::{ExtendedPlainIdentifier, HoverConfig};
use rotorid_link::msg::read_rls_state;
use rotorid_link::Reader;

fuzz_target!(|data: &[u8]| {
    let Ok(mut id) = ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()) else {
        return;
    };
    let mut r = Reader::new(data);
    let (Ok(velocity), Ok(pitch), Ok(yaw), Ok(roll)) = (
        read_rls_state::<7, 28>(&mut r),
        read_rls_state::<5, 15>(&mut r),
        read_rls_state::<5, 15>(&mut r),
        read_rls_state::<5, 15>(&mut r),
    ) else {
        return;
    };
    let snapshot = rotorid::hover::HoverSnapshot {
        velocity,
        pitch,
        yaw,
        roll,
    };
    let before = id.clone();
    if id.import(&snapshot).is_err() {
        assert!(id == before, "a refused import changed the identifier");
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
            // An imported state may be absurd (huge but finite θ); the core then refuses what
            // would overflow rather than return a non-finite number.
            assert!(out.prediction.to_array().iter().all(|x| x.is_finite()));
        }
    }
});
