//! Wide-envelope flights: the pilot carries the X-Cell 60 through operating points from hover
//! to 12 m/s forward, ±5 m/s sideways and ±3 m/s vertical, while doublets and 3-2-1-1
//! multisteps on all four controls excite the dynamics at each of them.
//!
//! Hover data are nearly linear, so a fuzzy model can only show what it is for (the paper's
//! "more global model ... a wider range of operation of the flight envelope") where the local
//! dynamics change with the operating point: the fin's yaw damping and the stabiliser's pitch
//! damping grow with airspeed, the rotor's flapping couples with the advance ratio, drag is
//! quadratic in speed. The plant tests check that the linearised dynamics at 0 and 10 m/s do
//! differ.
//!
//! * [`EnvelopeKind::Identification`] (seed 1 in the reports) and
//!   [`EnvelopeKind::Verification`] (seed 2) fly different set-point schedules and different
//!   manoeuvres (the same generator as the hover verification flight, [`crate::plant::verification_excitation`]).
//! * The set-points are in the heading frame, `[forward, right, down]` (m/s), ramped at
//!   1 m/s² (horizontal) and 0.5 m/s² (vertical); each is held for [`DWELL_S`] seconds.
//! * The hover-hold pilot flies all four channels around its set-point, with slow integrators
//!   that find the trim attitude and collective away from hover (its own loops are
//!   proportional); a manoeuvre is added to the pilot's command on its channel.

use crate::plant::{
    verification_excitation_scaled, Flight, FlightConfig, HoverPilot, PlantError, SensorSample,
};

/// Seconds each operating point is flown (ramp included).
pub const DWELL_S: f64 = 25.0;

/// Which envelope flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnvelopeKind {
    /// The training flight: 12 operating points.
    Identification,
    /// The held-out flight: 8 other operating points, in another order.
    Verification,
}

/// `[forward, right, down]` set-points (m/s) of an envelope flight, flown in order.
pub fn operating_points(kind: EnvelopeKind) -> &'static [[f64; 3]] {
    match kind {
        EnvelopeKind::Identification => &[
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [8.0, 0.0, 0.0],
            [12.0, 0.0, 0.0],
            [12.0, 0.0, -3.0],
            [12.0, 0.0, 3.0],
            [6.0, 0.0, 0.0],
            [0.0, 5.0, 0.0],
            [0.0, -5.0, 0.0],
            [0.0, 0.0, -3.0],
            [0.0, 0.0, 3.0],
            [0.0, 0.0, 0.0],
        ],
        EnvelopeKind::Verification => &[
            [10.0, 0.0, 0.0],
            [10.0, 3.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, -4.0, 0.0],
            [6.0, 0.0, -2.0],
            [11.0, 0.0, 2.0],
            [0.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
        ],
    }
}

/// Duration of an envelope flight (s).
pub fn duration_s(kind: EnvelopeKind) -> f64 {
    operating_points(kind).len() as f64 * DWELL_S
}

/// Integral gains of the trim-finding loops: pitch and roll attitude per m/s of velocity
/// error per second (rad/(m/s)/s), collective per m/s of vertical-speed error per second.
/// About 3 s time constants against the pilot's proportional velocity loop.
const TRIM_GAINS: [f64; 3] = [0.02, 0.02, 0.03];
/// Limits of the trim offsets: pitch, roll (rad), collective (stick).
const TRIM_LIMITS: [f64; 3] = [0.3, 0.3, 0.3];
/// Set-point slew rates (m/s²): horizontal, vertical.
const SLEW: [f64; 2] = [1.0, 0.5];

/// Flies an envelope flight with realistic sensors from `seed`.
pub fn envelope_flight(seed: u64, kind: EnvelopeKind) -> Result<Vec<SensorSample>, PlantError> {
    envelope_flight_with(&FlightConfig::realistic(seed, duration_s(kind)), kind)
}

/// [`envelope_flight`] with any flight configuration (its duration is the schedule's).
pub fn envelope_flight_with(
    config: &FlightConfig,
    kind: EnvelopeKind,
) -> Result<Vec<SensorSample>, PlantError> {
    let duration = duration_s(kind);
    let config = FlightConfig {
        duration,
        ..*config
    };
    let period = 1.0 / config.sample_rate;
    let n = (duration * config.sample_rate + 1e-9).floor() as u64;
    let mut excitation = verification_excitation_scaled(config.seed, duration, config.stick_scale);
    let mut flight = Flight::new(&config)?;
    let trim = *flight.trim();
    let mut pilot = HoverPilot::new(config.pilot_gains(), &trim.state);
    // The collective's trim integrator works in stick units: scaled like the pilot.
    let col_scale = config.stick_scale.col;
    let trim_gains = [TRIM_GAINS[0], TRIM_GAINS[1], TRIM_GAINS[2] * col_scale];
    let trim_limits = [TRIM_LIMITS[0], TRIM_LIMITS[1], TRIM_LIMITS[2] * col_scale];
    let points = operating_points(kind);
    let mut reference = [0.0f64; 3];
    let mut out = Vec::with_capacity(n as usize);
    for k in 0..n {
        let t = k as f64 * period;
        let index = ((t / DWELL_S) as usize).min(points.len() - 1);
        let target = points[index];
        for (axis, (r, &goal)) in reference.iter_mut().zip(target.iter()).enumerate() {
            let slew = if axis == 2 { SLEW[1] } else { SLEW[0] } * period;
            *r += (goal - *r).clamp(-slew, slew);
        }
        pilot.velocity_ref = reference;
        let state = *flight.state();
        // Trim-finding integrators on the heading-frame velocity errors.
        let (_, _, yaw) = state.euler();
        let v = state.vel_ned();
        let (sy, cy) = yaw.sin_cos();
        let errors = [
            cy * v.x + sy * v.y - reference[0],
            -(-sy * v.x + cy * v.y - reference[1]),
            v.z - reference[2],
        ];
        for ((o, &e), (&gain, &limit)) in pilot
            .offsets
            .iter_mut()
            .zip(errors.iter())
            .zip(trim_gains.iter().zip(trim_limits.iter()))
        {
            *o = (*o + gain * e * period).clamp(-limit, limit);
        }
        let e = excitation(k, flight.time());
        let mut sticks = pilot.command(&state, &trim, None, 0.0);
        if let Some(ch) = e.channel {
            let value = if e.value.is_finite() { e.value } else { 0.0 };
            sticks.set(ch, sticks.get(ch) + value);
        }
        out.push(flight.step_with_sticks(sticks)?);
    }
    Ok(out)
}
