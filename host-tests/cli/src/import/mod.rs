//! Flight-log import: PX4 ULog (`.ulg`) and ArduPilot DataFlash (`.bin`) into the same
//! [`SensorSample`]s as the CSV format (NED velocity, FRD rates in rad/s, normalised controls),
//! resampled at 50 Hz and split at gaps ([`resample`]). Which topics and messages are read, and
//! their units and checks: `docs/log-format.md`.
//!
//! The format is told by the file's first bytes ([`detect`]): ULog magic `ULog\x01\x12\x35`;
//! DataFlash framing `0xA3 0x95`, an old PX4 `sdlog2` log when its formats say so
//! ([`sdlog2::is_sdlog2`]); text is read as CSV ([`crate::log`]), except a Git LFS pointer and
//! the text and JSON exports of other formats, which are named; anything else is refused.
//! Files are streamed, never read whole into memory. A CSV log is taken as it is at 50 Hz; at
//! another rate (its mean interval off by more than [`resample::RATE_TOLERANCE`]) it is
//! resampled like the others.

pub mod clean;
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
pub use clean::{ImportOptions, InAirSource, NativeRates};
pub use resample::{Channels, Cut, Segment, Series};
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
    /// The file is ArduPilot's DataFlash log converted to text.
    #[error("{file}: ArduPilot's DataFlash log as text (`FMT, …` lines: Mission Planner's .log or mavlogdump's output), which rotorid does not read: give it the binary .bin the flight controller wrote (its SD card's APM/LOGS, or download the log as .bin)")]
    TextDataFlash {
        /// The file.
        file: String,
    },
    /// The file is a JSON export of a log.
    #[error("{file}: a JSON export of a log (mavlogdump.py --format json, say), which rotorid does not read: give it the log it came from (.bin, .ulg) or a CSV (docs/log-format.md)")]
    Json {
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
    #[error("{file}: no {quantity}: {format} log has none of {tried}{}{}{}", also_missing(&.context.also), firmware_remark(&.context.written_by), while_reading(.remark))]
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
        remark: Option<Box<str>>,
        /// The other quantities missing, and who wrote the log (boxed: errors stay small).
        context: Box<MissingContext>,
    },
    /// All channels are there but never together without a gap.
    #[error("{file}: no stretch where attitude, velocity, rates and controls all have data without a gap over {max_gap_s} s")]
    NoSegment {
        /// The file.
        file: String,
        /// [`resample::MAX_SOURCE_GAP_S`].
        max_gap_s: f64,
    },
    /// There were stretches with every channel, but the cuts (ground time, implausible values,
    /// `--from`/`--to`) left out every one of them.
    #[error("{file}: nothing left after the cuts: {reasons} ({hint})")]
    AllCut {
        /// The file.
        file: String,
        /// The cuts' distinct reasons, `; `-separated.
        reasons: String,
        /// What to look at: the in-air detector, or the units of a channel that was out of
        /// its range throughout.
        hint: &'static str,
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

/// What an [`ImportError::Missing`] knows besides the first missing quantity.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MissingContext {
    /// The other quantities that are missing too.
    pub also: Vec<&'static str>,
    /// The firmware that wrote the log, when it says (DataFlash `MSG`: "ArduPlane V4.2.3").
    pub written_by: Option<String>,
}

impl ImportError {
    /// [`ImportError::Missing`] naming every absent quantity `(quantity, tried)` of `absent`
    /// (the first, then the others); `None` when none is absent.
    fn missing_all(
        file: &str,
        format: &'static str,
        absent: impl IntoIterator<Item = (&'static str, &'static str)>,
        remark: Option<Box<str>>,
        written_by: Option<String>,
    ) -> Option<Self> {
        let mut absent = absent.into_iter();
        let (quantity, tried) = absent.next()?;
        Some(Self::Missing {
            file: file.to_string(),
            format,
            quantity,
            tried,
            remark,
            context: Box::new(MissingContext {
                also: absent.map(|(q, _)| q).collect(),
                written_by,
            }),
        })
    }
}

/// `; also no …` for [`ImportError::Missing`]: every missing quantity in one error.
fn also_missing(also: &[&str]) -> String {
    if also.is_empty() {
        String::new()
    } else {
        format!("; also no {}", also.join(", no "))
    }
}

/// ` (written by …)` for [`ImportError::Missing`], saying when the firmware is not a
/// rotorcraft's.
fn firmware_remark(firmware: &Option<String>) -> String {
    let Some(f) = firmware else {
        return String::new();
    };
    let rotorcraft = ["Copter", "Heli", "PX4"].iter().any(|k| f.contains(k));
    if dataflash::arducopter_version(f).is_some_and(|v| v < (3, 3)) {
        format!(
            " (written by {f}: ArduCopter logs `RATE`, its rate controller's rates and outputs, from 3.3 on, so no log of an older version can be identified)"
        )
    } else if rotorcraft {
        format!(" (written by {f})")
    } else {
        format!(
            " (written by {f}, not a rotorcraft's firmware: rotorid reads the messages ArduCopter, TradHeli included, and PX4 write)"
        )
    }
}

