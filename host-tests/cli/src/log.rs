//! The flight-log CSV format (see `docs/log-format.md`): one row per sample, in the flight
//! computer's convention (NED velocity, forward-right-down body rates in rad/s), read into
//! [`SensorSample`]s and converted to the paper's axes by
//! [`flights::to_hover_samples`](rotorid_sim::flights::to_hover_samples).
//!
//! | column | quantity | unit |
//! |---|---|---|
//! | `time_s` | sample time, strictly increasing, no gap over [`MAX_INTERVAL_S`] (or 1.5 times the first interval, for a log at a lower rate) | s |
//! | `u_col`, `u_ped`, `u_lon`, `u_lat` | sticks, collective clearly positive at hover | −1…1 |
//! | `roll_rad`, `pitch_rad`, `yaw_rad` | ZYX Euler angles φ, θ, ψ | rad |
//! | `v_north_mps`, `v_east_mps`, `v_down_mps` | inertial velocity, NED | m/s |
//! | `p_radps`, `q_radps`, `r_radps` | body rates about forward, right, down | rad/s |
//!
//! Columns may come in any order; other columns are ignored; lines starting with `#` are
//! comments. Every problem is a [`LogError`] naming the file, the line and the column.

use std::fmt;
use std::io::{Read, Write};
use std::path::Path;
use std::sync::Arc;

use rotorid_sim::plant::{SensorSample, Sticks};

/// The columns, in the order [`write_log`] writes them.
pub const COLUMNS: [&str; 14] = [
    "time_s",
    "u_col",
    "u_ped",
    "u_lon",
    "u_lat",
    "roll_rad",
    "pitch_rad",
    "yaw_rad",
    "v_north_mps",
    "v_east_mps",
    "v_down_mps",
    "p_radps",
    "q_radps",
    "r_radps",
];

/// Largest accepted interval between samples (s): the identifiers run at 50 Hz and accept
/// 20 ms ± 10 ms.
pub const MAX_INTERVAL_S: f64 = 0.030;

/// Largest plausible |body rate| (rad/s): 2000 deg/s, a common gyro range and the core's limit.
/// A larger value almost certainly means the column is in deg/s.
pub const MAX_RATE_RADPS: f64 = 34.9;

/// Largest |roll| and |yaw| (rad, 2π plus margin); |pitch| ≤ π/2 + margin. Beyond: degrees.
const MAX_ANGLE_RAD: [f64; 3] = [3.2, 1.6, 6.3];

/// Largest plausible |velocity| (m/s), the core's limit.
const MAX_VELOCITY_MPS: f64 = 100.0;

