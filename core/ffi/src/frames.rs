//! Samples in a flight stack's own convention: NED velocity and forward-right-down body rates
//! in rad/s, as PX4's `vehicle_local_position` / `vehicle_angular_velocity` and ArduPilot's
//! `AP_AHRS` give them (`rotorid::frames`: the same conversion as the Rust API, the same bits).

use nalgebra::Vector3;
use rotorid::frames::{state_to_ned_frd, NedFrdSample};
use rotorid::hover::{Attitude, Controls, HoverState};

use crate::error::*;
use crate::types::{rotorid_sample_t, rotorid_state_t, ROTORID_ATTITUDE_EULER};

/// One sample in the NED / FRD convention.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct rotorid_ned_frd_sample_t {
    /// Time stamp (µs, monotonic).
    pub time_us: u64,
    /// ZYX Euler angles `[φ θ ψ]` (rad): roll, pitch, yaw (heading from north).
    pub euler: [f32; 3],
    /// Velocity `[v_n v_e v_d]` (m/s).
    pub velocity_ned: [f32; 3],
    /// Body rates `[p q r]` about forward, right, down (rad/s).
    pub rates_frd: [f32; 3],
    /// Controls `[u_col u_ped u_lon u_lat]` (−1…1).
    pub controls: [f32; 4],
}

/// Converts a NED/FRD sample to the identifier's axes and units (paper axes, deg/s).
///
/// # Safety
/// `input` and `out` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_sample_from_ned_frd(
    input: *const rotorid_ned_frd_sample_t,
    out: *mut rotorid_sample_t,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(i), Some(out)) = (unsafe { input.as_ref() }, unsafe { out.as_mut() }) else {
        return ROTORID_E_NULL;
    };
    let [roll, pitch, yaw] = i.euler;
    let [col, ped, lon, lat] = i.controls;
    let s = NedFrdSample {
        time_us: i.time_us,
        attitude: Attitude { roll, pitch, yaw },
        velocity_ned: Vector3::from(i.velocity_ned),
        rates_frd: Vector3::from(i.rates_frd),
        controls: Controls { col, ped, lon, lat },
    }
    .to_paper();
    *out = rotorid_sample_t {
        time_us: s.time_us,
        roll: s.attitude.roll,
        pitch: s.attitude.pitch,
        yaw: s.attitude.yaw,
        velocity: s.velocity,
        rates: s.rates,
        controls: s.controls.to_array(),
        attitude_form: ROTORID_ATTITUDE_EULER,
        q: [0.0; 4],
    };
    ROTORID_OK
}

/// Converts a predicted state back to NED velocity (m/s) and FRD body rates (rad/s).
///
/// # Safety
/// `state` is NULL or valid; `velocity_ned` and `rates_frd` are NULL or point to 3 floats each.
#[no_mangle]
pub unsafe extern "C" fn rotorid_state_to_ned_frd(
    state: *const rotorid_state_t,
    velocity_ned: *mut f32,
    rates_frd: *mut f32,
) -> i32 {
    // SAFETY: the caller's contract.
    let pointers = unsafe {
        (
            state.as_ref(),
            velocity_ned.cast::<[f32; 3]>().as_mut(),
            rates_frd.cast::<[f32; 3]>().as_mut(),
        )
    };
    let (Some(s), Some(v), Some(w)) = pointers else {
        return ROTORID_E_NULL;
    };
    let (ned, frd) = state_to_ned_frd(&HoverState::from(s));
    *v = [ned.x, ned.y, ned.z];
    *w = [frd.x, frd.y, frd.z];
    ROTORID_OK
}
