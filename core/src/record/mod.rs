//! The persistence record: a learnt identifier kept across resets in two flash slots (A/B),
//! so that a power cut during a write never loses more than the record being written.
//!
//! All fields little-endian u32:
//!
//! ```text
//! header (24 B):  "RIDR"  record version (= 1)  kind  configuration hash  sequence  payload length
//! payload:        the identifier's snapshot (crate::snapshot, "RIDX" v2, with its own CRC)
//! trailer (4 B):  CRC-32 of every byte before it
//! ```
//!
//! The first six words keep their place in every version, so that a reader can always find
//! the CRC and tell a record of another version from a torn one. The configuration hash is
//! [`Snapshot::config_hash`] (CRC-32 of the configuration and every model's premise sets): a
//! record learnt under other settings is refused, not imported into a model it does not fit.
//!
//! **Writing** goes to the slot that does not hold the newest valid record (A when neither
//! does): erase the slot, then program the record front to back, its CRC last. A cut
//! anywhere in that leaves the other slot, with the newest record, untouched. **Reading**
//! takes the valid record with the newest sequence number (compared with wrap-around:
//! `a` is newer than `b` when `a − b mod 2³²` is in 1…2³¹−1), ignoring a slot that is erased,
//! torn (its CRC fails) or holds garbage. Then it checks version, kind and configuration hash,
//! and imports through the snapshot's streaming decoder, which checks every value before it
//! writes: on any error nothing was imported.
//!
//! Storage: either a flash through `embedded-storage`'s [`NorFlash`](embedded_storage::nor_flash::NorFlash)/
//! [`ReadNorFlash`](embedded_storage::nor_flash::ReadNorFlash)
//! (erase-then-write; [`write()`], [`read()`]: the integrator plugs in their flash driver), or two
//! byte slices the caller reads and programs itself ([`plan`], [`encode`], [`decode`]; [`seal`]
//! and [`open`] frame and unframe a snapshot the caller writes and imports itself, as the C
//! interface does with its export and import). The flash path streams through a 64-byte buffer; neither path holds a
//! copy of the snapshot.

use embedded_storage::nor_flash::NorFlashErrorKind;

use crate::error::Error;
use crate::snapshot::{Snapshot, WordSource, CRC32};

mod flash;

pub use flash::{newest_in, read, write, Slots};

/// The first four bytes of every record.
pub const MAGIC: [u8; 4] = *b"RIDR";
/// Version of the record format.
pub const VERSION: u32 = 1;
/// Length of the record header (bytes).
pub const HEADER_SIZE: usize = 24;
/// Length of the record trailer: the CRC-32 of everything before it (bytes).
pub const TRAILER_SIZE: usize = 4;
/// Bytes the flash path reads and programs at a time: `READ_SIZE` and `WRITE_SIZE` of the
/// flash must divide it.
pub const CHUNK: usize = 64;

/// Bytes of a record whose payload is a snapshot of `snapshot_size` bytes.
pub const fn size(snapshot_size: usize) -> usize {
    HEADER_SIZE + snapshot_size + TRAILER_SIZE
}

/// Bytes of a record of the identifier type `I`.
pub const fn size_of<I: Snapshot>() -> usize {
    size(I::SNAPSHOT_SIZE)
}

/// One of the two slots.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Slot {
    /// The first slot.
    A,
    /// The second slot.
    B,
}

impl Slot {
    /// The other slot.
    pub const fn other(self) -> Self {
        match self {
            Self::A => Self::B,
            Self::B => Self::A,
        }
    }
}

/// Where a record is (read) or goes (written).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RecordInfo {
    /// Its slot.
    pub slot: Slot,
    /// Its sequence number.
    pub sequence: u32,
}

