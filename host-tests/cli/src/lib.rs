//! The library behind the `rotorid` command-line tool: the CSV log format and the importers of
//! PX4 ULog and ArduPilot DataFlash logs, identification with every identifier variant
//! (training, one-step and free-run evaluation, the Table 4 analogue, f32 against f64), and the
//! report with its plots.
//!
//! It may depend on `rotorid`, `rotorid-sim` (flights to identify and the plant the report
//! compares against) and general-purpose crates; never on the test suite or the firmware link
//! (arrows point down: tool → simulator → core).

pub mod derivatives;
pub mod error_chain;
pub mod experiments;
pub mod flight_report;
pub mod holdout;
pub mod identify;
pub mod import;
pub mod log;
pub mod precision;
pub mod report;
pub mod results;
pub mod robustness;
pub mod simulate;
pub mod verdict;
