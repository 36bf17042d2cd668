//! A synthetic flight for the tests: second-order rate dynamics, noisy gyros.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use rotorid::hover::{Attitude, Controls, HoverSample};

/// A manoeuvring helicopter whose rates follow second-order dynamics driven by the sticks,
/// flying forward at up to 10 m/s and back (every forward-speed rule fires), and its gyros
/// measured with uniform white noise of standard deviation `sigma` (deg/s), drawn by an
/// xorshift generator from `seed` (non-zero): another seed, another flight.
pub fn flight_log(samples: u64, sigma: f64, seed: u64) -> Vec<HoverSample<f32>> {
    let mut state = seed;
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
