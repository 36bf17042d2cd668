//! rotorid's test and benchmark suite: agreement with the independent reference, properties,
//! golden bits, the firmware under QEMU (the link driver [`firmware_link`], the onboard
//! identification driver [`onboard`], the MAVLink mapping [`mavlink`]), the onboard demo, the
//! soak and the step cost and profile tools; its tests and benchmarks live beside it.
//!
//! It sits at the top and may depend on everything: `rotorid`, `rotorid-link`,
//! `rotorid-mavlink`, `rotorid-sim`, `rotorid-cli` and (tests, benchmarks) `rotorid-reference`;
//! nothing depends on it.

pub mod firmware_link;
#[path = "../../core/tests/support/golden.rs"]
pub mod golden;
pub mod mavlink;
pub mod onboard;
pub mod soak;

/// The code blocks of the repository's README, compiled and run as doc tests so the README
/// stays true.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
