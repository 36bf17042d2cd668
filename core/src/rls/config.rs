//! The settings of one RLS estimator: the covariance form and its bounds.

use crate::error::{ConfigError, Error};
use crate::scalar::Real;

use super::COVARIANCE_LIMIT;

/// How the covariance is propagated (see the [module docs](crate::rls)).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Algorithm {
    /// The covariance form of the paper's Section 4 (packed symmetric P).
    Covariance,
    /// Bierman's U-D factorisation (packed unit upper U with D on the diagonal).
    UdFactor,
}

impl Algorithm {
    /// The form's code in every rotorid byte format (telemetry, exports, the C interface):
    /// 0 covariance, 1 U-D.
    pub const fn code(self) -> u8 {
        match self {
            Self::Covariance => 0,
            Self::UdFactor => 1,
        }
    }

    /// The form of a [`code`](Self::code); `None` for any other byte.
    pub const fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::Covariance),
            1 => Some(Self::UdFactor),
            _ => None,
        }
    }
}

/// Settings of one RLS estimator.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RlsConfig<T> {
    /// Covariance propagation.
    pub algorithm: Algorithm,
    /// α in `P(0) = α I`: the prior variance of each parameter (in (0, 1e12]).
    pub initial_covariance: T,
    /// Forgetting factor λ ∈ [0.9, 1]; 1 (the paper) forgets nothing.
    pub forgetting: T,
    /// Windup guard for λ < 1: upper bound on trace(P) (> 0, ≤ 1e12).
    pub max_trace: T,
}

impl<T: Real> RlsConfig<T> {
    /// The paper's RLS: covariance form, λ = 1, `P(0) = αI`.
    pub fn paper(alpha: T) -> Self {
        Self {
            algorithm: Algorithm::Covariance,
            initial_covariance: alpha,
            forgetting: T::one(),
            max_trace: T::lit(COVARIANCE_LIMIT),
        }
    }

    /// Bierman U-D form, λ = 1, `P(0) = αI`: the paper's estimator, computed robustly.
    pub fn robust(alpha: T) -> Self {
        Self {
            algorithm: Algorithm::UdFactor,
            ..Self::paper(alpha)
        }
    }

    /// Returns `self` with forgetting factor λ and trace bound (windup guard).
    pub fn with_forgetting(self, lambda: T, max_trace: T) -> Self {
        Self {
            forgetting: lambda,
            max_trace,
            ..self
        }
    }

    /// Checks the ranges documented on the fields.
    pub fn validate(&self) -> Result<(), Error> {
        let limit = T::lit(COVARIANCE_LIMIT);
        let a = self.initial_covariance;
        if !(a.is_finite() && a > T::zero() && a <= limit) {
            return Err(ConfigError::InitialCovariance.into());
        }
        let l = self.forgetting;
        let t = self.max_trace;
        let lambda_ok = l.is_finite() && l >= T::lit(0.9) && l <= T::one();
        let trace_ok = t.is_finite() && t > T::zero() && t <= limit;
        if !(lambda_ok && trace_ok) {
            return Err(ConfigError::Forgetting.into());
        }
        Ok(())
    }
}

impl<T: Real> Default for RlsConfig<T> {
    /// [`RlsConfig::robust`] with α = 10⁶.
    fn default() -> Self {
        Self::robust(T::lit(1e6))
    }
}
