//! Resampling of a log's topics onto the identifier's 50 Hz grid, split at gaps.
//!
//! - States (attitude, velocity, rates) are interpolated linearly between the two samples
//!   around each grid time; yaw is unwrapped first and wrapped back to (−π, π].
//! - Controls are held (zero-order hold): a command applies from its time stamp until the next,
//!   as in the CSV format. Below the log's own rate, each grid time gets the mean of the
//!   commands logged since the previous grid time, `(t_k − Δt, t_k]`: a rate controller's
//!   output changes within a 100 ms step, and one point sample of it is aliased noise (a
//!   causal boxcar decimator, as a flight computer would decimate). At or above the log's
//!   rate a step holds one command or none, and gets the held value bit for bit.
//! - A **gap** is an interval over [`MAX_SOURCE_GAP_S`] between two finite samples of any
//!   channel (a non-finite sample counts as missing). The log is split there, and into the
//!   span where every channel has data, giving [`Segment`]s; grids start at each segment's
//!   start.

use rotorid_sim::plant::{SensorSample, Sticks};

/// Identifier rate (Hz).
pub const RATE_HZ: f64 = 50.0;

/// Longest interval between two samples of a channel that is interpolated over (s): 2.5 times
/// the slowest default PX4 logging interval (100 ms, `vehicle_local_position`).
pub const MAX_SOURCE_GAP_S: f64 = 0.25;

/// One channel: time stamps (s, increasing) and values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series<const N: usize> {
    /// Time stamps (s).
    pub t: Vec<f64>,
    /// Values at the time stamps.
    pub v: Vec<[f64; N]>,
    /// The time-stamp glitches [`push`](Self::push) repaired or cut, in log order.
    pub glitches: Vec<TimeGlitch>,
}

/// A time stamp out of order in a channel, and what [`Series::push`] did about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeGlitch {
    /// A run of samples stamped in the future (a jump forward by more than a gap, then back):
    /// the run is dropped and the channel goes on from the sample after it.
    Spike {
        /// Time of the last good sample before the run (s).
        at_s: f64,
        /// The run's first (wrong) time stamp (s).
        to_s: f64,
        /// Samples dropped.
        dropped: usize,
    },
    /// Time went back over more history than a spike (a clock reset): the samples stamped
    /// before the channel's latest time are dropped until time passes it again.
    Backwards {
        /// The channel's latest time when it happened (s).
        at_s: f64,
        /// Samples dropped.
        dropped: usize,
    },
}

/// Most samples a [`TimeGlitch::Spike`] drops; a longer run ahead in time is taken as the
/// truth and the later, earlier-stamped samples as the glitch ([`TimeGlitch::Backwards`]).
pub const MAX_SPIKE_SAMPLES: usize = 50;

impl<const N: usize> Series<N> {
    /// Appends a sample in log order. A non-finite sample is dropped (it counts as missing:
    /// a gap where there are several). A time stamp at or before the previous one is a
    /// glitch: when the samples after it are a short run stamped ahead of time (a jump
    /// forward by more than a gap, at most [`MAX_SPIKE_SAMPLES`]), that run is dropped;
    /// otherwise this sample is. Either way it is recorded in
    /// [`glitches`](Self::glitches), so that one bad time stamp costs a few samples, never the
    /// rest of the channel.
    pub fn push(&mut self, t: f64, v: [f64; N]) {
        if !(t.is_finite() && v.iter().all(|x| x.is_finite())) {
            return;
        }
        if self.t.last() == Some(&t) {
            // The same instant logged twice: keep the first.
            return;
        }
        if self.t.last().is_some_and(|&last| t < last) {
            let keep = self.t.partition_point(|&x| x < t);
            let run = self.t.len() - keep;
            let jumped = keep
                .checked_sub(1)
                .and_then(|i| Some(self.t.get(keep)? - self.t.get(i)?))
                .is_some_and(|dt| dt > MAX_SOURCE_GAP_S);
            let at_s = keep
                .checked_sub(1)
                .and_then(|i| self.t.get(i).copied())
                .unwrap_or(t);
            let to_s = self.t.get(keep).copied().unwrap_or(t);
            let equal = self.t.get(keep).is_some_and(|&x| x == t);
            if !equal && jumped && run <= MAX_SPIKE_SAMPLES {
                self.t.truncate(keep);
                self.v.truncate(keep);
                self.glitches.push(TimeGlitch::Spike {
                    at_s,
                    to_s,
                    dropped: run,
                });
            } else {
                let latest = self.t.last().copied().unwrap_or(t);
                match self.glitches.last_mut() {
                    Some(TimeGlitch::Backwards { at_s, dropped }) if *at_s == latest => {
                        *dropped += 1;
                    }
                    _ => self.glitches.push(TimeGlitch::Backwards {
                        at_s: latest,
                        dropped: 1,
                    }),
                }
                return;
            }
        }
        self.t.push(t);
        self.v.push(v);
    }

