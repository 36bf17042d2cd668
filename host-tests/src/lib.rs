//! Host-side (std) companion of the `rotorid` core: plant simulator, experiments, log format
//! and the firmware link driver.
pub mod firmware_link;
#[path = "../../core/tests/support/golden.rs"]
pub mod golden;
pub mod mavlink;
pub mod onboard;
pub mod soak;

pub use rotorid_cli::{experiments, flight_report, import, log, precision, report};
pub use rotorid_sim::{envelope, flights, plant};

/// The code blocks of the repository's README, compiled and run as doc tests so the README
/// stays true.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
