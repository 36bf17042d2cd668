//! A streaming PX4 ULog reader, after PX4's "ULog File Format" specification: the header,
//! flag bits ('B'), formats ('F', nested formats and arrays), subscriptions ('A', 'R'), data
//! ('D'), dropouts ('O') and sync markers ('S'); information and parameter messages ('I',
//! 'M', 'P', 'Q') and log strings ('L', 'C') are skipped by their size without being parsed.
//!
//! It replaces the `px4-ulog` crate, which panics on some corrupt inputs (an empty or
//! inconsistent parameter message), reads the whole file into memory and gives no byte offsets.
//! This one reads a record at a time through [`ByteStream`] (memory bounded by the largest
//! record: a 128 KiB buffer, plus the formats), never panics, and reports each problem with its offset:
//!
//! - a record cut by the end of the input: a [`TRUNCATED`] remark, reading stops;
//! - a data record of no subscription, or whose length does not fit its format (corrupt
//!   data): a remark, and reading resumes after the next sync marker ('S'), or stops when there
//!   is none;
//! - an unknown message type: skipped by its size (the specification asks readers to skip
//!   types they do not know), with a remark;
//! - a format or subscription that cannot be laid out (unknown nested type, a cycle, a size
//!   past 65 535 bytes, a field it cannot parse): a remark; its data is then corrupt data.
//!
//! Every record consumes at least its 3-byte header, so reading always ends.

use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Read;

use super::super::issues::{excerpt, Issues, TRUNCATED};
use super::super::malformed::{Malformation, ReadError};
use super::super::stream::ByteStream;

/// The first 7 bytes of a ULog file.
pub const MAGIC: &[u8; 7] = b"ULog\x01\x12\x35";
/// The payload of a sync message ('S').
pub const SYNC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
/// Header length: magic, version byte, start time (µs, u64).
const HEADER_LEN: usize = 16;
/// Deepest nesting of formats followed (PX4 nests 2 or 3 deep).
const MAX_DEPTH: usize = 16;
/// Most formats kept (PX4 defines a few hundred); past it 'F' messages are skipped.
const MAX_FORMATS: usize = 4096;
/// The largest message payload (the size field is a u16).
const MAX_SIZE: usize = u16::MAX as usize;

/// A primitive ULog type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prim {
    /// `int8_t`.
    I8,
    /// `uint8_t`.
    U8,
    /// `int16_t`.
    I16,
    /// `uint16_t`.
    U16,
    /// `int32_t`.
    I32,
    /// `uint32_t`.
    U32,
    /// `int64_t`.
    I64,
    /// `uint64_t`.
    U64,
    /// `float`.
    F32,
    /// `double`.
    F64,
    /// `bool` (one byte, non-zero = true).
    Bool,
    /// `char` (one byte).
    Char,
}

impl Prim {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "int8_t" => Self::I8,
            "uint8_t" => Self::U8,
            "int16_t" => Self::I16,
            "uint16_t" => Self::U16,
            "int32_t" => Self::I32,
            "uint32_t" => Self::U32,
            "int64_t" => Self::I64,
            "uint64_t" => Self::U64,
            "float" => Self::F32,
            "double" => Self::F64,
            "bool" => Self::Bool,
            "char" => Self::Char,
            _ => return None,
        })
    }

    /// Size in bytes.
    pub fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 | Self::Bool | Self::Char => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::I64 | Self::U64 | Self::F64 => 8,
        }
    }

    /// The value at `at` in `bytes` (little-endian), `None` past the end.
    pub fn read(self, bytes: &[u8], at: usize) -> Option<f64> {
        let b = bytes.get(at..at.checked_add(self.size())?)?;
        let arr = |n: usize| -> Option<[u8; 8]> {
            let mut a = [0u8; 8];
            a.get_mut(..n)?.copy_from_slice(b.get(..n)?);
            Some(a)
        };
        let a = arr(self.size())?;
        let [a0, a1, a2, a3, ..] = a;
        Some(match self {
            Self::I8 => f64::from(a0 as i8),
            Self::U8 | Self::Char => f64::from(a0),
            Self::Bool => f64::from(u8::from(a0 != 0)),
            Self::I16 => f64::from(i16::from_le_bytes([a0, a1])),
            Self::U16 => f64::from(u16::from_le_bytes([a0, a1])),
            Self::I32 => f64::from(i32::from_le_bytes([a0, a1, a2, a3])),
            Self::U32 => f64::from(u32::from_le_bytes([a0, a1, a2, a3])),
            Self::F32 => f64::from(f32::from_le_bytes([a0, a1, a2, a3])),
            Self::I64 => i64::from_le_bytes(a) as f64,
            Self::U64 => u64::from_le_bytes(a) as f64,
            Self::F64 => f64::from_le_bytes(a),
        })
    }
}

