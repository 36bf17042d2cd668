#![no_std]
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod convergence;
pub mod error;
pub mod frames;
pub mod hover;
pub mod learning;
pub mod local;
pub mod membership;
pub mod premise;
pub mod rls;
pub mod rule_base;
pub mod scalar;
pub mod sweep;
pub mod telemetry;
pub mod ts;

pub use error::{ConfigError, Error, Quantity};
pub use hover::{
    ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier,
    FlightPlainIdentifier, HoverConfig, HoverIdentifier, HoverSample, HoverState,
    PaperFuzzyIdentifier, PaperLocalIdentifier, PaperPlainIdentifier,
};
pub use learning::{Learning, TsEstimator};
pub use local::LocalTsRls;
pub use membership::MembershipFunction;
pub use rls::{Algorithm, Rls, RlsConfig, RlsState};
pub use rule_base::RuleBase;
pub use scalar::Real;
pub use ts::{Scaling, TsRls};