/// What is wrong at a [`LogError`]'s position.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum LogErrorKind {
    /// The file could not be opened.
    #[error("cannot open")]
    Open(#[source] Arc<std::io::Error>),
    /// The file could not be created.
    #[error("cannot create")]
    Create(#[source] Arc<std::io::Error>),
    /// Writing the samples failed.
    #[error("cannot write")]
    Write(#[source] Arc<csv::Error>),
    /// The file is empty (no header).
    #[error("empty file: expected a header line with the columns {}", COLUMNS.join(","))]
    Empty,
    /// A header but no sample.
    #[error("no samples after the header")]
    NoSamples,
    /// A required column is not in the header.
    #[error("missing column `{0}`")]
    MissingColumn(&'static str),
    /// A column appears twice.
    #[error("column `{0}` appears twice")]
    DuplicateColumn(String),
    /// A header names a quantity in the wrong unit (for example `p_degps`).
    #[error("column `{found}` is in the wrong unit; the format wants `{expected}`")]
    WrongUnit {
        /// The header found.
        found: String,
        /// The column the format wants.
        expected: &'static str,
    },
    /// A row has fewer fields than the header.
    #[error("row has {found} fields, the header has {expected}")]
    MissingField {
        /// Fields in the row.
        found: usize,
        /// Fields in the header.
        expected: usize,
    },
    /// A row has more fields than the header (often decimal commas splitting numbers).
    #[error("row has {found} fields, the header has {expected}{hint}")]
    ExtraField {
        /// Fields in the row.
        found: usize,
        /// Fields in the header.
        expected: usize,
        /// A hint when the extra fields look like decimal commas.
        hint: &'static str,
    },
    /// A field written with a decimal comma (`"0,5"`, quoted so it stays one field).
    #[error("`{0}` has a decimal comma? use '.' for decimals")]
    DecimalComma(String),
    /// The header is separated by `;` (a spreadsheet's export with decimal commas).
    #[error("the header is separated by ';'; the format separates fields with ',' and writes decimals with '.'")]
    Semicolons,
    /// A field is not a number.
    #[error("not a number: `{0}`")]
    NotANumber(String),
    /// A field is NaN or infinite.
    #[error("not finite: `{0}`")]
    NonFinite(String),
    /// A value outside its range.
    #[error("{value} is outside [{min}, {max}] {unit}")]
    OutOfRange {
        /// The value.
        value: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// Unit.
        unit: &'static str,
    },
    /// A rate or angle far beyond what radians allow: the column is in degrees.
    #[error("{value} is implausible in {unit} (beyond ±{limit}); is the column in degrees?")]
    LooksLikeDegrees {
        /// The value.
        value: f64,
        /// Largest plausible magnitude.
        limit: f64,
        /// The unit the format wants.
        unit: &'static str,
    },
    /// Time does not increase.
    #[error("time {t} s does not increase (previous sample {previous} s)")]
    NonMonotonicTime {
        /// This sample's time (s).
        t: f64,
        /// The previous sample's time (s).
        previous: f64,
    },
    /// Too long an interval since the previous sample.
    #[error("gap of {dt:.4} s since the previous sample (at most {max} s; split the log)")]
    Gap {
        /// The interval (s).
        dt: f64,
        /// [`MAX_INTERVAL_S`].
        max: f64,
    },
    /// Any other CSV problem (the reader's, e.g. a line that is not UTF-8).
    #[error("unreadable CSV")]
    Csv(#[source] Arc<csv::Error>),
}

/// A problem with a log, with its position: file, line (1-based, counting the header and
/// comments) and column (1-based, with its name).
#[derive(Debug, Clone)]
pub struct LogError {
    /// The file (as given).
    pub file: String,
    /// Line, when the problem has one.
    pub line: Option<u64>,
    /// Column number and name, when the problem has one.
    pub column: Option<(usize, String)>,
    /// What is wrong.
    pub kind: LogErrorKind,
}

impl fmt::Display for LogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = Position(self.line, &self.column);
        write!(f, "{}{at}: {}", self.file, self.kind)
    }
}

/// The kind is part of the message; its cause (an I/O or CSV error) is the source.
impl std::error::Error for LogError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.kind.source()
    }
}

struct Position<'a>(Option<u64>, &'a Option<(usize, String)>);

impl fmt::Display for Position<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.0 {
            write!(f, ": line {line}")?;
        }
        if let Some((col, name)) = self.1 {
            write!(f, ", column {col} (`{name}`)")?;
        }
        Ok(())
    }
}

fn err(
    file: &str,
    line: Option<u64>,
    column: Option<(usize, &str)>,
    kind: LogErrorKind,
) -> LogError {
    LogError {
        file: file.to_string(),
        line,
        column: column.map(|(c, n)| (c, n.to_string())),
        kind,
    }
}

/// At most [`EXCERPT_CHARS`] characters of a field, for an error message (a field of a
/// corrupt file can be megabytes long).
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(EXCERPT_CHARS) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_string(),
    }
}

/// Longest excerpt of a field quoted in an error (characters).
pub const EXCERPT_CHARS: usize = 40;

/// Longest first interval of a CSV log (s): a 5 Hz log's, the slowest rate `identify`
/// runs at; the first interval then sets the limit of the others (1.5 times it, at least
/// [`MAX_INTERVAL_S`]).
pub const SLOWEST_INTERVAL_S: f64 = 0.2;

