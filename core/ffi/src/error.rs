//! Error codes: one per core error (positive) and one per interface error (negative), and the
//! detail struct that carries what the core's error holds.
//!
//! The core's errors are `#[non_exhaustive]`: an error added to the core after this library was
//! written reads as [`ROTORID_E_UNKNOWN`] until a code is given to it here.

use rotorid::hover::SampleField;
use rotorid::{ConfigError, Error, Quantity};

/// Success.
pub const ROTORID_OK: i32 = 0;

// --- the core's `rotorid::Error` (positive codes) ---
/// A value is NaN or ±∞ (`Error::NonFinite`; `quantity`/`index` say which).
pub const ROTORID_E_NON_FINITE: i32 = 1;
/// A finite value is outside its accepted range (`Error::OutOfRange`; `quantity`/`index`).
pub const ROTORID_E_OUT_OF_RANGE: i32 = 2;
/// The interval since the previous sample is outside ΔT ± tolerance (`Error::TimeStep`;
/// `dt_us`, `min_us`, `max_us`). After a gap, call `rotorid_resume`.
pub const ROTORID_E_TIME_STEP: i32 = 3;
/// The time stamp does not increase (`Error::NonMonotonicTime`).
pub const ROTORID_E_NON_MONOTONIC_TIME: i32 = 4;
/// Imported state does not fit this identifier (`Error::Incompatible`), or its bytes are not
/// an export of this kind.
pub const ROTORID_E_INCOMPATIBLE: i32 = 5;
/// The update or prediction would produce a non-finite number (`Error::Numerical`).
pub const ROTORID_E_NUMERICAL: i32 = 6;

// --- `rotorid::ConfigError` (Error::Config) ---
/// A membership function has a non-finite centre or a spread that is not finite and > 0
/// (`variable`, `set`).
pub const ROTORID_E_CONFIG_MEMBERSHIP: i32 = 10;
/// The premise sets make another number of rules than the identifier holds (`expected`, `found`).
pub const ROTORID_E_CONFIG_RULE_COUNT: i32 = 11;
/// Inconsistent sizes inside the core (`ConfigError::Dimensions`).
pub const ROTORID_E_CONFIG_DIMENSIONS: i32 = 12;
/// α is not finite and in (0, 1e12].
pub const ROTORID_E_CONFIG_INITIAL_COVARIANCE: i32 = 13;
/// λ is not in [0.9, 1], or the trace bound is not finite and in (0, 1e12].
pub const ROTORID_E_CONFIG_FORGETTING: i32 = 14;
/// A structure needs more consequent terms than the type holds (`expected` = needed, `found`).
pub const ROTORID_E_CONFIG_CONSEQUENT_TERMS: i32 = 15;
/// Sample period 0, or its tolerance not below it.
pub const ROTORID_E_CONFIG_SAMPLE_PERIOD: i32 = 16;
/// Sweep settings out of range (ω_min ≥ ω_max, T_rec ≤ 0, rate 0 or > 10 kHz, ...).
pub const ROTORID_E_CONFIG_SWEEP: i32 = 17;
/// A regressor scale is not finite and > 0.
pub const ROTORID_E_CONFIG_SCALE: i32 = 18;
/// A configuration error the core added after this library (update the library).
pub const ROTORID_E_CONFIG_UNKNOWN: i32 = 19;
/// An observer gain is not finite and in [0, 1] (`index`: its state, or the candidate's
/// number; `rotorid::hover::Observer`, which this library does not wrap yet).
pub const ROTORID_E_CONFIG_OBSERVER_GAIN: i32 = 20;
/// `rotorid_config_t.algorithm` is not a `ROTORID_ALGORITHM_*`.
pub const ROTORID_E_CONFIG_ALGORITHM: i32 = 21;
/// `rotorid_config_t.scaling` is not a `ROTORID_SCALING_*`.
pub const ROTORID_E_CONFIG_SCALING: i32 = 22;
/// A gyro noise σ given to `rotorid_compensate` is not finite, or not in [0, 2000] deg/s.
pub const ROTORID_E_CONFIG_GYRO_NOISE: i32 = 23;
/// A choice given to `rotorid_compensate_each` is not a `ROTORID_COMPENSATION_*` (`index`:
/// its rate, 0 q, 1 r, 2 p).
pub const ROTORID_E_CONFIG_GYRO_COMPENSATION: i32 = 24;
// --- `rotorid::record::RecordError` (rotorid_record_read) ---
/// Neither slot holds a valid persistence record (erased, torn, never written): start afresh.
pub const ROTORID_E_NO_RECORD: i32 = 30;
/// The newest record is of another record format version (`found`): start afresh.
pub const ROTORID_E_RECORD_VERSION: i32 = 31;
/// The newest record holds another identifier kind (`found`; `expected`: the handle's kind).
pub const ROTORID_E_RECORD_KIND: i32 = 32;
/// The newest record was learnt under another configuration or other premise sets (`found`,
/// `expected`: the configuration hashes): initialise with those, or start afresh.
pub const ROTORID_E_RECORD_CONFIG: i32 = 33;

