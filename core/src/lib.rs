#![no_std]
#![doc = include_str!("../README.md")]
// One `unsafe` block in the crate, allowed where it is: the Arm FPU's square root instruction
// (`scalar::sqrt_f32`).
#![deny(unsafe_code)]
// No panic path: the workspace's lints (Cargo.toml) fail clippy and CI on any unwrap, expect,
// panic or unchecked index outside the tests.

// The `std` feature links std for its conveniences only (`From<Error> for std::io::Error`,
// `DynIdentifier::snapshot_vec`).
#[cfg(feature = "std")]
extern crate std;

pub mod convergence;
pub mod dyn_identifier;
pub mod error;
pub mod frames;
pub mod hover;
pub mod learning;
pub mod membership;
pub mod premise;
pub mod record;
pub mod rls;
pub mod rule_base;
pub mod scalar;
pub mod snapshot;
pub mod sweep;
pub mod ts;

// The integrator's set: the identifiers, what they take and give, and the errors. Building
// blocks (RLS, TS estimators, rule bases, membership functions) stay in their modules.
pub use dyn_identifier::DynIdentifier;
pub use error::{ConfigError, Error, Quantity};
pub use hover::{
    flight_sets, unscheduled_sets, Attitude, Controls, ExtendedFuzzyIdentifier,
    ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier, FlightPlainIdentifier,
    HoverConfig, HoverIdentifier, HoverSample, HoverState, Observer, PaperFuzzyIdentifier,
    PaperLocalIdentifier, PaperPlainIdentifier, Quaternion, RateNoise, RotationMatrix, StepOutput,
};
pub use scalar::Real;
