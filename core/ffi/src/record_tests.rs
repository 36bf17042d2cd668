//! The persistence record's C calls (`record.rs`), through the C interface.

extern crate std;

use core::ptr::{null, null_mut};
use std::vec;
use std::vec::Vec;

use crate::error::*;
use crate::handle::{rotorid_init, rotorid_storage_size};
use crate::kinds::*;
use crate::promises::Prepared;
use crate::record::*;
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
        assert_eq!(
            first.len(),
            rotorid_export_size(kind) + ROTORID_RECORD_OVERHEAD
        );
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
    let rc =
        unsafe { rotorid_record_read(h, rec.as_ptr(), rec.len(), null(), 0, &mut info, &mut e) };
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
