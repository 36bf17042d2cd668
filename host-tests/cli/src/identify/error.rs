//! What can go wrong in an identification ([`IdentifyError`]), and the JSON reads and writes
//! that give its file variants.

use std::path::{Path, PathBuf};

use crate::experiments::EvaluateError;
use crate::import::ImportError;
use crate::report::FigureError;

/// What went wrong in an identification.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// The free-run window is out of range.
    #[error("--window must be in (0, 3600] s, got {0}")]
    Window(f64),
    /// No training log was given.
    #[error("no log to identify from: give LOG... (or --train LOG...)")]
    NoLogs,
    /// A log could not be imported.
    #[error(transparent)]
    Import(#[from] ImportError),
    /// The verification log has no usable samples.
    #[error("{}: no samples", .0.display())]
    NoSamples(PathBuf),
    /// The training data cannot be split into training and verification.
    #[error(transparent)]
    Split(#[from] crate::holdout::SplitError),
    /// Too little verification data.
    #[error("{}: needs at least 2 samples", .0.display())]
    TooFewSamples(PathBuf),
    /// The warm-start file cannot be read.
    #[error("{}: cannot read", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file cannot be written.
    #[error("{}: cannot write", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The output directory cannot be created.
    #[error("{}: cannot create the directory", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The warm-start snapshot (`snapshot-*.ridx`) is not one of the first variant's type and
    /// configuration, or its values are refused.
    #[error("{}: not a snapshot the first variant can start from ({source}); it must come from the same kind of identifier (`snapshot-<variant>.ridx` of that variant)", path.display())]
    Snapshot {
        /// The file.
        path: PathBuf,
        /// Why the core refused it.
        source: rotorid::Error,
    },
    /// The warm-start file is not a params-*.json.
    #[error("{}: not the expected JSON", path.display())]
    ParseJson {
        /// The file.
        path: PathBuf,
        /// Why.
        source: serde_json::Error,
    },
    /// A result cannot be encoded.
    #[error("{}: cannot encode as JSON", path.display())]
    ToJson {
        /// The file it was for.
        path: PathBuf,
        /// Why.
        source: serde_json::Error,
    },
    /// A variant's evaluation failed.
    #[error(transparent)]
    Evaluate(#[from] EvaluateError),
    /// The f32 against f64 comparison failed.
    #[error("comparing f32 with f64")]
    Precision(#[source] rotorid::Error),
    /// The controls' delay could not be chosen (an identifier refused its configuration).
    #[error("choosing the controls' delay")]
    Delay(#[source] rotorid::Error),
    /// A figure cannot be drawn or written.
    #[error(transparent)]
    Figure(#[from] FigureError),
}

pub(super) fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, IdentifyError> {
    let text = std::fs::read_to_string(path).map_err(|source| IdentifyError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| IdentifyError::ParseJson {
        path: path.to_path_buf(),
        source,
    })
}

/// Pretty JSON with a final newline (the text of every JSON file the tool writes).
pub(super) fn json_text(
    path: &Path,
    value: &impl serde::Serialize,
) -> Result<String, IdentifyError> {
    serde_json::to_string_pretty(value)
        .map(|text| text + "\n")
        .map_err(|source| IdentifyError::ToJson {
            path: path.to_path_buf(),
            source,
        })
}

pub(super) fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<(), IdentifyError> {
    let text = json_text(path, value)?;
    std::fs::write(path, text).map_err(|source| IdentifyError::Write {
        path: path.to_path_buf(),
        source,
    })
}
