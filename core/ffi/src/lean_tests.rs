//! The lean calls keep the generic calls' promises: the same bits as `rotorid_step` /
//! `rotorid_resume` with a quaternion attitude, for every kind; a damaged header refused bit
//! by bit; a handle of another kind, an Euler sample and NULL pointers refused with nothing
//! changed.
//!
//! (That the generic calls refuse a storage only a lean init prepared cannot be shown here:
//! every test shares one process, whose other tests run the full init of every kind.
//! `c/lean_only.c`, a program of its own, shows it: `tests/c_interface.rs` runs it.)

extern crate std;

use core::ptr::{null, null_mut};
use std::vec;
use std::vec::Vec;

use crate::calls::*;
use crate::error::*;
use crate::handle::*;
use crate::kinds::*;
use crate::lean::*;
use crate::promises::sample;
use crate::types::*;

type Init = unsafe extern "C" fn(
    *mut core::ffi::c_void,
    usize,
    *const rotorid_config_t,
    *const rotorid_flight_sets_t,
    *mut *mut rotorid_ident_t,
    *mut rotorid_error_t,
) -> i32;
type Step = unsafe extern "C" fn(
    *mut rotorid_ident_t,
    *const rotorid_sample_t,
    *mut rotorid_step_output_t,
    *mut rotorid_error_t,
) -> i32;
type Resume = unsafe extern "C" fn(
    *mut rotorid_ident_t,
    *const rotorid_sample_t,
    *mut rotorid_state_t,
    *mut rotorid_error_t,
) -> i32;

/// Every kind with its lean calls.
const LEAN: [(u32, Init, Step, Resume); 8] = [
    (
        ROTORID_KIND_FLIGHT,
        rotorid_lean_init_flight,
        rotorid_lean_step_flight,
        rotorid_lean_resume_flight,
    ),
    (
        ROTORID_KIND_FLIGHT_PLAIN,
        rotorid_lean_init_flight_plain,
        rotorid_lean_step_flight_plain,
        rotorid_lean_resume_flight_plain,
    ),
    (
        ROTORID_KIND_PAPER_FUZZY,
        rotorid_lean_init_paper_fuzzy,
        rotorid_lean_step_paper_fuzzy,
        rotorid_lean_resume_paper_fuzzy,
    ),
    (
        ROTORID_KIND_PAPER_PLAIN,
        rotorid_lean_init_paper_plain,
        rotorid_lean_step_paper_plain,
        rotorid_lean_resume_paper_plain,
    ),
    (
        ROTORID_KIND_EXTENDED_FUZZY,
        rotorid_lean_init_extended_fuzzy,
        rotorid_lean_step_extended_fuzzy,
        rotorid_lean_resume_extended_fuzzy,
    ),
    (
        ROTORID_KIND_EXTENDED_PLAIN,
        rotorid_lean_init_extended_plain,
        rotorid_lean_step_extended_plain,
        rotorid_lean_resume_extended_plain,
    ),
    (
        ROTORID_KIND_PAPER_LOCAL,
        rotorid_lean_init_paper_local,
        rotorid_lean_step_paper_local,
        rotorid_lean_resume_paper_local,
    ),
    (
        ROTORID_KIND_EXTENDED_LOCAL,
        rotorid_lean_init_extended_local,
        rotorid_lean_step_extended_local,
        rotorid_lean_resume_extended_local,
    ),
];

/// Sample `k` of `promises::sample` with its Euler angles as a unit quaternion (ZYX), and a
/// 5 s gap after sample 60 (a TIME_STEP, then a resume).
fn quaternion_sample(k: u64) -> rotorid_sample_t {
    let mut s = sample(k);
    if k > 60 {
        s.time_us += 5_000_000;
    }
    let (sr, cr) = (0.5 * s.roll).sin_cos();
    let (sp, cp) = (0.5 * s.pitch).sin_cos();
    let (sy, cy) = (0.5 * s.yaw).sin_cos();
    s.q = [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ];
    s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
    s
}

/// Storage of `kind`, zeroed, in 8-byte words (aligned).
fn storage(kind: u32) -> Vec<u64> {
    vec![0u64; rotorid_storage_size(kind).div_ceil(8)]
}

/// The bytes of an output struct without padding (`rotorid_step_output_t`,
/// `rotorid_state_t`: f32 and u32 fields only), to compare floats bit for bit.
fn bytes<T: Copy>(v: &T) -> Vec<u8> {
    // SAFETY: reads a plain-old-data value without padding (the callers' types).
    unsafe { core::slice::from_raw_parts((v as *const T).cast::<u8>(), size_of::<T>()) }.to_vec()
}

