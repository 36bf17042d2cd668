//! What a real flight log needs before identification, between reading its channels and
//! resampling them: implausible stretches cut out, ground time trimmed, time-stamp glitches
//! reported, and the identification rate chosen from the channels' own logging rates.
//!
//! Every decision is a [`Cut`] or a note, so the user sees what was left out and why; nothing
//! refuses a whole flight for one bad stretch.

use super::resample::{Channels, Cut, Series, TimeGlitch, MAX_SOURCE_GAP_S, RATE_HZ};
use crate::log::MAX_RATE_RADPS;

/// Largest plausible |velocity| component (m/s): the core's sample limit.
pub const MAX_VELOCITY_MPS: f64 = 100.0;

/// A normalised control beyond ±1 by more than this is implausible (a unit or scaling
/// problem, a corrupt record). Within it, the controller asked for more than the actuators
/// give (PX4's `ATTC` outputs go a few per cent past ±1 in real logs): the mixer saturates
/// it, the rotor saw ±1, and the value is clamped, with a note.
pub const CONTROL_SLACK: f64 = 1.0;

/// A collective (thrust) at or below this, normalised 0…1, is the rotor at idle: on the
/// ground, whatever the autopilot's land detector says (it declares a landing late).
pub const IDLE_COLLECTIVE: f64 = 0.05;

/// The rates the identification may run at (Hz), fastest first: divisors of the core's
/// 50 Hz default period in whole milliseconds.
pub const IDENTIFICATION_RATES_HZ: [f64; 5] = [50.0, 25.0, 20.0, 10.0, 5.0];

/// A channel whose native rate is within this fraction below a candidate rate still
/// supports it (logging jitter: 49 Hz logs are 50 Hz logs).
const RATE_SLACK: f64 = 0.05;

/// How a log is prepared for identification (`rotorid identify --rate --from --to`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ImportOptions {
    /// Identification rate (Hz); `None`: the fastest of [`IDENTIFICATION_RATES_HZ`] that
    /// every channel supports ([`identification_rate`]).
    pub rate_hz: Option<f64>,
    /// Log time (s, as logged) before which nothing is used; with `to_s`, it replaces the
    /// in-air detector.
    pub from_s: Option<f64>,
    /// Log time (s) after which nothing is used.
    pub to_s: Option<f64>,
}

/// Each channel's native logging rate (Hz; `None` when it has fewer than two samples).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NativeRates {
    /// Attitude.
    pub attitude: Option<f64>,
    /// Velocity.
    pub velocity: Option<f64>,
    /// Body rates.
    pub rates: Option<f64>,
    /// Controls.
    pub controls: Option<f64>,
}

impl NativeRates {
    /// The rates of `ch`'s channels.
    pub fn of(ch: &Channels) -> Self {
        Self {
            attitude: ch.attitude.native_rate_hz(),
            velocity: ch.velocity_ned.native_rate_hz(),
            rates: ch.rates_frd.native_rate_hz(),
            controls: ch.controls.native_rate_hz(),
        }
    }