/// Why a record was not read or written. On every one nothing was imported.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RecordError {
    /// Neither slot holds a valid record (erased, torn or never written): start afresh.
    NoValidRecord,
    /// The newest record is of another record format version: this build cannot read it.
    WrongVersion {
        /// Its version.
        found: u32,
    },
    /// The newest record holds another identifier kind: build the identifier of that kind,
    /// or start afresh.
    WrongKind {
        /// Its kind.
        found: u32,
        /// The kind asked for.
        expected: u32,
    },
    /// The newest record was learnt under another configuration or other premise sets
    /// ([`Snapshot::config_hash`]): build the identifier with those, or start afresh.
    WrongConfiguration {
        /// Its configuration hash.
        found: u32,
        /// This identifier's.
        expected: u32,
    },
    /// The record is intact but its snapshot was refused by the import checks (a payload
    /// length that does not fit this type, or a value out of range): start afresh.
    Refused(Error),
    /// The flash driver failed: check the driver and the slots' addresses.
    Storage(NorFlashErrorKind),
    /// The slots do not fit the flash: each must start on an erase boundary, span whole
    /// erase sectors, not overlap the other, lie within the flash and hold the record; the
    /// flash's read and write sizes must divide [`CHUNK`].
    Layout,
    /// The output buffer is shorter than the record: give one of `needed` bytes.
    BufferTooShort {
        /// Bytes of the record.
        needed: usize,
        /// Bytes of the buffer given.
        got: usize,
    },
}

impl core::fmt::Display for RecordError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NoValidRecord => f.write_str("no valid record in either slot: start afresh"),
            Self::WrongVersion { found } => write!(
                f,
                "record of format version {found}, this build reads {VERSION}: start afresh"
            ),
            Self::WrongKind { found, expected } => write!(
                f,
                "record of identifier kind {found}, not {expected}: build that kind or start afresh"
            ),
            Self::WrongConfiguration { found, expected } => write!(
                f,
                "record learnt under configuration {found:08x}, not this identifier's \
                 {expected:08x}: build it with the same settings and sets, or start afresh"
            ),
            Self::Refused(e) => write!(f, "record's snapshot refused ({e}): start afresh"),
            Self::Storage(k) => write!(f, "flash driver failed ({k}): check driver and slots"),
            Self::Layout => f.write_str(
                "record slots do not fit the flash: align them on erase sectors, \
                 make them disjoint and large enough",
            ),
            Self::BufferTooShort { needed, got } => write!(
                f,
                "record buffer of {got} bytes is too short: give one of {needed} bytes"
            ),
        }
    }
}

impl core::error::Error for RecordError {}

/// Whether sequence number `a` is newer than `b` (wrap-around: serial number arithmetic).
pub const fn newer(a: u32, b: u32) -> bool {
    let d = a.wrapping_sub(b);
    d != 0 && d < 0x8000_0000
}

/// The header of a valid record.
#[derive(Copy, Clone)]
struct Header {
    version: u32,
    kind: u32,
    hash: u32,
    sequence: u32,
    payload: usize,
}

/// Reads bytes of one slot.
trait ReadAt {
    /// Bytes of the slot.
    fn len(&self) -> usize;
    /// Fills `buf` from `offset` (a multiple of [`CHUNK`]; `buf` at most [`CHUNK`] bytes,
    /// to the end of the slot).
    fn read_at(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), NorFlashErrorKind>;
}

impl ReadAt for &[u8] {
    fn len(&self) -> usize {
        <[u8]>::len(self)
    }
    fn read_at(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), NorFlashErrorKind> {
        let src = self.get(offset..).ok_or(NorFlashErrorKind::OutOfBounds)?;
        for (d, s) in buf.iter_mut().zip(src) {
            *d = *s;
        }
        Ok(())
    }
}

/// The words of bytes `start..end` of a slot, read a chunk at a time.
struct Words<'r, R: ReadAt> {
    slot: &'r mut R,
    start: usize,
    end: usize,
    at: usize,
    chunk: [u8; CHUNK],
    /// Offset of `chunk` in the slot (`usize::MAX`: none read yet).
    chunk_at: usize,
    failed: Option<NorFlashErrorKind>,
}

impl<'r, R: ReadAt> Words<'r, R> {
    fn new(slot: &'r mut R, start: usize, end: usize) -> Self {
        Self {
            slot,
            start,
            end,
            at: start,
            chunk: [0xFF; CHUNK],
            chunk_at: usize::MAX,
            failed: None,
        }
    }

    fn byte(&mut self, offset: usize) -> Option<u8> {
        let base = offset - offset % CHUNK;
        if base != self.chunk_at {
            let len = self.slot.len().saturating_sub(base).min(CHUNK);
            let buf = self.chunk.get_mut(..len)?;
            if let Err(e) = self.slot.read_at(base, buf) {
                self.failed = Some(e);
                return None;
            }
            self.chunk_at = base;
        }
        self.chunk.get(offset - base).copied()
    }
}

