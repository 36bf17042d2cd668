//! The byte format of an exported identifier (warm start across flights).
//!
//! All fields little-endian; floats are IEEE-754 binary32 bit patterns:
//!
//! ```text
//! header (12 B):  "RIDX"  format version u32 (= 2)  kind u32 (ROTORID_KIND_*)
//! then for each model, in the order velocity, q̂, r̂, p̂,
//!   for each estimator of the model (1 when learnt globally, one per rule when locally):
//!     algorithm u32 (0 covariance, 1 U-D)   updates u32   θ: N × f32   packed P or U-D: N(N+1)/2 × f32
//! trailer (4 B):  CRC-32 u32 of every byte before it
//! ```
//!
//! The CRC is CRC-32/ISO-HDLC (the IEEE CRC of zlib, Ethernet and Python's `binascii.crc32`:
//! polynomial 0x04C11DB7 reflected, initial value and final XOR 0xFFFFFFFF), the CRC of the
//! telemetry link (`rotorid-link`), computed by the same crate (`crc`; bit by bit, see
//! `CRC32_RUNTIME`).
//! Its Hamming distance is 4 up to 91 607 bits (11 450 bytes: every kind's export but
//! `ROTORID_KIND_EXTENDED_FUZZY`'s) and 3 beyond (Koopman's tables): one or two flipped bits
//! anywhere, and any burst up to 32 bits, are caught in every export.
//!
//! The length is fixed per kind (`ROTORID_<KIND>_EXPORT_SIZE`). An import checks the length,
//! the CRC, the header and every value (through the core's own import checks) before it
//! writes anything; `docs/c-interface.md` shows a worked example that
//! `tests` regenerate (`export_format_example`).

use rotorid::hover::StateModel;
use rotorid::rls::{Algorithm, RlsState, RlsView};
use rotorid::{Error, HoverIdentifier};

/// Length of the export header: magic, format version, kind.
pub const ROTORID_EXPORT_HEADER_SIZE: usize = 12;
/// Length of the export trailer: the CRC-32 of everything before it.
pub const ROTORID_EXPORT_TRAILER_SIZE: usize = 4;
/// Version of the export format (2: with the CRC-32 trailer; version 1 had none).
pub const ROTORID_EXPORT_VERSION: u32 = 2;
const MAGIC: [u8; 4] = *b"RIDX";

/// CRC-32/ISO-HDLC (see the module docs), for compile-time use (the storage header's check
/// words).
pub(crate) const CRC32: crc::Crc<u32, crc::Table<1>> =
    crc::Crc::<u32, crc::Table<1>>::new(&crc::CRC_32_ISO_HDLC);

/// The same CRC at run time, bit by bit (`NoTable`): no 1 KiB table in flash (a firmware
/// with every kind is within a few KiB of a 256 KiB flash), at about 8 cycles a bit, a few
/// milliseconds for the largest export on a Cortex-M4F: exports and imports happen at boot
/// and landing, never in the 50 Hz loop.
static CRC32_RUNTIME: crc::Crc<u32, crc::NoTable> =
    crc::Crc::<u32, crc::NoTable>::new(&crc::CRC_32_ISO_HDLC);

/// The CRC-32 of `bytes` (the export trailer).
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    CRC32_RUNTIME.checksum(bytes)
}

/// A value with a fixed-length byte form.
pub(crate) trait Wire: Copy {
    /// Bytes of the byte form.
    const LEN: usize;
    /// A value to decode into (contents irrelevant).
    fn blank() -> Self;
    /// Reads the byte form into `self`, in place (a state can be kilobytes: no copies on the
    /// stack); `Incompatible` when too short or not a valid form.
    fn read(&mut self, input: &mut In<'_>) -> Result<(), Error>;
}

/// A write cursor that never writes past its buffer (callers size it first; a short buffer
/// only loses bytes, which the length check before every export rules out).
pub(crate) struct Out<'a> {
    bytes: &'a mut [u8],
    at: usize,
}

impl<'a> Out<'a> {
    pub(crate) fn new(bytes: &'a mut [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    fn word(&mut self, w: [u8; 4]) {
        // Byte by byte: `copy_from_slice` would keep a length-mismatch panic path.
        if let Some(dst) = self.bytes.get_mut(self.at..) {
            for (d, s) in dst.iter_mut().zip(w) {
                *d = s;
            }
        }
        self.at = self.at.saturating_add(4);
    }
}

/// A read cursor.
pub(crate) struct In<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> In<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    fn word(&mut self) -> Result<[u8; 4], Error> {
        let end = self.at.saturating_add(4);
        let w = self
            .bytes
            .get(self.at..end)
            .and_then(|w| <[u8; 4]>::try_from(w).ok())
            .ok_or(Error::Incompatible)?;
        self.at = end;
        Ok(w)
    }

    fn u32(&mut self) -> Result<u32, Error> {
        self.word().map(u32::from_le_bytes)
    }
}

impl<const N: usize, const NP: usize> Wire for RlsState<f32, N, NP> {
    const LEN: usize = 4 * (2 + N + NP);

    fn blank() -> Self {
        Self {
            algorithm: Algorithm::UdFactor,
            theta: [0.0; N],
            factor: [0.0; NP],
            updates: 0,
        }
    }

    fn read(&mut self, input: &mut In<'_>) -> Result<(), Error> {
        self.algorithm = u8::try_from(input.u32()?)
            .ok()
            .and_then(Algorithm::from_code)
            .ok_or(Error::Incompatible)?;
        self.updates = input.u32()?;
        for x in self.theta.iter_mut().chain(self.factor.iter_mut()) {
            *x = f32::from_bits(input.u32()?);
        }
        Ok(())
    }
}

