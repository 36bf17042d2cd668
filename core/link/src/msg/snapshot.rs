//! Export and import over the link: the core's one snapshot format ([`rotorid::snapshot`],
//! "RIDX" v2 with its CRC-32 trailer, the bytes the C interface's `rotorid_export` writes)
//! cut into [`DataChunk`]s, for both identifier pairs.
//!
//! * [`snapshot_kind`]: the kind code a snapshot's header carries for each identifier the
//!   link names, the C interface's `ROTORID_KIND_*` numbers, so that a snapshot taken over
//!   the link imports through the C interface and the other way round.
//! * [`export_chunks`]: a sender streams an identifier's snapshot straight from its
//!   estimators into chunks (no copy of the snapshot in RAM: two passes over the state, one
//!   for the stream CRC every chunk carries, one for the bytes).
//! * [`ImportProgress`]: a receiver stages the chunks, in order, in a buffer of its own; the
//!   complete stream then goes to [`Snapshot::read_snapshot`], which checks length, CRC,
//!   header and every value before it writes anything. The core's decoder needs the same
//!   words three times (CRC, check, import), so the stream is staged rather than decoded on
//!   the fly: a link cannot rewind.

use core::fmt;

use rotorid::snapshot::{KindCode, Snapshot, WordSink};
use rotorid::{
    ExtendedPlainIdentifier, FlightIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier,
};

use super::ident::{Ident, IdentPair};
use super::message::{MsgType, Payload};
use crate::payload::{Field, PayloadError, Reader, Writer};

/// Snapshot kind of the flight default, `FlightIdentifier` (`ROTORID_KIND_FLIGHT`).
pub const KIND_FLIGHT: u32 = <FlightIdentifier<f32> as KindCode>::KIND;
/// Snapshot kind of `PaperFuzzyIdentifier` (`ROTORID_KIND_PAPER_FUZZY`).
pub const KIND_PAPER_FUZZY: u32 = <PaperFuzzyIdentifier<f32> as KindCode>::KIND;
/// Snapshot kind of `PaperPlainIdentifier` (`ROTORID_KIND_PAPER_PLAIN`).
pub const KIND_PAPER_PLAIN: u32 = <PaperPlainIdentifier<f32> as KindCode>::KIND;
/// Snapshot kind of `ExtendedPlainIdentifier` (`ROTORID_KIND_EXTENDED_PLAIN`).
pub const KIND_EXTENDED_PLAIN: u32 = <ExtendedPlainIdentifier<f32> as KindCode>::KIND;

/// The kind code in the snapshot header of identifier `ident` of `pair` (the C interface's
/// `ROTORID_KIND_*` of the same identifier type): paper pair 3 (fuzzy) and 4 (plain), flight
/// pair 1 (`FlightIdentifier`) and 6 (`ExtendedPlainIdentifier`).
pub const fn snapshot_kind(pair: IdentPair, ident: Ident) -> u32 {
    match (pair, ident) {
        (IdentPair::Paper, Ident::Fuzzy) => KIND_PAPER_FUZZY,
        (IdentPair::Paper, Ident::Plain) => KIND_PAPER_PLAIN,
        (IdentPair::Flight, Ident::Fuzzy) => KIND_FLIGHT,
        (IdentPair::Flight, Ident::Plain) => KIND_EXTENDED_PLAIN,
    }
}

/// `ExportChunk` / `ImportChunk` payload (13 B + data): ident u8, offset u32 (of the first data
/// byte in the snapshot), total u32 (snapshot length), crc u32 (CRC-32/ISO-HDLC of the whole
/// snapshot, trailer included, the same in every chunk), then up to [`DataChunk::MAX_DATA`]
/// bytes. Chunks travel in order; the receiver checks offsets, length and CRC before it
/// hands the snapshot to the core. Since a snapshot ends with the CRC-32 of the bytes before
/// it, `crc` of an intact one is always CRC-32's residue, 0x2144DF1C: the check is the
/// snapshot's own CRC, made before staging ends. The field stays so that the layout is
/// version 1's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DataChunk<'a> {
    /// Which identifier of the active pair.
    pub ident: Ident,
    /// Offset of `data` in the snapshot.
    pub offset: u32,
    /// Snapshot length, in bytes.
    pub total: u32,
    /// CRC-32 of the whole snapshot.
    pub crc: u32,
    /// The bytes.
    pub data: &'a [u8],
}

