//! The persistence record (`rotorid::record`) over slots the caller reads and programs: a
//! learnt model kept across resets in two flash slots (A/B), so that a power cut during a
//! write loses at most the record being written.
//!
//! The caller owns the flash: it passes what the two slots hold now (a pointer into
//! memory-mapped flash, or a copy it read), and programs what `rotorid_record_write` returns
//! into the slot it names, after erasing it. Nothing here touches flash.

use rotorid::record::{self, RecordError, RecordInfo, Slot};

use crate::error::*;
use crate::handle::{ident, ident_mut, kind_of, put, rotorid_ident_t};

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
            let n = id.record_encode(kind, plan.sequence, out)?;
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
            let read = ident_mut(h)?.record_decode(kind, a, b)?;
            if !info.is_null() {
                put(info, self::info(read, 0))?;
            }
            Ok(())
        })();
        report(result, error)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use core::ptr::{null, null_mut};
    use std::vec;
    use std::vec::Vec;

    use super::*;
    use crate::handle::rotorid_init;
    use crate::kinds::*;
    use crate::promises::Prepared;
    use crate::types::*;

    const KINDS: [u32; 8] = [
        ROTORID_KIND_FLIGHT,
        ROTORID_KIND_FLIGHT_PLAIN,
        ROTORID_KIND_PAPER_FUZZY,
        ROTORID_KIND_PAPER_PLAIN,
        ROTORID_KIND_EXTENDED_FUZZY,
        ROTORID_KIND_EXTENDED_PLAIN,
        ROTORID_KIND_PAPER_LOCAL,
        ROTORID_KIND_EXTENDED_LOCAL,
    ];

    fn write(p: &mut Prepared, a: &[u8], b: &[u8]) -> (i32, rotorid_record_info_t, Vec<u8>) {
        let mut buf = vec![0u8; rotorid_record_size(p.kind)];
        let mut info = rotorid_record_info_t::default();
        let ptr = |s: &[u8]| if s.is_empty() { null() } else { s.as_ptr() };
        // SAFETY: valid pointers and lengths.
        let rc = unsafe {
            rotorid_record_write(
                p.h(),
                ptr(a),
                a.len(),
                ptr(b),
                b.len(),
                buf.as_mut_ptr(),
                buf.len(),
                &mut info,
                null_mut(),
            )
        };
        (rc, info, buf)
    }

    fn read(p: &mut Prepared, a: &[u8], b: &[u8]) -> (i32, rotorid_record_info_t, rotorid_error_t) {
        let mut info = rotorid_record_info_t::default();
        let mut e = rotorid_error_t::default();
        // SAFETY: valid pointers and lengths.
        let rc = unsafe {
            rotorid_record_read(
                p.h(),
                a.as_ptr(),
                a.len(),
                b.as_ptr(),
                b.len(),
                &mut info,
                &mut e,
            )
        };
        (rc, info, e)
    }

    #[test]
    fn every_kind_round_trips_through_two_slots() {
        for kind in KINDS {
            let mut p = Prepared::new(kind);
            for k in 0..40 {
                assert_eq!(p.step(k), ROTORID_OK, "kind {kind}");
            }
            let (rc, info, first) = write(&mut p, &[], &[]);
            assert_eq!(rc, ROTORID_OK);
            assert_eq!((info.slot, info.sequence), (ROTORID_RECORD_SLOT_A, 0));
            assert_eq!(info.length, first.len());
            assert_eq!(first.len(), rotorid_export_size(kind) + 28);
            // The payload is the export, byte for byte.
            assert_eq!(first[24..first.len() - 4], p.export()[..], "kind {kind}");
            for k in 40..60 {
                assert_eq!(p.step(k), ROTORID_OK);
            }
            let (rc, info, second) = write(&mut p, &first, &[]);
            assert_eq!(rc, ROTORID_OK);
            assert_eq!((info.slot, info.sequence), (ROTORID_RECORD_SLOT_B, 1));

            let mut q = Prepared::new(kind);
            let (rc, info, _) = read(&mut q, &first, &second);
            assert_eq!(rc, ROTORID_OK);
            assert_eq!((info.slot, info.sequence), (ROTORID_RECORD_SLOT_B, 1));
            assert_eq!(q.export(), p.export(), "kind {kind}");
            // The newest torn: the older one is read.
            let mut torn = second.clone();
            torn[100] ^= 4;
            let mut q = Prepared::new(kind);
            assert_eq!(read(&mut q, &first, &torn).0, ROTORID_OK);
            assert_eq!(q.export()[..], first[24..first.len() - 4]);
            let (rc, info, _) = write(&mut p, &first, &torn);
            assert_eq!(
                (rc, info.slot, info.sequence),
                (ROTORID_OK, ROTORID_RECORD_SLOT_B, 1)
            );
        }
    }

    #[test]
    fn refused_records_change_nothing() {
        let mut p = Prepared::new(ROTORID_KIND_FLIGHT);
        for k in 0..40 {
            assert_eq!(p.step(k), ROTORID_OK);
        }
        let (_, _, rec) = write(&mut p, &[], &[]);

        let mut other = Prepared::new(ROTORID_KIND_FLIGHT_PLAIN);
        let before = other.bytes();
        let (rc, _, e) = read(&mut other, &rec, &[]);
        assert_eq!(rc, ROTORID_E_RECORD_KIND);
        assert_eq!(
            (e.found, e.expected),
            (ROTORID_KIND_FLIGHT, ROTORID_KIND_FLIGHT_PLAIN)
        );
        assert_eq!(other.bytes(), before);

        // The same kind at 100 Hz: another configuration.
        let mut config = core::mem::MaybeUninit::<rotorid_config_t>::zeroed();
        // SAFETY: valid pointer; the call fills the whole struct.
        let mut config = unsafe {
            assert_eq!(rotorid_config_default(config.as_mut_ptr()), ROTORID_OK);
            config.assume_init()
        };
        config.sample_period_us = 10_000;
        config.period_tolerance_us = 5_000;
        let size = rotorid_storage_size(ROTORID_KIND_FLIGHT);
        let mut storage = vec![0u64; size.div_ceil(8)];
        let mut h = null_mut();
        // SAFETY: aligned storage of `size` bytes; valid pointers.
        let rc = unsafe {
            rotorid_init(
                storage.as_mut_ptr().cast(),
                size,
                ROTORID_KIND_FLIGHT,
                &config,
                null(),
                &mut h,
                null_mut(),
            )
        };
        assert_eq!(rc, ROTORID_OK);
        let before = storage.clone();
        let mut info = rotorid_record_info_t::default();
        let mut e = rotorid_error_t::default();
        // SAFETY: valid pointers and lengths.
        let rc = unsafe {
            rotorid_record_read(h, rec.as_ptr(), rec.len(), null(), 0, &mut info, &mut e)
        };
        assert_eq!(rc, ROTORID_E_RECORD_CONFIG);
        assert_ne!(e.found, e.expected);
        assert_eq!(storage, before);

        // Erased slots, a short buffer.
        let mut q = Prepared::new(ROTORID_KIND_FLIGHT);
        let before = q.bytes();
        assert_eq!(
            read(&mut q, &[0xFF; 4096], &[0xFF; 4096]).0,
            ROTORID_E_NO_RECORD
        );
        assert_eq!(q.bytes(), before);
        let mut info = rotorid_record_info_t::default();
        let mut short = vec![0u8; rec.len() - 1];
        // SAFETY: valid pointers and lengths.
        let rc = unsafe {
            rotorid_record_write(
                p.h(),
                null(),
                0,
                null(),
                0,
                short.as_mut_ptr(),
                short.len(),
                &mut info,
                null_mut(),
            )
        };
        assert_eq!(rc, ROTORID_E_BUFFER_SIZE);
    }
}
