//! The excitation generator: Table 2's logarithmic frequency sweeps (paper Eqs. 31–33) and a
//! schedule that plays the four one after another (`rotorid::sweep`). Computed in double
//! precision, bit-identical on every target.

use rotorid::sweep::{Channel, Sweep, SweepSchedule};
use rotorid::Error;

use crate::error::*;

/// Channel: main-rotor collective `u_col`.
pub const ROTORID_CHANNEL_COLLECTIVE: u32 = 0;
/// Channel: pedal `u_ped`.
pub const ROTORID_CHANNEL_PEDAL: u32 = 1;
/// Channel: longitudinal cyclic `u_lon`.
pub const ROTORID_CHANNEL_LONGITUDINAL: u32 = 2;
/// Channel: lateral cyclic `u_lat`.
pub const ROTORID_CHANNEL_LATERAL: u32 = 3;

/// One frequency sweep with trim pads (`rotorid::sweep::Sweep`):
/// `u(t) = A(t) sin f(t)`, `ν(t) = ω_min + K(t)(ω_max − ω_min)`, `K(t) = C2 (exp(C1 t/T_rec) − 1)`.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct rotorid_sweep_t {
    /// `ROTORID_CHANNEL_*`: the control it drives (its index in `[u_col u_ped u_lon u_lat]`).
    pub channel: u32,
    /// Lowest frequency ω_min (rad/s).
    pub omega_min: f64,
    /// Highest frequency ω_max (rad/s).
    pub omega_max: f64,
    /// Recorded length T_rec (s).
    pub duration_s: f64,
    /// Amplitude A at full gain (stick units, added to trim).
    pub amplitude: f64,
    /// C1 of Eq. 31.
    pub c1: f64,
    /// C2 of Eq. 31.
    pub c2: f64,
    /// Gain on A at ω_min (0…1).
    pub low_frequency_gain: f64,
    /// Frequency (rad/s) from which the full amplitude applies.
    pub full_amplitude_from: f64,
    /// Time at trim before and after the sweep (s).
    pub trim_s: f64,
}

fn core_channel(code: u32) -> Result<Channel, Error> {
    match code {
        ROTORID_CHANNEL_COLLECTIVE => Ok(Channel::Collective),
        ROTORID_CHANNEL_PEDAL => Ok(Channel::Pedal),
        ROTORID_CHANNEL_LONGITUDINAL => Ok(Channel::Longitudinal),
        ROTORID_CHANNEL_LATERAL => Ok(Channel::Lateral),
        _ => Err(rotorid::ConfigError::Sweep.into()),
    }
}

fn channel_code(c: Channel) -> u32 {
    match c {
        Channel::Collective => ROTORID_CHANNEL_COLLECTIVE,
        Channel::Pedal => ROTORID_CHANNEL_PEDAL,
        Channel::Longitudinal => ROTORID_CHANNEL_LONGITUDINAL,
        Channel::Lateral => ROTORID_CHANNEL_LATERAL,
    }
}

impl From<Sweep> for rotorid_sweep_t {
    fn from(s: Sweep) -> Self {
        Self {
            channel: channel_code(s.channel),
            omega_min: s.omega_min,
            omega_max: s.omega_max,
            duration_s: s.duration_s,
            amplitude: s.amplitude,
            c1: s.c1,
            c2: s.c2,
            low_frequency_gain: s.low_frequency_gain,
            full_amplitude_from: s.full_amplitude_from,
            trim_s: s.trim_s,
        }
    }
}

impl TryFrom<&rotorid_sweep_t> for Sweep {
    type Error = Error;

    /// The sweep, validated (`CONFIG_SWEEP` when out of range).
    fn try_from(s: &rotorid_sweep_t) -> Result<Self, Error> {
        let sweep = Sweep {
            channel: core_channel(s.channel)?,
            omega_min: s.omega_min,
            omega_max: s.omega_max,
            duration_s: s.duration_s,
            amplitude: s.amplitude,
            c1: s.c1,
            c2: s.c2,
            low_frequency_gain: s.low_frequency_gain,
            full_amplitude_from: s.full_amplitude_from,
            trim_s: s.trim_s,
        };
        sweep.validate()?;
        Ok(sweep)
    }
}

/// Table 2's four sweeps in the order lon, lat, ped, col, sampled at `rate_hz`.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct rotorid_schedule_t {
    /// The sweeps, played one after another.
    pub sweeps: [rotorid_sweep_t; 4],
    /// Sample rate (Hz, 1…10 000).
    pub rate_hz: u32,
}

fn core_schedule(s: &rotorid_schedule_t) -> Result<SweepSchedule<4>, Error> {
    let [a, b, c, d] = &s.sweeps;
    SweepSchedule::new(
        [a.try_into()?, b.try_into()?, c.try_into()?, d.try_into()?],
        s.rate_hz,
    )
}

