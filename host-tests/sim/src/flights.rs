//! The paper's flights on the X-Cell 60 plant (Section 6, Table 2).
//!
//! * [`identification_flight`]: the four Table 2 sweeps made by the core's
//!   [`SweepSchedule`], one channel at a time (the hover-hold pilot flies the other three),
//!   3 s at trim before and after each, reduced amplitude at low frequency, flown back to back
//!   in one continuous flight (so the sweeps are concatenated without time jumps).
//! * [`verification_flight`]: different inputs (doublets and 3-2-1-1 multisteps on all four
//!   controls, some large, separated by pilot-held hover: the paper "periodically perturbs the
//!   helicopter to a new hover state"), flown with a different seed by the caller.
//! * [`to_hover_samples`]: NED / forward-right-down (rad/s) samples to the paper's axes
//!   (`v^s = [v_x v_y v_z]` m/s east-up-south, `ω^b = [q r p]` deg/s) with
//!   [`rotorid::frames`].
//!
//! Both flights use [`FlightConfig::realistic`]: 50 Hz with ±2 ms jitter, GPS/INS-like
//! measurement noise and light turbulence.

use nalgebra::Vector3;
use rotorid::frames::NedFrdSample;
use rotorid::hover::{Attitude, Controls, HoverSample};
use rotorid::sweep::{Channel as SweepChannel, Sweep, SweepSchedule};

use crate::plant::{
    simulate, verification_excitation_scaled, Channel, Flight, FlightConfig, HoverPilot,
    PilotGains, PlantError, SensorSample,
};

/// Sample rate of every flight (Hz); the identifiers' ΔT is 20 ms.
pub const SAMPLE_RATE_HZ: u32 = 50;

/// The sweeps of the identification flight, as flown on the X-Cell 60 plant, in the order
/// lon, lat, ped, col.
///
/// Frequencies and lengths are Table 2's; C1 = 4, C2 = 0.0187 (the paper's values); 3 s trim
/// pads. The paper gives no amplitudes; ours (stick units, added to trim) and their
/// low-frequency reduction (`low_frequency_gain` at ω_min rising linearly in ν to full at
/// `full_amplitude_from`) are chosen so each sweep stays within ≈ 2 m/s of hover (seed 1:
/// lon 1.6 m/s, lat 1.6 m/s, ped 0.4 m/s, col 1.8 m/s peak) while the rates reach the range the
/// verification flight visits:
///
/// | channel | A | gain at ω_min | full from (rad/s) | why |
/// |---|---|---|---|---|
/// | `u_lon` | 0.20 | 0.3 | 4 | the pitch axis integrates the stick; low frequencies tilt the disc longest |
/// | `u_lat` | 0.20 | 0.3 | 4 | the same for roll |
/// | `u_ped` | 0.08 | 0.5 | 4 | no yaw damper: ≈ 39 rad/s² per unit of pedal |
/// | `u_col` | 0.10 | 0.5 | 1 | ≈ 27 m/s² per unit; hover collective ≈ 0.5 stays far above 0 |
///
/// The drift the plant engineer warned of (a lon sweep of 0.013 reaching ≈ 7 m/s) is not a
/// matter of amplitude: left alone, the X-Cell's pitch attitude wanders off under turbulence
/// and the start of a sine sweep leaves a mean attitude offset `≈ 1.75 A(0)/ω_min` behind, so
/// any uncontrolled 45 s sweep drifts. The flight therefore keeps a pilot in the loop on the
/// swept channel at [`SWEPT_CHANNEL_PILOT_GAIN`] of the hover-hold gains, whose corrections lie
/// below the sweep band (see [`identification_flight`]).
pub fn identification_sweeps() -> [Sweep; 4] {
    let mut lon = Sweep::table2(SweepChannel::Longitudinal, 0.2);
    lon.low_frequency_gain = 0.3;
    lon.full_amplitude_from = 4.0;
    let mut lat = Sweep::table2(SweepChannel::Lateral, 0.2);
    lat.low_frequency_gain = 0.3;
    lat.full_amplitude_from = 4.0;
    let mut ped = Sweep::table2(SweepChannel::Pedal, 0.08);
    ped.low_frequency_gain = 0.5;
    ped.full_amplitude_from = 4.0;
    let mut col = Sweep::table2(SweepChannel::Collective, 0.1);
    col.low_frequency_gain = 0.5;
    col.full_amplitude_from = 1.0;
    [lon, lat, ped, col]
}