impl<'a> DataChunk<'a> {
    /// Header bytes.
    pub const HEADER: usize = 13;
    /// Most data bytes in one chunk.
    pub const MAX_DATA: usize = crate::wire::MAX_PAYLOAD - Self::HEADER;
}

impl<'a> Payload<'a> for DataChunk<'a> {
    const TYPES: &'static [MsgType] = &[MsgType::ExportChunk, MsgType::ImportChunk];

    fn encoded_len(&self) -> usize {
        Self::HEADER + self.data.len()
    }

    fn put_fields(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        if self.data.len() > Self::MAX_DATA {
            return Err(PayloadError::InvalidValue);
        }
        self.ident.put(w)?;
        w.put_u32(self.offset)?;
        w.put_u32(self.total)?;
        w.put_u32(self.crc)?;
        w.put_bytes(self.data)
    }

    fn get_fields(r: &mut Reader<'a>) -> Result<Self, PayloadError> {
        let ident = Field::get(r)?;
        let offset = r.get_u32()?;
        let total = r.get_u32()?;
        let crc = r.get_u32()?;
        let data = r.get_bytes(r.remaining())?;
        let end = u64::from(offset) + data.len() as u64;
        if data.len() > Self::MAX_DATA || end > u64::from(total) {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            ident,
            offset,
            total,
            crc,
            data,
        })
    }
}

/// CRC-32/ISO-HDLC of a byte stream (the frame CRC), for [`DataChunk::crc`].
pub fn stream_crc(bytes: &[u8]) -> u32 {
    crate::wire::CRC.checksum(bytes)
}

/// A [`WordSink`] that only digests (the first export pass: the stream CRC).
struct CrcOnly(crc::Digest<'static, u32>);

impl WordSink for CrcOnly {
    fn put_word(&mut self, word: [u8; 4]) {
        self.0.update(&word);
    }
}

/// A [`WordSink`] that cuts the words into full [`DataChunk`]s and hands each to `send`.
struct Chunker<'s> {
    head: DataChunk<'static>,
    buf: [u8; DataChunk::MAX_DATA],
    len: usize,
    send: &'s mut dyn FnMut(&DataChunk<'_>),
}

impl Chunker<'_> {
    fn flush(&mut self) {
        let chunk = DataChunk {
            data: self.buf.get(..self.len).unwrap_or_default(),
            ..self.head
        };
        (self.send)(&chunk);
        self.head.offset = self.head.offset.saturating_add(self.len as u32);
        self.len = 0;
    }
}

impl WordSink for Chunker<'_> {
    fn put_word(&mut self, word: [u8; 4]) {
        // Byte by byte: MAX_DATA (227) is not a multiple of 4, words straddle chunks.
        for b in word {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = b;
                self.len += 1;
            }
            if self.len == DataChunk::MAX_DATA {
                self.flush();
            }
        }
    }
}

