//! Random call sequences on the C interface, read from a byte string: the body of the fuzz
//! target `c_interface` (`host-tests/fuzz`, which compiles this crate's sources into a crate
//! of its own, `host-tests/fuzz/ffi`) and of this crate's unit tests, which feed it
//! pseudo-random bytes. Never in the library itself.
//!
//! One identifier of a kind the bytes choose, then calls until the bytes run out: steps of
//! legal, extreme and hostile samples (Euler angles or quaternions), with gaps, through the
//! generic and the lean calls (`rotorid_lean_step_<kind>`, `rotorid_lean_resume_<kind>`, now and
//! then of another kind than the handle's); resumes, predictions, resets, compensations;
//! exports; imports of its own export, of its export with words replaced by hostile values (the
//! CRC made right again, so that the values reach the core's checks) and of raw bytes; damage
//! to the storage's header (one bit, later repaired) and moves of the storage to another
//! address. After every call it asserts that
//!
//! - a call that returned an error changed no byte of the storage, and wrote no output;
//! - a successful step, resume or prediction wrote finite numbers;
//! - a damaged header is refused (`ROTORID_E_NOT_INITIALISED`).
//!
//! Damage to the identifier past the header is not tried: the storage is the identifier's
//! memory, and a byte written there behind the library's back may be an invalid value for
//! Rust (a `bool` of 2), which no check can read safely.

// Test code: a broken promise is a panic, and indexing into buffers it sized itself is fine.
#![allow(clippy::indexing_slicing)]

extern crate std;

use core::ptr::null_mut;
use std::vec;
use std::vec::Vec;

use crate::calls::*;
use crate::error::*;
use crate::export::crc32;
use crate::handle::*;
use crate::kinds::*;
use crate::lean::*;
use crate::types::*;

/// The bytes, read one value at a time (zeros once they run out).
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// In [−1, 1).
    fn unit(&mut self) -> f32 {
        f32::from(self.u8()) / 128.0 - 1.0
    }
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A float for a sample field or an imported word: mostly ordinary, at times hostile.
fn hostile(d: &mut Bytes<'_>, ordinary: f32) -> f32 {
    match d.u8() % 16 {
        0 => f32::NAN,
        1 => f32::INFINITY,
        2 => -f32::MAX,
        3 => f32::from_bits(d.u32()),
        4 => 1e12,
        5 => -1e18,
        6 => 2e12,
        7 => 1e30,
        8 => f32::MIN_POSITIVE,
        9 => ordinary * 1e6,
        _ => ordinary,
    }
}

fn sample(d: &mut Bytes<'_>, time_us: u64) -> rotorid_sample_t {
    let mode = d.u8() % 8;
    let mut s = rotorid_sample_t {
        time_us,
        roll: 0.1 * d.unit(),
        pitch: 0.1 * d.unit(),
        yaw: 3.0 * d.unit(),
        velocity: [10.0 * d.unit(), 2.0 * d.unit(), 10.0 * d.unit()],
        rates: [50.0 * d.unit(), 50.0 * d.unit(), 50.0 * d.unit()],
        controls: [d.unit(), d.unit(), d.unit(), d.unit()],
        ..rotorid_sample_t::default()
    };
    // The attitude as a quaternion in a quarter of the samples (its components at times
    // hostile or off unit norm), a form that does not exist now and then.
    match d.u8() % 8 {
        0 | 1 => {
            s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
            let (roll, pitch, yaw) = (s.roll, s.pitch, s.yaw);
            let q = rotorid::hover::Quaternion::from_euler(&rotorid::hover::Attitude {
                roll,
                pitch,
                yaw,
            });
            s.q = q.to_array().map(|c| hostile(d, c));
        }
        2 if d.u8() < 16 => s.attitude_form = 2 + d.u32() % 8,
        _ => {}
    }
    match mode {
        // Every field up to its limit.
        0 => {
            s.roll = 3.2 * d.unit();
            s.pitch = 1.6 * d.unit();
            s.velocity = [100.0 * d.unit(), 100.0 * d.unit(), 100.0 * d.unit()];
            s.rates = [2000.0 * d.unit(), 2000.0 * d.unit(), 2000.0 * d.unit()];
        }
        // One field hostile.
        1 => {
            let v = hostile(d, s.rates[0]);
            match d.u8() % 4 {
                0 => s.rates[usize::from(d.u8() % 3)] = v,
                1 => s.velocity[usize::from(d.u8() % 3)] = v,
                2 => s.controls[usize::from(d.u8() % 4)] = v,
                _ => s.roll = v,
            }
        }
        _ => {}
    }
    s
}

