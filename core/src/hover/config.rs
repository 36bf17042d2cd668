//! The settings every model of a [`HoverIdentifier`](super::HoverIdentifier) shares.

use crate::error::{ConfigError, Error};
use crate::hover::models::{RateAxis, RateStructure, VelocityStructure};
use crate::rls::RlsConfig;
use crate::scalar::Real;
use crate::ts::Scaling;

/// Whether the models divide their terms by nominal scales (see [`crate::ts::Scaling`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RegressorScaling {
    /// Raw physical units, as the paper: bit-identical to an implementation without scaling.
    None,
    /// The nominal miniature-helicopter scales of
    /// [`VelocityStructure::helicopter_scaling`] and [`RateStructure::helicopter_scaling`]:
    /// a well-conditioned problem in f32. Parameters are still reported in physical units by
    /// [`TsRls::physical_parameter`](crate::ts::TsRls::physical_parameter).
    Helicopter,
}

/// Settings shared by the four models of a [`HoverIdentifier`](super::HoverIdentifier).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HoverConfig<T> {
    /// Estimator settings of every model.
    pub rls: RlsConfig<T>,
    /// Nominal sample period ΔT (µs). The identified parameters are per-step quantities
    /// (Eqs. 22–25 contain ΔT), so a model is only valid at the rate it was learnt at.
    pub sample_period_us: u32,
    /// Accepted deviation of one interval from ΔT (µs), for timing jitter.
    pub period_tolerance_us: u32,
    /// Regressor scaling of every model.
    pub scaling: RegressorScaling,
}

impl<T: Real> Default for HoverConfig<T> {
    /// The flight settings: robust (U-D) RLS with α = 10⁶, helicopter regressor scaling,
    /// 50 Hz (20 000 µs) ± 50 %.
    fn default() -> Self {
        Self {
            rls: RlsConfig::default(),
            sample_period_us: 20_000,
            period_tolerance_us: 10_000,
            scaling: RegressorScaling::Helicopter,
        }
    }
}

impl<T: Real> HoverConfig<T> {
    /// The paper's settings: covariance-form RLS, λ = 1, α = 10⁶, no scaling, 50 Hz ± 50 %.
    pub fn paper() -> Self {
        Self {
            rls: RlsConfig::paper(T::lit(1e6)),
            scaling: RegressorScaling::None,
            ..Self::default()
        }
    }

    /// The paper's estimator computed robustly: U-D RLS, α = 10⁶, no scaling.
    pub fn paper_robust() -> Self {
        Self {
            scaling: RegressorScaling::None,
            ..Self::default()
        }
    }

    pub(crate) fn velocity_scaling<const D: usize>(&self, s: VelocityStructure) -> Scaling<T, D> {
        match self.scaling {
            RegressorScaling::None => Scaling::unit(),
            RegressorScaling::Helicopter => s.helicopter_scaling(),
        }
    }

    pub(crate) fn rate_scaling<const D: usize>(
        &self,
        s: RateStructure,
        axis: RateAxis,
    ) -> Scaling<T, D> {
        match self.scaling {
            RegressorScaling::None => Scaling::unit(),
            RegressorScaling::Helicopter => s.helicopter_scaling(axis),
        }
    }

    pub(super) fn validate(&self) -> Result<(), Error> {
        self.rls.validate()?;
        if self.sample_period_us == 0 || self.period_tolerance_us >= self.sample_period_us {
            return Err(ConfigError::SamplePeriod.into());
        }
        Ok(())
    }
}