/// The identification schedule: [`identification_sweeps`] in the order lon, lat, ped, col at
/// [`SAMPLE_RATE_HZ`].
pub fn identification_schedule() -> Result<SweepSchedule<4>, rotorid::Error> {
    SweepSchedule::new(identification_sweeps(), SAMPLE_RATE_HZ)
}

/// The plant's channel for a sweep channel.
pub fn plant_channel(ch: SweepChannel) -> Channel {
    match ch {
        SweepChannel::Collective => Channel::Col,
        SweepChannel::Pedal => Channel::Ped,
        SweepChannel::Longitudinal => Channel::Lon,
        SweepChannel::Lateral => Channel::Lat,
    }
}

/// Length of the identification flight (s): the four sweeps with their trim pads (255 s).
pub fn identification_duration_s() -> f64 {
    identification_sweeps().iter().map(Sweep::total_s).sum()
}

/// The identification flight: the four Table 2 sweeps of [`identification_sweeps`],
/// concatenated in one continuous realistic flight (noise, turbulence, jitter from `seed`),
/// 255 s, 12 750 samples.
///
/// The hover-hold pilot flies the three channels that are not swept; the swept channel gets
/// `slow-pilot correction + sweep offset`, the slow pilot being the hover-hold pilot at
/// [`SWEPT_CHANNEL_PILOT_GAIN`] of its gains. The recorded sticks are what was applied.
pub fn identification_flight(seed: u64) -> Result<Vec<SensorSample>, PlantError> {
    identification_flight_for(seed, f64::INFINITY)
}

/// The first `duration_s` seconds of [`identification_flight`] (the whole flight if longer),
/// for short tests and demos.
pub fn identification_flight_for(
    seed: u64,
    duration_s: f64,
) -> Result<Vec<SensorSample>, PlantError> {
    identification_flight_with(&FlightConfig::realistic(seed, 0.0), duration_s)
}

/// [`identification_flight_for`] with any flight configuration (for example without noise
/// and turbulence); its `duration` is replaced by `duration_s` (at most the sweeps' length).
pub fn identification_flight_with(
    config: &FlightConfig,
    duration_s: f64,
) -> Result<Vec<SensorSample>, PlantError> {
    let schedule = identification_schedule()
        .map_err(|e| PlantError::InvalidConfig(format!("identification sweeps: {e}")))?;
    let full = f64::from(schedule.len()) / f64::from(SAMPLE_RATE_HZ);
    let duration = if duration_s.is_nan() {
        full
    } else {
        duration_s.clamp(0.0, full)
    };
    let config = FlightConfig {
        duration,
        ..*config
    };
    let n = (duration * f64::from(SAMPLE_RATE_HZ) + 1e-9).floor();
    let n = if n > 0.0 { n as u32 } else { 0 };
    let mut flight = Flight::new(&config)?;
    let trim = *flight.trim();
    let gains = config.pilot_gains();
    let mut pilot = HoverPilot::new(gains, &trim.state);
    let mut slow_pilot = HoverPilot::new(slow_gains(&gains), &trim.state);
    let mut out = Vec::with_capacity(n as usize);
    for k in 0..n {
        let state = *flight.state();
        let sticks = match schedule.at(k) {
            Some(e) => {
                let ch = plant_channel(e.channel);
                let mut sticks = pilot.command(&state, &trim, Some(ch), 0.0);
                let slow = slow_pilot.command(&state, &trim, None, 0.0);
                sticks.set(ch, slow.get(ch) + e.offset * config.stick_scale.get(ch));
                sticks
            }
            None => pilot.command(&state, &trim, None, 0.0),
        };
        out.push(flight.step_with_sticks(sticks)?);
    }
    Ok(out)
}

/// Gain of the pilot on the swept channel relative to the hover-hold pilot: at 1/5 the
/// attitude loops close near 0.6 rad/s (pitch, roll), below Table 2's ω_min of lon and lat,
/// so the pilot's corrections stay below the sweep band, as a human pilot's slow retrimming
/// does during a sweep, while the axis no longer drifts away (the uncontrolled pitch axis of
/// the X-Cell drifts several m/s within a 45 s sweep).
pub const SWEPT_CHANNEL_PILOT_GAIN: f64 = 0.2;