/// An error the core added after this library (update the library).
pub const ROTORID_E_UNKNOWN: i32 = 99;

// --- interface errors (negative codes) ---
/// A required pointer is NULL.
pub const ROTORID_E_NULL: i32 = -1;
/// The storage or handle is not aligned to `ROTORID_STORAGE_ALIGN`.
pub const ROTORID_E_MISALIGNED: i32 = -2;
/// The storage is smaller than the kind's `ROTORID_<KIND>_STORAGE_SIZE`.
pub const ROTORID_E_STORAGE_SIZE: i32 = -3;
/// The handle does not point to storage prepared by `rotorid_init`.
pub const ROTORID_E_NOT_INITIALISED: i32 = -4;
/// The kind code is not a `ROTORID_KIND_*`.
pub const ROTORID_E_KIND: i32 = -5;
/// The output buffer is smaller than the kind's `ROTORID_<KIND>_EXPORT_SIZE`.
pub const ROTORID_E_BUFFER_SIZE: i32 = -6;
/// An argument that must be NULL for this kind is not (premise sets for a kind without them).
pub const ROTORID_E_ARGUMENT: i32 = -7;

/// What a quantity in `rotorid_error_t` names (`rotorid::Quantity`).
pub const ROTORID_QUANTITY_NONE: u32 = 0;
/// Roll φ.
pub const ROTORID_QUANTITY_ROLL: u32 = 1;
/// Pitch θ.
pub const ROTORID_QUANTITY_PITCH: u32 = 2;
/// Yaw ψ.
pub const ROTORID_QUANTITY_YAW: u32 = 3;
/// Velocity `v[index]`.
pub const ROTORID_QUANTITY_VELOCITY: u32 = 4;
/// Body rate `[q r p][index]`.
pub const ROTORID_QUANTITY_RATE: u32 = 5;
/// Control `[u_col u_ped u_lon u_lat][index]`.
pub const ROTORID_QUANTITY_CONTROL: u32 = 6;
/// Time stamp.
pub const ROTORID_QUANTITY_TIME: u32 = 7;
/// Premise variable `x[index]`.
pub const ROTORID_QUANTITY_PREMISE: u32 = 8;
/// Regressor entry `ξ[index]`.
pub const ROTORID_QUANTITY_REGRESSOR: u32 = 9;
/// Regression target `y[index]`.
pub const ROTORID_QUANTITY_TARGET: u32 = 10;
/// Consequent parameter `θ[index]` (import).
pub const ROTORID_QUANTITY_PARAMETER: u32 = 11;
/// Covariance or factor entry `P[index]` (import).
pub const ROTORID_QUANTITY_COVARIANCE: u32 = 12;
/// A configuration value.
pub const ROTORID_QUANTITY_CONFIG: u32 = 13;
/// `rotorid_sample_t.attitude_form` (not a `ROTORID_ATTITUDE_*`).
pub const ROTORID_QUANTITY_ATTITUDE_FORM: u32 = 14;
/// The attitude quaternion `q`: index 0–3 a component `[w x y z]`, 4 its norm.
pub const ROTORID_QUANTITY_QUATERNION: u32 = 15;
/// An attitude rotation matrix (Rust callers): index `3 × row + column`, 9 its orthonormality.
pub const ROTORID_QUANTITY_MATRIX: u32 = 16;
/// A quantity the core added after this library.
pub const ROTORID_QUANTITY_UNKNOWN: u32 = 255;