/// The kind a lean call is made for (the handle's, or one time in eight another, which must be
/// refused) and its sample: the attitude made a quaternion unless the bytes keep the sample's
/// own form (a lean call refuses any other form).
fn lean_call(d: &mut Bytes<'_>, kind: u32, mut s: rotorid_sample_t) -> (u32, rotorid_sample_t) {
    let pick = d.u8();
    let lean_kind = if pick.is_multiple_of(8) {
        1 + u32::from((pick / 8) % 8)
    } else {
        kind
    };
    if s.attitude_form == ROTORID_ATTITUDE_EULER && pick % 16 != 1 {
        s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
        let q = rotorid::hover::Quaternion::from_euler(&rotorid::hover::Attitude {
            roll: s.roll,
            pitch: s.pitch,
            yaw: s.yaw,
        });
        s.q = q.to_array();
    }
    (lean_kind, s)
}

/// `rotorid_lean_step_<kind>` for `kind`.
///
/// # Safety
/// As `rotorid_step`.
unsafe fn lean_step(
    kind: u32,
    h: *mut rotorid_ident_t,
    s: &rotorid_sample_t,
    out: &mut rotorid_step_output_t,
    err: &mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        match kind {
            ROTORID_KIND_FLIGHT => rotorid_lean_step_flight(h, s, out, err),
            ROTORID_KIND_FLIGHT_PLAIN => rotorid_lean_step_flight_plain(h, s, out, err),
            ROTORID_KIND_PAPER_FUZZY => rotorid_lean_step_paper_fuzzy(h, s, out, err),
            ROTORID_KIND_PAPER_PLAIN => rotorid_lean_step_paper_plain(h, s, out, err),
            ROTORID_KIND_EXTENDED_FUZZY => rotorid_lean_step_extended_fuzzy(h, s, out, err),
            ROTORID_KIND_EXTENDED_PLAIN => rotorid_lean_step_extended_plain(h, s, out, err),
            ROTORID_KIND_PAPER_LOCAL => rotorid_lean_step_paper_local(h, s, out, err),
            _ => rotorid_lean_step_extended_local(h, s, out, err),
        }
    }
}

/// `rotorid_lean_resume_<kind>` for `kind`.
///
/// # Safety
/// As `rotorid_resume`.
unsafe fn lean_resume(
    kind: u32,
    h: *mut rotorid_ident_t,
    s: &rotorid_sample_t,
    state: &mut rotorid_state_t,
    err: &mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        match kind {
            ROTORID_KIND_FLIGHT => rotorid_lean_resume_flight(h, s, state, err),
            ROTORID_KIND_FLIGHT_PLAIN => rotorid_lean_resume_flight_plain(h, s, state, err),
            ROTORID_KIND_PAPER_FUZZY => rotorid_lean_resume_paper_fuzzy(h, s, state, err),
            ROTORID_KIND_PAPER_PLAIN => rotorid_lean_resume_paper_plain(h, s, state, err),
            ROTORID_KIND_EXTENDED_FUZZY => rotorid_lean_resume_extended_fuzzy(h, s, state, err),
            ROTORID_KIND_EXTENDED_PLAIN => rotorid_lean_resume_extended_plain(h, s, state, err),
            ROTORID_KIND_PAPER_LOCAL => rotorid_lean_resume_paper_local(h, s, state, err),
            _ => rotorid_lean_resume_extended_local(h, s, state, err),
        }
    }
}