impl<R: ReadAt> WordSource for Words<'_, R> {
    fn next_word(&mut self) -> Option<[u8; 4]> {
        let end = self.at.checked_add(4)?;
        if end > self.end || end > self.slot.len() || self.failed.is_some() {
            return None;
        }
        let at = self.at;
        let w = [
            self.byte(at)?,
            self.byte(at + 1)?,
            self.byte(at + 2)?,
            self.byte(at + 3)?,
        ];
        self.at = end;
        Some(w)
    }

    fn rewind(&mut self) {
        self.at = self.start;
    }
}

fn u32_of(w: [u8; 4]) -> u32 {
    u32::from_le_bytes(w)
}

/// The header of the valid record in `slot`, `None` when it holds none (erased, torn,
/// garbage); `Err` only when the storage cannot be read.
fn scan<R: ReadAt>(slot: &mut R) -> Result<Option<Header>, NorFlashErrorKind> {
    let len = slot.len();
    let mut words = Words::new(slot, 0, len);
    let mut next = || words.next_word().map(u32_of);
    let fields = [next(), next(), next(), next(), next(), next()];
    if let Some(e) = words.failed {
        return Err(e);
    }
    let [Some(magic), Some(version), Some(kind), Some(hash), Some(sequence), Some(payload)] =
        fields
    else {
        return Ok(None);
    };
    if magic.to_le_bytes() != MAGIC || !payload.is_multiple_of(4) {
        return Ok(None);
    }
    // Checked: a garbage length near 2³² must not wrap on a 32-bit target.
    let Some(total) = usize::try_from(payload)
        .ok()
        .and_then(|p| p.checked_add(HEADER_SIZE + TRAILER_SIZE))
    else {
        return Ok(None);
    };
    if total > len {
        return Ok(None);
    }
    words.rewind();
    let mut digest = CRC32.digest();
    for _ in 0..(total - TRAILER_SIZE) / 4 {
        match words.next_word() {
            Some(w) => digest.update(&w),
            None => return words.failed.map_or(Ok(None), Err),
        }
    }
    let Some(crc) = words.next_word() else {
        return words.failed.map_or(Ok(None), Err);
    };
    Ok((u32_of(crc) == digest.finalize()).then_some(Header {
        version,
        kind,
        hash,
        sequence,
        payload: total - HEADER_SIZE - TRAILER_SIZE,
    }))
}

/// The newest valid record of the two slots.
fn newest<R: ReadAt>(a: &mut R, b: &mut R) -> Result<Option<(Slot, Header)>, NorFlashErrorKind> {
    Ok(pick(scan(a)?, scan(b)?))
}

/// The newer of two slots' records (A on a tie, which two writes never make).
fn pick(a: Option<Header>, b: Option<Header>) -> Option<(Slot, Header)> {
    match (a, b) {
        (Some(x), Some(y)) if newer(y.sequence, x.sequence) => Some((Slot::B, y)),
        (Some(x), _) => Some((Slot::A, x)),
        (None, Some(y)) => Some((Slot::B, y)),
        (None, None) => None,
    }
}

/// `h`'s version, kind and configuration hash are this build's, `kind` and `config_hash`.
fn check_header(h: &Header, kind: u32, config_hash: u32) -> Result<(), RecordError> {
    if h.version != VERSION {
        return Err(RecordError::WrongVersion { found: h.version });
    }
    if h.kind != kind {
        return Err(RecordError::WrongKind {
            found: h.kind,
            expected: kind,
        });
    }
    if h.hash != config_hash {
        return Err(RecordError::WrongConfiguration {
            found: h.hash,
            expected: config_hash,
        });
    }
    Ok(())
}

// ---- Byte slices: the caller reads and programs the slots itself -------------------------

/// Where the next record goes, given what the two slots hold now (`a`, `b`: their bytes, or
/// an empty slice for an erased or unread slot): the slot that does not hold the newest valid
/// record, and the sequence number after it (A and 0 when neither holds one).
pub fn plan(a: &[u8], b: &[u8]) -> RecordInfo {
    let (mut a, mut b) = (a, b);
    // Slices cannot fail to read.
    match newest(&mut a, &mut b).ok().flatten() {
        Some((slot, h)) => RecordInfo {
            slot: slot.other(),
            sequence: h.sequence.wrapping_add(1),
        },
        None => RecordInfo {
            slot: Slot::A,
            sequence: 0,
        },
    }
}