/// A field's type as written in a format: a primitive or another format's name.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Kind {
    Prim(Prim),
    Nested(String),
}

/// One field of a format ('F'): `type[len] name`.
#[derive(Debug, Clone, PartialEq, Eq)]
struct FieldDef {
    kind: Kind,
    /// Array length (`None`: a scalar).
    len: Option<usize>,
    name: String,
}

impl FieldDef {
    fn count(&self) -> usize {
        self.len.unwrap_or(1)
    }
}

/// Parses `type name` or `type[n] name`.
fn parse_field(text: &str) -> Option<FieldDef> {
    let (ty, name) = text.trim().split_once(' ')?;
    let name = name.trim();
    if name.is_empty() || ty.is_empty() {
        return None;
    }
    let (base, len) = match ty.split_once('[') {
        Some((base, rest)) => {
            let n: usize = rest.strip_suffix(']')?.parse().ok()?;
            (base, Some(Some(n).filter(|n| *n <= MAX_SIZE)?))
        }
        None => (ty, None),
    };
    let kind = match Prim::parse(base) {
        Some(p) => Kind::Prim(p),
        None if !base.is_empty() => Kind::Nested(base.to_string()),
        None => return None,
    };
    Some(FieldDef {
        kind,
        len,
        name: name.to_string(),
    })
}

/// Sizes of formats already computed (`None`: cannot be laid out, or being sized).
type Memo = HashMap<String, Option<(usize, usize)>>;

/// A located primitive field of a topic's data: its offset in the data payload (after the
/// 2-byte message id) and type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// Offset (bytes) from the start of the data.
    pub offset: usize,
    /// Type.
    pub prim: Prim,
}

impl Field {
    /// The field's value in `data`, `None` when `data` is too short.
    pub fn read(self, data: &[u8]) -> Option<f64> {
        self.prim.read(data, self.offset)
    }
}

/// A subscribed topic instance ('A').
#[derive(Debug, Clone)]
struct Subscription {
    format: String,
    /// Data payload length bounds: trailing padding may be left out of the data.
    min_len: usize,
    max_len: usize,
}

/// What the reader gives, in log order.
#[derive(Debug)]
pub enum Event<'a> {
    /// A topic instance was subscribed ('A'); its data records carry `msg_id`.
    Subscribed {
        /// The data records' id.
        msg_id: u16,
        /// The topic (format) name.
        topic: String,
        /// Instance (0 for the first).
        multi_id: u8,
    },
    /// A data record ('D') of subscription `msg_id`; `data` starts at its `timestamp`.
    Data {
        /// Byte offset of the record.
        offset: u64,
        /// Subscription id.
        msg_id: u16,
        /// The data after the id.
        data: &'a [u8],
    },
    /// The logger dropped messages ('O') for `ms` milliseconds.
    Dropout {
        /// Byte offset of the record.
        offset: u64,
        /// Duration (ms).
        ms: u16,
    },
}