    /// `(name, rate)` of each channel.
    pub fn named(&self) -> [(&'static str, Option<f64>); 4] {
        [
            ("attitude", self.attitude),
            ("velocity", self.velocity),
            ("body rates", self.rates),
            ("controls", self.controls),
        ]
    }

    /// The slowest channel's rate.
    pub fn slowest(&self) -> Option<f64> {
        self.named()
            .iter()
            .filter_map(|(_, r)| *r)
            .min_by(f64::total_cmp)
    }
}

/// The fastest of [`IDENTIFICATION_RATES_HZ`] that every channel is logged at (within
/// `RATE_SLACK`): identifying faster than the slowest channel would learn from samples the
/// resampling invented, and flatter the one-step scores. Below the slowest candidate, the
/// slowest candidate (the caller warns).
pub fn identification_rate(native: &NativeRates) -> f64 {
    let slowest = native.slowest().unwrap_or(RATE_HZ);
    IDENTIFICATION_RATES_HZ
        .iter()
        .copied()
        .find(|&r| slowest >= r * (1.0 - RATE_SLACK))
        .unwrap_or(IDENTIFICATION_RATES_HZ[IDENTIFICATION_RATES_HZ.len() - 1])
}

/// Cuts the samples no flight produces: body rates beyond the gyro range, velocities beyond
/// the core's limit, controls beyond their normalised range (slightly beyond: clamped). A
/// crash or a sensor fault then costs the stretch it spoils, not the flight.
pub fn implausible_cuts(ch: &mut Channels) -> Vec<Cut> {
    let mut cuts = ch.rates_frd.drop_where(|w| {
        let i = (0..3).find(|&i| w[i].abs() > MAX_RATE_RADPS)?;
        Some(format!(
            "{} rate {:.2} rad/s is beyond the gyro range (±{MAX_RATE_RADPS} rad/s, 2000 deg/s)",
            ["roll", "pitch", "yaw"][i],
            w[i]
        ))
    });
    cuts.extend(ch.velocity_ned.drop_where(|v| {
        let i = (0..3).find(|&i| v[i].abs() > MAX_VELOCITY_MPS)?;
        Some(format!(
            "velocity {} {:.1} m/s is beyond ±{MAX_VELOCITY_MPS} m/s",
            ["north", "east", "down"][i],
            v[i]
        ))
    }));
    cuts.extend(ch.controls.drop_where(|u| {
        let i = (0..4).find(|&i| u[i].abs() > 1.0 + CONTROL_SLACK)?;
        Some(format!(
            "{} command {:.3} is beyond the normalised range ±1",
            [
                "collective",
                "pedal",
                "longitudinal cyclic",
                "lateral cyclic"
            ][i],
            u[i]
        ))
    }));
    cuts
}

/// Clamps the controls to ±1 (what the mixer lets through); returns how many samples were
/// clamped.
pub fn saturate_controls(ch: &mut Channels) -> usize {
    let mut clamped = 0;
    for u in &mut ch.controls.v {
        if u.iter().any(|x| x.abs() > 1.0) {
            clamped += 1;
            u.iter_mut().for_each(|x| *x = x.clamp(-1.0, 1.0));
        }
    }
    clamped
}

/// The cuts outside the window `[from, to]` (log time, s).
pub fn window_cuts(from_s: Option<f64>, to_s: Option<f64>) -> Vec<Cut> {
    let mut cuts = Vec::new();
    if let Some(from) = from_s {
        cuts.push(span(
            f64::NEG_INFINITY,
            from,
            &format!("before --from {from} s"),
        ));
    }
    if let Some(to) = to_s {
        cuts.push(span(to, f64::INFINITY, &format!("after --to {to} s")));
    }
    cuts
}

/// Attitude tracking error beyond which control counts as lost (rad): 30°, the angle
/// deviation of ArduCopter's crash check (`CRASH_CHECK_ANGLE_DEVIATION_DEG`). A controlled
/// vehicle tracks its demand within a few degrees; a tumble after a failure or a collision is
/// far beyond (the committed `ekf_failure.ulg`'s final tumble: 113°, see docs/real-logs.md).
pub const LOST_CONTROL_RAD: f64 = 30.0 * std::f64::consts::PI / 180.0;
/// Time left out on each side of a sample beyond [`LOST_CONTROL_RAD`] (s): the error grows
/// for a moment before it passes the bound, and the vehicle needs a moment to recover after.
pub const LOST_CONTROL_MARGIN_S: f64 = 1.0;

/// Stretches where the attitude is more than [`LOST_CONTROL_RAD`] off the autopilot's demand
/// (with [`LOST_CONTROL_MARGIN_S`] on each side): the vehicle was not flying the dynamics a
/// model identifies (a failure, a collision, a tumble). Nothing for a log without the demand.
pub fn lost_control_cuts(ch: &Channels) -> Vec<Cut> {
    // (from, to, worst error) of each stretch; a sample within reach of the last extends it.
    let mut spans: Vec<(f64, f64, f64)> = Vec::new();
    for (t, e) in ch.attitude_error.t.iter().zip(&ch.attitude_error.v) {
        if !(e[0].is_finite() && e[0] > LOST_CONTROL_RAD) {
            continue;
        }
        let (from, to) = (t - LOST_CONTROL_MARGIN_S, t + LOST_CONTROL_MARGIN_S);
        match spans.last_mut() {
            Some(last) if from <= last.1 => {
                last.1 = to;
                last.2 = last.2.max(e[0]);
            }
            _ => spans.push((from, to, e[0])),
        }
    }
    spans
        .into_iter()
        .map(|(from, to, worst)| {
            span(
                from,
                to,
                &format!(
                    "attitude up to {:.0}° off the autopilot's demand (beyond {:.0}°, ArduCopter's crash-check deviation): control lost (a failure, a collision or a tumble)",
                    worst.to_degrees(),
                    LOST_CONTROL_RAD.to_degrees()
                ),
            )
        })
        .collect()
}

/// Where the ground time came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InAirSource {
    /// The autopilot's own land detector or arming state, logged.
    Autopilot,
    /// The collective at idle only (the log has no land detector or arming state).
    Data,
}

