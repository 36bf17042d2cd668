//! The plain C structs a caller fills and reads: sample, state, step output, settings and the
//! flight identifier's premise sets. Units and axes are the core's (see `rotorid::hover`): the
//! paper's inertial axes (x east, y up, z south), body rates `[q r p]` in deg/s.

use rotorid::hover::{
    flight_sets, unscheduled_sets, AnyAttitude, Attitude, Controls, HoverSample, HoverState,
    Quaternion, RegressorScaling, StepOutput,
};
use rotorid::rls::{Algorithm, RlsConfig};
use rotorid::HoverConfig;

use crate::error::*;
use crate::ptr::put;

/// One measurement sample at time step k.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct rotorid_sample_t {
    /// Time stamp (µs, monotonic).
    pub time_us: u64,
    /// Roll φ (rad), right side down positive; |φ| ≤ 3.2.
    pub roll: f32,
    /// Pitch θ (rad), nose up positive; |θ| ≤ 1.6.
    pub pitch: f32,
    /// Yaw ψ (rad), clockwise from north seen from above; |ψ| ≤ 6.3.
    pub yaw: f32,
    /// Inertial velocity `[v_x v_y v_z]` (m/s; paper axes: x east, y up, z south); each ≤ 100.
    pub velocity: [f32; 3],
    /// Body rates `[q r p]` (deg/s: pitch, yaw, roll); each ≤ 2000.
    pub rates: [f32; 3],
    /// Controls `[u_col u_ped u_lon u_lat]` applied from this sample to the next (−1…1).
    pub controls: [f32; 4],
    /// The attitude this sample carries: `ROTORID_ATTITUDE_EULER` (0, what a zero-initialised
    /// sample says: `roll`, `pitch`, `yaw`) or `ROTORID_ATTITUDE_QUATERNION` (1: `q`, no
    /// trigonometry in the step). The other attitude fields are not read.
    pub attitude_form: u32,
    /// Attitude quaternion `[w x y z]` rotating body forward-right-down vectors into
    /// north-east-down (PX4's `vehicle_attitude.q` as it stands); `|‖q‖² − 1| ≤ 0.01`.
    pub q: [f32; 4],
}

/// `rotorid_sample_t.attitude_form`: ZYX Euler angles `roll`, `pitch`, `yaw`.
pub const ROTORID_ATTITUDE_EULER: u32 = 0;
/// `rotorid_sample_t.attitude_form`: the quaternion `q`.
pub const ROTORID_ATTITUDE_QUATERNION: u32 = 1;

impl TryFrom<&rotorid_sample_t> for HoverSample<f32, AnyAttitude<f32>> {
    type Error = rotorid_error_t;

    /// The sample, or OUT_OF_RANGE (quantity `ROTORID_QUANTITY_ATTITUDE_FORM`) for an
    /// `attitude_form` that is not a `ROTORID_ATTITUDE_*`.
    fn try_from(s: &rotorid_sample_t) -> Result<Self, rotorid_error_t> {
        let attitude = match s.attitude_form {
            ROTORID_ATTITUDE_EULER => AnyAttitude::Euler(Attitude {
                roll: s.roll,
                pitch: s.pitch,
                yaw: s.yaw,
            }),
            ROTORID_ATTITUDE_QUATERNION => {
                let [w, x, y, z] = s.q;
                AnyAttitude::Quaternion(Quaternion { w, x, y, z })
            }
            _ => return Err(rotorid_error_t::attitude_form()),
        };
        Ok(with_attitude(s, attitude))
    }
}

impl TryFrom<&rotorid_sample_t> for HoverSample<f32, Quaternion<f32>> {
    type Error = rotorid_error_t;

    /// The sample of a lean call (`crate::lean`), whose step has no Euler path: OUT_OF_RANGE
    /// (quantity `ROTORID_QUANTITY_ATTITUDE_FORM`) unless `attitude_form` is
    /// `ROTORID_ATTITUDE_QUATERNION`.
    fn try_from(s: &rotorid_sample_t) -> Result<Self, rotorid_error_t> {
        if s.attitude_form != ROTORID_ATTITUDE_QUATERNION {
            return Err(rotorid_error_t::attitude_form());
        }
        let [w, x, y, z] = s.q;
        Ok(with_attitude(s, Quaternion { w, x, y, z }))
    }
}

