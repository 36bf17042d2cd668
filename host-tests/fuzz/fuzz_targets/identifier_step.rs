//! Arbitrary sample streams into the flight and the paper's fuzzy identifiers: never a panic,
//! a refused sample changes nothing (compared with a copy taken before), an accepted one never
//! yields a non-finite prediction.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample};
use rotorid::{FlightIdentifier, HoverConfig, PaperFuzzyIdentifier};

const SAMPLE_BYTES: usize = 8 + 13 * 4;

fn sample(b: &[u8]) -> HoverSample<f32> {
    let f =
        |i: usize| f32::from_le_bytes([b[8 + 4 * i], b[9 + 4 * i], b[10 + 4 * i], b[11 + 4 * i]]);
    HoverSample {
        // Mostly 20 ms steps, so that the models really learn; any value now and then.
        time_us: u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        attitude: Attitude {
            roll: f(0),
            pitch: f(1),
            yaw: f(2),
        },
        velocity: [f(3), f(4), f(5)],
        rates: [f(6), f(7), f(8)],
        controls: Controls {
            col: f(9),
            ped: f(10),
            lon: f(11),
            lat: f(12),
        },
    }
}

macro_rules! drive {
    ($id:expr, $data:expr) => {{
        let mut id = $id;
        let mut t = 0u64;
        for chunk in $data.chunks_exact(SAMPLE_BYTES) {
            let mut s = sample(chunk);
            // The first byte picks the timing: 0..=199 a regular 20 ms step, else as given.
            if chunk[0] < 200 {
                t += 20_000;
                s.time_us = t;
            }
            let before = id.clone();
            match id.step(&s) {
                Ok(out) => assert!(out.prediction.to_array().iter().all(|x| x.is_finite())),
                Err(_) => assert!(id == before, "a refused sample changed the identifier"),
            }
        }
    }};
}

fuzz_target!(|data: &[u8]| {
    if let Ok(id) = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()) {
        drive!(id, data);
    }
    if let Ok(id) = PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()) {
        drive!(id, data);
    }
});