/// Wrong-unit spellings of each column's quantity (lower case), e.g. `p_degps` for `p_radps`.
fn wrong_unit(header: &str) -> Option<&'static str> {
    let h = header.trim().to_ascii_lowercase();
    let (stem, unit) = h.rsplit_once('_')?;
    let deg = ["deg", "degps", "degs", "dps", "deg/s", "degpersec"];
    let any_unit = deg.contains(&unit)
        || ["rad", "radps", "rads", "ms", "mps", "kmh", "kts", "fps"].contains(&unit);
    if !any_unit {
        return None;
    }
    COLUMNS.iter().copied().find(|c| {
        c.rsplit_once('_')
            .is_some_and(|(cstem, cunit)| cstem == stem && cunit != unit)
    })
}

/// Reads and checks a log file.
pub fn read_log(path: &Path) -> Result<Vec<SensorSample>, LogError> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path)
        .map_err(|e| err(&name, None, None, LogErrorKind::Open(Arc::new(e))))?;
    parse_log(&name, file)
}

/// Parses and checks a log from any reader; `file` names it in errors. A last line without
/// its line end is dropped (see [`parse_log_noted`], which says so).
pub fn parse_log(file: &str, reader: impl Read) -> Result<Vec<SensorSample>, LogError> {
    parse_log_noted(file, reader).map(|(samples, _)| samples)
}

/// Remembers the last byte read, to tell a file cut mid-line.
struct LastByte<R> {
    inner: R,
    last: Option<u8>,
}

impl<R: Read> Read for LastByte<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if let Some(b) = buf[..n].last() {
            self.last = Some(*b);
        }
        Ok(n)
    }
}

/// [`parse_log`], with notes: a last line without its line end (a file cut while it was
/// written, its last number possibly short of digits) is dropped, and a note says so.
pub fn parse_log_noted(
    file: &str,
    reader: impl Read,
) -> Result<(Vec<SensorSample>, Vec<String>), LogError> {
    let mut reader = LastByte {
        inner: reader,
        last: None,
    };
    let mut out = parse_rows(file, &mut reader)?;
    let mut notes = Vec::new();
    if !matches!(reader.last, Some(b'\n' | b'\r')) && out.len() > 1 {
        out.pop();
        notes.push(format!(
            "{file}: the last line has no line end (the file was cut while written?): its row is dropped"
        ));
    }
    Ok((out, notes))
}