    /// The channel's native logging rate (Hz): the inverse of its median sample interval;
    /// `None` below two samples.
    pub fn native_rate_hz(&self) -> Option<f64> {
        let mut dt: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if dt.is_empty() {
            return None;
        }
        dt.sort_by(f64::total_cmp);
        let median = dt[dt.len() / 2];
        (median > 0.0).then(|| 1.0 / median)
    }

    /// Drops the samples for which `bad` gives a reason, and returns each stretch dropped as a
    /// [`Cut`] with the first sample's reason. [`spans`] splits the log there.
    pub fn drop_where(&mut self, bad: impl Fn(&[f64; N]) -> Option<String>) -> Vec<Cut> {
        let mut cuts: Vec<Cut> = Vec::new();
        let mut keep = vec![true; self.t.len()];
        let mut open = false;
        let mut last_good: Option<f64> = None;
        for (k, (t, v)) in self.t.iter().zip(&self.v).enumerate() {
            match bad(v) {
                Some(reason) => {
                    keep[k] = false;
                    match cuts.last_mut() {
                        Some(c) if open => c.to_s = *t,
                        _ => cuts.push(Cut {
                            from_s: *t,
                            to_s: *t,
                            gap: (last_good.unwrap_or(*t), f64::INFINITY),
                            reason,
                        }),
                    }
                    open = true;
                }
                None => {
                    if open {
                        if let Some(c) = cuts.last_mut() {
                            c.gap.1 = *t;
                        }
                    }
                    open = false;
                    last_good = Some(*t);
                }
            }
        }
        if !cuts.is_empty() {
            let mut k = 0;
            self.t.retain(|_| {
                k += 1;
                keep[k - 1]
            });
            let mut k = 0;
            self.v.retain(|_| {
                k += 1;
                keep[k - 1]
            });
        }
        cuts
    }

    /// Gaps `(from, to)` longer than [`MAX_SOURCE_GAP_S`].
    fn gaps(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.t
            .windows(2)
            .filter(|w| w[1] - w[0] > MAX_SOURCE_GAP_S)
            .map(|w| (w[0], w[1]))
    }

    /// Value at `t` by linear interpolation (`hold`: the last sample at or before `t`);
    /// `cursor` advances monotonically for increasing `t`.
    fn at(&self, t: f64, cursor: &mut usize, hold: bool) -> Option<[f64; N]> {
        while *cursor + 1 < self.t.len() && self.t[*cursor + 1] <= t {
            *cursor += 1;
        }
        let (t0, v0) = (*self.t.get(*cursor)?, *self.v.get(*cursor)?);
        if hold || t <= t0 {
            return Some(v0);
        }
        let (t1, v1) = (*self.t.get(*cursor + 1)?, *self.v.get(*cursor + 1)?);
        let a = (t - t0) / (t1 - t0);
        Some(core::array::from_fn(|i| v0[i] + a * (v1[i] - v0[i])))
    }

