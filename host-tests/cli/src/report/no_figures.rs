//! [`write_figures`] in a build without the `figures` feature (no plotters): it draws nothing
//! and says so, rather than leaving a run without its figures in silence.

use std::path::{Path, PathBuf};

use rotorid::hover::HoverSample;

use crate::experiments::VariantResult;

/// Why a figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FigureError {
    /// This build of the library has no plotting (the `figures` feature is off).
    #[error("this build of rotorid-cli draws no figures (its `figures` feature is off): run without plots, or build with the feature")]
    NotBuilt,
}

/// Refuses: without the `figures` feature there is nothing to draw with.
pub fn write_figures(
    _dir: &Path,
    _samples: &[HoverSample<f32>],
    _all: &[VariantResult],
    _shown: &[&str],
    _span_s: Option<f64>,
) -> Result<Vec<PathBuf>, FigureError> {
    Err(FigureError::NotBuilt)
}