fn export(h: *mut rotorid_ident_t, kind: u32) -> Vec<u8> {
    let mut buf = vec![0u8; rotorid_export_size(kind)];
    let mut len = 0;
    // SAFETY: valid pointers.
    let rc = unsafe { rotorid_export(h, buf.as_mut_ptr(), buf.len(), &mut len, null_mut()) };
    assert_eq!((rc, len), (ROTORID_OK, buf.len()));
    buf
}

/// For every kind: a lean identifier stepped by its lean step (and resumed after the gap by
/// its lean resume) gives, call by call, the codes, outputs and errors of a full one stepped
/// by `rotorid_step` / `rotorid_resume`, and learns the same model (equal exports).
#[test]
fn the_lean_calls_give_the_generic_calls_bits() {
    for (kind, init, lean_step, lean_resume) in LEAN {
        let (mut full, mut lean) = (storage(kind), storage(kind));
        let size = rotorid_storage_size(kind);
        let (mut hf, mut hl) = (null_mut(), null_mut());
        // SAFETY: aligned storage of `size` bytes; valid pointers.
        unsafe {
            assert_eq!(
                rotorid_init(
                    full.as_mut_ptr().cast(),
                    size,
                    kind,
                    null(),
                    null(),
                    &mut hf,
                    null_mut()
                ),
                ROTORID_OK
            );
            assert_eq!(
                init(
                    lean.as_mut_ptr().cast(),
                    size,
                    null(),
                    null(),
                    &mut hl,
                    null_mut()
                ),
                ROTORID_OK
            );
        }
        let mut resumed = 0;
        for k in 0..120 {
            let s = quaternion_sample(k);
            let (mut of, mut ol) = (
                rotorid_step_output_t::default(),
                rotorid_step_output_t::default(),
            );
            let (mut ef, mut el) = (rotorid_error_t::default(), rotorid_error_t::default());
            // SAFETY: valid pointers.
            let (rf, rl) = unsafe {
                (
                    rotorid_step(hf, &s, &mut of, &mut ef),
                    lean_step(hl, &s, &mut ol, &mut el),
                )
            };
            assert_eq!(
                (rf, bytes(&of), ef),
                (rl, bytes(&ol), el),
                "kind {kind}, sample {k}"
            );
            if rf == ROTORID_E_TIME_STEP {
                let (mut pf, mut pl) = (rotorid_state_t::default(), rotorid_state_t::default());
                // SAFETY: valid pointers.
                let (rf, rl) = unsafe {
                    (
                        rotorid_resume(hf, &s, &mut pf, null_mut()),
                        lean_resume(hl, &s, &mut pl, null_mut()),
                    )
                };
                assert_eq!(
                    (rf, bytes(&pf)),
                    (ROTORID_OK, bytes(&pl)),
                    "kind {kind}, sample {k}"
                );
                assert_eq!(rl, ROTORID_OK);
                resumed += 1;
            } else {
                assert_eq!(rf, ROTORID_OK, "kind {kind}, sample {k}");
            }
        }
        assert_eq!(resumed, 1, "kind {kind}: the gap is one TIME_STEP");
        // The generic export reads the lean storage here because this process ran the full
        // init of `kind` above.
        assert_eq!(export(hf, kind), export(hl, kind), "kind {kind}");
    }
}

/// Every single bit flipped in the header of a lean storage is refused by the lean step and
/// resume with NOT_INITIALISED and changes nothing; flipped back, the storage steps again.
#[test]
fn every_header_bit_flip_is_refused_by_the_lean_calls() {
    for (kind, init, lean_step, lean_resume) in LEAN {
        let mut st = storage(kind);
        let mut h = null_mut();
        // SAFETY: aligned storage; valid pointers.
        let rc = unsafe {
            init(
                st.as_mut_ptr().cast(),
                rotorid_storage_size(kind),
                null(),
                null(),
                &mut h,
                null_mut(),
            )
        };
        assert_eq!(rc, ROTORID_OK);
        let (mut out, mut state) = (rotorid_step_output_t::default(), rotorid_state_t::default());
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { lean_step(h, &quaternion_sample(0), &mut out, null_mut()) },
            ROTORID_OK
        );
        for bit in 0..128 {
            st[bit / 64] ^= 1 << (bit % 64);
            let damaged = st.clone();
            let h = st.as_mut_ptr().cast();
            let s = quaternion_sample(1);
            // SAFETY: valid pointers; `h` points to damaged storage, which must be refused.
            let codes = unsafe {
                [
                    lean_step(h, &s, &mut out, null_mut()),
                    lean_resume(h, &s, &mut state, null_mut()),
                ]
            };
            assert_eq!(
                codes, [ROTORID_E_NOT_INITIALISED; 2],
                "kind {kind}, bit {bit}"
            );
            assert!(st == damaged, "kind {kind}, bit {bit}: storage changed");
            st[bit / 64] ^= 1 << (bit % 64);
        }
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { lean_step(h, &quaternion_sample(1), &mut out, null_mut()) },
            ROTORID_OK
        );
    }
}

