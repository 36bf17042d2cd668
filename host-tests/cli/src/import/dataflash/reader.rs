//! A streaming reader of the DataFlash framing: ArduPilot `.bin` logs and PX4 `sdlog2`
//! `.px4log` logs (same framing, other messages). A record is `0xA3 0x95`, a type byte and a
//! payload whose length the type's `FMT` record (type 128, 89 bytes: type, length, name\[4\],
//! format\[16\], labels\[64\]) gives; field types after ArduPilot's `AP_Logger` documentation
//! (`b B h H i I f d n N Z c C e E L M q Q a`).
//!
//! It replaces the `ardupilot-binlog` crate, which underflows on an `FMT` with a length below
//! 3 ("capacity overflow"), reads the whole file into memory and gives no byte offsets. This
//! one reads a record at a time through [`ByteStream`] (memory bounded by its 128 KiB buffer and the 255
//! formats a type byte allows), never panics, and reports with byte offsets:
//!
//! - bytes that start no record of a known type (corrupt data, a type with no `FMT`): skipped
//!   byte by byte up to the next record, one remark per kind;
//! - an `FMT` that cannot be used (length below 3, a format character it does not know, a
//!   format longer than the length, labels and format characters that do not pair up): a
//!   remark; fields past the problem read as absent; an `FMT` that redefines a type
//!   differently: a remark;
//! - a record cut by the end of the input: a [`TRUNCATED`] remark.
//!
//! Every step consumes at least one byte, so reading always ends.

use std::io::Read;

use super::super::issues::{excerpt, Issues, TRUNCATED};
use super::super::malformed::ReadError;
use super::super::stream::ByteStream;

/// The two bytes that start every record.
pub const MAGIC: [u8; 2] = [0xA3, 0x95];
/// The type of format records.
pub const FMT_TYPE: u8 = 128;
/// Length of a format record, header included.
const FMT_LEN: usize = 89;

/// Size (bytes) of a format character's field; `None` for a character the format does not
/// define.
fn char_size(c: u8) -> Option<usize> {
    Some(match c {
        b'b' | b'B' | b'M' => 1,
        b'h' | b'H' | b'c' | b'C' => 2,
        b'i' | b'I' | b'f' | b'e' | b'E' | b'L' | b'n' => 4,
        b'd' | b'q' | b'Q' => 8,
        b'N' => 16,
        b'Z' | b'a' => 64,
        _ => return None,
    })
}

/// The numeric value of a field of format character `c` in `b` (exactly its size): scaled as
/// ArduPilot's tools do (`c C e E` hundredths, `L` 1e-7 degrees); `None` for text and arrays.
fn char_value(c: u8, b: &[u8]) -> Option<f64> {
    let a2 = || -> Option<[u8; 2]> { b.try_into().ok() };
    let a4 = || -> Option<[u8; 4]> { b.try_into().ok() };
    let a8 = || -> Option<[u8; 8]> { b.try_into().ok() };
    Some(match c {
        b'b' => f64::from(*b.first()? as i8),
        b'B' | b'M' => f64::from(*b.first()?),
        b'h' => f64::from(i16::from_le_bytes(a2()?)),
        b'H' => f64::from(u16::from_le_bytes(a2()?)),
        b'c' => f64::from(i16::from_le_bytes(a2()?)) / 100.0,
        b'C' => f64::from(u16::from_le_bytes(a2()?)) / 100.0,
        b'i' => f64::from(i32::from_le_bytes(a4()?)),
        b'I' => f64::from(u32::from_le_bytes(a4()?)),
        b'e' => f64::from(i32::from_le_bytes(a4()?)) / 100.0,
        b'E' => f64::from(u32::from_le_bytes(a4()?)) / 100.0,
        b'L' => f64::from(i32::from_le_bytes(a4()?)) * 1e-7,
        b'f' => f64::from(f32::from_le_bytes(a4()?)),
        b'd' => f64::from_le_bytes(a8()?),
        b'q' => i64::from_le_bytes(a8()?) as f64,
        b'Q' => u64::from_le_bytes(a8()?) as f64,
        _ => return None,
    })
}

/// A NUL-padded text field, lossy UTF-8, at most its bytes.
fn text(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8_lossy(b.get(..end).unwrap_or_default()).into_owned()
}

/// One message type, from its `FMT` record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageFormat {
    /// Message name (`ATT`, `TIME`, …).
    pub name: String,
    /// Record length, header included (bytes).
    pub length: usize,
    /// Fields that can be read: label, format character, offset in the payload.
    fields: Vec<(String, u8, usize)>,
}

impl MessageFormat {
    /// The labels of the readable fields, in order.
    pub fn labels(&self) -> impl Iterator<Item = &str> {
        self.fields.iter().map(|(l, _, _)| l.as_str())
    }

