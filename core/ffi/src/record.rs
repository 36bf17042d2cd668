//! The persistence record (`rotorid::record`) over slots the caller reads and programs: a
//! learnt model kept across resets in two flash slots (A/B), so that a power cut during a
//! write loses at most the record being written.
//!
//! The caller owns the flash: it passes what the two slots hold now (a pointer into
//! memory-mapped flash, or a copy it read), and programs what `rotorid_record_write` returns
//! into the slot it names, after erasing it. Nothing here touches flash.

use rotorid::record::{self, RecordError, RecordInfo, Slot};

use crate::error::*;
use crate::handle::{ident, ident_mut, kind_of, rotorid_ident_t};
use crate::ptr::put;

/// Bytes a persistence record adds to the export of its kind (header 24, CRC-32 4):
/// `rotorid_record_size(kind) == rotorid_export_size(kind) + ROTORID_RECORD_OVERHEAD`.
pub const ROTORID_RECORD_OVERHEAD: usize = 28;

const _: () = assert!(record::size(0) == ROTORID_RECORD_OVERHEAD);

/// Slot A (`rotorid_record_info_t::slot`).
pub const ROTORID_RECORD_SLOT_A: u32 = 0;
/// Slot B (`rotorid_record_info_t::slot`).
pub const ROTORID_RECORD_SLOT_B: u32 = 1;

/// Where a record is (read) or goes (write).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct rotorid_record_info_t {
    /// `ROTORID_RECORD_SLOT_A` or `ROTORID_RECORD_SLOT_B`.
    pub slot: u32,
    /// The record's sequence number (wraps around after 2³² − 1).
    pub sequence: u32,
    /// Bytes of the record (write: to program; read: 0).
    pub length: usize,
}

fn info(i: RecordInfo, length: usize) -> rotorid_record_info_t {
    rotorid_record_info_t {
        slot: match i.slot {
            Slot::A => ROTORID_RECORD_SLOT_A,
            Slot::B => ROTORID_RECORD_SLOT_B,
        },
        sequence: i.sequence,
        length,
    }
}

impl From<RecordError> for rotorid_error_t {
    fn from(e: RecordError) -> Self {
        let mut d = rotorid_error_t::default();
        match e {
            RecordError::NoValidRecord => d.code = ROTORID_E_NO_RECORD,
            RecordError::WrongVersion { found } => {
                d.code = ROTORID_E_RECORD_VERSION;
                d.found = found;
            }
            RecordError::WrongKind { found, expected } => {
                d.code = ROTORID_E_RECORD_KIND;
                (d.found, d.expected) = (found, expected);
            }
            RecordError::WrongConfiguration { found, expected } => {
                d.code = ROTORID_E_RECORD_CONFIG;
                (d.found, d.expected) = (found, expected);
            }
            RecordError::Refused(e) => d = e.into(),
            RecordError::BufferTooShort { .. } => d.code = ROTORID_E_BUFFER_SIZE,
            // Flash errors and slot layouts belong to the Rust flash path, not to slices.
            _ => d.code = ROTORID_E_UNKNOWN,
        }
        d
    }
}

/// A slot's bytes: empty for a NULL pointer (an erased or unread slot).
///
/// # Safety
/// `p` is NULL or valid for reads of `len` bytes.
unsafe fn slot<'a>(p: *const u8, len: usize) -> &'a [u8] {
    if p.is_null() {
        &[]
    } else {
        // SAFETY: the caller's contract.
        unsafe { core::slice::from_raw_parts(p, len) }
    }
}

/// Writes the persistence record of the identifier into `buffer` and says where it goes:
/// `info->slot`, the slot that does not hold the newest valid record (A when neither does),
/// with `info->sequence` the sequence number after it, and `info->length` bytes
/// (`rotorid_record_size(kind)`). Erase that slot, then program the bytes front to back; a
/// power cut in between leaves the other slot's record intact. Then this buffer may go.
///
/// `slot_a`, `slot_b`: what the slots hold now (`len_a`, `len_b` bytes; each at least the
/// record size to be recognised), NULL for a slot known to be erased.
///
/// Required: `h`, `buffer`, `info`. Optional: `slot_a`, `slot_b`, `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; BUFFER_SIZE (`capacity` below the record
/// size). On success: `buffer[0 .. info->length]` and `*info`. On an error: only `*error`.
///
/// # Safety
/// `h` is NULL or a handle from `rotorid_init*`; `slot_a`, `slot_b` are NULL or valid for
/// reads of `len_a`, `len_b` bytes; `buffer` is NULL or valid for writes of `capacity` bytes
/// and overlaps neither slot; `info` and `error` are NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn rotorid_record_write(
    h: *const rotorid_ident_t,
    slot_a: *const u8,
    len_a: usize,
    slot_b: *const u8,
    len_b: usize,
    buffer: *mut u8,
    capacity: usize,
    info: *mut rotorid_record_info_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            if buffer.is_null() || info.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let kind = kind_of(h)?;
            let id = ident(h)?;
            let plan = record::plan(slot(slot_a, len_a), slot(slot_b, len_b));
            let out = core::slice::from_raw_parts_mut(buffer, capacity);
            // The export between header and CRC: the export's own code, no second encoder.
            let payload = out
                .get_mut(record::HEADER_SIZE..)
                .ok_or(rotorid_error_t::interface(ROTORID_E_BUFFER_SIZE))?;
            let n = id
                .write_snapshot(kind, payload)
                .map_err(|_| rotorid_error_t::interface(ROTORID_E_BUFFER_SIZE))?;
            let n = record::seal(out, kind, id.config_hash(), plan.sequence, n)?;
            put(info, self::info(plan, n))
        })();
        report(result, error)
    }
}

/// Restores the identifier from the newest valid persistence record of the two slots: a slot
/// that is erased, torn by a power cut or holds garbage is ignored. The record's kind,
/// configuration hash (settings and premise sets, see `docs/c-interface.md`) and version must
/// match, and its snapshot passes every check of `rotorid_import`, before anything is
/// written. The sample chain restarts (the next step only anchors).
///
/// `slot_a`, `slot_b`: what the slots hold (`len_a`, `len_b` bytes), NULL for a slot not read.
///
/// Required: `h`. Optional: `slot_a`, `slot_b`, `info`, `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; NO_RECORD (start afresh), RECORD_VERSION,
/// RECORD_KIND, RECORD_CONFIG (`found`, `expected`); the codes of `rotorid_import` for a
/// snapshot its checks refuse. On success: the identifier and `*info` (slot and sequence of
/// the record read). On an error: only `*error`; the identifier is unchanged.
///
/// # Safety
/// As `rotorid_record_write`; `h` is NULL or a handle from `rotorid_init*`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_record_read(
    h: *mut rotorid_ident_t,
    slot_a: *const u8,
    len_a: usize,
    slot_b: *const u8,
    len_b: usize,
    info: *mut rotorid_record_info_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let kind = kind_of(h)?;
            let (a, b) = (slot(slot_a, len_a), slot(slot_b, len_b));
            let id = ident_mut(h)?;
            let (read, payload) = record::open(a, b, kind, id.config_hash())?;
            // The export's import: every check before anything is written.
            id.read_snapshot(kind, payload)?;
            if !info.is_null() {
                put(info, self::info(read, 0))?;
            }
            Ok(())
        })();
        report(result, error)
    }
}
