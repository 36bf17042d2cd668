//! The one byte format of a saved identifier (warm start across flights, the persistence
//! [`record`](crate::record)'s payload, the C interface's export).
//!
//! All fields little-endian; floats are IEEE-754 binary32 bit patterns:
//!
//! ```text
//! header (12 B):  "RIDX"  format version u32 (= 2)  kind u32 (the caller's kind code)
//! then for each model, in the order velocity, q̂, r̂, p̂,
//!   for each estimator of the model (1 when learnt globally, one per rule when locally):
//!     algorithm u32 (0 covariance, 1 U-D)   updates u32   θ: N × f32   packed P or U-D: N(N+1)/2 × f32
//! trailer (4 B):  CRC-32 u32 of every byte before it
//! ```
//!
//! The kind is a number the caller chooses for the identifier type (the C interface's
//! `ROTORID_KIND_*`); a snapshot is only read back under the same number.
//!
//! The CRC is CRC-32/ISO-HDLC (the IEEE CRC of zlib, Ethernet and Python's `binascii.crc32`:
//! polynomial 0x04C11DB7 reflected, initial value and final XOR 0xFFFFFFFF), the CRC of the
//! telemetry link (`rotorid-link`), computed by the same crate (`crc`), bit by bit (`NoTable`:
//! no 1 KiB table in flash; about 8 cycles a bit, a few milliseconds for the largest snapshot
//! on a Cortex-M4F: snapshots are taken at boot and landing, never in the 50 Hz loop).
//! Its Hamming distance is 4 up to 91 607 bits (11 450 bytes: every kind's snapshot but the
//! extended fuzzy identifier's) and 3 beyond (Koopman's tables): one or two flipped bits
//! anywhere, and any burst up to 32 bits, are caught in every snapshot.
//!
//! The length is fixed per identifier type ([`Snapshot::SNAPSHOT_SIZE`]). The decoder streams:
//! it reads the snapshot word by word from a [`WordSource`] (a byte slice, or a flash driver),
//! so that no copy of a snapshot need be held in RAM, in three passes over the same words:
//! the CRC, then the header and every value (through the core's own import checks, one
//! model's staged state on the stack at a time), and only then the import. A refused
//! snapshot leaves the identifier bit for bit unchanged.

use crate::error::Error;
use crate::hover::{HoverConfig, HoverIdentifier, Premise, RegressorScaling, StateModel};
use crate::membership::MembershipFunction;
use crate::rls::{Algorithm, RlsState, RlsView};
use crate::rule_base::PremiseSets;

/// Length of the snapshot header: magic, format version, kind (bytes).
pub const HEADER_SIZE: usize = 12;
/// Length of the snapshot trailer: the CRC-32 of everything before it (bytes).
pub const TRAILER_SIZE: usize = 4;
/// Version of the snapshot format (2: with the CRC-32 trailer; version 1 had none).
pub const VERSION: u32 = 2;
/// The first four bytes of every snapshot.
pub const MAGIC: [u8; 4] = *b"RIDX";

/// CRC-32/ISO-HDLC (see the module docs), bit by bit.
pub(crate) static CRC32: crc::Crc<u32, crc::NoTable> =
    crc::Crc::<u32, crc::NoTable>::new(&crc::CRC_32_ISO_HDLC);

/// The CRC-32 of `bytes` (the snapshot trailer's, the record's; see the module docs).
pub fn crc32(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

mod sealed {
    pub trait Sealed {}
}

/// Where a decoder reads a snapshot from: 4-byte words, in order, from the start.
pub trait WordSource {
    /// The next word; `None` past the end or when the storage cannot be read.
    fn next_word(&mut self) -> Option<[u8; 4]>;
    /// Back to the first word (the decoder reads the same words in three passes).
    fn rewind(&mut self);
}

/// Where an encoder writes a snapshot to: 4-byte words, in order.
pub trait WordSink {
    /// Appends one word.
    fn put_word(&mut self, word: [u8; 4]);
}

/// A [`WordSource`] over a byte slice.
pub struct SliceWords<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> SliceWords<'a> {
    /// Reads `bytes` from its start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }
}

impl WordSource for SliceWords<'_> {
    fn next_word(&mut self) -> Option<[u8; 4]> {
        let end = self.at.checked_add(4)?;
        let w = self
            .bytes
            .get(self.at..end)
            .and_then(|w| <[u8; 4]>::try_from(w).ok())?;
        self.at = end;
        Some(w)
    }

    fn rewind(&mut self) {
        self.at = 0;
    }
}

/// A [`WordSink`] into a byte slice: never writes past it (callers size it first).
pub(crate) struct SliceSink<'a> {
    bytes: &'a mut [u8],
    at: usize,
}