    /// Whether the message has a field `label`.
    pub fn has(&self, label: &str) -> bool {
        self.labels().any(|l| l == label)
    }
}

/// One data record.
#[derive(Debug, Clone, Copy)]
pub struct Record<'a> {
    /// Byte offset of the record.
    pub offset: u64,
    /// Its type's format.
    pub format: &'a MessageFormat,
    /// The payload after the 3-byte header.
    pub payload: &'a [u8],
}

impl Record<'_> {
    /// The numeric field `label`, `None` when absent, text, or past the record's end.
    pub fn get(&self, label: &str) -> Option<f64> {
        let (_, c, at) = self.format.fields.iter().find(|(l, _, _)| l == label)?;
        let size = char_size(*c)?;
        char_value(*c, self.payload.get(*at..at.checked_add(size)?)?)
    }

    /// The text field `label` (format characters `n`, `N`, `Z`) up to its first NUL, `None`
    /// when absent, numeric, or past the record's end.
    pub fn text(&self, label: &str) -> Option<String> {
        let (_, c, at) = self.format.fields.iter().find(|(l, _, _)| l == label)?;
        if !matches!(*c, b'n' | b'N' | b'Z') {
            return None;
        }
        let bytes = self.payload.get(*at..at.checked_add(char_size(*c)?)?)?;
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        Some(String::from_utf8_lossy(bytes.get(..end)?).into_owned())
    }

    /// `N` numeric fields at once.
    pub fn fields<const N: usize>(&self, labels: [&str; N]) -> Option<[f64; N]> {
        let mut out = [0.0; N];
        for (o, l) in out.iter_mut().zip(labels) {
            *o = self.get(l)?;
        }
        Some(out)
    }

    /// The ArduPilot time stamp (µs since boot): `TimeUS`, or older logs' `TimeMS` × 1000.
    pub fn time_us(&self) -> Option<f64> {
        self.get("TimeUS")
            .or_else(|| self.get("TimeMS").map(|ms| ms * 1e3))
    }
}

/// Reads DataFlash-framed records from any [`Read`].
#[derive(Debug)]
pub struct Reader<R> {
    stream: ByteStream<R>,
    formats: Vec<Option<MessageFormat>>,
    pending: usize,
    /// Inside a run of skipped bytes (one remark per run).
    skipping: bool,
    records: u64,
    done: bool,
    issues: Issues,
}

impl<R: Read> Reader<R> {
    /// A reader at the start of `input`.
    pub fn new(input: R) -> Self {
        Self {
            stream: ByteStream::new(input),
            formats: vec![None; 256],
            pending: 0,
            skipping: false,
            records: 0,
            done: false,
            issues: Issues::default(),
        }
    }

    /// What the reader read past (with offsets).
    pub fn issues(&self) -> &Issues {
        &self.issues
    }

    /// Records read so far (formats included).
    pub fn records(&self) -> u64 {
        self.records
    }

    /// The formats defined so far.
    pub fn formats(&self) -> impl Iterator<Item = &MessageFormat> {
        self.formats.iter().flatten()
    }

    /// Skips one byte of what is no record; `why` keys the remark of the run.
    fn skip_byte(&mut self, offset: u64, why: &'static str, message: fn() -> String) {
        if !self.skipping {
            self.issues.add(why, offset, message);
        }
        self.skipping = true;
        self.stream.consume(1);
    }