/// What [`Reader::advance`] found: an event without borrowed data, or a data record left in
/// the buffer (returned from there, so that no borrow crosses the loop).
enum Step {
    Event(Event<'static>),
    Data { offset: u64, msg_id: u16 },
}

/// Reads a ULog from any [`Read`].
#[derive(Debug)]
pub struct Reader<R> {
    stream: ByteStream<R>,
    formats: HashMap<String, Vec<FieldDef>>,
    /// Format sizes computed since the last format was defined (a subscription or a field
    /// lookup then costs one map look-up, whatever the nesting).
    memo: RefCell<Memo>,
    subs: HashMap<u16, Subscription>,
    /// Bytes of the record returned last, consumed on the next call.
    pending: usize,
    done: bool,
    issues: Issues,
}

impl<R: Read> Reader<R> {
    /// Reads the header; an error when the input is not a ULog or ends inside its header.
    pub fn new(input: R) -> Result<Self, ReadError> {
        let mut stream = ByteStream::new(input);
        let head = stream.peek(HEADER_LEN)?;
        if !head.starts_with(MAGIC) && head.len() >= MAGIC.len() {
            return Err(ReadError::Malformed {
                offset: 0,
                reason: Malformation::BadMagic,
            });
        }
        if head.len() < HEADER_LEN {
            return Err(ReadError::Malformed {
                offset: head.len() as u64,
                reason: Malformation::ShortHeader {
                    expected: HEADER_LEN,
                    got: head.len(),
                },
            });
        }
        stream.consume(HEADER_LEN);
        Ok(Self {
            stream,
            formats: HashMap::new(),
            memo: RefCell::new(Memo::new()),
            subs: HashMap::new(),
            pending: 0,
            done: false,
            issues: Issues::default(),
        })
    }

    /// What the reader read past (with offsets).
    pub fn issues(&self) -> &Issues {
        &self.issues
    }

    /// The field at `path` (`name`, `name[i]`, `nested.name[i]` …) of subscription `msg_id`'s
    /// data; `None` when it has no such primitive field.
    pub fn locate(&self, msg_id: u16, path: &str) -> Option<Field> {
        let sub = self.subs.get(&msg_id)?;
        let mut format = sub.format.as_str();
        let mut base = 0usize;
        let mut memo = self.memo.borrow_mut();
        let mut parts = path.split('.').peekable();
        while let Some(part) = parts.next() {
            let (name, index) = match part.split_once('[') {
                Some((n, rest)) => (n, Some(rest.strip_suffix(']')?.parse::<usize>().ok()?)),
                None => (part, None),
            };
            let fields = self.formats.get(format)?;
            let mut offset = 0usize;
            let mut found = None;
            for f in fields {
                let elem = self.kind_size(&f.kind, 0, &mut memo)?;
                if f.name == name {
                    found = Some((f, elem));
                    break;
                }
                offset = offset.checked_add(elem.checked_mul(f.count())?)?;
            }
            let (f, elem) = found?;
            match (index, f.len) {
                (Some(i), Some(n)) if i < n => offset = offset.checked_add(i.checked_mul(elem)?)?,
                (None, None) => {}
                _ => return None,
            }
            base = base.checked_add(offset)?;
            match (&f.kind, parts.peek()) {
                (Kind::Prim(p), None) => {
                    return Some(Field {
                        offset: base,
                        prim: *p,
                    })
                }
                (Kind::Nested(n), Some(_)) => format = n,
                _ => return None,
            }
        }
        None
    }

    /// Size of a field kind (bytes), `None` for an unknown format, a cycle or past 64 KiB.
    fn kind_size(&self, kind: &Kind, depth: usize, memo: &mut Memo) -> Option<usize> {
        match kind {
            Kind::Prim(p) => Some(p.size()),
            Kind::Nested(name) => self.format_size(name, depth + 1, memo).map(|(s, _)| s),
        }
    }

    /// Size of format `name` and its size without trailing padding fields (bytes). `memo`
    /// keeps each format's size, so that wide nested formats cost their field count, not its
    /// power; an entry of `None` while a format is being sized marks a cycle.
    fn format_size(&self, name: &str, depth: usize, memo: &mut Memo) -> Option<(usize, usize)> {
        if let Some(known) = memo.get(name) {
            return *known;
        }
        if depth > MAX_DEPTH {
            return None;
        }
        memo.insert(name.to_string(), None);
        let mut sizes = || {
            let (mut size, mut unpadded) = (0usize, 0usize);
            for f in self.formats.get(name)? {
                let elem = self.kind_size(&f.kind, depth, memo)?;
                size = size.checked_add(elem.checked_mul(f.count())?)?;
                if size > MAX_SIZE {
                    return None;
                }
                if !f.name.starts_with("_padding") {
                    unpadded = size;
                }
            }
            Some((size, unpadded))
        };
        let result = sizes();
        memo.insert(name.to_string(), result);
        result
    }