/// The detail of an error; every call that can fail takes a `rotorid_error_t *` (NULL when
/// the detail is not wanted) and fills it on failure. Fields not named by the code are 0.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct rotorid_error_t {
    /// The code the call returned.
    pub code: i32,
    /// `ROTORID_QUANTITY_*` of a NON_FINITE or OUT_OF_RANGE value.
    pub quantity: u32,
    /// Index within the quantity (axis, control, entry); CONFIG_OBSERVER_GAIN: the gain's
    /// state or candidate; CONFIG_GYRO_COMPENSATION: the rate (0 q, 1 r, 2 p).
    pub index: u32,
    /// TIME_STEP: measured interval (µs).
    pub dt_us: u64,
    /// TIME_STEP: shortest accepted interval (µs).
    pub min_us: u64,
    /// TIME_STEP: longest accepted interval (µs).
    pub max_us: u64,
    /// CONFIG_MEMBERSHIP: premise variable.
    pub variable: u32,
    /// CONFIG_MEMBERSHIP: set within the variable.
    pub set: u32,
    /// CONFIG_RULE_COUNT: rules the identifier holds; CONFIG_CONSEQUENT_TERMS: terms needed.
    pub expected: u32,
    /// CONFIG_RULE_COUNT: rules the sets make; CONFIG_CONSEQUENT_TERMS: terms provided.
    pub found: u32,
}

impl rotorid_error_t {
    /// The detail of an interface error (no core error behind it).
    pub(crate) fn interface(code: i32) -> Self {
        Self {
            code,
            ..Self::default()
        }
    }

    /// OUT_OF_RANGE: a `rotorid_sample_t.attitude_form` that is not a `ROTORID_ATTITUDE_*`.
    pub(crate) fn attitude_form() -> Self {
        Self {
            code: ROTORID_E_OUT_OF_RANGE,
            quantity: ROTORID_QUANTITY_ATTITUDE_FORM,
            ..Self::default()
        }
    }
}

fn quantity(q: Quantity) -> (u32, u32) {
    match q {
        Quantity::Sample(field) => match field {
            SampleField::Roll => (ROTORID_QUANTITY_ROLL, 0),
            SampleField::Pitch => (ROTORID_QUANTITY_PITCH, 0),
            SampleField::Yaw => (ROTORID_QUANTITY_YAW, 0),
            SampleField::Velocity(i) => (ROTORID_QUANTITY_VELOCITY, i.into()),
            SampleField::Rate(i) => (ROTORID_QUANTITY_RATE, i.into()),
            SampleField::Control(i) => (ROTORID_QUANTITY_CONTROL, i.into()),
            SampleField::Time => (ROTORID_QUANTITY_TIME, 0),
            SampleField::Quaternion(i) => (ROTORID_QUANTITY_QUATERNION, i.into()),
            SampleField::QuaternionNorm => (ROTORID_QUANTITY_QUATERNION, 4),
            SampleField::Matrix(i) => (ROTORID_QUANTITY_MATRIX, i.into()),
            SampleField::MatrixOrthonormality => (ROTORID_QUANTITY_MATRIX, 9),
            _ => (ROTORID_QUANTITY_UNKNOWN, 0),
        },
        Quantity::Premise(i) => (ROTORID_QUANTITY_PREMISE, i.into()),
        Quantity::Regressor(i) => (ROTORID_QUANTITY_REGRESSOR, i.into()),
        Quantity::Target(i) => (ROTORID_QUANTITY_TARGET, i.into()),
        Quantity::Parameter(i) => (ROTORID_QUANTITY_PARAMETER, i.into()),
        Quantity::Covariance(i) => (ROTORID_QUANTITY_COVARIANCE, i.into()),
        Quantity::Config => (ROTORID_QUANTITY_CONFIG, 0),
        _ => (ROTORID_QUANTITY_UNKNOWN, 0),
    }
}

fn config(e: ConfigError) -> rotorid_error_t {
    let mut d = rotorid_error_t::default();
    d.code = match e {
        ConfigError::MembershipFunction { variable, set } => {
            d.variable = variable.into();
            d.set = set.into();
            ROTORID_E_CONFIG_MEMBERSHIP
        }
        ConfigError::RuleCount { expected, found } => {
            d.expected = expected.into();
            d.found = found;
            ROTORID_E_CONFIG_RULE_COUNT
        }
        ConfigError::Dimensions => ROTORID_E_CONFIG_DIMENSIONS,
        ConfigError::InitialCovariance => ROTORID_E_CONFIG_INITIAL_COVARIANCE,
        ConfigError::Forgetting => ROTORID_E_CONFIG_FORGETTING,
        ConfigError::ConsequentTerms { needed, found } => {
            d.expected = needed.into();
            d.found = found.into();
            ROTORID_E_CONFIG_CONSEQUENT_TERMS
        }
        ConfigError::SamplePeriod => ROTORID_E_CONFIG_SAMPLE_PERIOD,
        ConfigError::Sweep => ROTORID_E_CONFIG_SWEEP,
        ConfigError::Scale => ROTORID_E_CONFIG_SCALE,
        ConfigError::ObserverGain { index } => {
            d.index = index.into();
            ROTORID_E_CONFIG_OBSERVER_GAIN
        }
        _ => ROTORID_E_CONFIG_UNKNOWN,
    };
    d
}