/// Streams the snapshot of `id` (kind `kind`, see [`snapshot_kind`]) as `ExportChunk`
/// payloads of identifier `ident`, in order, each full but the last, into `send`. The bytes
/// are exactly [`Snapshot::write_snapshot`]'s; nothing of the size of a snapshot is held
/// (one chunk buffer, 227 B, on the stack).
pub fn export_chunks<I: Snapshot>(
    id: &I,
    kind: u32,
    ident: Ident,
    send: &mut dyn FnMut(&DataChunk<'_>),
) {
    let mut crc = CrcOnly(crate::wire::CRC.digest());
    id.put_snapshot(kind, &mut crc);
    let mut chunker = Chunker {
        head: DataChunk {
            ident,
            offset: 0,
            total: I::SNAPSHOT_SIZE as u32,
            crc: crc.0.finalize(),
            data: &[],
        },
        buf: [0; DataChunk::MAX_DATA],
        len: 0,
        send,
    };
    id.put_snapshot(kind, &mut chunker);
    if chunker.len > 0 {
        chunker.flush();
    }
}

/// Why [`ImportProgress`] refused a chunk (the receiver answers `Nack` `BadPayload` and drops
/// the import; nothing was imported).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum StageError {
    /// The first chunk announces a snapshot of `got` bytes where the identifier's is
    /// `expected` bytes long: export from the same identifier type (same pair, same ident).
    Length {
        /// The identifier's snapshot length.
        expected: u32,
        /// The chunk's `total`.
        got: u32,
    },
    /// A chunk whose offset, length, CRC or ident does not continue the import in progress
    /// (or no import in progress): send the chunks in order from offset 0.
    OutOfOrder {
        /// The offset the receiver expected.
        expected: u32,
        /// The chunk's offset.
        got: u32,
    },
    /// All bytes arrived but their CRC-32 is not the chunks' `crc`: send the snapshot again.
    Crc,
}

impl fmt::Display for StageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Length { expected, got } => write!(
                f,
                "import of {got} bytes refused: this identifier's snapshot is {expected} bytes \
                 (export it from the same identifier type)"
            ),
            Self::OutOfOrder { expected, got } => write!(
                f,
                "import chunk at offset {got} refused: expected offset {expected} of the \
                 import in progress (send the chunks in order from offset 0)"
            ),
            Self::Crc => write!(
                f,
                "import refused: the snapshot's CRC-32 differs from the chunks' (send it again)"
            ),
        }
    }
}

impl core::error::Error for StageError {}

/// What [`ImportProgress::take`] did with a chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Staged {
    /// Staged; more chunks to come.
    More,
    /// The last chunk: the whole snapshot, CRC checked, is the first `len` bytes of the
    /// buffer.
    Complete {
        /// Bytes of the snapshot.
        len: usize,
    },
}

/// An import being staged: which identifier, how much arrived, what the chunks promised.
/// The bytes live in the receiver's buffer (a static in a firmware), passed to every call.
#[derive(Clone)]
pub struct ImportProgress {
    ident: Ident,
    received: u32,
    total: u32,
    crc: u32,
    digest: crc::Digest<'static, u32>,
}

impl ImportProgress {
    /// Starts an import on its first chunk (offset 0), into an identifier whose snapshot is
    /// `expected` bytes (`Snapshot::SNAPSHOT_SIZE`), staged in a buffer of `capacity` bytes.
    pub fn start(
        first: &DataChunk<'_>,
        expected: usize,
        capacity: usize,
    ) -> Result<Self, StageError> {
        if first.offset != 0 {
            return Err(StageError::OutOfOrder {
                expected: 0,
                got: first.offset,
            });
        }
        if first.total as usize != expected || expected > capacity {
            return Err(StageError::Length {
                expected: u32::try_from(expected).unwrap_or(u32::MAX),
                got: first.total,
            });
        }
        Ok(Self {
            ident: first.ident,
            received: 0,
            total: first.total,
            crc: first.crc,
            digest: crate::wire::CRC.digest(),
        })
    }

    /// The identifier being imported into.
    pub fn ident(&self) -> Ident {
        self.ident
    }