    /// The next event, `None` at the end of the log (or where it becomes unreadable; see
    /// [`Self::issues`]).
    pub fn next_event(&mut self) -> Result<Option<Event<'_>>, ReadError> {
        self.stream.consume(self.pending);
        self.pending = 0;
        Ok(match self.advance()? {
            None => None,
            Some(Step::Event(e)) => Some(e),
            Some(Step::Data { offset, msg_id }) => {
                let rec = self.stream.peek(self.pending)?;
                Some(Event::Data {
                    offset,
                    msg_id,
                    data: rec.get(5..).unwrap_or_default(),
                })
            }
        })
    }

    /// Reads up to the next event; a data record is left in the buffer.
    fn advance(&mut self) -> Result<Option<Step>, ReadError> {
        loop {
            if self.done {
                return Ok(None);
            }
            let offset = self.stream.offset();
            let head = self.stream.peek(3)?;
            if head.len() < 3 {
                if !head.is_empty() {
                    self.issues.add(TRUNCATED, offset, String::new);
                }
                self.done = true;
                continue;
            }
            let size = usize::from(u16::from_le_bytes([head[0], head[1]]));
            let kind = head[2];
            let rec = self.stream.peek(3 + size)?;
            if rec.len() < 3 + size {
                self.issues.add(TRUNCATED, offset, String::new);
                self.done = true;
                continue;
            }
            let payload = &rec[3..];
            if let Some(min) = short(kind, payload) {
                self.issues.add("short message", offset, || {
                    format!(
                        "a `{}` message of {size} bytes, shorter than its {min} bytes of fixed fields and key, was skipped",
                        char::from(kind).escape_default()
                    )
                });
                self.stream.consume(3 + size);
                continue;
            }
            match kind {
                b'D' => {
                    let id = payload.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]]));
                    let ok = id.and_then(|id| {
                        let sub = self.subs.get(&id)?;
                        let n = size - 2;
                        (sub.min_len..=sub.max_len).contains(&n).then_some(id)
                    });
                    let Some(msg_id) = ok else {
                        self.issues.add("bad data", offset, || {
                            "corrupt data (a data record of no subscription, or of the wrong length for its format); resumed at the next sync marker".into()
                        });
                        self.resync(offset)?;
                        continue;
                    };
                    self.pending = 3 + size;
                    return Ok(Some(Step::Data { offset, msg_id }));
                }
                b'A' => {
                    let sub = match payload {
                        [multi, lo, hi, name @ ..] if !name.is_empty() => {
                            Some((*multi, u16::from_le_bytes([*lo, *hi]), name))
                        }
                        _ => None,
                    };
                    let Some((multi_id, msg_id, name)) = sub else {
                        self.issues.add("bad subscription", offset, || {
                            format!("a subscription message of {size} bytes (at least 4 expected) was skipped")
                        });
                        self.stream.consume(3 + size);
                        continue;
                    };
                    let topic = String::from_utf8_lossy(name).into_owned();
                    let layout = self.format_size(&topic, 0, &mut self.memo.borrow_mut());
                    self.stream.consume(3 + size);
                    let Some((max_len, min_len)) = layout else {
                        self.issues.add("bad layout", offset, || {
                            format!("topic `{}` has no format that can be laid out (undefined, nested too deep or in a cycle, or over 65 535 bytes); its data is skipped", excerpt(topic.as_bytes(), 40))
                        });
                        self.subs.remove(&msg_id);
                        continue;
                    };
                    self.subs.insert(
                        msg_id,
                        Subscription {
                            format: topic.clone(),
                            min_len,
                            max_len,
                        },
                    );
                    return Ok(Some(Step::Event(Event::Subscribed {
                        msg_id,
                        topic,
                        multi_id,
                    })));
                }
                b'F' => {
                    let parsed = parse_format(payload);
                    self.stream.consume(3 + size);
                    match parsed {
                        Ok((name, fields)) => {
                            if self.formats.len() >= MAX_FORMATS
                                && !self.formats.contains_key(&name)
                            {
                                self.issues.add("too many formats", offset, || {
                                    format!(
                                        "more than {MAX_FORMATS} formats: the others are skipped"
                                    )
                                });
                            } else {
                                self.formats.insert(name, fields);
                                self.memo.get_mut().clear();
                            }
                        }
                        Err(bad) => self.issues.add("bad format", offset, || {
                            format!("a format it cannot parse was skipped (`{bad}`)")
                        }),
                    }
                }
                b'B' => {
                    // Incompatible flags: byte 0 bit 0 (appended data) is the only one known.
                    let unknown = payload.get(8..16).and_then(|incompat| {
                        incompat.iter().enumerate().find_map(|(i, &b)| {
                            let bits = if i == 0 { b & !1 } else { b };
                            (bits != 0).then_some((i, bits))
                        })
                    });
                    if let Some((byte, bits)) = unknown {
                        return Err(ReadError::Malformed {
                            offset,
                            reason: Malformation::UnknownIncompatFlags { byte, bits },
                        });
                    }
                    self.stream.consume(3 + size);
                }
                b'R' => {
                    if let [lo, hi, ..] = payload {
                        self.subs.remove(&u16::from_le_bytes([*lo, *hi]));
                    }
                    self.stream.consume(3 + size);
                }
                b'O' => {
                    let ms = payload.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]]));
                    self.pending = 3 + size;
                    match ms {
                        Some(ms) => return Ok(Some(Step::Event(Event::Dropout { offset, ms }))),
                        None => self.issues.add("bad dropout", offset, || {
                            "a dropout message without its duration was skipped".into()
                        }),
                    }
                    self.stream.consume(std::mem::take(&mut self.pending));
                }
                b'S' | b'I' | b'M' | b'P' | b'Q' | b'L' | b'C' => {
                    self.stream.consume(3 + size);
                }
                other => {
                    self.issues.add("unknown type", offset, || {
                        format!("a message of unknown type {other:#04x} ({size} bytes) was skipped")
                    });
                    self.stream.consume(3 + size);
                }
            }
        }
    }

    /// Skips to just after the next sync marker (from the byte after `offset`); the end of
    /// the input when there is none.
    fn resync(&mut self, offset: u64) -> Result<(), ReadError> {
        self.stream.consume(1);
        loop {
            let window = self.stream.peek(super::super::stream::CAPACITY)?;
            if let Some(i) = window.windows(SYNC.len()).position(|w| w == SYNC) {
                self.stream.consume(i + SYNC.len());
                return Ok(());
            }
            if window.len() < SYNC.len() {
                let n = window.len();
                self.stream.consume(n);
                self.issues.add("no sync", offset, || {
                    "corrupt data and no sync marker after it: the data from here on is not used"
                        .into()
                });
                self.done = true;
                return Ok(());
            }
            let n = window.len() + 1 - SYNC.len();
            self.stream.consume(n);
        }
    }
}