    /// Mean of the samples stamped in `(t − step, t]`, or the held value at `t` when there is
    /// none: decimation by averaging what was logged since the previous grid time (a causal
    /// boxcar, the anti-aliasing a point sample lacks). A step with one sample in it gets
    /// that sample bit for bit, so at or above the log's own rate this is the held value.
    /// `cursor` as in [`at`](Self::at).
    fn mean_since(&self, t: f64, step: f64, cursor: &mut usize) -> Option<[f64; N]> {
        let held = self.at(t, cursor, true)?;
        // Half a µs of slack: log time stamps are whole µs, and `t − step` rounded must not
        // take in the sample one step back when the log's rate is the grid's.
        let from = t - step + 0.5e-6;
        let mut sum = [0.0; N];
        let mut n = 0u32;
        for (&ti, vi) in self.t[..=*cursor].iter().zip(&self.v[..=*cursor]).rev() {
            if ti <= from {
                break;
            }
            if ti <= t {
                for (s, x) in sum.iter_mut().zip(vi) {
                    *s += x;
                }
                n += 1;
            }
        }
        Some(match n {
            0 | 1 => held,
            n => sum.map(|s| s / f64::from(n)),
        })
    }
}

/// Joins two channels logged separately: at each sample of `a`, the latest sample of `b` at or
/// before it (zero-order hold), combined by `f`; samples of `a` before the first of `b` are
/// dropped.
pub fn merge_held<const N: usize, const M: usize, const K: usize>(
    a: &Series<N>,
    b: &Series<M>,
    f: impl Fn(&[f64; N], &[f64; M]) -> [f64; K],
) -> Series<K> {
    merge_recent(a, b, f64::INFINITY, f)
}

