//! The studies' side of rotorid (`rotorid-lab`): what generates the documents under `docs/`
//! and is no part of the product a user runs.
//!
//! * [`ablations`]: the flight default with one choice undone each; [`ablations::full_catalogue`]
//!   is the product's catalogue followed by them, which `rotorid-lab identify` evaluates.
//! * [`results`] (with [`tables`] and [`flight_report`]): docs/results.md from the metrics of
//!   `rotorid-lab identify` runs.
//! * [`robustness`]: docs/robustness.md from the metrics of plant variations.
//! * [`rate_orders`]: the rate models' order and gyro-noise compensation fitted offline
//!   (docs/rate-orders.md).
//!
//! It depends on `rotorid-cli` (the identification, the metrics, the verdict), never the
//! reverse: the product carries no report generator and no ablation.

pub mod ablations;
pub mod error;
pub mod flight_report;
pub mod rate_orders;
pub mod results;
pub mod robustness;
pub mod tables;