impl From<Error> for rotorid_error_t {
    fn from(e: Error) -> Self {
        let mut d = Self::default();
        match e {
            Error::NonFinite(q) => {
                d.code = ROTORID_E_NON_FINITE;
                (d.quantity, d.index) = quantity(q);
            }
            Error::OutOfRange(q) => {
                d.code = ROTORID_E_OUT_OF_RANGE;
                (d.quantity, d.index) = quantity(q);
            }
            Error::TimeStep {
                dt_us,
                min_us,
                max_us,
            } => {
                d.code = ROTORID_E_TIME_STEP;
                (d.dt_us, d.min_us, d.max_us) = (dt_us, min_us, max_us);
            }
            Error::NonMonotonicTime => d.code = ROTORID_E_NON_MONOTONIC_TIME,
            Error::Config(c) => d = config(c),
            Error::Incompatible => d.code = ROTORID_E_INCOMPATIBLE,
            Error::Numerical => d.code = ROTORID_E_NUMERICAL,
            _ => d.code = ROTORID_E_UNKNOWN,
        }
        d
    }
}

/// Writes `detail` to `out` (when not NULL) and returns its code: the tail of every call.
///
/// # Safety
/// `out` is NULL or valid for one write of a `rotorid_error_t`.
pub(crate) unsafe fn report(result: Result<(), rotorid_error_t>, out: *mut rotorid_error_t) -> i32 {
    match result {
        Ok(()) => ROTORID_OK,
        Err(detail) => {
            // SAFETY: the caller's contract (documented on every function).
            if let Some(out) = unsafe { out.as_mut() } {
                *out = detail;
            }
            detail.code
        }
    }
}