/// The difference `a − b` of two angles (rad), wrapped to [−π, π): a roll of 179° against a
/// demand of −179° is 2° off, not 358°.
pub fn angle_difference(a: f64, b: f64) -> f64 {
    (a - b + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// Like [`merge_held`], but only where `b`'s latest sample is at most `max_age_s` old: a
/// demand that stopped being published (a mode without it) is not held against later samples.
pub fn merge_recent<const N: usize, const M: usize, const K: usize>(
    a: &Series<N>,
    b: &Series<M>,
    max_age_s: f64,
    f: impl Fn(&[f64; N], &[f64; M]) -> [f64; K],
) -> Series<K> {
    let mut out = Series::default();
    let mut j = 0usize;
    for (t, x) in a.t.iter().zip(&a.v) {
        while b.t.get(j + 1).is_some_and(|tb| tb <= t) {
            j += 1;
        }
        if let (Some(tb), Some(y)) = (b.t.get(j), b.v.get(j)) {
            if *tb <= *t && *t - *tb <= max_age_s {
                out.push(*t, f(x, y));
            }
        }
    }
    out
}

/// A stretch of the log left out, with why: the log is split there.
#[derive(Debug, Clone, PartialEq)]
pub struct Cut {
    /// First time left out (s).
    pub from_s: f64,
    /// Last time left out (s).
    pub to_s: f64,
    /// The channel's good samples around the cut (s): the log ends at the first and resumes
    /// at the second (infinite when nothing follows).
    pub gap: (f64, f64),
    /// Why.
    pub reason: String,
}

/// A log's channels in the flight computer's convention, before resampling.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Channels {
    /// ZYX Euler angles `[φ θ ψ]` (rad).
    pub attitude: Series<3>,
    /// Velocity `[v_n v_e v_d]` (m/s).
    pub velocity_ned: Series<3>,
    /// Body rates `[p q r]` about forward, right, down (rad/s).
    pub rates_frd: Series<3>,
    /// Normalised controls `[col ped lon lat]`.
    pub controls: Series<4>,
    /// Whether the vehicle is flying, from the autopilot's own state where the log has it
    /// (1 = in the air, 0 = on the ground or disarmed; held until the next sample); empty
    /// when the log says nothing, and the in-air detector then falls back on the data.
    pub in_air: Series<1>,
    /// The attitude controller's tracking error `max(|φ_d − φ|, |θ_d − θ|)` (rad), where the
    /// log has its demand beside the attitude; empty otherwise. Heading is left out: a yaw
    /// demand may lead the heading by any amount in a yaw-rate mode.
    pub attitude_error: Series<1>,
}

impl Channels {
    /// Whether every channel has as many values as time stamps, its time stamps finite and
    /// strictly increasing: what [`Series::push`] keeps true, and the fuzz targets check.
    pub fn is_well_formed(&self) -> bool {
        fn ordered<const N: usize>(s: &Series<N>) -> bool {
            s.t.len() == s.v.len()
                && s.t.iter().all(|t| t.is_finite())
                && s.t.windows(2).all(|w| w[0] < w[1])
        }
        ordered(&self.attitude)
            && ordered(&self.velocity_ned)
            && ordered(&self.rates_frd)
            && ordered(&self.controls)
            && ordered(&self.in_air)
            && ordered(&self.attitude_error)
    }

    /// The channels of samples that carry every quantity at each time stamp (a CSV log), so
    /// that a log at another rate than [`RATE_HZ`] can be put on its grid like the others.
    pub fn of_samples(samples: &[SensorSample]) -> Self {
        let mut ch = Self::default();
        for s in samples {
            ch.attitude.push(s.t, [s.roll, s.pitch, s.yaw]);
            ch.velocity_ned.push(s.t, [s.v_north, s.v_east, s.v_down]);
            ch.rates_frd.push(s.t, [s.p, s.q, s.r]);
            let u = &s.sticks;
            ch.controls.push(s.t, [u.col, u.ped, u.lon, u.lat]);
        }
        ch
    }
}

/// Largest relative difference between a log's mean sample interval and the 50 Hz grid's
/// for the log to be taken as it is (the identifiers accept each interval within 20 ± 10 ms;
/// a log whose typical interval differs by more than this is at another rate, and its samples
/// taken one by one as 50 Hz steps would stretch or squeeze the dynamics).
pub const RATE_TOLERANCE: f64 = 0.05;

/// The mean interval (s) of samples whose time stamps increase (their span over their
/// count less one: jitter, even alternating, averages out), `None` below two samples.
pub fn mean_interval(samples: &[SensorSample]) -> Option<f64> {
    let (first, last) = (samples.first()?, samples.last()?);
    (samples.len() > 1).then(|| (last.t - first.t) / (samples.len() - 1) as f64)
}

/// The log's rate (Hz) when its mean interval is not the 50 Hz grid's (within
/// [`RATE_TOLERANCE`]); `None` for a 50 Hz log.
pub fn other_rate(samples: &[SensorSample]) -> Option<f64> {
    let dt = mean_interval(samples)?;
    let nominal = 1.0 / RATE_HZ;
    ((dt - nominal).abs() > RATE_TOLERANCE * nominal && dt > 0.0).then(|| 1.0 / dt)
}

/// A stretch of the log without gaps, resampled at [`RATE_HZ`].
pub type Segment = Vec<SensorSample>;

/// Unwraps yaw (index 2) so that interpolation never crosses ±π the long way.
fn unwrap_yaw(att: &Series<3>) -> Series<3> {
    let mut out = att.clone();
    let mut offset = 0.0;
    for k in 1..out.v.len() {
        let d = att.v[k][2] - att.v[k - 1][2];
        if d > std::f64::consts::PI {
            offset -= std::f64::consts::TAU;
        } else if d < -std::f64::consts::PI {
            offset += std::f64::consts::TAU;
        }
        out.v[k][2] = att.v[k][2] + offset;
    }
    out
}

fn wrap_pi(x: f64) -> f64 {
    let y = x.rem_euclid(std::f64::consts::TAU);
    if y > std::f64::consts::PI {
        y - std::f64::consts::TAU
    } else {
        y
    }
}

/// The spans `(start, end)` where every channel has data without a gap, and outside `cuts`.
pub fn spans(ch: &Channels, cuts: &[Cut]) -> Vec<(f64, f64)> {
    let firsts = [
        ch.attitude.t.first(),
        ch.velocity_ned.t.first(),
        ch.rates_frd.t.first(),
        ch.controls.t.first(),
    ];
    let lasts = [
        ch.attitude.t.last(),
        ch.velocity_ned.t.last(),
        ch.rates_frd.t.last(),
        ch.controls.t.last(),
    ];
    let (Some(start), Some(end)) = (
        firsts
            .iter()
            .try_fold(f64::MIN, |m, t| t.map(|t| m.max(*t))),
        lasts.iter().try_fold(f64::MAX, |m, t| t.map(|t| m.min(*t))),
    ) else {
        return Vec::new();
    };
    let mut gaps: Vec<(f64, f64)> = ch
        .attitude
        .gaps()
        .chain(ch.velocity_ned.gaps())
        .chain(ch.rates_frd.gaps())
        .chain(ch.controls.gaps())
        .chain(cuts.iter().map(|c| c.gap))
        .collect();
    gaps.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    let mut from = start;
    for (g0, g1) in gaps {
        // A gap (or a cut) that starts after the common span ends changes nothing.
        if g0 >= end {
            break;
        }
        if g0 > from {
            out.push((from, g0));
        }
        from = from.max(g1);
    }
    if end > from {
        out.push((from, end));
    }
    out
}

/// Resamples every gap-free span at [`RATE_HZ`] (see the module documentation), longest
/// spans kept in log order; spans shorter than one step are dropped.
pub fn resample(ch: &Channels) -> Vec<Segment> {
    resample_at(ch, RATE_HZ, &[])
}

/// Resamples every gap-free span outside `cuts` at `rate_hz`, as [`resample`].
pub fn resample_at(ch: &Channels, rate_hz: f64, cuts: &[Cut]) -> Vec<Segment> {
    let attitude = unwrap_yaw(&ch.attitude);
    let mut out = Vec::new();
    for (start, end) in spans(ch, cuts) {
        let mut cursors = [0usize; 4];
        let mut seg = Vec::new();
        for k in 0u32.. {
            // On whole microseconds (log time stamps are µs), so the CSV stays readable.
            let t = ((start + f64::from(k) / rate_hz) * 1e6).round() / 1e6;
            if t > end {
                break;
            }
            let (Some(a), Some(v), Some(w), Some(u)) = (
                attitude.at(t, &mut cursors[0], false),
                ch.velocity_ned.at(t, &mut cursors[1], false),
                ch.rates_frd.at(t, &mut cursors[2], false),
                ch.controls.mean_since(t, 1.0 / rate_hz, &mut cursors[3]),
            ) else {
                break;
            };
            seg.push(SensorSample {
                t,
                sticks: Sticks {
                    col: u[0],
                    ped: u[1],
                    lon: u[2],
                    lat: u[3],
                },
                roll: a[0],
                pitch: a[1],
                yaw: wrap_pi(a[2]),
                v_north: v[0],
                v_east: v[1],
                v_down: v[2],
                p: w[0],
                q: w[1],
                r: w[2],
            });
        }
        if seg.len() > 1 {
            out.push(seg);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series<const N: usize>(ts: &[f64], f: impl Fn(f64) -> [f64; N]) -> Series<N> {
        let mut s = Series::default();
        ts.iter().for_each(|&t| s.push(t, f(t)));
        s
    }

    fn channels(ts: &[f64]) -> Channels {
        Channels {
            attitude: series(ts, |t| [0.1 * t, 0.0, 3.0 + t]),
            velocity_ned: series(ts, |t| [t, 0.0, 0.0]),
            rates_frd: series(ts, |t| [0.0, 0.0, 2.0 * t]),
            controls: series(ts, |t| [0.5, t, 0.0, 0.0]),
            in_air: Series::default(),
            attitude_error: Series::default(),
        }
    }

    #[test]
    fn below_the_logs_rate_a_control_is_the_mean_since_the_last_grid_time() {
        // Controls at 40 Hz, states at 40 Hz, grid at 10 Hz: the grid time 0.5 s gets the mean
        // of the commands stamped in (0.4, 0.5], i.e. at 0.425, 0.45, 0.475 and 0.5 s.
        // Stamped on whole µs, as the grid is.
        let ts: Vec<f64> = (0..=40).map(|k| f64::from(k * 25_000) / 1e6).collect();
        let seg = resample_at(&channels(&ts), 10.0, &[]);
        let x = seg[0].iter().find(|x| (x.t - 0.5).abs() < 1e-9).unwrap();
        let mean = (0.425 + 0.45 + 0.475 + 0.5) / 4.0;
        assert!((x.sticks.ped - mean).abs() < 1e-12, "{}", x.sticks.ped);
        assert_eq!(
            x.sticks.col.to_bits(),
            0.5f64.to_bits(),
            "a constant stays bit for bit"
        );
        // At the log's own rate a step holds one command: the held value, bit for bit.
        let same = resample_at(&channels(&ts), 40.0, &[]);
        for (x, t) in same[0].iter().zip(&ts) {
            assert_eq!(x.sticks.ped.to_bits(), t.to_bits(), "at {t}");
        }
    }

    #[test]
    fn linear_states_held_controls_wrapped_yaw() {
        let ts: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.1).collect();
        let seg = resample(&channels(&ts));
        assert_eq!(seg.len(), 1);
        let s = &seg[0];
        assert_eq!(s.len(), 51, "1 s at 50 Hz, both ends");
        let x = &s[6]; // t = 0.12, between 0.1 and 0.2
        assert!((x.t - 0.12).abs() < 1e-12);
        assert!((x.v_north - 0.12).abs() < 1e-12, "linear: {}", x.v_north);
        assert!((x.r - 0.24).abs() < 1e-12);
        assert!((x.sticks.ped - 0.1).abs() < 1e-12, "held: {}", x.sticks.ped);
        // Yaw 3.0 + t passes π at t ≈ 0.14 and comes back wrapped near −π.
        let y = &s[10]; // t = 0.2 → 3.2 → 3.2 − 2π
        assert!(
            (y.yaw - (3.2 - std::f64::consts::TAU)).abs() < 1e-9,
            "{}",
            y.yaw
        );
        assert!(s
            .iter()
            .all(|x| x.yaw > -std::f64::consts::PI && x.yaw <= std::f64::consts::PI));
    }

    fn samples_at(dt: f64, n: usize) -> Vec<SensorSample> {
        (0..n)
            .map(|k| SensorSample {
                t: k as f64 * dt,
                v_north: k as f64,
                ..SensorSample::default()
            })
            .collect()
    }

    #[test]
    fn other_rate_sees_100_hz_and_40_hz_but_not_jittered_50_hz() {
        assert!(other_rate(&samples_at(0.010, 50)).is_some_and(|r| (r - 100.0).abs() < 1e-6));
        assert!(other_rate(&samples_at(0.025, 50)).is_some_and(|r| (r - 40.0).abs() < 1e-6));
        // 50 Hz with ±2 ms jitter in turn (intervals of 16 and 24 ms).
        let mut jittered = samples_at(0.020, 51);
        for (k, s) in jittered.iter_mut().enumerate() {
            s.t += if k % 2 == 0 { 0.002 } else { -0.002 };
        }
        assert_eq!(other_rate(&jittered), None);
        assert_eq!(other_rate(&samples_at(0.020, 1)), None);
    }

    #[test]
    fn split_at_a_gap_and_to_the_common_span() {
        let mut ts: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.1).collect();
        ts.extend((20..=40).map(|k| f64::from(k) * 0.1));
        let mut ch = channels(&ts);
        // Velocity starts late: the first segment starts at 0.3 s.
        ch.velocity_ned = series(&ts[3..], |t| [t, 0.0, 0.0]);
        let seg = resample(&ch);
        assert_eq!(seg.len(), 2);
        assert!((seg[0][0].t - 0.3).abs() < 1e-12);
        assert!(seg[0].last().is_some_and(|s| s.t <= 1.0 + 1e-12));
        assert!((seg[1][0].t - 2.0).abs() < 1e-12);
        assert_eq!(seg[1].len(), 101);
    }

    /// A cut after the data (ground time after the log's last sample) leaves the data whole.
    #[test]
    fn a_cut_after_the_end_changes_nothing() {
        let ts: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.1).collect();
        let cut = Cut {
            from_s: 1.5,
            to_s: 9.0,
            gap: (1.5, 9.0),
            reason: String::new(),
        };
        assert_eq!(spans(&channels(&ts), &[cut]), vec![(0.0, 1.0)]);
    }

    #[test]
    fn non_finite_samples_are_missing() {
        let mut s = Series::<1>::default();
        s.push(0.0, [1.0]);
        s.push(0.1, [f64::NAN]);
        s.push(0.05, [2.0]);
        s.push(0.04, [2.5]);
        s.push(0.2, [3.0]);
        assert_eq!(s.t, vec![0.0, 0.05, 0.2]);
    }
}