/// `; while reading: …` for [`ImportError::Missing`] when the reader made a remark.
fn while_reading(remark: &Option<Box<str>>) -> String {
    remark
        .as_ref()
        .map(|r| format!(" (while reading: {r})"))
        .unwrap_or_default()
}

/// An imported log: its segments (each gap-free, at [`rate_hz`](Self::rate_hz)) and remarks
/// for the user.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// Format read.
    pub format: LogFormat,
    /// Gap-free stretches in log order.
    pub segments: Vec<Segment>,
    /// Remarks (truncation, segments dropped, sources chosen, cuts, rates).
    pub notes: Vec<String>,
    /// Warnings: what makes the identification less trustworthy (channels logged too slowly).
    pub warnings: Vec<String>,
    /// The rate the segments are sampled at (Hz).
    pub rate_hz: f64,
    /// Each channel's native logging rate (`None` for a CSV log taken as it is).
    pub native_rates: Option<NativeRates>,
    /// What was left out, and why (implausible stretches, ground time, `--from`/`--to`).
    pub cuts: Vec<Cut>,
    /// Where the ground time came from (`None`: not looked for, as for CSV logs, or
    /// replaced by `--from`/`--to`).
    pub in_air: Option<InAirSource>,
}

impl Imported {
    /// The longest segment (the first of equals).
    pub fn longest(&self) -> Option<&Segment> {
        self.segments.iter().rev().max_by_key(|s| s.len())
    }

    /// Seconds of data in the segments.
    pub fn duration_s(&self) -> f64 {
        self.segments
            .iter()
            .map(|s| s.len().saturating_sub(1) as f64 / self.rate_hz)
            .sum()
    }
}

/// The segments `identify` uses: for training (`all`), every segment of at least
/// [`log::MIN_USEFUL_S`] seconds (or the longest when none is that long), learnt one after
/// another; for verification, the longest.
pub fn segments_for_identify(imported: &Imported, all: bool) -> Vec<&Segment> {
    let min = min_useful_samples(imported.rate_hz);
    let long: Vec<&Segment> = imported
        .segments
        .iter()
        .filter(|s| s.len() >= min)
        .collect();
    if all && !long.is_empty() {
        long
    } else {
        imported.longest().into_iter().collect()
    }
}

/// [`log::MIN_USEFUL_S`] in samples at `rate_hz` ([`log::MIN_USEFUL_SAMPLES`] at 50 Hz).
pub fn min_useful_samples(rate_hz: f64) -> usize {
    let n = (log::MIN_USEFUL_S * rate_hz).ceil();
    if n.is_finite() && n >= 2.0 {
        n as usize
    } else {
        2
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
    /// ArduPilot's DataFlash log as text (`FMT, 128, 89, …` lines: Mission Planner's `.log`,
    /// or `mavlogdump.py` without `--format`).
    TextDataFlash,
    /// A JSON export (`mavlogdump.py --format json`, a flight-review download).
    Json,
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
        return Err(NotALog::Binary);
    }
    // The first lines that are neither blank nor CSV comments tell a CSV log (its header
    // first) from the text exports of other formats: ArduPilot's text log has `FMT, …` lines
    // after a few lines of preamble (the firmware's name, free memory).
    let lines: Vec<&[u8]> = head
        .split(|&b| b == b'\n')
        .map(|l| l.trim_ascii())
        .filter(|l| !l.is_empty() && !l.starts_with(b"#"))
        .take(20)
        .collect();
    let first = lines.first().copied().unwrap_or_default();
    let csv_header = first.windows(6).any(|w| w == b"time_s");
    if !csv_header && lines.iter().any(|l| l.starts_with(b"FMT,")) {
        Err(NotALog::TextDataFlash)
    } else if first.starts_with(b"{") || first.starts_with(b"[") {
        Err(NotALog::Json)
    } else {
        Ok(LogFormat::Csv)
    }
}

/// Reads a log of any supported format, prepared for identification as
/// [`ImportOptions::default`] says (the log's own rate, ground time trimmed).
pub fn import(path: &Path) -> Result<Imported, ImportError> {
    import_with(path, &ImportOptions::default())
}

/// What a format's reader gives: a CSV log at 50 Hz taken as it is, or channels to resample.
enum Reading {
    AsIs(Vec<SensorSample>, Vec<String>),
    Channels(Box<Channels>, Vec<String>),
}

