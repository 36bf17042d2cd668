//! Flight-log import: PX4 ULog (`.ulg`) and ArduPilot DataFlash (`.bin`) into the same
//! [`SensorSample`]s as the CSV format (NED velocity, FRD rates in rad/s, normalised controls),
//! resampled at 50 Hz and split at gaps ([`resample`]). Which topics and messages are read, and
//! their units and checks: `docs/log-format.md`.
//!
//! The format is told by the file's first bytes ([`detect`]): ULog magic `ULog\x01\x12\x35`;
//! DataFlash framing `0xA3 0x95`, an old PX4 `sdlog2` log when its formats say so
//! ([`sdlog2::is_sdlog2`]); text is read as CSV ([`crate::log`]), except a Git LFS pointer;
//! anything else is refused. Files are streamed, never read whole into memory. A CSV log is
//! taken as it is at 50 Hz; at another rate (its mean interval off by more than
//! [`resample::RATE_TOLERANCE`]) it is resampled like the others.

pub mod dataflash;
pub mod issues;
pub mod malformed;
pub mod resample;
pub mod sdlog2;
pub mod stream;
pub mod synth;
pub mod ulog;

use std::io::Read;
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
    /// Old PX4 `sdlog2` (`.px4log`): DataFlash framing, time from `TIME` messages.
    Sdlog2,
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
    /// The log is unreadable from a byte on (what a reader can read past is a note instead).
    #[error("{file}: malformed {format} log at byte {offset}: {reason}")]
    Malformed {
        /// The file.
        file: String,
        /// "ULog", "DataFlash" or "PX4 sdlog2".
        format: &'static str,
        /// Byte offset of the offending structure.
        offset: u64,
        /// What is wrong.
        reason: malformed::Malformation,
    },
    /// The file is a Git LFS pointer (a few lines of text naming the real file's hash).
    #[error("{file}: a Git LFS pointer, not the log: run `git lfs pull`")]
    LfsPointer {
        /// The file.
        file: String,
    },
    /// The file is binary and in none of the formats.
    #[error("{file}: not a ULog, DataFlash or CSV log (binary data without the ULog or DataFlash magic bytes)")]
    NotALog {
        /// The file.
        file: String,
    },
    /// A quantity's topic or message is absent (or has no finite sample).
    #[error("{file}: no {quantity}: {format} log has none of {tried}{}", while_reading(.remark))]
    Missing {
        /// The file.
        file: String,
        /// "ULog", "DataFlash" or "PX4 sdlog2".
        format: &'static str,
        /// What is missing ("attitude", "helicopter controls", …).
        quantity: &'static str,
        /// The topics/messages looked for.
        tried: &'static str,
        /// The first problem the reader read past, when there was one (it may be the cause).
        remark: Option<String>,
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

/// `; while reading: …` for [`ImportError::Missing`] when the reader made a remark.
fn while_reading(remark: &Option<String>) -> String {
    remark
        .as_ref()
        .map(|r| format!(" (while reading: {r})"))
        .unwrap_or_default()
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

/// Bytes [`import`] reads first to tell the format ([`detect`]).
pub const HEAD_LEN: usize = 64 * 1024;

/// What a file is, when it is no log [`import`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NotALog {
    /// A Git LFS pointer.
    LfsPointer,
    /// Binary data in none of the formats.
    Binary,
}

/// The format of a file from its first bytes (up to [`HEAD_LEN`]; fewer only when the file
/// is shorter).
pub fn detect(head: &[u8]) -> Result<LogFormat, NotALog> {
    if head.starts_with(ulog::reader::MAGIC) {
        return Ok(LogFormat::ULog);
    }
    if head.starts_with(&dataflash::reader::MAGIC) {
        let mut reader = dataflash::reader::Reader::new(head);
        while let Ok(Some(_)) = reader.next_record() {}
        return Ok(if sdlog2::is_sdlog2(reader.formats()) {
            LogFormat::Sdlog2
        } else {
            LogFormat::DataFlash
        });
    }
    if head.starts_with(b"version https://git-lfs.github.com/spec/") {
        return Err(NotALog::LfsPointer);
    }
    // Text in any ASCII-compatible encoding: no NUL byte, and control characters other than
    // white space (a stray DOS end-of-file mark, say) under 1 % of the bytes.
    let controls = head
        .iter()
        .filter(|&&b| (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0c)) || b == 0x7f)
        .count();
    if head.contains(&0) || controls * 100 > head.len() {
        Err(NotALog::Binary)
    } else {
        Ok(LogFormat::Csv)
    }
}

/// Reads a log of any supported format, streamed.
pub fn import(path: &Path) -> Result<Imported, ImportError> {
    let file = path.display().to_string();
    let read_err = |e| ImportError::Read {
        file: file.clone(),
        source: Arc::new(e),
    };
    let mut input = std::fs::File::open(path).map_err(read_err)?;
    let mut head = Vec::new();
    (&mut input)
        .take(HEAD_LEN as u64)
        .read_to_end(&mut head)
        .map_err(read_err)?;
    let format = detect(&head).map_err(|not| match not {
        NotALog::LfsPointer => ImportError::LfsPointer { file: file.clone() },
        NotALog::Binary => ImportError::NotALog { file: file.clone() },
    })?;
    let input = std::io::BufReader::new(std::io::Cursor::new(head).chain(input));
    let (channels, mut notes) = match format {
        LogFormat::ULog => ulog::channels(&file, input)?,
        LogFormat::DataFlash => dataflash::channels(&file, input)?,
        LogFormat::Sdlog2 => sdlog2::channels(&file, input)?,
        LogFormat::Csv => {
            let samples = log::parse_log(&file, input)?;
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