    /// The next data record (format records are read on the way), `None` at the end.
    pub fn next_record(&mut self) -> Result<Option<Record<'_>>, ReadError> {
        self.stream.consume(self.pending);
        self.pending = 0;
        let Some((offset, kind, len)) = self.advance()? else {
            return Ok(None);
        };
        self.pending = len;
        let rec = self.stream.peek(len)?;
        Ok(self.formats[usize::from(kind)]
            .as_ref()
            .map(|format| Record {
                offset,
                format,
                payload: rec.get(3..).unwrap_or_default(),
            }))
    }

    /// Reads up to the next data record: its offset, type and length, all in the buffer.
    fn advance(&mut self) -> Result<Option<(u64, u8, usize)>, ReadError> {
        loop {
            if self.done {
                return Ok(None);
            }
            let offset = self.stream.offset();
            let head = self.stream.peek(3)?;
            let [a, b, kind] = match *head {
                [a, b, kind] => [a, b, kind],
                [] => {
                    self.done = true;
                    continue;
                }
                _ => {
                    if head.starts_with(&MAGIC[..head.len()]) {
                        self.issues.add(TRUNCATED, offset, String::new);
                    }
                    self.done = true;
                    continue;
                }
            };
            if [a, b] != MAGIC {
                self.skip_byte(offset, "garbage", || {
                    "bytes that start no record (corrupt data) were skipped".into()
                });
                continue;
            }
            let len = if kind == FMT_TYPE {
                FMT_LEN
            } else if let Some(f) = &self.formats[usize::from(kind)] {
                f.length
            } else {
                self.skip_byte(offset, "undefined type", || {
                    "a record of a type with no FMT (or corrupt data) was skipped".into()
                });
                continue;
            };
            let rec = self.stream.peek(len)?;
            if rec.len() < len {
                self.issues.add(TRUNCATED, offset, String::new);
                self.done = true;
                continue;
            }
            self.skipping = false;
            self.records += 1;
            if kind == FMT_TYPE {
                let fmt: [u8; FMT_LEN] = rec.try_into().unwrap_or([0; FMT_LEN]);
                self.stream.consume(FMT_LEN);
                self.define(offset, &fmt);
                continue;
            }
            return Ok(Some((offset, kind, len)));
        }
    }

    /// Reads an `FMT` record (header included).
    fn define(&mut self, offset: u64, rec: &[u8; FMT_LEN]) {
        let (kind, length) = (rec[3], usize::from(rec[4]));
        let name = text(&rec[5..9]);
        let chars: Vec<u8> = rec[9..25].iter().copied().take_while(|&c| c != 0).collect();
        let labels = text(&rec[25..89]);
        if kind == FMT_TYPE {
            return; // The format of FMT itself: fixed.
        }
        if length < 3 {
            self.issues.add("short FMT", offset, || {
                format!(
                    "an FMT gives message `{}` (type {kind}) a length of {length}, below its 3-byte header; its records are skipped",
                    excerpt(name.as_bytes(), 8)
                )
            });
            self.formats[usize::from(kind)] = None;
            return;
        }
        // An empty label list is no labels (ArduCopter up to 3.2 writes `STRT` so), not one
        // empty label.
        let label_count = if labels.is_empty() {
            0
        } else {
            labels.split(',').count()
        };
        if label_count != chars.len() {
            self.issues.add("FMT labels", offset, || {
                format!(
                    "the FMT of `{}` has {} format characters but {label_count} labels; the fields of either without the other are not read",
                    excerpt(name.as_bytes(), 8),
                    chars.len()
                )
            });
        }
        let mut fields = Vec::new();
        let mut at = 0usize;
        for (label, c) in labels.split(',').zip(chars.iter().copied()) {
            let Some(size) = char_size(c) else {
                self.issues.add("unknown format char", offset, || {
                    format!(
                        "the FMT of `{}` has format character `{}` that DataFlash does not define; its fields from there on are not read",
                        excerpt(name.as_bytes(), 8),
                        excerpt(&[c], 1)
                    )
                });
                break;
            };
            if at + size > length - 3 {
                self.issues.add("FMT too short", offset, || {
                    format!(
                        "the FMT of `{}` gives a length of {length}, shorter than its format `{}`; the fields past it are not read",
                        excerpt(name.as_bytes(), 8),
                        excerpt(&chars, 16)
                    )
                });
                break;
            }
            fields.push((label.to_string(), c, at));
            at += size;
        }
        let format = MessageFormat {
            name,
            length,
            fields,
        };
        let slot = &mut self.formats[usize::from(kind)];
        if slot.as_ref().is_some_and(|old| *old != format) {
            self.issues.add("FMT redefined", offset, || {
                format!(
                    "an FMT redefines message type {kind} (`{}`); its records are read with the new format from here on",
                    excerpt(format.name.as_bytes(), 8)
                )
            });
        }
        *slot = Some(format);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(kind: u8, len: u8, name: &str, format: &str, labels: &str) -> Vec<u8> {
        let mut r = vec![0xA3, 0x95, FMT_TYPE, kind, len];
        let mut pad = |s: &str, n: usize| {
            let mut b = s.as_bytes().to_vec();
            b.resize(n, 0);
            r.extend_from_slice(&b);
        };
        pad(name, 4);
        pad(format, 16);
        pad(labels, 64);
        r
    }

    #[test]
    fn every_format_character_reads_as_documented() {
        let mut log = fmt(
            5,
            3 + 1 + 1 + 2 + 2 + 4 + 4 + 4 + 8 + 2 + 2 + 4 + 4 + 4 + 1 + 8 + 8,
            "ALL",
            // 16 characters: all the format field holds.
            "bBhHiIfdcCeELMqQ",
            "b,B,h,H,i,I,f,d,c,C,e,E,L,M,q,Q",
        );
        log.extend_from_slice(&[0xA3, 0x95, 5]);
        log.push(-2i8 as u8);
        log.push(200);
        log.extend_from_slice(&(-300i16).to_le_bytes());
        log.extend_from_slice(&60_000u16.to_le_bytes());
        log.extend_from_slice(&(-70_000i32).to_le_bytes());
        log.extend_from_slice(&4_000_000_000u32.to_le_bytes());
        log.extend_from_slice(&1.5f32.to_le_bytes());
        log.extend_from_slice(&(-2.25f64).to_le_bytes());
        log.extend_from_slice(&(-1234i16).to_le_bytes());
        log.extend_from_slice(&1234u16.to_le_bytes());
        log.extend_from_slice(&(-123_456i32).to_le_bytes());
        log.extend_from_slice(&123_456u32.to_le_bytes());
        log.extend_from_slice(&(-351_234_567i32).to_le_bytes());
        log.push(7);
        log.extend_from_slice(&(-5i64).to_le_bytes());
        log.extend_from_slice(&u64::from(u32::MAX).to_le_bytes());
        let mut r = Reader::new(log.as_slice());
        let rec = r.next_record().expect("reads").expect("a record");
        let got: Vec<Option<f64>> = [
            "b", "B", "h", "H", "i", "I", "f", "d", "c", "C", "e", "E", "L", "M", "q", "Q",
        ]
        .iter()
        .map(|l| rec.get(l))
        .collect();
        let want = [
            Some(-2.0),
            Some(200.0),
            Some(-300.0),
            Some(60_000.0),
            Some(-70_000.0),
            Some(4e9),
            Some(1.5),
            Some(-2.25),
            Some(-12.34),
            Some(12.34),
            Some(-1234.56),
            Some(1234.56),
            Some(-35.123_456_7),
            Some(7.0),
            Some(-5.0),
            Some(f64::from(u32::MAX)),
        ];
        for (g, w) in got.iter().zip(want) {
            match (g, w) {
                (Some(g), Some(w)) => assert!((g - w).abs() <= 1e-9 * w.abs(), "{g} vs {w}"),
                _ => assert_eq!(*g, w),
            }
        }
        assert!(r.next_record().expect("reads").is_none());
        assert!(r.issues().items().is_empty(), "{:?}", r.issues());
    }

    #[test]
    fn text_and_array_fields_are_placed_but_not_numbers() {
        let mut log = fmt(6, 3 + 4 + 16 + 64 + 64 + 4, "TXT", "nNZaf", "n,N,Z,a,v");
        log.extend_from_slice(&[0xA3, 0x95, 6]);
        log.extend_from_slice(&[b'x'; 4 + 16 + 64 + 64]);
        log.extend_from_slice(&2.5f32.to_le_bytes());
        let mut r = Reader::new(log.as_slice());
        let rec = r.next_record().expect("reads").expect("a record");
        assert_eq!(["n", "N", "Z", "a"].map(|l| rec.get(l)), [None; 4]);
        assert_eq!(rec.get("v"), Some(2.5));
        assert!(r.issues().items().is_empty(), "{:?}", r.issues());
    }

    /// ArduCopter up to 3.2 defines `STRT` with no fields at all: no format characters and
    /// no labels, which is no mismatch to remark on.
    #[test]
    fn a_format_without_fields_reads_without_a_remark() {
        let mut log = fmt(10, 3, "STRT", "", "");
        log.extend_from_slice(&[0xA3, 0x95, 10]);
        let mut r = Reader::new(log.as_slice());
        let rec = r.next_record().expect("reads").expect("a record");
        assert_eq!(rec.format.name, "STRT");
        assert!(r.next_record().expect("reads").is_none());
        assert!(r.issues().items().is_empty(), "{:?}", r.issues());
        // Labels without characters are still a mismatch.
        let log = fmt(11, 3, "BAD", "", "a,b");
        let mut r = Reader::new(log.as_slice());
        assert!(r.next_record().expect("reads").is_none());
        assert_eq!(r.issues().items().len(), 1, "{:?}", r.issues());
    }

    #[test]
    fn garbage_between_records_is_skipped_once_with_its_offset() {
        let mut log = fmt(9, 3 + 4, "X", "f", "v");
        let rec = |v: f32| [&[0xA3, 0x95, 9][..], &v.to_le_bytes()].concat();
        log.extend(rec(1.0));
        let garbage_at = log.len() as u64;
        log.extend_from_slice(&[0xA3, 0x00, 0x95, 0xA3, 0x95, 77, 1, 2]);
        log.extend(rec(2.0));
        let mut r = Reader::new(log.as_slice());
        let mut got = Vec::new();
        while let Some(rec) = r.next_record().expect("reads") {
            got.push(rec.get("v"));
        }
        assert_eq!(got, vec![Some(1.0), Some(2.0)]);
        assert_eq!(r.issues().items().len(), 1, "{:?}", r.issues());
        assert_eq!(r.issues().items()[0].offset, garbage_at);
    }
}
