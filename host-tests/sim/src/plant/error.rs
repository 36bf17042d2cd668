//! The errors of the plant simulator ([`PlantError`]).

/// Errors of the plant simulator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlantError {
    /// The trim Newton iteration did not converge.
    #[error("hover trim did not converge (largest residual {residual:e})")]
    TrimFailed {
        /// Largest remaining residual (m/s² or rad/s²).
        residual: f64,
    },
    /// Trim needs a stick outside [−1, 1] (the stick map cannot fly this configuration).
    #[error("hover trim needs sticks outside [-1, 1]: col {col}, ped {ped}, lon {lon}, lat {lat}")]
    TrimOutOfRange {
        /// Collective.
        col: f64,
        /// Pedal.
        ped: f64,
        /// Longitudinal cyclic.
        lon: f64,
        /// Lateral cyclic.
        lat: f64,
    },
    /// The flight configuration is not usable.
    #[error("invalid flight configuration: {0}")]
    InvalidConfig(String),
    /// The vehicle left the flight envelope (or the state stopped being finite).
    #[error("vehicle diverged at t = {t:.3} s: {quantity} = {value}")]
    Diverged {
        /// Simulation time (s).
        t: f64,
        /// Which quantity crossed its limit.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
}
