//! The library behind the `rotorid` command-line tool: the CSV log format and the importers of
//! PX4 ULog and ArduPilot DataFlash logs, identification with the product's identifier variants
//! (training, one-step and free-run evaluation, the Table 4 analogue, f32 against f64), the
//! verdict, the derivatives, and the metrics with their plots.
//!
//! The studies' report generators and the ablations live in `rotorid-lab`, which depends on
//! this crate (never the reverse); [`identify::identify_with`] is their seam.
//!
//! It may depend on `rotorid`, `rotorid-sim` (flights to identify and the plant the report
//! compares against) and general-purpose crates; never on the test suite or the firmware link
//! (arrows point down: tool → simulator → core).

#[cfg(feature = "command-line")]
pub mod command_line;
pub mod derivatives;
pub mod error_chain;
pub mod experiments;
pub mod holdout;
pub mod identify;
pub mod import;
pub mod log;
pub mod precision;
pub mod report;
pub mod simulate;
pub mod terminal;
pub mod verdict;
