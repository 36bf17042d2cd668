//! Host-side (std) companion of the `rotorid` core: plant simulator, experiments, log format
//! and the firmware link driver.
pub mod experiments;
pub mod firmware_link;
pub mod flight_report;
#[path = "../../core/tests/support/golden.rs"]
pub mod golden;
pub mod import;
pub mod log;
pub mod mavlink;
pub mod onboard;
pub mod precision;
pub mod report;
pub mod soak;

pub use rotorid_sim::{envelope, flights, plant};

/// The code blocks of the repository's README, compiled and run as doc tests so the README
/// stays true.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
