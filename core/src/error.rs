//! The one error type of the core.
//!
//! Every public fallible call returns [`Error`]. Whenever a call returns `Err`, the object it
//! was called on is left exactly as it was (bit for bit): inputs are checked completely before
//! anything is written.

use core::fmt;

/// Which input quantity a rejected value belongs to.
///
/// The generic layers (RLS, TS models, rule bases) name their own inputs here; the fields of
/// the helicopter's measured sample are one variant, [`Quantity::Sample`], whose names live
/// with the sample ([`SampleField`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Quantity {
    /// A field of the measured sample ([`HoverSample`](crate::hover::HoverSample)).
    Sample(SampleField),
    /// Premise variable `x[index]` of a rule base.
    Premise(u8),
    /// Regressor entry `ξ[index]`.
    Regressor(u16),
    /// Regression target `y` of output `index`.
    Target(u8),
    /// Consequent parameter `θ[index]` (import).
    Parameter(u16),
    /// Covariance or factor entry `P[index]` (packed, import).
    Covariance(u16),
    /// A configuration value (membership centre or spread, α, λ, bounds, sweep settings).
    Config,
}

impl From<SampleField> for Quantity {
    fn from(f: SampleField) -> Self {
        Quantity::Sample(f)
    }
}

/// Why a configuration was refused.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ConfigError {
    /// A membership function has a non-finite centre, or a spread σ that is not finite and > 0.
    MembershipFunction {
        /// Premise variable.
        variable: u8,
        /// Set within the variable.
        set: u8,
    },
    /// The product of the per-variable set counts is not the rule count `R` of the type.
    RuleCount {
        /// Rules the type holds (`R`).
        expected: u16,
        /// Rules the sets make.
        found: u32,
    },
    /// A const-generic size is inconsistent (for example `N != R·D`).
    Dimensions,
    /// Initial covariance α is not finite and in (0, 1e12].
    InitialCovariance,
    /// Forgetting factor λ is not in [0.9, 1], or its trace bound is not finite and > 0.
    Forgetting,
    /// A model structure needs `needed` consequent terms per rule, the type holds `found`.
    ConsequentTerms {
        /// Terms the structure needs.
        needed: u8,
        /// Terms the type provides (`D`).
        found: u8,
    },
    /// Sample period or its tolerance out of range.
    SamplePeriod,
    /// Sweep parameters out of range (ω_min ≥ ω_max, T_rec ≤ 0, …).
    Sweep,
    /// A regressor scale is not finite and > 0.
    Scale,
    /// An observer gain is not finite and in [0, 1]
    /// ([`Observer`](crate::hover::Observer)).
    ObserverGain {
        /// The gain's state in `[v_x v_y v_z q r p]` (0–5), or the candidate's number in a
        /// [`GainSearch`](crate::hover::GainSearch).
        index: u8,
    },
}

/// The error of every fallible call in the core.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// A value is NaN or ±∞.
    NonFinite(Quantity),
    /// A finite value lies outside the range the estimator accepts (see the quantity's docs).
    OutOfRange(Quantity),
    /// The time since the previous sample is outside the accepted window around the nominal
    /// sample period. Call `resume` to restart the sample chain after a gap.
    TimeStep {
        /// Measured interval (µs).
        dt_us: u64,
        /// Shortest accepted interval (µs).
        min_us: u64,
        /// Longest accepted interval (µs).
        max_us: u64,
    },
    /// The time stamp does not increase.
    NonMonotonicTime,
    /// A configuration was refused.
    Config(ConfigError),
    /// Imported state does not fit (wrong form or size).
    Incompatible,
    /// The update would produce a non-finite number; nothing was changed.
    Numerical,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Quantity::Sample(field) => write!(f, "{field}"),
            Quantity::Premise(i) => write!(f, "premise variable x[{i}]"),
            Quantity::Regressor(i) => write!(f, "regressor ξ[{i}]"),
            Quantity::Target(i) => write!(f, "target y[{i}]"),
            Quantity::Parameter(i) => write!(f, "parameter θ[{i}]"),
            Quantity::Covariance(i) => write!(f, "covariance entry P[{i}]"),
            Quantity::Config => f.write_str("configuration value"),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ConfigError::MembershipFunction { variable, set } => write!(
                f,
                "membership function {set} of premise variable {variable} needs a finite centre and a finite spread > 0"
            ),
            ConfigError::RuleCount { expected, found } => {
                write!(f, "the sets make {found} rules, the type holds {expected}")
            }
            ConfigError::Dimensions => f.write_str("inconsistent const-generic sizes"),
            ConfigError::InitialCovariance => {
                f.write_str("initial covariance α must be finite and in (0, 1e12]")
            }
            ConfigError::Forgetting => f.write_str(
                "forgetting factor λ must be in [0.9, 1] and the trace bound finite and > 0",
            ),
            ConfigError::ConsequentTerms { needed, found } => write!(
                f,
                "the model structure needs {needed} consequent terms per rule, the type holds {found}"
            ),
            ConfigError::SamplePeriod => f.write_str("sample period or tolerance out of range"),
            ConfigError::Sweep => f.write_str("sweep parameters out of range"),
            ConfigError::Scale => f.write_str("regressor scales must be finite and > 0"),
            ConfigError::ObserverGain { index } => {
                write!(f, "observer gain {index} must be finite and in [0, 1]")
            }
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NonFinite(q) => write!(f, "{q} is not finite"),
            Error::OutOfRange(q) => write!(f, "{q} is out of range"),
            Error::TimeStep { dt_us, min_us, max_us } => write!(
                f,
                "sample interval {dt_us} µs outside the accepted {min_us}…{max_us} µs (call resume after a gap)"
            ),
            Error::NonMonotonicTime => f.write_str("time stamp does not increase"),
            Error::Config(c) => write!(f, "invalid configuration: {c}"),
            Error::Incompatible => f.write_str("imported state does not fit this estimator"),
            Error::Numerical => f.write_str("update would produce a non-finite value; nothing changed"),
        }
    }
}