/// Reads the channels of a log (the format's reader, streamed), or a 50 Hz CSV log as it is.
fn read_log(path: &Path, file: &str) -> Result<(LogFormat, Reading), ImportError> {
    let read_err = |e| ImportError::Read {
        file: file.to_string(),
        source: Arc::new(e),
    };
    let mut input = std::fs::File::open(path).map_err(read_err)?;
    let mut head = Vec::new();
    (&mut input)
        .take(HEAD_LEN as u64)
        .read_to_end(&mut head)
        .map_err(read_err)?;
    let format = detect(&head).map_err(|not| match not {
        NotALog::LfsPointer => ImportError::LfsPointer {
            file: file.to_string(),
        },
        NotALog::Binary => ImportError::NotALog {
            file: file.to_string(),
        },
        NotALog::TextDataFlash => ImportError::TextDataFlash {
            file: file.to_string(),
        },
        NotALog::Json => ImportError::Json {
            file: file.to_string(),
        },
    })?;
    let input = std::io::BufReader::new(std::io::Cursor::new(head).chain(input));
    let (channels, notes) = match format {
        LogFormat::ULog => ulog::channels(file, input)?,
        LogFormat::DataFlash => dataflash::channels(file, input)?,
        LogFormat::Sdlog2 => sdlog2::channels(file, input)?,
        LogFormat::Csv => {
            let (samples, mut notes) = log::parse_log_noted(file, input)?;
            let Some(rate) = resample::other_rate(&samples) else {
                return Ok((format, Reading::AsIs(samples, notes)));
            };
            notes.push(format!(
                "{file}: sampled at {rate:.1} Hz, not {} Hz: resampled (states interpolated linearly, controls held)",
                resample::RATE_HZ
            ));
            (Channels::of_samples(&samples), notes)
        }
    };
    Ok((format, Reading::Channels(Box::new(channels), notes)))
}

/// Reads a log of any supported format and prepares it for identification: implausible
/// stretches and ground time cut out (or everything outside `--from`/`--to`), time-stamp
/// glitches repaired, resampled at the identification rate, split at gaps; every cut and
/// repair in a note.
pub fn import_with(path: &Path, options: &ImportOptions) -> Result<Imported, ImportError> {
    let file = path.display().to_string();
    let (format, read) = read_log(path, &file)?;
    let (mut channels, mut notes) = match read {
        Reading::AsIs(samples, notes) => {
            return as_is(&file, format, samples, notes, options);
        }
        Reading::Channels(ch, notes) => (*ch, notes),
    };
    for (name, glitches) in [
        ("attitude", &channels.attitude.glitches),
        ("velocity", &channels.velocity_ned.glitches),
        ("body rates", &channels.rates_frd.glitches),
        ("controls", &channels.controls.glitches),
    ] {
        notes.extend(clean::glitch_notes(&file, name, glitches));
    }
    let native = NativeRates::of(&channels);
    let rate_hz = options
        .rate_hz
        .unwrap_or_else(|| clean::identification_rate(&native));
    let mut warnings = Vec::new();
    let slow: Vec<String> = native
        .named()
        .iter()
        .filter_map(|(name, r)| {
            let r = (*r)?;
            (r < rate_hz * 0.95 || r < resample::RATE_HZ * 0.95)
                .then(|| format!("{name} {r:.1} Hz"))
        })
        .collect();
    if !slow.is_empty() {
        let what = if rate_hz < resample::RATE_HZ {
            format!("identified at {rate_hz} Hz, the rate the log supports, not 50 Hz")
        } else {
            format!("identified at {rate_hz} Hz (--rate): the slower channels are interpolated")
        };
        warnings.push(format!(
            "{file}: logged below 50 Hz: {}; {what}. {}",
            slow.join(", "),
            clean::rate_advice(format)
        ));
    }
    let lengths = |c: &Channels| {
        [
            c.attitude.t.len(),
            c.velocity_ned.t.len(),
            c.rates_frd.t.len(),
            c.controls.t.len(),
        ]
    };
    let before = lengths(&channels);
    let mut cuts = clean::implausible_cuts(&mut channels);
    // A channel that was implausible throughout: then the cuts, not gaps, left nothing.
    let emptied = lengths(&channels)
        .iter()
        .zip(before)
        .any(|(&after, before)| after == 0 && before > 0);
    cuts.extend(clean::lost_control_cuts(&channels));
    let clamped = clean::saturate_controls(&mut channels);
    if clamped > 0 {
        notes.push(format!(
            "{file}: {clamped} control sample(s) beyond ±1 (the controller asked for more than the actuators give) clamped to ±1"
        ));
    }
    let in_air = if options.from_s.is_some() || options.to_s.is_some() {
        cuts.extend(clean::window_cuts(options.from_s, options.to_s));
        None
    } else {
        let (ground, source) = clean::ground_cuts(&channels);
        cuts.extend(ground);
        Some(source)
    };
    cuts.sort_by(|a, b| a.from_s.total_cmp(&b.from_s));
    for c in &cuts {
        notes.push(format!("{file}: cut {}", clean::describe(c)));
    }
    let mut segments = Vec::new();
    for seg in resample::resample_at(&channels, rate_hz, &cuts) {
        segments.extend(split_failing(&file, seg, &mut notes));
    }
    if segments.is_empty() && !cuts.is_empty() {
        // Say that the cuts, not gaps in the data, left nothing (when there was something).
        if emptied || !resample::resample_at(&channels, rate_hz, &[]).is_empty() {
            let mut reasons: Vec<&str> = Vec::new();
            for c in &cuts {
                if !reasons.contains(&c.reason.as_str()) {
                    reasons.push(&c.reason);
                }
            }
            let hint = if emptied {
                "a channel was out of its range throughout: the log may hold it in other units \
                 than docs/log-format.md says this format has (an older firmware's, say)"
            } else {
                "the log may never have left the ground; `--from S --to S` replaces the in-air \
                 detector"
            };
            return Err(ImportError::AllCut {
                file,
                reasons: reasons.join("; "),
                hint,
            });
        }
    }
    finish(
        &file,
        Imported {
            format,
            segments,
            notes,
            warnings,
            rate_hz,
            native_rates: Some(native),
            cuts,
            in_air,
        },
    )
}