fn parse_rows(file: &str, reader: impl Read) -> Result<Vec<SensorSample>, LogError> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(reader);
    let mut records = rdr.records();
    let csv_err = |e: csv::Error| {
        let line = e.position().map(csv::Position::line);
        err(file, line, None, LogErrorKind::Csv(Arc::new(e)))
    };
    let header = match records.next() {
        None => return Err(err(file, None, None, LogErrorKind::Empty)),
        Some(r) => r.map_err(csv_err)?,
    };
    let header_line = header.position().map_or(1, csv::Position::line);
    // Column index of each required column.
    let mut index = [usize::MAX; 14];
    for (i, h) in header.iter().enumerate() {
        if let Some(k) = COLUMNS.iter().position(|c| *c == h) {
            if index[k] != usize::MAX {
                return Err(err(
                    file,
                    Some(header_line),
                    Some((i + 1, h)),
                    LogErrorKind::DuplicateColumn(excerpt(h)),
                ));
            }
            index[k] = i;
        } else if let Some(expected) = wrong_unit(h) {
            return Err(err(
                file,
                Some(header_line),
                Some((i + 1, h)),
                LogErrorKind::WrongUnit {
                    found: excerpt(h),
                    expected,
                },
            ));
        }
    }
    if header.len() == 1 && header.get(0).is_some_and(|h| h.contains(';')) {
        return Err(err(file, Some(header_line), None, LogErrorKind::Semicolons));
    }
    for (k, &i) in index.iter().enumerate() {
        if i == usize::MAX {
            return Err(err(
                file,
                Some(header_line),
                None,
                LogErrorKind::MissingColumn(COLUMNS[k]),
            ));
        }
    }

    let mut out: Vec<SensorSample> = Vec::new();
    let mut first_interval: Option<f64> = None;
    for record in records {
        let record = record.map_err(csv_err)?;
        let line = record.position().map_or(0, csv::Position::line);
        if record.iter().all(str::is_empty) {
            continue;
        }
        if record.len() > header.len() {
            // "0,5" in a comma-separated file is two fields: a decimal comma shows up as extra
            // fields whose text is all digits.
            let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
            let hint = if record.iter().skip(1).any(digits) {
                " (decimal commas? the format separates fields with ',' and writes decimals with '.')"
            } else {
                ""
            };
            return Err(err(
                file,
                Some(line),
                None,
                LogErrorKind::ExtraField {
                    found: record.len(),
                    expected: header.len(),
                    hint,
                },
            ));
        }
        let mut v = [0.0f64; 14];
        for (k, &i) in index.iter().enumerate() {
            let col = Some((i + 1, COLUMNS[k]));
            let text = record.get(i).ok_or_else(|| {
                err(
                    file,
                    Some(line),
                    col,
                    LogErrorKind::MissingField {
                        found: record.len(),
                        expected: header.len(),
                    },
                )
            })?;
            let x: f64 = text.parse().map_err(|_| {
                let comma = text.replacen(',', ".", 1).parse::<f64>().is_ok();
                let kind = if comma {
                    LogErrorKind::DecimalComma(excerpt(text))
                } else {
                    LogErrorKind::NotANumber(excerpt(text))
                };
                err(file, Some(line), col, kind)
            })?;
            if !x.is_finite() {
                return Err(err(
                    file,
                    Some(line),
                    col,
                    LogErrorKind::NonFinite(excerpt(text)),
                ));
            }
            check_range(k, x).map_err(|kind| err(file, Some(line), col, kind))?;
            v[k] = x;
        }
        let t = v[0];
        if let Some(prev) = out.last() {
            let col = Some((index[0] + 1, COLUMNS[0]));
            if t <= prev.t {
                return Err(err(
                    file,
                    Some(line),
                    col,
                    LogErrorKind::NonMonotonicTime {
                        t,
                        previous: prev.t,
                    },
                ));
            }
            // A log at a lower rate (a 10 Hz conversion) sets its own limit by its first
            // interval, which may be as long as a 5 Hz log's.
            let max = first_interval.map_or(SLOWEST_INTERVAL_S, |dt| MAX_INTERVAL_S.max(1.5 * dt));
            if t - prev.t > max {
                return Err(err(
                    file,
                    Some(line),
                    col,
                    LogErrorKind::Gap {
                        dt: t - prev.t,
                        max,
                    },
                ));
            }
            first_interval.get_or_insert(t - prev.t);
        }
        out.push(SensorSample {
            t,
            sticks: Sticks {
                col: v[1],
                ped: v[2],
                lon: v[3],
                lat: v[4],
            },
            roll: v[5],
            pitch: v[6],
            yaw: v[7],
            v_north: v[8],
            v_east: v[9],
            v_down: v[10],
            p: v[11],
            q: v[12],
            r: v[13],
        });
    }
    if out.is_empty() {
        return Err(err(file, Some(header_line), None, LogErrorKind::NoSamples));
    }
    Ok(out)
}

/// Range check of column `k` of [`COLUMNS`].
pub fn check_range(k: usize, x: f64) -> Result<(), LogErrorKind> {
    match k {
        0 if x < 0.0 => Err(LogErrorKind::OutOfRange {
            value: x,
            min: 0.0,
            max: f64::INFINITY,
            unit: "s",
        }),
        1..=4 if x.abs() > 1.0 => Err(LogErrorKind::OutOfRange {
            value: x,
            min: -1.0,
            max: 1.0,
            unit: "(normalised stick)",
        }),
        5..=7 if x.abs() > MAX_ANGLE_RAD[k - 5] => Err(LogErrorKind::LooksLikeDegrees {
            value: x,
            limit: MAX_ANGLE_RAD[k - 5],
            unit: "rad",
        }),
        8..=10 if x.abs() > MAX_VELOCITY_MPS => Err(LogErrorKind::OutOfRange {
            value: x,
            min: -MAX_VELOCITY_MPS,
            max: MAX_VELOCITY_MPS,
            unit: "m/s",
        }),
        11..=13 if x.abs() > MAX_RATE_RADPS => Err(LogErrorKind::LooksLikeDegrees {
            value: x,
            limit: MAX_RATE_RADPS,
            unit: "rad/s",
        }),
        _ => Ok(()),
    }
}