/// The core's sample from a C sample and its attitude in the form a call takes.
fn with_attitude<A>(s: &rotorid_sample_t, attitude: A) -> HoverSample<f32, A> {
    let [col, ped, lon, lat] = s.controls;
    HoverSample {
        time_us: s.time_us,
        attitude,
        velocity: s.velocity,
        rates: s.rates,
        controls: Controls { col, ped, lon, lat },
    }
}

/// The six states the identifier predicts.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct rotorid_state_t {
    /// `[v_x v_y v_z]` (m/s, paper axes).
    pub velocity: [f32; 3],
    /// `[q r p]` (deg/s).
    pub rates: [f32; 3],
}

impl From<HoverState<f32>> for rotorid_state_t {
    fn from(s: HoverState<f32>) -> Self {
        Self {
            velocity: s.velocity,
            rates: s.rates,
        }
    }
}

impl From<&rotorid_state_t> for HoverState<f32> {
    fn from(s: &rotorid_state_t) -> Self {
        HoverState {
            velocity: s.velocity,
            rates: s.rates,
        }
    }
}

/// What `rotorid_step` reports.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct rotorid_step_output_t {
    /// One-step prediction of the next sample's state, from the updated parameters.
    pub prediction: rotorid_state_t,
    /// Prior innovations `Δy − ξᵀθ(k)` of this step's update; zero when `has_innovation` is 0.
    pub innovation: rotorid_state_t,
    /// 1 when the step learnt (and `innovation` is valid), 0 when it only started a sample
    /// chain (first sample, or after a resume, reset or import).
    pub has_innovation: u32,
}

impl From<StepOutput<f32>> for rotorid_step_output_t {
    fn from(o: StepOutput<f32>) -> Self {
        Self {
            prediction: o.prediction.into(),
            innovation: o.innovation.map(Into::into).unwrap_or_default(),
            has_innovation: u32::from(o.innovation.is_some()),
        }
    }
}

/// RLS covariance form: the paper's covariance propagation (packed symmetric P).
pub const ROTORID_ALGORITHM_COVARIANCE: u32 = 0;
/// RLS covariance form: Bierman's U-D factorisation (the robust form, the default).
pub const ROTORID_ALGORITHM_UD: u32 = 1;
/// Regressor scaling: raw physical units, as the paper.
pub const ROTORID_SCALING_NONE: u32 = 0;
/// Regressor scaling: nominal miniature-helicopter scales (well conditioned in f32; default).
pub const ROTORID_SCALING_HELICOPTER: u32 = 1;

/// Settings of an identifier (`rotorid::HoverConfig`). Fill it with
/// `rotorid_config_default` or
/// `rotorid_config_paper` and change what you need.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct rotorid_config_t {
    /// `ROTORID_ALGORITHM_COVARIANCE` or `ROTORID_ALGORITHM_UD`.
    pub algorithm: u32,
    /// α in P(0) = αI, the prior variance of each parameter; in (0, 1e12].
    pub initial_covariance: f32,
    /// Forgetting factor λ ∈ [0.9, 1]; 1 forgets nothing.
    pub forgetting: f32,
    /// Windup guard for λ < 1: upper bound on trace(P); in (0, 1e12].
    pub max_trace: f32,
    /// Nominal sample period ΔT (µs); the parameters are per-step quantities.
    pub sample_period_us: u32,
    /// Accepted deviation of one interval from ΔT (µs); less than ΔT.
    pub period_tolerance_us: u32,
    /// `ROTORID_SCALING_NONE` or `ROTORID_SCALING_HELICOPTER`.
    pub scaling: u32,
}

impl From<HoverConfig<f32>> for rotorid_config_t {
    fn from(c: HoverConfig<f32>) -> Self {
        Self {
            algorithm: match c.rls.algorithm {
                Algorithm::Covariance => ROTORID_ALGORITHM_COVARIANCE,
                Algorithm::UdFactor => ROTORID_ALGORITHM_UD,
            },
            initial_covariance: c.rls.initial_covariance,
            forgetting: c.rls.forgetting,
            max_trace: c.rls.max_trace,
            sample_period_us: c.sample_period_us,
            period_tolerance_us: c.period_tolerance_us,
            scaling: match c.scaling {
                RegressorScaling::None => ROTORID_SCALING_NONE,
                // `RegressorScaling` may grow; a new kind reads as the default.
                _ => ROTORID_SCALING_HELICOPTER,
            },
        }
    }
}

impl TryFrom<&rotorid_config_t> for HoverConfig<f32> {
    type Error = rotorid_error_t;