impl<'a> SliceSink<'a> {
    pub(crate) fn new(bytes: &'a mut [u8]) -> Self {
        Self { bytes, at: 0 }
    }
}

impl WordSink for SliceSink<'_> {
    fn put_word(&mut self, word: [u8; 4]) {
        // Byte by byte: `copy_from_slice` would keep a length-mismatch panic path.
        if let Some(dst) = self.bytes.get_mut(self.at..) {
            for (d, s) in dst.iter_mut().zip(word) {
                *d = s;
            }
        }
        self.at = self.at.saturating_add(4);
    }
}

/// A [`WordSink`] that also feeds a CRC digest (the trailer of what it forwarded).
pub(crate) struct CrcSink<'s, S: WordSink> {
    pub(crate) sink: &'s mut S,
    pub(crate) digest: crc::Digest<'static, u32, crc::NoTable>,
}

impl<'s, S: WordSink> CrcSink<'s, S> {
    pub(crate) fn new(sink: &'s mut S) -> Self {
        Self {
            sink,
            digest: CRC32.digest(),
        }
    }
}

impl<S: WordSink> WordSink for CrcSink<'_, S> {
    fn put_word(&mut self, word: [u8; 4]) {
        self.digest.update(&word);
        self.sink.put_word(word);
    }
}

/// Why [`Snapshot::write_snapshot`] wrote nothing.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum WriteError {
    /// The output buffer is shorter than the snapshot: give one of `needed` bytes
    /// ([`Snapshot::SNAPSHOT_SIZE`]).
    BufferTooShort {
        /// Bytes of the snapshot.
        needed: usize,
        /// Bytes of the buffer given.
        got: usize,
    },
}

impl core::fmt::Display for WriteError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::BufferTooShort { needed, got } => write!(
                f,
                "snapshot buffer of {got} bytes is too short: give one of {needed} bytes"
            ),
        }
    }
}

impl core::error::Error for WriteError {}

/// One estimator state's byte form (sealed: the states of the core's estimators).
pub trait SnapshotState: Copy + sealed::Sealed {
    /// Bytes of the byte form.
    const LEN: usize;
    #[doc(hidden)]
    /// A value to decode into (contents irrelevant).
    fn blank() -> Self;
    #[doc(hidden)]
    /// Reads the byte form into `self`, in place (a state can be kilobytes: no copies on the
    /// stack); `Incompatible` when too short or not a valid form.
    fn read(&mut self, input: &mut impl WordSource) -> Result<(), Error>;
}

impl<const N: usize, const NP: usize> sealed::Sealed for RlsState<f32, N, NP> {}

impl<const N: usize, const NP: usize> SnapshotState for RlsState<f32, N, NP> {
    const LEN: usize = 4 * (2 + N + NP);

    fn blank() -> Self {
        Self {
            algorithm: Algorithm::UdFactor,
            theta: [0.0; N],
            factor: [0.0; NP],
            updates: 0,
        }
    }

    fn read(&mut self, input: &mut impl WordSource) -> Result<(), Error> {
        self.algorithm = u8::try_from(u32_of(input)?)
            .ok()
            .and_then(Algorithm::from_code)
            .ok_or(Error::Incompatible)?;
        self.updates = u32_of(input)?;
        for x in self.theta.iter_mut().chain(self.factor.iter_mut()) {
            *x = f32::from_bits(u32_of(input)?);
        }
        Ok(())
    }
}

impl<S: SnapshotState, const R: usize> sealed::Sealed for [S; R] {}

impl<S: SnapshotState, const R: usize> SnapshotState for [S; R] {
    const LEN: usize = S::LEN * R;

    fn blank() -> Self {
        [S::blank(); R]
    }

    fn read(&mut self, input: &mut impl WordSource) -> Result<(), Error> {
        self.iter_mut().try_for_each(|s| s.read(input))
    }
}

fn u32_of(input: &mut impl WordSource) -> Result<u32, Error> {
    input
        .next_word()
        .map(u32::from_le_bytes)
        .ok_or(Error::Incompatible)
}

/// An identifier that has a snapshot (sealed: the core's f32 identifiers).
pub trait Snapshot: sealed::Sealed {
    /// Bytes of a snapshot of this identifier type.
    const SNAPSHOT_SIZE: usize;

    /// Streams the snapshot into `sink`, word by word, the CRC trailer last.
    fn put_snapshot(&self, kind: u32, sink: &mut impl WordSink);

    /// Checks the snapshot `source` holds (CRC, header, every value) without importing it.
    fn check_snapshot(&self, kind: u32, source: &mut impl WordSource) -> Result<(), Error>;

    /// Imports the snapshot `source` holds, after [`check_snapshot`](Self::check_snapshot)
    /// accepted it. The sample chain restarts (the next step only anchors). On `Err` nothing
    /// changed, provided the source gives the same words on every pass (a slice, a flash no
    /// one writes meanwhile).
    fn import_snapshot(&mut self, kind: u32, source: &mut impl WordSource) -> Result<(), Error>;

