//! Are a log's body rates in rad/s? Judged from the data: the body rates implied by the
//! attitude's rate of change are compared with the logged rates. A log in deg/s whose rates
//! stay under the plausibility limit (34.9, gentle flight) passes every per-value check but
//! is 57.3 times too large here.
//!
//! Over windows of [`WINDOW`] samples, the attitude difference gives the Euler rates
//! (φ̇, θ̇, ψ̇) (yaw unwrapped), turned into body rates at the window's mid attitude:
//! `p = φ̇ − ψ̇ sin θ`, `q = θ̇ cos φ + ψ̇ cos θ sin φ`, `r = −θ̇ sin φ + ψ̇ cos θ cos φ`.
//! The logged rates are averaged over the same window. The least-squares gain
//! `k = Σ ω_att·ω_log / Σ ω_log²` is about 1 for rad/s and about 1/57.3 for deg/s (the gain
//! regresses the attitude's noisier differences on the logged rates, so noise does not bias it).

use crate::plant::SensorSample;

/// Samples per window (0.1 s at 50 Hz): long enough that attitude noise (0.2 deg) differences
/// to a few deg/s, short enough for manoeuvres.
pub const WINDOW: usize = 5;

/// Below this root-mean-square attitude-implied body rate (rad/s, about 3 deg/s) the flight is
/// too calm to judge the rates' unit.
pub const MIN_RMS_RADPS: f64 = 0.05;

/// Gain `k` below which the rates are judged to be in deg/s (geometric middle of 1 and 1/57.3
/// is 0.13).
pub const DEGREES_BELOW: f64 = 0.13;

/// The least-squares gain `k` from logged to attitude-implied body rates, or `None` when the
/// flight is too short or too calm to judge.
pub fn rate_gain(samples: &[SensorSample]) -> Option<f64> {
    let (mut cross, mut log_sq, mut att_sq, mut n) = (0.0, 0.0, 0.0, 0usize);
    for w in samples.windows(WINDOW + 1).step_by(WINDOW) {
        let (a, b) = (&w[0], &w[WINDOW]);
        let dt = b.t - a.t;
        if dt <= 0.0 {
            continue;
        }
        let mut dyaw = b.yaw - a.yaw;
        while dyaw > std::f64::consts::PI {
            dyaw -= std::f64::consts::TAU;
        }
        while dyaw < -std::f64::consts::PI {
            dyaw += std::f64::consts::TAU;
        }
        let (dphi, dtheta, dpsi) = ((b.roll - a.roll) / dt, (b.pitch - a.pitch) / dt, dyaw / dt);
        let (phi, theta) = ((a.roll + b.roll) / 2.0, (a.pitch + b.pitch) / 2.0);
        let att = [
            dphi - dpsi * theta.sin(),
            dtheta * phi.cos() + dpsi * theta.cos() * phi.sin(),
            -dtheta * phi.sin() + dpsi * theta.cos() * phi.cos(),
        ];
        // Mean logged rate over the window (the rate of a row holds until the next).
        let m = WINDOW as f64;
        let logged = w[..WINDOW].iter().fold([0.0; 3], |acc, s| {
            [acc[0] + s.p / m, acc[1] + s.q / m, acc[2] + s.r / m]
        });
        for i in 0..3 {
            cross += att[i] * logged[i];
            log_sq += logged[i] * logged[i];
            att_sq += att[i] * att[i];
        }
        n += 1;
    }
    let rms = (att_sq / (3 * n.max(1)) as f64).sqrt();
    (n >= 4 && rms >= MIN_RMS_RADPS && log_sq > 0.0).then(|| cross / log_sq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::Sticks;

    /// A gentle roll-and-yaw oscillation: rates about 0.3 rad/s (18 deg/s), under 34.9 either way.
    fn gentle(scale: f64) -> Vec<SensorSample> {
        (0..500)
            .map(|k| {
                let t = k as f64 * 0.02;
                let w = std::f64::consts::PI;
                SensorSample {
                    t,
                    sticks: Sticks {
                        col: 0.5,
                        ped: 0.4,
                        lon: 0.0,
                        lat: 0.0,
                    },
                    roll: 0.1 * (w * t).sin(),
                    pitch: 0.0,
                    yaw: 0.1 * (w * t).cos(),
                    v_north: 0.0,
                    v_east: 0.0,
                    v_down: 0.0,
                    p: scale * 0.1 * w * (w * t).cos(),
                    q: 0.0,
                    r: -scale * 0.1 * w * (w * t).sin(),
                }
            })
            .collect()
    }

    #[test]
    fn radians_give_about_one_degrees_about_one_over_57() {
        let k = rate_gain(&gentle(1.0)).expect("enough motion");
        assert!((k - 1.0).abs() < 0.1, "{k}");
        let k = rate_gain(&gentle(180.0 / std::f64::consts::PI)).expect("enough motion");
        assert!(k < DEGREES_BELOW && k > 0.01, "{k}");
    }

    #[test]
    fn calm_or_short_flight_gives_no_verdict() {
        let mut calm = gentle(1.0);
        calm.iter_mut().for_each(|s| {
            s.roll = 0.01;
            s.yaw = 0.0;
        });
        assert_eq!(rate_gain(&calm), None);
        assert_eq!(rate_gain(&gentle(1.0)[..10]), None);
    }
}