    /// Copies chunk `c` into `buf` at its offset, after checking that it continues this
    /// import (same ident, total and CRC, the next offset). On the last chunk, checks the CRC
    /// of all the bytes. On `Err` drop the import: what is in `buf` means nothing.
    pub fn take(&mut self, buf: &mut [u8], c: &DataChunk<'_>) -> Result<Staged, StageError> {
        let continues = c.ident == self.ident
            && c.offset == self.received
            && c.total == self.total
            && c.crc == self.crc;
        let start = self.received as usize;
        let end = start
            .checked_add(c.data.len())
            .filter(|&end| continues && end <= self.total as usize);
        let dst = end.and_then(|end| buf.get_mut(start..end).map(|dst| (end, dst)));
        let Some((end, dst)) = dst else {
            return Err(StageError::OutOfOrder {
                expected: self.received,
                got: c.offset,
            });
        };
        // Element by element: the lengths are equal by construction, and a zip has no
        // length-mismatch panic for the firmware's no-panic check to find.
        for (d, &b) in dst.iter_mut().zip(c.data) {
            *d = b;
        }
        self.digest.update(c.data);
        self.received = end as u32;
        if self.received < self.total {
            return Ok(Staged::More);
        }
        if self.digest.clone().finalize() == self.crc {
            Ok(Staged::Complete { len: end })
        } else {
            Err(StageError::Crc)
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate alloc;
    use super::super::message::testing::roundtrip;
    use super::*;
    use alloc::vec;
    use alloc::vec::Vec;
    use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample};
    use rotorid::{FlightIdentifier, HoverConfig, PaperPlainIdentifier};

    #[test]
    fn chunk_roundtrips_and_checks_bounds() {
        let data = [9u8; DataChunk::MAX_DATA];
        let d = DataChunk {
            ident: Ident::Plain,
            offset: 7,
            total: 7 + DataChunk::MAX_DATA as u32,
            crc: 0xDEAD_BEEF,
            data: &data,
        };
        let b = roundtrip(&d);
        assert_eq!(b.len(), crate::wire::MAX_PAYLOAD);
        assert_eq!(DataChunk::read(&b), Ok(d));
        for n in 0..DataChunk::HEADER {
            assert!(DataChunk::read(&b[..n]).is_err());
        }
        let mut bad = b;
        bad[5] = 0; // total < offset + len
        assert!(DataChunk::read(&bad).is_err());
    }

    /// A flight identifier that has learnt from `n` samples (θ and P away from their start).
    fn learnt(n: u64) -> FlightIdentifier<f32> {
        let mut id =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        for k in 0..n {
            let t = k as f32 * 0.02;
            let s = HoverSample {
                time_us: k * 20_000,
                attitude: Attitude {
                    roll: 0.02 * libm::sinf(t),
                    pitch: -0.01,
                    yaw: 0.1 * t,
                },
                velocity: [libm::sinf(0.7 * t), 0.1 * libm::cosf(t), -0.2],
                rates: [libm::sinf(2.0 * t), -0.5 * t, 0.3],
                controls: Controls {
                    col: 0.5,
                    ped: 0.02 * libm::cosf(3.0 * t),
                    lon: 0.01 * libm::sinf(t),
                    lat: -0.01,
                },
            };
            id.step(&s).unwrap();
        }
        id
    }

    fn chunks_of<I: Snapshot>(
        id: &I,
        kind: u32,
        ident: Ident,
    ) -> Vec<(DataChunk<'static>, Vec<u8>)> {
        let mut got = Vec::new();
        export_chunks(id, kind, ident, &mut |c| {
            got.push((DataChunk { data: &[], ..*c }, c.data.to_vec()))
        });
        got
    }

    #[test]
    fn export_chunks_carry_exactly_the_core_snapshot() {
        let id = learnt(120);
        let mut want = vec![0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        id.write_snapshot(KIND_FLIGHT, &mut want).unwrap();
        let chunks = chunks_of(&id, KIND_FLIGHT, Ident::Fuzzy);
        assert_eq!(chunks.len(), want.len().div_ceil(DataChunk::MAX_DATA));
        let mut bytes = Vec::new();
        for (head, data) in &chunks {
            assert_eq!(head.offset as usize, bytes.len());
            assert_eq!(head.total as usize, want.len());
            assert_eq!(head.crc, stream_crc(&want));
            assert_eq!(head.crc, 0x2144_DF1C, "CRC-32 residue (see DataChunk)");
            assert_eq!(head.ident, Ident::Fuzzy);
            assert!(!data.is_empty() && data.len() <= DataChunk::MAX_DATA);
            bytes.extend_from_slice(data);
        }
        assert_eq!(bytes, want);
        // A snapshot one chunk or less long is one chunk.
        let plain = PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::default()).unwrap();
        let one = chunks_of(&plain, KIND_PAPER_PLAIN, Ident::Plain);
        assert_eq!(one.len(), 1);
        assert_eq!(one[0].1.len(), PaperPlainIdentifier::<f32>::SNAPSHOT_SIZE);
    }

    /// Stages `chunks` into a fresh buffer; the first error, or the staged bytes.
    fn stage(
        chunks: &[(DataChunk<'static>, Vec<u8>)],
        expected: usize,
    ) -> Result<Vec<u8>, StageError> {
        let mut buf = vec![0u8; expected + 8];
        let mut p: Option<ImportProgress> = None;
        for (head, data) in chunks {
            let c = DataChunk { data, ..*head };
            if c.offset == 0 {
                p = Some(ImportProgress::start(&c, expected, buf.len())?);
            }
            let Some(progress) = p.as_mut() else {
                return Err(StageError::OutOfOrder {
                    expected: 0,
                    got: c.offset,
                });
            };
            if let Staged::Complete { len } = progress.take(&mut buf, &c)? {
                return Ok(buf[..len].to_vec());
            }
        }
        Err(StageError::Crc)
    }

    #[test]
    fn staged_import_is_the_snapshot_and_refusals_change_nothing() {
        let src = learnt(150);
        let size = FlightIdentifier::<f32>::SNAPSHOT_SIZE;
        let chunks = chunks_of(&src, KIND_FLIGHT, Ident::Fuzzy);
        let bytes = stage(&chunks, size).unwrap();
        let mut dst = learnt(3);
        let mut a = vec![0u8; size];
        let mut b = vec![0u8; size];
        src.write_snapshot(KIND_FLIGHT, &mut a).unwrap();
        dst.write_snapshot(KIND_FLIGHT, &mut b).unwrap();
        assert_ne!(a, b, "the two identifiers must differ before the import");
        dst.read_snapshot(KIND_FLIGHT, &bytes).unwrap();
        dst.write_snapshot(KIND_FLIGHT, &mut b).unwrap();
        assert_eq!(a, b);

        // Link-level failures: refused by the stage, before the core sees anything.
        assert_eq!(
            stage(&chunks, size + 4).unwrap_err(),
            StageError::Length {
                expected: size as u32 + 4,
                got: size as u32
            }
        );
        let mut skipped = chunks.clone();
        skipped.remove(2);
        assert!(matches!(
            stage(&skipped, size),
            Err(StageError::OutOfOrder { .. })
        ));
        let mut flipped = chunks.clone();
        flipped[3].1[17] ^= 0x40;
        assert_eq!(stage(&flipped, size), Err(StageError::Crc));
        let mut other_ident = chunks.clone();
        other_ident[1].0.ident = Ident::Plain;
        assert!(matches!(
            stage(&other_ident, size),
            Err(StageError::OutOfOrder { .. })
        ));
        let mut other_crc = chunks.clone();
        other_crc[4].0.crc ^= 1;
        assert!(matches!(
            stage(&other_crc, size),
            Err(StageError::OutOfOrder { .. })
        ));

        // An intact stream the core refuses (another kind's header): the identifier is bit
        // for bit what it was.
        let wrong_kind = chunks_of(&src, KIND_PAPER_FUZZY, Ident::Fuzzy);
        let bytes = stage(&wrong_kind, size).unwrap();
        let before = dst.clone();
        assert!(dst.read_snapshot(KIND_FLIGHT, &bytes).is_err());
        assert!(dst == before);
    }

    #[test]
    fn kinds_are_distinct_per_identifier() {
        let mut kinds = Vec::new();
        for &pair in IdentPair::ALL {
            for &ident in Ident::ALL {
                kinds.push(snapshot_kind(pair, ident));
            }
        }
        assert_eq!(kinds, [3, 4, 1, 6]);
    }
}