/// The name of a code (`"ROTORID_E_TIME_STEP"`, ...), a static NUL-terminated string;
/// `"ROTORID_E_?"` for a code this library does not know.
#[no_mangle]
pub extern "C" fn rotorid_error_name(code: i32) -> *const core::ffi::c_char {
    let name: &'static core::ffi::CStr = match code {
        ROTORID_OK => c"ROTORID_OK",
        ROTORID_E_NON_FINITE => c"ROTORID_E_NON_FINITE",
        ROTORID_E_OUT_OF_RANGE => c"ROTORID_E_OUT_OF_RANGE",
        ROTORID_E_TIME_STEP => c"ROTORID_E_TIME_STEP",
        ROTORID_E_NON_MONOTONIC_TIME => c"ROTORID_E_NON_MONOTONIC_TIME",
        ROTORID_E_INCOMPATIBLE => c"ROTORID_E_INCOMPATIBLE",
        ROTORID_E_NUMERICAL => c"ROTORID_E_NUMERICAL",
        ROTORID_E_CONFIG_MEMBERSHIP => c"ROTORID_E_CONFIG_MEMBERSHIP",
        ROTORID_E_CONFIG_RULE_COUNT => c"ROTORID_E_CONFIG_RULE_COUNT",
        ROTORID_E_CONFIG_DIMENSIONS => c"ROTORID_E_CONFIG_DIMENSIONS",
        ROTORID_E_CONFIG_INITIAL_COVARIANCE => c"ROTORID_E_CONFIG_INITIAL_COVARIANCE",
        ROTORID_E_CONFIG_FORGETTING => c"ROTORID_E_CONFIG_FORGETTING",
        ROTORID_E_CONFIG_CONSEQUENT_TERMS => c"ROTORID_E_CONFIG_CONSEQUENT_TERMS",
        ROTORID_E_CONFIG_SAMPLE_PERIOD => c"ROTORID_E_CONFIG_SAMPLE_PERIOD",
        ROTORID_E_CONFIG_SWEEP => c"ROTORID_E_CONFIG_SWEEP",
        ROTORID_E_CONFIG_SCALE => c"ROTORID_E_CONFIG_SCALE",
        ROTORID_E_CONFIG_UNKNOWN => c"ROTORID_E_CONFIG_UNKNOWN",
        ROTORID_E_CONFIG_OBSERVER_GAIN => c"ROTORID_E_CONFIG_OBSERVER_GAIN",
        ROTORID_E_CONFIG_ALGORITHM => c"ROTORID_E_CONFIG_ALGORITHM",
        ROTORID_E_CONFIG_SCALING => c"ROTORID_E_CONFIG_SCALING",
        ROTORID_E_CONFIG_GYRO_NOISE => c"ROTORID_E_CONFIG_GYRO_NOISE",
        ROTORID_E_CONFIG_GYRO_COMPENSATION => c"ROTORID_E_CONFIG_GYRO_COMPENSATION",
        ROTORID_E_NO_RECORD => c"ROTORID_E_NO_RECORD",
        ROTORID_E_RECORD_VERSION => c"ROTORID_E_RECORD_VERSION",
        ROTORID_E_RECORD_KIND => c"ROTORID_E_RECORD_KIND",
        ROTORID_E_RECORD_CONFIG => c"ROTORID_E_RECORD_CONFIG",
        ROTORID_E_UNKNOWN => c"ROTORID_E_UNKNOWN",
        ROTORID_E_NULL => c"ROTORID_E_NULL",
        ROTORID_E_MISALIGNED => c"ROTORID_E_MISALIGNED",
        ROTORID_E_STORAGE_SIZE => c"ROTORID_E_STORAGE_SIZE",
        ROTORID_E_NOT_INITIALISED => c"ROTORID_E_NOT_INITIALISED",
        ROTORID_E_KIND => c"ROTORID_E_KIND",
        ROTORID_E_BUFFER_SIZE => c"ROTORID_E_BUFFER_SIZE",
        ROTORID_E_ARGUMENT => c"ROTORID_E_ARGUMENT",
        _ => c"ROTORID_E_?",
    };
    name.as_ptr()
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    #[test]
    fn every_core_error_has_its_own_code() {
        let errors = [
            Error::NonFinite(Quantity::Sample(SampleField::Rate(2))),
            Error::OutOfRange(Quantity::Sample(SampleField::Control(3))),
            Error::TimeStep {
                dt_us: 1,
                min_us: 2,
                max_us: 3,
            },
            Error::NonMonotonicTime,
            Error::Incompatible,
            Error::Numerical,
            Error::Config(ConfigError::MembershipFunction {
                variable: 1,
                set: 2,
            }),
            Error::Config(ConfigError::RuleCount {
                expected: 3,
                found: 9,
            }),
            Error::Config(ConfigError::Dimensions),
            Error::Config(ConfigError::InitialCovariance),
            Error::Config(ConfigError::Forgetting),
            Error::Config(ConfigError::ConsequentTerms {
                needed: 7,
                found: 4,
            }),
            Error::Config(ConfigError::SamplePeriod),
            Error::Config(ConfigError::Sweep),
            Error::Config(ConfigError::Scale),
            Error::Config(ConfigError::ObserverGain { index: 4 }),
        ];
        let mut codes: std::vec::Vec<i32> = errors
            .iter()
            .map(|&e| rotorid_error_t::from(e).code)
            .collect();
        assert!(codes.iter().all(|&c| c > 0 && c != ROTORID_E_UNKNOWN));
        assert!(codes.iter().all(|&c| c != ROTORID_E_CONFIG_UNKNOWN));
        codes.sort_unstable();
        codes.dedup();
        assert_eq!(codes.len(), errors.len(), "two errors share a code");
        let d = rotorid_error_t::from(Error::NonFinite(Quantity::Sample(SampleField::Rate(2))));
        assert_eq!((d.quantity, d.index), (ROTORID_QUANTITY_RATE, 2));
        let d = rotorid_error_t::from(errors[2]);
        assert_eq!((d.dt_us, d.min_us, d.max_us), (1, 2, 3));
        let d = rotorid_error_t::from(errors[11]);
        assert_eq!((d.expected, d.found), (7, 4));
        let d = rotorid_error_t::from(errors[15]);
        assert_eq!(d.index, 4);
    }

    #[test]
    fn every_code_has_a_name() {
        for code in [-7, -6, -5, -4, -3, -2, -1, 0, 1, 2, 3, 4, 5, 6, 99]
            .into_iter()
            .chain(10..=23)
        {
            // SAFETY: the function returns a pointer to a static C string.
            let name = unsafe { core::ffi::CStr::from_ptr(rotorid_error_name(code)) };
            assert_ne!(name.to_bytes(), b"ROTORID_E_?", "code {code}");
        }
    }
}