/// Table 2's sweep for `channel` (`ROTORID_CHANNEL_*`) with amplitude A (stick units), the
/// paper's C1 and C2, 3 s trim pads, half amplitude at ω_min rising to full at 2·ω_min.
///
/// # Safety
/// `out` and `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_sweep_table2(
    channel: u32,
    amplitude: f64,
    out: *mut rotorid_sweep_t,
    error: *mut rotorid_error_t,
) -> i32 {
    let result = (|| {
        let sweep = Sweep::table2(core_channel(channel)?, amplitude);
        sweep.validate()?;
        // SAFETY: the caller's contract.
        let out = unsafe { out.as_mut() }.ok_or(rotorid_error_t::interface(ROTORID_E_NULL))?;
        *out = sweep.into();
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// The sweep's offset from trim at time `t_s` (s) from its start (0 during the trim pads
/// and after the end).
///
/// # Safety
/// `sweep`, `offset` and `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_sweep_offset(
    sweep: *const rotorid_sweep_t,
    t_s: f64,
    offset: *mut f64,
    error: *mut rotorid_error_t,
) -> i32 {
    let result = (|| {
        let null = rotorid_error_t::interface(ROTORID_E_NULL);
        // SAFETY: the caller's contract.
        let (sweep, offset) = unsafe { (sweep.as_ref(), offset.as_mut()) };
        let (sweep, offset) = (sweep.ok_or(null)?, offset.ok_or(null)?);
        if !t_s.is_finite() {
            // A time, not a setting: NON_FINITE with the time as its quantity.
            let time = rotorid::Quantity::Sample(rotorid::hover::SampleField::Time);
            return Err(Error::NonFinite(time).into());
        }
        *offset = Sweep::try_from(sweep)?.offset(t_s);
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// Table 2's schedule (lon, lat, ped, col) with amplitudes `[A_col A_ped A_lon A_lat]`
/// (stick units), sampled at `rate_hz` (1…10 000 Hz).
///
/// # Safety
/// `amplitudes` is NULL or points to 4 doubles; `out` and `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_schedule_table2(
    amplitudes: *const f64,
    rate_hz: u32,
    out: *mut rotorid_schedule_t,
    error: *mut rotorid_error_t,
) -> i32 {
    let result = (|| {
        let null = rotorid_error_t::interface(ROTORID_E_NULL);
        // SAFETY: the caller's contract.
        let (amplitudes, out) = unsafe { (amplitudes.cast::<[f64; 4]>().as_ref(), out.as_mut()) };
        let (amplitudes, out) = (amplitudes.ok_or(null)?, out.ok_or(null)?);
        let s = SweepSchedule::table2(*amplitudes, rate_hz)?;
        let [a, b, c, d] = *s.sweeps();
        *out = rotorid_schedule_t {
            sweeps: [a.into(), b.into(), c.into(), d.into()],
            rate_hz: s.rate_hz(),
        };
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// The number of samples in the schedule.
///
/// # Safety
/// `schedule`, `samples` and `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_schedule_len(
    schedule: *const rotorid_schedule_t,
    samples: *mut u32,
    error: *mut rotorid_error_t,
) -> i32 {
    let result = (|| {
        let null = rotorid_error_t::interface(ROTORID_E_NULL);
        // SAFETY: the caller's contract.
        let (s, samples) = unsafe { (schedule.as_ref(), samples.as_mut()) };
        let (s, samples) = (s.ok_or(null)?, samples.ok_or(null)?);
        *samples = core_schedule(s)?.len();
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// The command at sample `k` (time k / f_s from the schedule's start): the channel being swept
/// (`ROTORID_CHANNEL_*`; the others hold trim) and its offset from trim (stick units).
/// `*active` is 1 during the schedule, 0 past its end (channel and offset then 0).
///
/// # Safety
/// `schedule`, `active`, `channel`, `offset` and `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_schedule_at(
    schedule: *const rotorid_schedule_t,
    k: u32,
    active: *mut u32,
    channel: *mut u32,
    offset: *mut f64,
    error: *mut rotorid_error_t,
) -> i32 {
    let result = (|| {
        let null = rotorid_error_t::interface(ROTORID_E_NULL);
        // SAFETY: the caller's contract.
        let (s, active, channel, offset) = unsafe {
            (
                schedule.as_ref(),
                active.as_mut(),
                channel.as_mut(),
                offset.as_mut(),
            )
        };
        let (s, active) = (s.ok_or(null)?, active.ok_or(null)?);
        let (channel, offset) = (channel.ok_or(null)?, offset.ok_or(null)?);
        let e = core_schedule(s)?.at(k);
        *active = u32::from(e.is_some());
        *channel = e.map_or(0, |e| channel_code(e.channel));
        *offset = e.map_or(0.0, |e| e.offset);
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}