/// Writes the record of `id` (kind code `kind`, sequence number `sequence`) into `out`;
/// returns its length ([`size_of`]). The caller erases the slot [`plan`] named and programs
/// these bytes into it.
pub fn encode<I: Snapshot>(
    id: &I,
    kind: u32,
    sequence: u32,
    out: &mut [u8],
) -> Result<usize, RecordError> {
    let got = out.len();
    let needed = size_of::<I>();
    let payload = out
        .get_mut(HEADER_SIZE..)
        .ok_or(RecordError::BufferTooShort { needed, got })?;
    let n = id
        .write_snapshot(kind, payload)
        .map_err(|_| RecordError::BufferTooShort { needed, got })?;
    seal(out, kind, id.config_hash(), sequence, n)
}

/// Frames a snapshot into a record, in place: `out[HEADER_SIZE .. HEADER_SIZE + payload]`
/// already holds the snapshot (of kind `kind`, configuration hash `config_hash`); writes the
/// header before it and the CRC after it. Returns the record's length. For callers that
/// reach their identifier through its snapshot bytes only (the C interface): [`encode`] is
/// this with the snapshot written by [`Snapshot::write_snapshot`].
pub fn seal(
    out: &mut [u8],
    kind: u32,
    config_hash: u32,
    sequence: u32,
    payload: usize,
) -> Result<usize, RecordError> {
    let got = out.len();
    let needed = size(payload);
    let out = out
        .get_mut(..needed)
        .ok_or(RecordError::BufferTooShort { needed, got })?;
    let length = u32::try_from(payload).map_err(|_| RecordError::Layout)?;
    let header = [
        u32::from_le_bytes(MAGIC),
        VERSION,
        kind,
        config_hash,
        sequence,
        length,
    ];
    for (d, w) in out.chunks_exact_mut(4).zip(header) {
        for (d, s) in d.iter_mut().zip(w.to_le_bytes()) {
            *d = s;
        }
    }
    let body = needed - TRAILER_SIZE;
    let (body, trailer) = out.split_at_mut_checked(body).ok_or(RecordError::Layout)?;
    for (d, s) in trailer.iter_mut().zip(CRC32.checksum(body).to_le_bytes()) {
        *d = s;
    }
    Ok(needed)
}

/// The snapshot of the newest valid record of the two slots (`a`, `b`: their bytes; an empty
/// slice for a slot not read), after checking its version, kind and configuration hash
/// against `kind` and `config_hash`; import it with [`Snapshot::read_snapshot`] (which checks
/// every value before it writes). For callers that reach their identifier through its
/// snapshot bytes only (the C interface): [`decode`] is this followed by the import.
pub fn open<'s>(
    a: &'s [u8],
    b: &'s [u8],
    kind: u32,
    config_hash: u32,
) -> Result<(RecordInfo, &'s [u8]), RecordError> {
    let (mut ra, mut rb) = (a, b);
    let (slot, h) = newest(&mut ra, &mut rb)
        .map_err(RecordError::Storage)?
        .ok_or(RecordError::NoValidRecord)?;
    check_header(&h, kind, config_hash)?;
    let bytes = match slot {
        Slot::A => a,
        Slot::B => b,
    };
    let payload = bytes
        .get(HEADER_SIZE..HEADER_SIZE + h.payload)
        .ok_or(RecordError::NoValidRecord)?;
    Ok((
        RecordInfo {
            slot,
            sequence: h.sequence,
        },
        payload,
    ))
}

/// Imports the newest valid record of the two slots (`a`, `b`: their bytes; an empty slice
/// for a slot not read) into `id`, which must be of kind `kind` and built with the
/// configuration and sets the record was learnt under. On `Err` nothing was imported.
pub fn decode<I: Snapshot>(
    id: &mut I,
    kind: u32,
    a: &[u8],
    b: &[u8],
) -> Result<RecordInfo, RecordError> {
    let (info, payload) = open(a, b, kind, id.config_hash())?;
    id.read_snapshot(kind, payload)
        .map_err(RecordError::Refused)?;
    Ok(info)
}
