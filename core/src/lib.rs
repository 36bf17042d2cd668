#![no_std]
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]
// No panic path in the library: the lints below fail `cargo clippy` (and CI) on any unwrap,
// expect, panic or unchecked index outside the tests.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]
#![warn(missing_docs)]

// The `std` feature links std for its conveniences only (`From<Error> for std::io::Error`).
#[cfg(feature = "std")]
extern crate std;

pub mod convergence;
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
pub use error::{ConfigError, Error, Quantity};
pub use hover::{
    flight_sets, Attitude, Controls, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier,
    ExtendedPlainIdentifier, FlightIdentifier, FlightPlainIdentifier, HoverConfig, HoverIdentifier,
    HoverSample, HoverState, Observer, PaperFuzzyIdentifier, PaperLocalIdentifier,
    PaperPlainIdentifier, Quaternion, RateNoise, RotationMatrix, StepOutput,
};
pub use scalar::Real;
