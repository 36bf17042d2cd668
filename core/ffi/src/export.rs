//! The byte format of an exported identifier (warm start across flights): the core's one
//! snapshot format (`rotorid::snapshot`), whose encoder and decoder this interface calls.
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
//! `rotorid::snapshot`).
//! Its Hamming distance is 4 up to 91 607 bits (11 450 bytes: every kind's export but
//! `ROTORID_KIND_EXTENDED_FUZZY`'s) and 3 beyond (Koopman's tables): one or two flipped bits
//! anywhere, and any burst up to 32 bits, are caught in every export.
//!
//! The length is fixed per kind (`ROTORID_<KIND>_EXPORT_SIZE`). An import checks the length,
//! the CRC, the header and every value (through the core's own import checks) before it
//! writes anything; `docs/c-interface.md` shows a worked example that
//! `tests` regenerate (`export_format_example`).

use rotorid::snapshot;

/// Length of the export header: magic, format version, kind.
pub const ROTORID_EXPORT_HEADER_SIZE: usize = 12;
/// Length of the export trailer: the CRC-32 of everything before it.
pub const ROTORID_EXPORT_TRAILER_SIZE: usize = 4;
/// Version of the export format (2: with the CRC-32 trailer; version 1 had none).
pub const ROTORID_EXPORT_VERSION: u32 = 2;

// The C names are the core's format.
const _: () = {
    assert!(ROTORID_EXPORT_HEADER_SIZE == snapshot::HEADER_SIZE);
    assert!(ROTORID_EXPORT_TRAILER_SIZE == snapshot::TRAILER_SIZE);
    assert!(ROTORID_EXPORT_VERSION == snapshot::VERSION);
};

/// CRC-32/ISO-HDLC (see the module docs), for compile-time use (the storage header's check
/// words).
pub(crate) const CRC32: crc::Crc<u32, crc::Table<1>> =
    crc::Crc::<u32, crc::Table<1>>::new(&crc::CRC_32_ISO_HDLC);

/// The CRC-32 of `bytes` (the export trailer), bit by bit at run time (the core's). Used by
/// the call-sequence driver (`sequences`: the tests and the fuzz target `c_interface`).
#[allow(dead_code)]
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    snapshot::crc32(bytes)
}
