//! Why docs/results.md could not be assembled from a run's metrics and parameters.

use std::path::PathBuf;

/// Why [`results_markdown`](crate::results::results_markdown) (or the flight section it holds)
/// failed; every variant that involves a file names it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A run's metrics lack the Table 4 analogue.
    #[error("{run} metrics have no Table 4")]
    MissingTable4 {
        /// "realistic" or "clean".
        run: &'static str,
    },
    /// A run's metrics lack one of Table 4's two variants (the first two).
    #[error("{run} metrics have no {role} variant")]
    MissingVariant {
        /// "realistic" or "clean".
        run: &'static str,
        /// "fuzzy" (the first) or "plain" (the second).
        role: &'static str,
    },
    /// The flight identifier's parameter file could not be read.
    #[error("{}: cannot read", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        #[source]
        source: std::io::Error,
    },
    /// The flight identifier's parameter file is not parameters JSON.
    #[error("{}: not a parameters file", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// The parser's reason.
        #[source]
        source: serde_json::Error,
    },
    /// The parameters are not the flight identifier's (three rules of seven per rate model).
    #[error("{}: unexpected layout for the flight identifier's parameters", path.display())]
    Layout {
        /// The file.
        path: PathBuf,
    },
    /// A plant's hover trim or stick scaling (for the airframe table, or the derivatives
    /// beside the identified ones) failed.
    #[error("plant {airframe}")]
    Plant {
        /// The airframe's name.
        airframe: &'static str,
        /// The simulator's reason.
        #[source]
        source: rotorid_sim::plant::PlantError,
    },
}