/// The storage as bytes.
fn image(storage: &[u64]) -> Vec<u8> {
    storage.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// What a sequence did, counted per operation (0–15, see `run`): calls accepted and refused,
/// so that a test can see it exercised both.
#[derive(Default, Debug)]
pub struct Counts {
    /// Accepted calls per operation.
    pub ok: [u32; 16],
    /// Refused calls per operation.
    pub refused: [u32; 16],
    /// Steps accepted after an import of damaged values was accepted.
    pub steps_after_hostile_import: u32,
}

/// Runs one sequence (see the module docs); panics when a promise breaks.
pub fn run(data: &[u8]) -> Counts {
    let mut counts = Counts::default();
    let mut hostile_import = false;
    let mut d = Bytes(data);
    let kind = 1 + u32::from(d.u8() % 8);
    let size = rotorid_storage_size(kind);
    let words = size.div_ceil(8);
    let mut storage = vec![0u64; words];
    let mut spare = vec![0u64; words];
    let mut h: *mut rotorid_ident_t = null_mut();
    let mut config = rotorid_config_t::from(rotorid::HoverConfig::<f32>::default());
    if d.u8() % 4 == 0 {
        // SAFETY: valid pointer.
        unsafe { rotorid_config_paper(&mut config) };
    }
    // SAFETY: storage of `size` bytes, aligned to 8; valid pointers.
    let rc = unsafe {
        rotorid_init(
            storage.as_mut_ptr().cast(),
            size,
            kind,
            &config,
            core::ptr::null(),
            &mut h,
            null_mut(),
        )
    };
    assert_eq!(rc, ROTORID_OK, "init of kind {kind}");
    let export_size = rotorid_export_size(kind);
    let mut export = vec![0u8; export_size];
    let mut exported = false;
    let mut damaged: Option<(usize, u8)> = None;
    let mut time = 1_000_000u64;
    while !d.is_empty() {
        let before = image(&storage);
        let op = d.u8() % 16;
        // Sentinels: an output a refused call must leave as it is.
        let mut out = rotorid_step_output_t {
            has_innovation: 0xdead_beef,
            ..Default::default()
        };
        let mut state = rotorid_state_t {
            velocity: [7.0; 3],
            ..Default::default()
        };
        let mut err = rotorid_error_t::default();
        let (rc, wrote) = match op {
            0..=6 => {
                time += match d.u8() % 12 {
                    0 => 2_000_000,
                    1 => 0,
                    2 => 25_000,
                    _ => 20_000,
                };
                let s = sample(&mut d, time);
                let rc = if op == 6 {
                    let (lean_kind, s) = lean_call(&mut d, kind, s);
                    // SAFETY: valid pointers (`h` may point to a damaged header).
                    unsafe { lean_step(lean_kind, h, &s, &mut out, &mut err) }
                } else {
                    // SAFETY: valid pointers (`h` may point to a damaged header).
                    unsafe { rotorid_step(h, &s, &mut out, &mut err) }
                };
                let finite = out
                    .prediction
                    .velocity
                    .iter()
                    .chain(&out.prediction.rates)
                    .chain(&out.innovation.velocity)
                    .chain(&out.innovation.rates)
                    .all(|x| x.is_finite());
                (rc, (out.has_innovation != 0xdead_beef, finite))
            }
            7 | 8 => {
                let s = sample(&mut d, time);
                // SAFETY: valid pointers.
                let rc = unsafe {
                    if op == 7 && d.u8() % 2 == 0 {
                        let (lean_kind, s) = lean_call(&mut d, kind, s);
                        lean_resume(lean_kind, h, &s, &mut state, &mut err)
                    } else if op == 7 {
                        rotorid_resume(h, &s, &mut state, &mut err)
                    } else {
                        rotorid_predict(h, core::ptr::null(), &s, &mut state, &mut err)
                    }
                };
                let finite = state
                    .velocity
                    .iter()
                    .chain(&state.rates)
                    .all(|x| x.is_finite());
                (
                    rc,
                    (
                        state.velocity != [7.0; 3] || state.rates != [0.0; 3],
                        finite,
                    ),
                )
            }
            9 => {
                let mut len = usize::MAX;
                let mut buffer = vec![0xa5u8; export_size];
                // SAFETY: valid pointers, `buffer` of `export_size` bytes.
                let rc = unsafe {
                    rotorid_export(h, buffer.as_mut_ptr(), export_size, &mut len, &mut err)
                };
                if rc == ROTORID_OK {
                    assert_eq!(len, export_size);
                    export = buffer;
                    exported = true;
                    (rc, (true, true))
                } else {
                    (
                        rc,
                        (len != usize::MAX || buffer.iter().any(|&b| b != 0xa5), true),
                    )
                }
            }
            10 | 11 => {
                let mut bytes = if exported && op == 10 {
                    export.clone()
                } else {
                    (0..export_size).map(|_| d.u8()).collect()
                };
                // Replace 0 to 3 float words of the payload by hostile values.
                let replaced = d.u8() % 4;
                for _ in 0..replaced {
                    let words = (export_size - 16) / 4;
                    let at = 12 + 4 * (d.u32() as usize % words.max(1));
                    let old = bytes
                        .get(at..at + 4)
                        .map_or(0.0, |w| f32::from_le_bytes([w[0], w[1], w[2], w[3]]));
                    let v = hostile(&mut d, old).to_le_bytes();
                    if let Some(w) = bytes.get_mut(at..at + 4) {
                        w.copy_from_slice(&v);
                    }
                }
                // Mostly a valid CRC, so that the values reach the core's checks.
                if d.u8() % 8 != 0 {
                    let body = export_size - 4;
                    let crc = crc32(&bytes[..body]).to_le_bytes();
                    bytes[body..].copy_from_slice(&crc);
                }
                // SAFETY: valid pointers, `bytes` of `export_size` bytes.
                let rc = unsafe { rotorid_import(h, bytes.as_ptr(), bytes.len(), &mut err) };
                if rc == ROTORID_OK {
                    hostile_import = replaced > 0 || op == 11;
                }
                (rc, (false, true))
            }
            12 => {
                // Damage one bit of the header, or repair the damage.
                let byte = match damaged.take() {
                    Some((at, bit)) => Some((at, bit)),
                    None => {
                        let at = usize::from(d.u8() % 16);
                        let bit = d.u8() % 8;
                        damaged = Some((at, bit));
                        Some((at, bit))
                    }
                };
                if let Some((at, bit)) = byte {
                    let mut bytes = image(&storage);
                    bytes[at] ^= 1 << bit;
                    for (w, c) in storage.iter_mut().zip(bytes.chunks_exact(8)) {
                        *w = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
                    }
                }
                continue;
            }
            13 => {
                // Move the storage (the old place is no longer used).
                spare.copy_from_slice(&storage);
                core::mem::swap(&mut storage, &mut spare);
                spare.fill(0x5a5a_5a5a_5a5a_5a5a);
                h = storage.as_mut_ptr().cast();
                continue;
            }
            14 => {
                let sigma = [20.0 * d.unit(), hostile(&mut d, 0.5), 0.0];
                let mut count = 0xdead_beef_u32;
                // SAFETY: valid pointers, `sigma` of 3 floats.
                let rc = unsafe { rotorid_compensate(h, sigma.as_ptr(), &mut count, &mut err) };
                (rc, (count != 0xdead_beef, true))
            }
            _ => {
                let mut k = 0xdead_beef_u32;
                // SAFETY: valid pointers.
                let rc = unsafe {
                    if d.u8() % 4 == 0 {
                        rotorid_reset(h, &mut err)
                    } else {
                        rotorid_info(h, &mut k, null_mut(), &mut err)
                    }
                };
                if rc == ROTORID_OK && k != 0xdead_beef {
                    assert_eq!(k, kind);
                }
                (rc, (k != 0xdead_beef, true))
            }
        };
        let (wrote, finite) = wrote;
        let slot = usize::from(op);
        if rc == ROTORID_OK {
            counts.ok[slot] += 1;
            if op <= 6 && hostile_import {
                counts.steps_after_hostile_import += 1;
            }
            assert!(damaged.is_none(), "op {op}: a damaged header was accepted");
            assert!(finite, "op {op}: a non-finite number out of ROTORID_OK");
            assert_eq!(
                err,
                rotorid_error_t::default(),
                "op {op}: error written on success"
            );
        } else {
            counts.refused[slot] += 1;
            assert_eq!(err.code, rc, "op {op}: the detail's code");
            assert!(
                !wrote,
                "op {op}: a refused call (code {rc}) wrote an output"
            );
            assert!(
                before == image(&storage),
                "op {op}: a refused call (code {rc}) changed the storage"
            );
            if damaged.is_some() {
                assert_eq!(rc, ROTORID_E_NOT_INITIALISED, "op {op}: a damaged header");
            }
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Many short sequences of pseudo-random bytes (xorshift; the fuzz target runs millions).
    #[test]
    fn random_call_sequences_keep_every_promise() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut total = Counts::default();
        for case in 0..if cfg!(debug_assertions) { 500 } else { 1500 } {
            let len = 64 + case % 700;
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state >> 24) as u8
                })
                .collect();
            let c = run(&bytes);
            for op in 0..16 {
                total.ok[op] += c.ok[op];
                total.refused[op] += c.refused[op];
            }
            total.steps_after_hostile_import += c.steps_after_hostile_import;
        }
        // Not vacuous: steps (0–6; 6: the lean calls), imports of the own export (10) and compensations (14) were
        // both accepted and refused, raw bytes (11) refused, and steps were accepted after
        // imports of damaged values.
        for op in [0, 6, 10, 14] {
            assert!(
                total.ok[op] > 0 && total.refused[op] > 0,
                "op {op}: {total:?}"
            );
        }
        assert!(total.refused[11] > 0, "{total:?}");
        assert!(total.steps_after_hostile_import > 0, "{total:?}");
    }
}