/// The ground time of a log as cuts: where the autopilot's in-air channel says so, when the
/// log has one, and where the collective is at idle ([`InAirSource::Data`]).
pub fn ground_cuts(ch: &Channels) -> (Vec<Cut>, InAirSource) {
    // The collective at idle is ground time whatever the autopilot says: its land detector
    // declares the landing a second or two after the touchdown.
    let idle = data_ground(ch);
    if ch.in_air.t.is_empty() {
        return (idle, InAirSource::Data);
    }
    let mut cuts = autopilot_ground(&ch.in_air);
    cuts.extend(idle);
    (cuts, InAirSource::Autopilot)
}

/// Stretches where the autopilot says the vehicle is on the ground (held until its next
/// sample). Before its first sample nothing is known, and nothing is cut: an event log
/// (DataFlash `EV`) may begin with the landing of a flight that started before the log.
fn autopilot_ground(in_air: &Series<1>) -> Vec<Cut> {
    let mut cuts = Vec::new();
    let mut ground_from: Option<f64> = None;
    for (t, v) in in_air.t.iter().zip(&in_air.v) {
        let flying = v[0] > 0.5;
        match (flying, ground_from) {
            (false, None) => ground_from = Some(*t),
            (true, Some(from)) => {
                cuts.push(span(
                    from,
                    *t,
                    "on the ground (the autopilot's land detector or arming state)",
                ));
                ground_from = None;
            }
            _ => {}
        }
    }
    if let Some(from) = ground_from {
        cuts.push(span(
            from,
            f64::INFINITY,
            "on the ground (the autopilot's land detector or arming state)",
        ));
    }
    cuts
}

/// A cut of `[from, to]` (s) whose gap is the same stretch.
fn span(from: f64, to: f64, reason: &str) -> Cut {
    Cut {
        from_s: from,
        to_s: to,
        gap: (from, to),
        reason: reason.to_string(),
    }
}

/// The fallback in-air detector: the collective at idle. (A rule on stillness would cut a
/// steady hover; a vehicle on the ground with its rotor idling or its motors stopped has its
/// collective or thrust at the bottom, which a flying one never has for long.)
fn data_ground(ch: &Channels) -> Vec<Cut> {
    let mut cuts = Vec::new();
    // Idle collective, held until the next control sample.
    let mut idle_from: Option<f64> = None;
    for (t, u) in ch.controls.t.iter().zip(&ch.controls.v) {
        match (u[0] <= IDLE_COLLECTIVE, idle_from) {
            (true, None) => idle_from = Some(*t),
            (false, Some(from)) => {
                cuts.push(span(from, *t, IDLE_REASON));
                idle_from = None;
            }
            _ => {}
        }
    }
    if let Some(from) = idle_from {
        cuts.push(span(from, f64::INFINITY, IDLE_REASON));
    }
    cuts
}

const IDLE_REASON: &str = "collective at idle (≤ 0.05): on the ground";