    /// A hash of what a snapshot does not carry but must match to be read back: the
    /// configuration ([`HoverConfig`]: RLS form, α, λ, trace bound,
    /// sample period and tolerance, scaling) and each model's premise and sets. CRC-32 of
    /// this byte form (all u32 little-endian, floats as their bits):
    ///
    /// ```text
    /// algorithm code, α, λ, trace bound, ΔT (µs), tolerance (µs), scaling (0 none, 1 helicopter)
    /// then for each model (velocity, q̂, r̂, p̂): premise (0 velocity, 1 rates, 2 heading velocity),
    ///   variables; for each variable: sets; for each set: shape (0 Gaussian, 1 left shoulder,
    ///   2 right shoulder), centre, spread
    /// ```
    fn config_hash(&self) -> u32;

    /// Writes the snapshot into `out`; returns its length ([`Self::SNAPSHOT_SIZE`]).
    fn write_snapshot(&self, kind: u32, out: &mut [u8]) -> Result<usize, WriteError> {
        let got = out.len();
        let needed = Self::SNAPSHOT_SIZE;
        let out = out
            .get_mut(..needed)
            .ok_or(WriteError::BufferTooShort { needed, got })?;
        self.put_snapshot(kind, &mut SliceSink::new(out));
        Ok(needed)
    }

    /// Imports the snapshot `bytes` (exactly [`Self::SNAPSHOT_SIZE`] long) of kind `kind`:
    /// length, CRC, header and every value are checked before anything is written; on `Err`
    /// (`Incompatible` for the format, the import checks' own errors for the values) nothing
    /// changed.
    fn read_snapshot(&mut self, kind: u32, bytes: &[u8]) -> Result<(), Error> {
        if bytes.len() != Self::SNAPSHOT_SIZE {
            return Err(Error::Incompatible);
        }
        self.import_snapshot(kind, &mut SliceWords::new(bytes))
    }
}

/// The kind code of one of rotorid's identifier types: the number the C interface
/// (`ROTORID_KIND_*`), the telemetry link, the Python package and the CLI's snapshot files
/// write into its snapshot's header, so that a snapshot written by one is read by the others.
/// A caller with its own identifier types chooses its own numbers (from 1 000 on, say).
pub trait KindCode {
    /// The code (1 to 8 for the types below).
    const KIND: u32;
}

macro_rules! kind_codes {
    ($($ty:ident = $code:literal),* $(,)?) => {
        $(impl KindCode for crate::hover::$ty<f32> {
            const KIND: u32 = $code;
        })*
    };
}

kind_codes!(
    FlightIdentifier = 1,
    FlightPlainIdentifier = 2,
    PaperFuzzyIdentifier = 3,
    PaperPlainIdentifier = 4,
    ExtendedFuzzyIdentifier = 5,
    ExtendedPlainIdentifier = 6,
    PaperLocalIdentifier = 7,
    ExtendedLocalIdentifier = 8,
);

impl<V, Q, R, P> sealed::Sealed for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32, State: SnapshotState>,
    Q: StateModel<f32, State: SnapshotState>,
    R: StateModel<f32, State: SnapshotState>,
    P: StateModel<f32, State: SnapshotState>,
{
}

impl<V, Q, R, P> Snapshot for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32, State: SnapshotState>,
    Q: StateModel<f32, State: SnapshotState>,
    R: StateModel<f32, State: SnapshotState>,
    P: StateModel<f32, State: SnapshotState>,
{
    const SNAPSHOT_SIZE: usize =
        HEADER_SIZE + V::State::LEN + Q::State::LEN + R::State::LEN + P::State::LEN + TRAILER_SIZE;

    fn put_snapshot(&self, kind: u32, sink: &mut impl WordSink) {
        let mut w = CrcSink::new(sink);
        w.put_word(MAGIC);
        w.put_word(VERSION.to_le_bytes());
        w.put_word(kind.to_le_bytes());
        // Straight from the estimators (no copy of a state on the stack), in export order.
        self.for_each_rls(|_, _, v| put_view(&v, &mut w));
        let crc = w.digest.finalize();
        w.sink.put_word(crc.to_le_bytes());
    }

    fn check_snapshot(&self, kind: u32, source: &mut impl WordSource) -> Result<(), Error> {
        // The CRC first: a damaged snapshot is refused as a whole, whatever its values.
        source.rewind();
        check_crc(source, Self::SNAPSHOT_SIZE)?;
        source.rewind();
        header(source, kind)?;
        check_model(self.velocity_model(), source)?;
        check_model(self.pitch_model(), source)?;
        check_model(self.yaw_model(), source)?;
        check_model(self.roll_model(), source)
    }

    fn import_snapshot(&mut self, kind: u32, source: &mut impl WordSource) -> Result<(), Error> {
        self.check_snapshot(kind, source)?;
        // The same words again, now known to be accepted.
        source.rewind();
        header(source, kind)?;
        import_model(self.velocity_model_mut(), source)?;
        import_model(self.pitch_model_mut(), source)?;
        import_model(self.yaw_model_mut(), source)?;
        import_model(self.roll_model_mut(), source)?;
        self.end_chain();
        Ok(())
    }

    fn config_hash(&self) -> u32 {
        let mut discard = Discard;
        let mut w = CrcSink::new(&mut discard);
        put_config(&self.config(), &mut w);
        for (premise, sets) in [
            self.velocity_model().premise_sets(),
            self.pitch_model().premise_sets(),
            self.yaw_model().premise_sets(),
            self.roll_model().premise_sets(),
        ] {
            put_premise(premise, sets, &mut w);
        }
        w.digest.finalize()
    }
}