impl core::error::Error for Error {}

impl From<ConfigError> for Error {
    fn from(c: ConfigError) -> Self {
        Error::Config(c)
    }
}

/// With the `std` feature: a rotorid error as an I/O error of kind `InvalidData` (its message
/// kept), so that a host program replaying a log can `?` both through one `io::Result`.
#[cfg(feature = "std")]
impl From<Error> for std::io::Error {
    fn from(e: Error) -> Self {
        std::io::Error::new(std::io::ErrorKind::InvalidData, e)
    }
}

#[cfg(all(test, feature = "std"))]
mod std_tests {
    use super::*;

    #[test]
    fn an_error_becomes_an_io_error_with_its_message() {
        let io: std::io::Error = Error::NonMonotonicTime.into();
        assert_eq!(io.kind(), std::io::ErrorKind::InvalidData);
        assert_eq!(std::format!("{io}"), "time stamp does not increase");
    }
}

/// A field of a [`HoverSample`](crate::hover::HoverSample), as an error names it ([`Quantity::Sample`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SampleField {
    /// Roll angle φ (rad).
    Roll,
    /// Pitch angle θ (rad).
    Pitch,
    /// Yaw angle ψ (rad).
    Yaw,
    /// Inertial velocity component `v^s[index]` (m/s, paper axes: x east, y up, z south).
    Velocity(u8),
    /// Body rate `ω^b[index]` of `[q r p]` (deg/s).
    Rate(u8),
    /// Control `u[index]` of `[u_col u_ped u_lon u_lat]` (normalised, −1…1).
    Control(u8),
    /// Sample time stamp (µs).
    Time,
    /// Component of an attitude quaternion `[w x y z]` (index 0–3).
    Quaternion(u8),
    /// The norm of an attitude quaternion (`|‖q‖² − 1|`, see
    /// [`SampleLimits::QUATERNION_NORM`](crate::hover::SampleLimits::QUATERNION_NORM)).
    QuaternionNorm,
    /// Element of an attitude rotation matrix (index `3 × row + column`).
    Matrix(u8),
    /// The orthonormality of an attitude rotation matrix's columns (see
    /// [`SampleLimits::MATRIX_ORTHONORMALITY`](crate::hover::SampleLimits::MATRIX_ORTHONORMALITY)).
    MatrixOrthonormality,
}

impl fmt::Display for SampleField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const RATES: [&str; 3] = ["q", "r", "p"];
        const CONTROLS: [&str; 4] = ["u_col", "u_ped", "u_lon", "u_lat"];
        const AXES: [&str; 3] = ["x", "y", "z"];
        match *self {
            SampleField::Roll => f.write_str("roll φ (rad)"),
            SampleField::Pitch => f.write_str("pitch θ (rad)"),
            SampleField::Yaw => f.write_str("yaw ψ (rad)"),
            SampleField::Velocity(i) => match AXES.get(usize::from(i)) {
                Some(a) => write!(f, "velocity v_{a} (m/s)"),
                None => write!(f, "velocity[{i}] (m/s)"),
            },
            SampleField::Rate(i) => match RATES.get(usize::from(i)) {
                Some(a) => write!(f, "body rate {a} (deg/s)"),
                None => write!(f, "body rate[{i}] (deg/s)"),
            },
            SampleField::Control(i) => match CONTROLS.get(usize::from(i)) {
                Some(a) => write!(f, "control {a}"),
                None => write!(f, "control[{i}]"),
            },
            SampleField::Time => f.write_str("time stamp (µs)"),
            SampleField::Quaternion(i) => match ["w", "x", "y", "z"].get(usize::from(i)) {
                Some(a) => write!(f, "attitude quaternion {a}"),
                None => write!(f, "attitude quaternion[{i}]"),
            },
            SampleField::QuaternionNorm => f.write_str("attitude quaternion norm"),
            SampleField::Matrix(i) => write!(f, "attitude matrix R[{}][{}]", i / 3, i % 3),
            SampleField::MatrixOrthonormality => f.write_str("attitude matrix orthonormality"),
        }
    }
}

/// `NonFinite` for NaN/±∞, `OutOfRange` beyond `limit` (in magnitude).
pub(crate) fn check<T: crate::scalar::Real>(x: T, limit: f64, q: Quantity) -> Result<(), Error> {
    if !x.is_finite() {
        Err(Error::NonFinite(q))
    } else if x.abs() > T::lit(limit) {
        Err(Error::OutOfRange(q))
    } else {
        Ok(())
    }
}