/// A note for each time-stamp glitch of a channel.
pub fn glitch_notes(file: &str, channel: &str, glitches: &[TimeGlitch]) -> Vec<String> {
    glitches
        .iter()
        .map(|g| match g {
            TimeGlitch::Spike {
                at_s,
                to_s,
                dropped,
            } => format!(
                "{file}: {channel}: the time stamp jumps from {at_s:.3} s to {to_s:.3} s and back; {dropped} sample(s) stamped ahead dropped"
            ),
            TimeGlitch::Backwards { at_s, dropped } => format!(
                "{file}: {channel}: time goes back after {at_s:.3} s; {dropped} sample(s) stamped before it dropped"
            ),
        })
        .collect()
}

/// A cut as a line for the user (times in log seconds; open ends say "start"/"end").
pub fn describe(cut: &Cut) -> String {
    let t = |x: f64, open: &str| {
        if x.is_finite() {
            format!("{x:.2} s")
        } else {
            open.to_string()
        }
    };
    if cut.from_s == cut.to_s {
        format!("at {}: {}", t(cut.from_s, "start"), cut.reason)
    } else {
        format!(
            "{} to {}: {}",
            t(cut.from_s, "start"),
            t(cut.to_s, "end"),
            cut.reason
        )
    }
}

/// The autopilot settings that raise a channel's logging rate, for the rate warnings.
pub fn rate_advice(format: super::LogFormat) -> &'static str {
    match format {
        super::LogFormat::ULog => {
            "PX4: set SDLOG_PROFILE bit 3 (system identification) or bit 4 (high rate) to log attitude, rates and setpoints faster"
        }
        super::LogFormat::DataFlash => {
            "ArduPilot: set LOG_BITMASK bit 0 (ATTITUDE_FAST) to log the attitude (ANG from 4.7 on, \
             else ATT) and RATE at the loop rate (LOG_FILE_RATEMAX caps them); the EKF velocity \
             (XKF1, NKF1 with EKF2) comes at the logging task's rate whatever the bitmask (25 Hz \
             on ArduCopter 4.7)"
        }
        super::LogFormat::Sdlog2 => {
            "PX4 sdlog2: start the logger at a higher rate (`sdlog2 start -r 100`)"
        }
        _ => "log every quantity at 50 Hz or faster",
    }
}

/// Largest gap a resampled channel is interpolated over (s): re-exported for notes.
pub const MAX_GAP_S: f64 = MAX_SOURCE_GAP_S;

#[cfg(test)]
mod tests {
    use super::*;

    fn series<const N: usize>(ts: &[f64], f: impl Fn(f64) -> [f64; N]) -> Series<N> {
        let mut s = Series::default();
        ts.iter().for_each(|&t| s.push(t, f(t)));
        s
    }

    #[test]
    fn rate_is_the_slowest_channels_rounded_down() {
        let r = |a, v, w, u| NativeRates {
            attitude: Some(a),
            velocity: Some(v),
            rates: Some(w),
            controls: Some(u),
        };
        assert_eq!(identification_rate(&r(250.0, 50.0, 400.0, 100.0)), 50.0);
        assert_eq!(identification_rate(&r(250.0, 49.2, 400.0, 100.0)), 50.0);
        assert_eq!(identification_rate(&r(30.0, 50.0, 400.0, 100.0)), 25.0);
        assert_eq!(identification_rate(&r(10.0, 10.0, 10.0, 10.0)), 10.0);
        assert_eq!(identification_rate(&r(2.0, 10.0, 10.0, 10.0)), 5.0);
    }

    #[test]
    fn a_future_time_stamp_costs_one_sample_not_the_channel() {
        let mut s = Series::<1>::default();
        for k in 0..10 {
            s.push(f64::from(k) * 0.02, [1.0]);
        }
        s.push(99.0, [1.0]);
        for k in 10..20 {
            s.push(f64::from(k) * 0.02, [1.0]);
        }
        assert_eq!(s.t.len(), 20);
        assert!(s.t.windows(2).all(|w| w[1] > w[0]));
        assert!(matches!(
            s.glitches[..],
            [TimeGlitch::Spike { dropped: 1, .. }]
        ));
    }

    #[test]
    fn a_clock_reset_drops_what_is_stamped_before_and_says_so() {
        let mut s = Series::<1>::default();
        for k in 0..100 {
            s.push(f64::from(k) * 0.02, [1.0]);
        }
        for k in 0..10 {
            s.push(f64::from(k) * 0.02, [2.0]);
        }
        assert_eq!(s.t.len(), 100);
        assert!(matches!(
            s.glitches[..],
            [TimeGlitch::Backwards { dropped: 10, .. }]
        ));
    }