fn slow_gains(g: &PilotGains) -> PilotGains {
    let s = SWEPT_CHANNEL_PILOT_GAIN;
    PilotGains {
        pitch_att: g.pitch_att * s,
        pitch_rate: g.pitch_rate * s,
        roll_att: g.roll_att * s,
        roll_rate: g.roll_rate * s,
        vertical_speed: g.vertical_speed * s,
        altitude: g.altitude * s,
        yaw_rate: g.yaw_rate * s,
        heading: g.heading * s,
        ..*g
    }
}

/// A verification flight of `duration_s` seconds: after 3 s of hover, doublets and 3-2-1-1
/// multisteps on all four controls (one in four a large excursion) separated by 2.5–5 s of
/// pilot-held hover ([`crate::plant::verification_excitation`]); realistic sensors from `seed`. Use a seed
/// other than the identification flight's.
pub fn verification_flight(seed: u64, duration_s: f64) -> Result<Vec<SensorSample>, PlantError> {
    verification_flight_with(&FlightConfig::realistic(seed, duration_s))
}

/// [`verification_flight`] with any flight configuration (its seed, duration, airframe and
/// sensors); the manoeuvres are scaled by its [`FlightConfig::stick_scale`].
pub fn verification_flight_with(config: &FlightConfig) -> Result<Vec<SensorSample>, PlantError> {
    let mut excitation =
        verification_excitation_scaled(config.seed, config.duration, config.stick_scale);
    simulate(config, &mut excitation)
}

/// A sample in the paper's axes and units through [`NedFrdSample::to_paper`]:
/// `time_us = round(t · 10⁶)`, attitude (rad) unchanged, `v^s = [v_e, −v_d, −v_n]` (m/s),
/// `[q r p]` in deg/s, sticks as recorded.
pub fn to_hover_sample(s: &SensorSample) -> HoverSample<f32> {
    let time = (s.t * 1e6).round();
    let time_us = if time.is_finite() && time > 0.0 {
        time as u64
    } else {
        0
    };
    NedFrdSample {
        time_us,
        attitude: Attitude {
            roll: s.roll as f32,
            pitch: s.pitch as f32,
            yaw: s.yaw as f32,
        },
        velocity_ned: Vector3::new(s.v_north as f32, s.v_east as f32, s.v_down as f32),
        rates_frd: Vector3::new(s.p as f32, s.q as f32, s.r as f32),
        controls: Controls {
            col: s.sticks.col as f32,
            ped: s.sticks.ped as f32,
            lon: s.sticks.lon as f32,
            lat: s.sticks.lat as f32,
        },
    }
    .to_paper()
}

/// [`to_hover_sample`] over a whole log.
pub fn to_hover_samples(log: &[SensorSample]) -> Vec<HoverSample<f32>> {
    log.iter().map(to_hover_sample).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::Sticks;

    fn sensor(t: f64) -> SensorSample {
        SensorSample {
            t,
            sticks: Sticks {
                col: 0.5,
                ped: 0.1,
                lon: -0.2,
                lat: 0.3,
            },
            roll: 0.1,
            pitch: -0.05,
            yaw: 1.0,
            v_north: 1.0,
            v_east: 2.0,
            v_down: 3.0,
            p: 0.1,
            q: 0.2,
            r: 0.3,
        }
    }

    #[test]
    fn hover_sample_is_in_paper_axes() {
        let h = to_hover_sample(&sensor(1.234_567_4));
        assert_eq!(h.time_us, 1_234_567);
        assert_eq!(h.velocity, [2.0, -3.0, -1.0]);
        let deg = |x: f64| x.to_degrees() as f32;
        for (a, b) in h.rates.iter().zip([deg(0.2), deg(0.3), deg(0.1)]) {
            assert!((a - b).abs() < 1e-4, "{a} {b}");
        }
        assert_eq!(h.controls.col, 0.5);
        assert_eq!(h.controls.lat, 0.3);
        assert_eq!(h.attitude.yaw, 1.0);
    }

    #[test]
    fn sweeps_are_valid_and_table2_long() {
        let s = identification_schedule().expect("valid sweeps");
        assert_eq!(s.len(), 12_750);
        assert!((identification_duration_s() - 255.0).abs() < 1e-9);
    }
}