    /// The core validates the values; here only the two codes are checked
    /// (`ROTORID_E_CONFIG_ALGORITHM`, `ROTORID_E_CONFIG_SCALING` for an unknown one).
    fn try_from(c: &rotorid_config_t) -> Result<Self, rotorid_error_t> {
        let algorithm = match c.algorithm {
            ROTORID_ALGORITHM_COVARIANCE => Algorithm::Covariance,
            ROTORID_ALGORITHM_UD => Algorithm::UdFactor,
            _ => return Err(rotorid_error_t::interface(ROTORID_E_CONFIG_ALGORITHM)),
        };
        let scaling = match c.scaling {
            ROTORID_SCALING_NONE => RegressorScaling::None,
            ROTORID_SCALING_HELICOPTER => RegressorScaling::Helicopter,
            _ => return Err(rotorid_error_t::interface(ROTORID_E_CONFIG_SCALING)),
        };
        Ok(HoverConfig {
            rls: RlsConfig {
                algorithm,
                initial_covariance: c.initial_covariance,
                forgetting: c.forgetting,
                max_trace: c.max_trace,
            },
            sample_period_us: c.sample_period_us,
            period_tolerance_us: c.period_tolerance_us,
            scaling,
        })
    }
}

/// The speed premise sets of `ROTORID_KIND_FLIGHT` (m/s): the rate models' on the forward
/// speed (heading frame), the translational model's on the horizontal speed in any direction
/// (`rotorid::hover::Premise::HorizontalSpeed`). A left shoulder, a Gaussian and a right
/// shoulder, `μ = exp(−(u − c)² / (2σ²))` beyond each
/// shoulder's centre. Defaults (`rotorid_flight_sets_default`):
/// centres 0, 5, 10 and spreads 2.5; a tool can place them from a training flight
/// (`rotorid::premise::quantile_sets`).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct rotorid_flight_sets_t {
    /// Centres c of the left shoulder, the Gaussian and the right shoulder (m/s).
    pub centre: [f32; 3],
    /// Spreads σ of the same sets (m/s, > 0).
    pub spread: [f32; 3],
}

/// The flight settings (`rotorid::HoverConfig::default()`): U-D RLS, α = 10⁶, λ = 1,
/// helicopter scaling, 50 Hz ± 50 %. Returns `ROTORID_E_NULL` when `out` is NULL.
///
/// # Safety
/// `out` is NULL or points to a writable `rotorid_config_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_config_default(out: *mut rotorid_config_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        report(
            put(out, HoverConfig::<f32>::default().into()),
            core::ptr::null_mut(),
        )
    }
}

/// The paper's settings (`rotorid::HoverConfig::paper()`): covariance-form RLS, α = 10⁶,
/// λ = 1, no scaling, 50 Hz ± 50 %.
///
/// # Safety
/// As `rotorid_config_default`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_config_paper(out: *mut rotorid_config_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        report(
            put(out, HoverConfig::<f32>::paper().into()),
            core::ptr::null_mut(),
        )
    }
}

/// The default speed sets of `ROTORID_KIND_FLIGHT` (`rotorid::hover::flight_sets`).
///
/// # Safety
/// `out` is NULL or points to a writable `rotorid_flight_sets_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_flight_sets_default(out: *mut rotorid_flight_sets_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { report(put(out, c_sets(&flight_sets())), core::ptr::null_mut()) }
}

/// Speed sets under which a flight model has one rule in effect
/// (`rotorid::hover::unscheduled_sets`: the first set's membership is 1 at every speed a
/// sample can carry, the others' 0), for `rotorid_init_flight_per_model`.
///
/// # Safety
/// `out` is NULL or points to a writable `rotorid_flight_sets_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_flight_sets_unscheduled(out: *mut rotorid_flight_sets_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { report(put(out, c_sets(&unscheduled_sets())), core::ptr::null_mut()) }
}

/// Three sets (left shoulder, Gaussian, right shoulder) as the C interface holds them.
fn c_sets(sets: &[rotorid::membership::MembershipFunction<f32>]) -> rotorid_flight_sets_t {
    let mut out = rotorid_flight_sets_t::default();
    for (i, mf) in sets.iter().enumerate() {
        if let (Some(c), Some(s)) = (out.centre.get_mut(i), out.spread.get_mut(i)) {
            (*c, *s) = mf.parameters();
        }
    }
    out
}
