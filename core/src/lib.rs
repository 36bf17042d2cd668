#![no_std]
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod convergence;
pub mod error;
pub mod frames;
pub mod hover;
pub mod membership;
pub mod rls;
pub mod rule_base;
pub mod scalar;
pub mod sweep;
pub mod telemetry;
pub mod ts;

pub use error::{ConfigError, Error, Quantity};
pub use hover::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, HoverConfig, HoverIdentifier, HoverSample,
    HoverState, PaperFuzzyIdentifier, PaperPlainIdentifier,
};
pub use membership::MembershipFunction;
pub use rls::{Algorithm, Rls, RlsConfig, RlsState};
pub use rule_base::RuleBase;
pub use scalar::Real;
pub use ts::{Scaling, TsRls};