/// A sink that keeps nothing (the configuration hash only digests).
struct Discard;

impl WordSink for Discard {
    fn put_word(&mut self, _: [u8; 4]) {}
}

/// One estimator's byte form: algorithm, updates, θ, packed factor.
fn put_view(v: &RlsView<'_, f32>, w: &mut impl WordSink) {
    w.put_word(u32::from(v.algorithm().code()).to_le_bytes());
    w.put_word(v.counters().updates.to_le_bytes());
    for x in v.parameters().iter().chain(v.packed_factor()) {
        w.put_word(x.to_bits().to_le_bytes());
    }
}

/// Reads `len` bytes (a multiple of 4) and compares the last word with the CRC of the others.
fn check_crc(source: &mut impl WordSource, len: usize) -> Result<(), Error> {
    let mut digest = CRC32.digest();
    for _ in 0..(len.saturating_sub(TRAILER_SIZE) / 4) {
        digest.update(&source.next_word().ok_or(Error::Incompatible)?);
    }
    if u32_of(source)? == digest.finalize() {
        Ok(())
    } else {
        Err(Error::Incompatible)
    }
}

fn header(source: &mut impl WordSource, kind: u32) -> Result<(), Error> {
    let magic = source.next_word().ok_or(Error::Incompatible)?;
    if magic == MAGIC && u32_of(source)? == VERSION && u32_of(source)? == kind {
        Ok(())
    } else {
        Err(Error::Incompatible)
    }
}

// One model per call and never inlined, so that the stack holds one model's staged state at a
// time, never four (the paper's fuzzy velocity model alone is 6 KiB).
#[inline(never)]
fn check_model<M: StateModel<f32, State: SnapshotState>>(
    m: &M,
    source: &mut impl WordSource,
) -> Result<(), Error> {
    let mut s = M::State::blank();
    s.read(source)?;
    m.check_import(&s)
}

#[inline(never)]
fn import_model<M: StateModel<f32, State: SnapshotState>>(
    m: &mut M,
    source: &mut impl WordSource,
) -> Result<(), Error> {
    let mut s = M::State::blank();
    s.read(source)?;
    m.import(&s)
}

// ---- The configuration hash's byte form (see `Snapshot::config_hash`) ----------------------

fn put_config(c: &HoverConfig<f32>, w: &mut impl WordSink) {
    let scaling: u32 = match c.scaling {
        RegressorScaling::None => 0,
        RegressorScaling::Helicopter => 1,
    };
    for word in [
        u32::from(c.rls.algorithm.code()),
        c.rls.initial_covariance.to_bits(),
        c.rls.forgetting.to_bits(),
        c.rls.max_trace.to_bits(),
        c.sample_period_us,
        c.period_tolerance_us,
        scaling,
    ] {
        w.put_word(word.to_le_bytes());
    }
}

fn put_premise(premise: Premise, sets: &[PremiseSets<f32>], w: &mut impl WordSink) {
    let code: u32 = match premise {
        Premise::Velocity => 0,
        Premise::Rates => 1,
        Premise::HeadingVelocity => 2,
        Premise::HorizontalSpeed => 3,
    };
    w.put_word(code.to_le_bytes());
    w.put_word((sets.len() as u32).to_le_bytes());
    for variable in sets {
        w.put_word((variable.len() as u32).to_le_bytes());
        for set in variable {
            let (shape, (c, s)) = match set {
                MembershipFunction::Gaussian { .. } => (0u32, set.parameters()),
                MembershipFunction::LeftShoulder { .. } => (1, set.parameters()),
                MembershipFunction::RightShoulder { .. } => (2, set.parameters()),
            };
            for word in [shape, c.to_bits(), s.to_bits()] {
                w.put_word(word.to_le_bytes());
            }
        }
    }
}