impl<S: Wire, const R: usize> Wire for [S; R] {
    const LEN: usize = S::LEN * R;

    fn blank() -> Self {
        [S::blank(); R]
    }

    fn read(&mut self, input: &mut In<'_>) -> Result<(), Error> {
        self.iter_mut().try_for_each(|s| s.read(input))
    }
}

/// Bytes of an export of the identifier type `HoverIdentifier<f32, V, Q, R, P>`.
pub(crate) const fn export_size<V, Q, R, P>() -> usize
where
    V: StateModel<f32, State: Wire>,
    Q: StateModel<f32, State: Wire>,
    R: StateModel<f32, State: Wire>,
    P: StateModel<f32, State: Wire>,
{
    ROTORID_EXPORT_HEADER_SIZE
        + V::State::LEN
        + Q::State::LEN
        + R::State::LEN
        + P::State::LEN
        + ROTORID_EXPORT_TRAILER_SIZE
}

/// Writes the export of `id` (kind code `kind`) into `out`; returns the length written.
/// `Err(())` when `out` is too short (nothing meaningful was written).
pub(crate) fn export<V, Q, R, P>(
    id: &HoverIdentifier<f32, V, Q, R, P>,
    kind: u32,
    out: &mut [u8],
) -> Result<usize, ()>
where
    V: StateModel<f32, State: Wire>,
    Q: StateModel<f32, State: Wire>,
    R: StateModel<f32, State: Wire>,
    P: StateModel<f32, State: Wire>,
{
    let len = export_size::<V, Q, R, P>();
    let out = out.get_mut(..len).ok_or(())?;
    let body = len.saturating_sub(ROTORID_EXPORT_TRAILER_SIZE);
    let mut w = Out::new(out.get_mut(..body).ok_or(())?);
    w.word(MAGIC);
    w.word(ROTORID_EXPORT_VERSION.to_le_bytes());
    w.word(kind.to_le_bytes());
    // Straight from the estimators (no copy of a state on the stack), in export order.
    id.for_each_rls(|_, _, v| put_view(&v, &mut w));
    let (body, trailer) = out.split_at_mut_checked(body).ok_or(())?;
    let crc = crc32(body).to_le_bytes();
    for (d, s) in trailer.iter_mut().zip(crc) {
        *d = s;
    }
    Ok(len)
}

/// One estimator's byte form: algorithm, updates, θ, packed factor.
fn put_view(v: &RlsView<'_, f32>, w: &mut Out<'_>) {
    w.word(u32::from(v.algorithm().code()).to_le_bytes());
    w.word(v.counters().updates.to_le_bytes());
    for x in v.parameters().iter().chain(v.packed_factor()) {
        w.word(x.to_bits().to_le_bytes());
    }
}

// Import: one model per call and never inlined, so that the stack holds one model's staged
// state at a time, never four (the paper's fuzzy velocity model alone is 6 KiB).
#[inline(never)]
fn check_model<M: StateModel<f32, State: Wire>>(m: &M, r: &mut In<'_>) -> Result<(), Error> {
    let mut s = M::State::blank();
    s.read(r)?;
    m.check_import(&s)
}

#[inline(never)]
fn import_model<M: StateModel<f32, State: Wire>>(m: &mut M, r: &mut In<'_>) -> Result<(), Error> {
    let mut s = M::State::blank();
    s.read(r)?;
    m.import(&s)
}

/// Imports an export of kind `kind` into `id`. Every model's state is decoded and checked
/// before any is written; on `Err` nothing changed. The sample chain restarts.
pub(crate) fn import<V, Q, R, P>(
    id: &mut HoverIdentifier<f32, V, Q, R, P>,
    kind: u32,
    bytes: &[u8],
) -> Result<(), Error>
where
    V: StateModel<f32, State: Wire>,
    Q: StateModel<f32, State: Wire>,
    R: StateModel<f32, State: Wire>,
    P: StateModel<f32, State: Wire>,
{
    if bytes.len() != export_size::<V, Q, R, P>() {
        return Err(Error::Incompatible);
    }
    // The CRC first: a damaged export is refused as a whole, whatever its values.
    let (body, trailer) = bytes
        .split_at_checked(bytes.len().saturating_sub(ROTORID_EXPORT_TRAILER_SIZE))
        .ok_or(Error::Incompatible)?;
    if In::new(trailer).u32()? != crc32(body) {
        return Err(Error::Incompatible);
    }
    let header = |r: &mut In<'_>| -> Result<(), Error> {
        let ok = r.word()? == MAGIC && r.u32()? == ROTORID_EXPORT_VERSION && r.u32()? == kind;
        if ok {
            Ok(())
        } else {
            Err(Error::Incompatible)
        }
    };
    // Pass 1: decode and check each model.
    let mut r = In::new(body);
    header(&mut r)?;
    check_model(id.velocity_model(), &mut r)?;
    check_model(id.pitch_model(), &mut r)?;
    check_model(id.yaw_model(), &mut r)?;
    check_model(id.roll_model(), &mut r)?;
    // Pass 2: the same bytes again, now known to be accepted.
    let mut r = In::new(body);
    header(&mut r)?;
    import_model(id.velocity_model_mut(), &mut r)?;
    import_model(id.pitch_model_mut(), &mut r)?;
    import_model(id.yaw_model_mut(), &mut r)?;
    import_model(id.roll_model_mut(), &mut r)?;
    id.end_chain();
    Ok(())
}
