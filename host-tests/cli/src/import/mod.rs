//! Flight-log import: PX4 ULog (`.ulg`) and ArduPilot DataFlash (`.bin`) into the same
//! [`SensorSample`]s as the CSV format (NED velocity, FRD rates in rad/s, normalised controls),
//! resampled at 50 Hz and split at gaps ([`resample`]). Which topics and messages are read, and
//! their units and checks: `docs/log-format.md`.
//!
//! The format is told by the file's first bytes (ULog magic `ULog\x01\x12\x35`, DataFlash
//! `0xA3 0x95`), anything else is read as CSV ([`crate::log`]). A CSV log is taken as it is
//! at 50 Hz; at another rate (its mean interval off by more than
//! [`resample::RATE_TOLERANCE`]) it is resampled like the others.

pub mod dataflash;
pub mod resample;
pub mod synth;
pub mod ulog;

use std::path::Path;
use std::sync::Arc;

use crate::log::{self, LogErrorKind};
pub use resample::{Channels, Segment, Series};
use rotorid_sim::plant::SensorSample;

/// A log's format, from its first bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogFormat {
    /// PX4 ULog.
    ULog,
    /// ArduPilot DataFlash.
    DataFlash,
    /// rotorid's CSV (`docs/log-format.md`).
    Csv,
}

/// Why a log could not be imported; every variant names the file.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The file could not be read.
    #[error("{file}: cannot read")]
    Read {
        /// The file.
        file: String,
        /// The system's reason.
        source: Arc<std::io::Error>,
    },
    /// The ULog parser needs a UTF-8 path.
    #[error("{file}: the path is not UTF-8 (the {format} parser needs one)")]
    PathNotUtf8 {
        /// The file.
        file: String,
        /// "ULog".
        format: &'static str,
    },
    /// The parser gave up on the file.
    #[error("{file}: malformed {format} log")]
    Malformed {
        /// The file.
        file: String,
        /// "ULog" or "DataFlash".
        format: &'static str,
        /// The parser's reason.
        source: Arc<std::io::Error>,
    },
    /// A quantity's topic or message is absent (or has no finite sample).
    #[error("{file}: no {quantity}: {format} log has none of {tried}")]
    Missing {
        /// The file.
        file: String,
        /// "ULog" or "DataFlash".
        format: &'static str,
        /// What is missing ("attitude", "helicopter controls", …).
        quantity: &'static str,
        /// The topics/messages looked for.
        tried: &'static str,
    },
    /// All channels are there but never together without a gap.
    #[error("{file}: no stretch where attitude, velocity, rates and controls all have data without a gap over {max_gap_s} s")]
    NoSegment {
        /// The file.
        file: String,
        /// [`resample::MAX_SOURCE_GAP_S`].
        max_gap_s: f64,
    },
    /// A resampled value fails the CSV format's checks.
    #[error("{file}: at t = {t:.3} s, `{column}`: {kind}")]
    Check {
        /// The file.
        file: String,
        /// Sample time (s).
        t: f64,
        /// The CSV column of the quantity.
        column: &'static str,
        /// What is wrong.
        kind: LogErrorKind,
    },
    /// A CSV log's error.
    #[error(transparent)]
    Log(#[from] log::LogError),
}

/// An imported log: its segments (each gap-free, at 50 Hz) and remarks for the user.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// Format read.
    pub format: LogFormat,
    /// Gap-free stretches in log order.
    pub segments: Vec<Segment>,
    /// Remarks (truncation, segments dropped, sources chosen).
    pub notes: Vec<String>,
}

impl Imported {
    /// The longest segment (the first of equals).
    pub fn longest(&self) -> Option<&Segment> {
        self.segments.iter().rev().max_by_key(|s| s.len())
    }
}

/// The segments `identify` uses: for training (`all`), every segment of at least
/// [`log::MIN_USEFUL_SAMPLES`] (or the longest when none is that long), learnt one after another; for
/// verification, the longest.
pub fn segments_for_identify(imported: &Imported, all: bool) -> Vec<&Segment> {
    let long: Vec<&Segment> = imported
        .segments
        .iter()
        .filter(|s| s.len() >= log::MIN_USEFUL_SAMPLES)
        .collect();
    if all && !long.is_empty() {
        long
    } else {
        imported.longest().into_iter().collect()
    }
}

/// The format of a file from its first bytes.
pub fn detect(head: &[u8]) -> LogFormat {
    if head.starts_with(b"ULog\x01\x12\x35") {
        LogFormat::ULog
    } else if head.starts_with(&[0xA3, 0x95]) {
        LogFormat::DataFlash
    } else {
        LogFormat::Csv
    }
}

/// Reads a log of any supported format.
pub fn import(path: &Path) -> Result<Imported, ImportError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| ImportError::Read {
        file: file.clone(),
        source: Arc::new(e),
    })?;
    let format = detect(&bytes);
    let (channels, mut notes) = match format {
        LogFormat::ULog => ulog::channels(&file, path)?,
        LogFormat::DataFlash => dataflash::channels(&file, &bytes)?,
        LogFormat::Csv => {
            let samples = log::parse_log(&file, bytes.as_slice())?;
            let Some(rate) = resample::other_rate(&samples) else {
                return Ok(Imported {
                    format,
                    segments: vec![samples],
                    notes: Vec::new(),
                });
            };
            let note = format!(
                "{file}: sampled at {rate:.1} Hz, not {} Hz: resampled at {} Hz (states interpolated linearly, controls held)",
                resample::RATE_HZ,
                resample::RATE_HZ
            );
            (Channels::of_samples(&samples), vec![note])
        }
    };
    let segments = resample::resample(&channels);
    if segments.is_empty() {
        return Err(ImportError::NoSegment {
            file,
            max_gap_s: resample::MAX_SOURCE_GAP_S,
        });
    }
    if segments.len() > 1 {
        let list: Vec<String> = segments
            .iter()
            .map(|s| {
                let (a, b) = (s[0].t, s.last().map_or(s[0].t, |x| x.t));
                format!("{a:.2}–{b:.2} s ({} samples)", s.len())
            })
            .collect();
        notes.push(format!(
            "{file}: split at gaps over {} s into {} segments: {}",
            resample::MAX_SOURCE_GAP_S,
            segments.len(),
            list.join(", ")
        ));
    }
    for seg in &segments {
        check(&file, seg)?;
    }
    Ok(Imported {
        format,
        segments,
        notes,
    })
}

/// The CSV format's value checks on a resampled segment (the rate-unit comparison with the
/// attitude is among [`log::warnings`], printed by the tool).
fn check(file: &str, seg: &[SensorSample]) -> Result<(), ImportError> {
    for s in seg {
        for (k, x) in log::values(s).into_iter().enumerate() {
            log::check_range(k, x).map_err(|kind| ImportError::Check {
                file: file.to_string(),
                t: s.t,
                column: log::COLUMNS[k],
                kind,
            })?;
        }
    }
    Ok(())
}