/// A 50 Hz CSV log: taken as it is (its rows were checked on reading), within
/// `--from`/`--to`; a `--rate` other than 50 Hz resamples it.
fn as_is(
    file: &str,
    format: LogFormat,
    samples: Vec<SensorSample>,
    mut notes: Vec<String>,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    if options.rate_hz.is_some_and(|r| r != resample::RATE_HZ)
        || options.from_s.is_some()
        || options.to_s.is_some()
    {
        let rate_hz = options.rate_hz.unwrap_or(resample::RATE_HZ);
        let cuts = clean::window_cuts(options.from_s, options.to_s);
        let segments = resample::resample_at(&Channels::of_samples(&samples), rate_hz, &cuts);
        notes.extend(
            cuts.iter()
                .map(|c| format!("{file}: cut {}", clean::describe(c))),
        );
        return finish(
            file,
            Imported {
                format,
                segments,
                notes,
                warnings: Vec::new(),
                rate_hz,
                native_rates: None,
                cuts,
                in_air: None,
            },
        );
    }
    Ok(Imported {
        format,
        segments: vec![samples],
        notes,
        warnings: Vec::new(),
        rate_hz: resample::RATE_HZ,
        native_rates: None,
        cuts: Vec::new(),
        in_air: None,
    })
}

/// Lists the segments in a note (when several), or says there is none.
fn finish(file: &str, mut imported: Imported) -> Result<Imported, ImportError> {
    if imported.segments.is_empty() {
        return Err(ImportError::NoSegment {
            file: file.to_string(),
            max_gap_s: resample::MAX_SOURCE_GAP_S,
        });
    }
    if imported.segments.len() > 1 {
        let list: Vec<String> = imported
            .segments
            .iter()
            .map(|s| {
                let (a, b) = (s[0].t, s.last().map_or(s[0].t, |x| x.t));
                format!("{a:.2}–{b:.2} s ({} samples)", s.len())
            })
            .collect();
        imported.notes.push(format!(
            "{file}: {} segments (split at gaps over {} s and at cuts): {}",
            imported.segments.len(),
            resample::MAX_SOURCE_GAP_S,
            list.join(", ")
        ));
    }
    Ok(imported)
}

/// Splits a resampled segment at every sample that fails the CSV format's value checks
/// (cutting it out, with a note), rather than refusing the log.
fn split_failing(file: &str, seg: Segment, notes: &mut Vec<String>) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut current = Vec::new();
    for s in seg {
        match check(file, &s) {
            Ok(()) => current.push(s),
            Err(e) => {
                notes.push(format!("{e}: cut there"));
                if current.len() > 1 {
                    out.push(std::mem::take(&mut current));
                }
                current.clear();
            }
        }
    }
    if current.len() > 1 {
        out.push(current);
    }
    out
}

/// The CSV format's value checks on one resampled sample (the rate-unit comparison with the
/// attitude is among [`log::warnings`], printed by the tool).
fn check(file: &str, s: &SensorSample) -> Result<(), ImportError> {
    for (k, x) in log::values(s).into_iter().enumerate() {
        log::check_range(k, x).map_err(|kind| ImportError::Check {
            file: file.to_string(),
            t: s.t,
            column: log::COLUMNS[k],
            kind,
        })?;
    }
    Ok(())
}