/// A lean call refuses, writing nothing but the detail: a handle of another kind (KIND), a
/// sample with Euler angles or an unknown form (OUT_OF_RANGE, quantity ATTITUDE_FORM), NULL
/// pointers (NULL) and a misaligned handle (MISALIGNED).
#[test]
fn the_lean_calls_refuse_what_is_not_theirs() {
    for (i, (kind, init, lean_step, lean_resume)) in LEAN.into_iter().enumerate() {
        let mut st = storage(kind);
        let mut h = null_mut();
        // SAFETY: aligned storage; valid pointers.
        let rc = unsafe {
            init(
                st.as_mut_ptr().cast(),
                rotorid_storage_size(kind),
                null(),
                null(),
                &mut h,
                null_mut(),
            )
        };
        assert_eq!(rc, ROTORID_OK);
        let before = st.clone();
        let (_, _, other_step, other_resume) = LEAN[(i + 1) % LEAN.len()];
        let q = quaternion_sample(0);
        let mut euler = sample(0);
        euler.attitude_form = ROTORID_ATTITUDE_EULER;
        let mut unknown = q;
        unknown.attitude_form = 7;
        let sentinel = rotorid_step_output_t {
            has_innovation: 99,
            ..rotorid_step_output_t::default()
        };
        let mut out = sentinel;
        let mut state = rotorid_state_t {
            rates: [7.0; 3],
            ..rotorid_state_t::default()
        };
        let state_before = state;
        let misaligned = st
            .as_mut_ptr()
            .cast::<u8>()
            .wrapping_add(4)
            .cast::<rotorid_ident_t>();
        let mut details = vec![];
        // SAFETY: valid pointers (or NULL where refused); `misaligned` is refused before it
        // is read.
        let codes = unsafe {
            [
                (other_step(h, &q, &mut out, null_mut()), ROTORID_E_KIND),
                (other_resume(h, &q, &mut state, null_mut()), ROTORID_E_KIND),
                (
                    lean_step(h, &euler, &mut out, null_mut()),
                    ROTORID_E_OUT_OF_RANGE,
                ),
                (
                    lean_resume(h, &unknown, &mut state, null_mut()),
                    ROTORID_E_OUT_OF_RANGE,
                ),
                (
                    lean_step(null_mut(), &q, &mut out, null_mut()),
                    ROTORID_E_NULL,
                ),
                (lean_step(h, null(), &mut out, null_mut()), ROTORID_E_NULL),
                (lean_step(h, &q, null_mut(), null_mut()), ROTORID_E_NULL),
                (lean_resume(h, &q, null_mut(), null_mut()), ROTORID_E_NULL),
                (
                    lean_step(misaligned, &q, &mut out, null_mut()),
                    ROTORID_E_MISALIGNED,
                ),
            ]
        };
        for (j, (got, want)) in codes.into_iter().enumerate() {
            assert_eq!(got, want, "kind {kind}, case {j}");
        }
        for s in [&euler, &unknown] {
            let mut e = rotorid_error_t::default();
            // SAFETY: valid pointers.
            unsafe { lean_step(h, s, &mut out, &mut e) };
            details.push((e.code, e.quantity));
        }
        assert_eq!(
            details,
            [(ROTORID_E_OUT_OF_RANGE, ROTORID_QUANTITY_ATTITUDE_FORM); 2]
        );
        assert!(
            st == before,
            "kind {kind}: a refused call changed the storage"
        );
        assert_eq!(bytes(&out), bytes(&sentinel));
        assert_eq!(bytes(&state), bytes(&state_before));
    }
}