    #[test]
    fn implausible_rates_cut_a_stretch_and_name_it() {
        let ts: Vec<f64> = (0..50).map(|k| f64::from(k) * 0.02).collect();
        let mut ch = Channels {
            rates_frd: series(&ts, |t| {
                if (0.4..0.5).contains(&t) {
                    [0.0, 37.66, 0.0]
                } else {
                    [0.0, 0.1, 0.0]
                }
            }),
            ..Channels::default()
        };
        let cuts = implausible_cuts(&mut ch);
        assert_eq!(cuts.len(), 1);
        assert!(
            cuts[0].reason.contains("pitch rate 37.66"),
            "{}",
            cuts[0].reason
        );
        assert!((cuts[0].gap.0 - 0.38).abs() < 1e-9 && (cuts[0].gap.1 - 0.5).abs() < 1e-9);
        assert!(!cuts[0].reason.contains("degrees"));
        assert_eq!(ch.rates_frd.t.len(), 45);
    }

    /// A tumble (the attitude 40° off its demand, twice, 0.6 s apart) is one cut with a second
    /// on each side, named with its worst error; a 20° lag and a roll of 179° against a demand
    /// of −179° are flight.
    #[test]
    fn a_loss_of_control_is_cut_with_a_margin() {
        let ts: Vec<f64> = (0..500).map(|k| f64::from(k) * 0.02).collect();
        let deg = std::f64::consts::PI / 180.0;
        let ch = Channels {
            attitude_error: series(&ts, |t| {
                let e = if (3.0..3.2).contains(&t) {
                    40.0
                } else if (3.8..3.9).contains(&t) {
                    55.0
                } else if (6.0..6.5).contains(&t) {
                    20.0
                } else {
                    super::super::resample::angle_difference(179.0 * deg, -179.0 * deg).abs() / deg
                };
                [e * deg]
            }),
            ..Channels::default()
        };
        let cuts = lost_control_cuts(&ch);
        assert_eq!(cuts.len(), 1, "{cuts:?}");
        assert!((cuts[0].from_s - 2.0).abs() < 1e-9, "{cuts:?}");
        assert!((cuts[0].to_s - (3.88 + 1.0)).abs() < 1e-9, "{cuts:?}");
        assert!(cuts[0].reason.contains("up to 55°"), "{}", cuts[0].reason);
        assert!(lost_control_cuts(&Channels::default()).is_empty());
    }

    #[test]
    fn ground_from_the_autopilot_and_from_the_data() {
        let ts: Vec<f64> = (0..500).map(|k| f64::from(k) * 0.02).collect();
        let mut ch = Channels {
            in_air: series(&[0.0, 2.0, 8.0], |t| [if t == 2.0 { 1.0 } else { 0.0 }]),
            ..Channels::default()
        };
        let (cuts, source) = ground_cuts(&ch);
        assert_eq!(source, InAirSource::Autopilot);
        // (No controls: no idle collective.)
        assert_eq!(cuts.len(), 2);
        assert_eq!(cuts[0].gap, (0.0, 2.0));
        assert_eq!(cuts[1].gap, (8.0, f64::INFINITY));
        // No land detector: idle collective for the first 3 s and from 9 s on; a still
        // hover in between is flight.
        ch.in_air = Series::default();
        ch.controls = series(&ts, |t| {
            [
                if (3.0..9.0).contains(&t) { 0.5 } else { 0.0 },
                0.0,
                0.0,
                0.0,
            ]
        });
        ch.velocity_ned = series(&ts, |_| [0.0; 3]);
        ch.rates_frd = series(&ts, |_| [0.0; 3]);
        let (cuts, source) = ground_cuts(&ch);
        assert_eq!(source, InAirSource::Data);
        assert_eq!(cuts.len(), 2);
        assert_eq!(cuts[0].gap, (0.0, 3.0));
        assert_eq!(cuts[1].gap, (9.0, f64::INFINITY));
    }
}