/// Fewer samples than this (2 s at 50 Hz) cannot show anything about a model.
pub const MIN_USEFUL_SAMPLES: usize = 100;

/// [`MIN_USEFUL_SAMPLES`] as a duration (s), for logs identified at a lower rate.
pub const MIN_USEFUL_S: f64 = 2.0;

/// The body rates' RMS over the attitude's rate of change (Euler-angle derivatives, rad/s),
/// over the samples where the attitude moves: about 1 when the rates are in rad/s (for
/// moderate attitudes the two agree), about 57 when they are in deg/s. `None` when the
/// attitude hardly moves (under 0.01 rad/s RMS) or there are too few samples.
pub fn rate_unit_ratio(samples: &[SensorSample]) -> Option<f64> {
    let wrap = |a: f64| {
        let two_pi = 2.0 * std::f64::consts::PI;
        a - two_pi * (a / two_pi).round()
    };
    // Over spans of SPAN samples (0.2 s at 50 Hz), so that the attitude's noise, differentiated,
    // does not swamp its rate of change; the body rates are averaged over the same span.
    const SPAN: usize = 10;
    let (mut euler, mut body, mut n) = (0.0, 0.0, 0usize);
    for w in samples.windows(SPAN + 1).step_by(SPAN) {
        let (a, b) = (&w[0], &w[SPAN]);
        let dt = b.t - a.t;
        if !(dt > 0.0 && dt < 1.0) {
            continue;
        }
        let d = [
            wrap(b.roll - a.roll) / dt,
            wrap(b.pitch - a.pitch) / dt,
            wrap(b.yaw - a.yaw) / dt,
        ];
        let mean = |f: fn(&SensorSample) -> f64| w[..SPAN].iter().map(f).sum::<f64>() / SPAN as f64;
        let m = [mean(|s| s.p), mean(|s| s.q), mean(|s| s.r)];
        euler += d.iter().map(|x| x * x).sum::<f64>();
        body += m.iter().map(|x| x * x).sum::<f64>();
        n += 1;
    }
    if n < 5 {
        return None;
    }
    let (euler, body) = ((euler / n as f64).sqrt(), (body / n as f64).sqrt());
    (euler > 0.01).then(|| body / euler)
}

/// Warnings about usable but doubtful data: the collective at or below zero (the models
/// multiply by `u_col` as a stand-in for thrust, so it must stay clearly positive), body rates
/// that look like deg/s although every value is within the rad/s range, and logs too short to
/// show anything (or angles that look like degrees by the same comparison).
pub fn warnings(file: &str, samples: &[SensorSample]) -> Vec<String> {
    let mut out = Vec::new();
    out.extend(short_warning(file, &[samples]));
    out.extend(doubtful_data(file, samples));
    out
}

/// The one warning for the `segments` of `file` that are too short to show anything (fewer
/// than [`MIN_USEFUL_SAMPLES`]), one line however many there are.
pub fn short_warning(file: &str, segments: &[&[SensorSample]]) -> Option<String> {
    let short: Vec<String> = segments
        .iter()
        .filter(|s| s.len() < MIN_USEFUL_SAMPLES)
        .map(|s| {
            let span = s.last().map_or(0.0, |l| l.t) - s.first().map_or(0.0, |f| f.t);
            format!("{} samples ({span:.2} s)", s.len())
        })
        .collect();
    let (what, list) = match short.as_slice() {
        [] => return None,
        [one] => ("only".to_string(), one.clone()),
        many => (format!("{} segments of only", many.len()), many.join(", ")),
    };
    Some(format!(
        "{file}: {what} {list}; errors over fewer than {MIN_USEFUL_SAMPLES} samples say little about a model"
    ))
}