/// The least length of a message of type `kind` (its fixed fields, and the key that an
/// information or parameter message says it has) when `payload` is shorter; `None` when it
/// is long enough or the type has no fixed part.
fn short(kind: u8, payload: &[u8]) -> Option<usize> {
    let key = |at: usize| payload.get(at).map_or(0, |&n| usize::from(n));
    let min = match kind {
        b'B' => 40,
        b'F' | b'D' | b'R' | b'O' => 2,
        b'A' => 4,
        b'I' | b'P' => 1 + key(0),
        b'M' | b'Q' => 2 + key(1),
        b'L' => 9,
        b'C' => 11,
        b'S' => SYNC.len(),
        _ => 0,
    };
    (payload.len() < min).then_some(min)
}

/// Parses a format message's `name:type name;type name;…`; the error quotes it briefly.
fn parse_format(payload: &[u8]) -> Result<(String, Vec<FieldDef>), String> {
    let bad = || excerpt(payload, 40);
    let text = std::str::from_utf8(payload).map_err(|_| bad())?;
    let (name, fields) = text.split_once(':').ok_or_else(bad)?;
    if name.is_empty() {
        return Err(bad());
    }
    let fields = fields
        .split(';')
        .filter(|f| !f.trim().is_empty())
        .map(parse_field)
        .collect::<Option<Vec<_>>>()
        .ok_or_else(bad)?;
    Ok((name.to_string(), fields))
}

#[cfg(test)]
mod tests;