/// [`warnings`] other than [`short_warning`]: per segment.
pub fn doubtful_data(file: &str, samples: &[SensorSample]) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(ratio) = rate_unit_ratio(samples) {
        if ratio > 20.0 {
            out.push(format!(
                "{file}: the body rates are {ratio:.0} times the attitude's rate of change; in rad/s they should be about equal (57 = deg/s): are p_radps, q_radps, r_radps in deg/s?"
            ));
        } else if ratio < 1.0 / 20.0 {
            // Angles in degrees small enough for the range check (a gentle flight).
            out.push(format!(
                "{file}: the attitude changes {:.0} times faster than the body rates; they should be about equal (57 = degrees): are roll_rad, pitch_rad, yaw_rad in degrees?",
                1.0 / ratio
            ));
        }
    }
    if let Some((i, s)) = samples
        .iter()
        .enumerate()
        .find(|(_, s)| s.sticks.col <= 0.0)
    {
        out.push(format!(
            "{file}: the collective reaches {} at t = {} s (sample {}): u_col stands for thrust in the models and must stay clearly positive (hover near 0.5)",
            s.sticks.col, s.t, i + 1
        ));
    }
    out
}

/// A sample's values in the order of [`COLUMNS`].
pub fn values(s: &SensorSample) -> [f64; 14] {
    [
        s.t,
        s.sticks.col,
        s.sticks.ped,
        s.sticks.lon,
        s.sticks.lat,
        s.roll,
        s.pitch,
        s.yaw,
        s.v_north,
        s.v_east,
        s.v_down,
        s.p,
        s.q,
        s.r,
    ]
}

/// Writes samples in the log format (header, then one row per sample; full `f64` precision).
pub fn write_log_to(writer: impl Write, samples: &[SensorSample]) -> Result<(), csv::Error> {
    let mut w = csv::Writer::from_writer(writer);
    w.write_record(COLUMNS)?;
    for s in samples {
        w.write_record(values(s).iter().map(|x| x.to_string()))?;
    }
    w.flush()?;
    Ok(())
}

/// Writes a log file.
pub fn write_log(path: &Path, samples: &[SensorSample]) -> Result<(), LogError> {
    let name = path.display().to_string();
    let at_file = |kind| err(&name, None, None, kind);
    let file =
        std::fs::File::create(path).map_err(|e| at_file(LogErrorKind::Create(Arc::new(e))))?;
    write_log_to(std::io::BufWriter::new(file), samples)
        .map_err(|e| at_file(LogErrorKind::Write(Arc::new(e))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t: f64) -> String {
        format!("{t},0.5,0.1,0,0,0.01,0.02,0.3,0.1,0.2,0.3,0.01,0.02,0.03\n")
    }

    fn log(rows: &[f64]) -> String {
        let mut s = COLUMNS.join(",") + "\n";
        rows.iter().for_each(|t| s += &row(*t));
        s
    }

    #[test]
    fn roundtrip() {
        let text = log(&[0.0, 0.02, 0.04]);
        let a = parse_log("a.csv", text.as_bytes()).expect("valid");
        let mut buf = Vec::new();
        write_log_to(&mut buf, &a).expect("write");
        let b = parse_log("b.csv", buf.as_slice()).expect("valid");
        assert_eq!(a, b);
        assert_eq!(a[1].sticks.ped, 0.1);
        assert_eq!(a[2].r, 0.03);
    }

    #[test]
    fn positions() {
        let text = log(&[0.0, 0.02]).replace("0.02,0.5", "0.02,abc");
        let e = parse_log("x.csv", text.as_bytes()).expect_err("bad");
        assert_eq!(e.line, Some(3));
        assert_eq!(e.column, Some((2, "u_col".to_string())));
        assert_eq!(
            e.to_string(),
            "x.csv: line 3, column 2 (`u_col`): not a number: `abc`"
        );
    }
}
