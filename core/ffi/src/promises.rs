//! The interface's promises under attack, one test each: a damaged header is refused bit by
//! bit, a moved storage keeps working, a damaged export is refused bit by bit, a refused
//! call writes no output, configuration errors have `CONFIG_*` codes; and the worked export
//! example of `docs/c-interface.md`, regenerated here.

extern crate std;

use core::ptr::{null, null_mut};
use std::format;
use std::string::String;
use std::vec;
use std::vec::Vec;

use crate::calls::*;
use crate::error::*;
use crate::handle::*;
use crate::kinds::*;
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

/// An identifier of `kind` in storage of its own (8-byte words: aligned).
pub(crate) struct Prepared {
    storage: Vec<u64>,
    pub(crate) kind: u32,
}

impl Prepared {
    pub(crate) fn new(kind: u32) -> Self {
        let size = rotorid_storage_size(kind);
        let mut storage = vec![0u64; size.div_ceil(8)];
        let mut h = null_mut();
        // SAFETY: aligned storage of `size` bytes; valid pointers.
        let rc = unsafe {
            rotorid_init(
                storage.as_mut_ptr().cast(),
                size,
                kind,
                null(),
                null(),
                &mut h,
                null_mut(),
            )
        };
        assert_eq!(rc, ROTORID_OK);
        Self { storage, kind }
    }
    pub(crate) fn h(&mut self) -> *mut rotorid_ident_t {
        self.storage.as_mut_ptr().cast()
    }
    pub(crate) fn bytes(&self) -> Vec<u8> {
        self.storage.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
    fn flip(&mut self, bit: usize) {
        let word = &mut self.storage[bit / 64];
        *word ^= 1 << (bit % 64);
    }
    pub(crate) fn step(&mut self, k: u64) -> i32 {
        let s = sample(k);
        let mut out = rotorid_step_output_t::default();
        // SAFETY: valid pointers.
        unsafe { rotorid_step(self.h(), &s, &mut out, null_mut()) }
    }
    pub(crate) fn export(&mut self) -> Vec<u8> {
        let mut buf = vec![0u8; rotorid_export_size(self.kind)];
        let mut len = 0;
        // SAFETY: valid pointers.
        let rc =
            unsafe { rotorid_export(self.h(), buf.as_mut_ptr(), buf.len(), &mut len, null_mut()) };
        assert_eq!((rc, len), (ROTORID_OK, buf.len()));
        buf
    }
}

pub(crate) fn sample(k: u64) -> rotorid_sample_t {
    let t = k as f32 * 0.02;
    rotorid_sample_t {
        time_us: 1_000_000 + 20_000 * k,
        roll: 0.05 * (0.7 * t).sin(),
        pitch: -0.03 * (0.5 * t).cos(),
        yaw: 0.1 * t.sin(),
        velocity: [5.0 * (0.2 * t).sin(), 0.5 * (0.3 * t).cos(), -0.2],
        rates: [
            10.0 * (1.3 * t).sin(),
            8.0 * (1.7 * t).cos(),
            12.0 * (2.1 * t).sin(),
        ],
        controls: [
            0.5 + 0.1 * (1.1 * t).sin(),
            0.1 * (1.9 * t).sin(),
            0.1 * (0.9 * t).sin(),
            0.1 * (2.3 * t).cos(),
        ],
        ..rotorid_sample_t::default()
    }
}

/// Every single bit flipped in the 16-byte header, of every kind, is refused by every call
/// with `ROTORID_E_NOT_INITIALISED`, changes nothing, and works again once flipped back.
#[test]
fn every_header_bit_flip_is_refused() {
    for kind in KINDS {
        let mut id = Prepared::new(kind);
        assert_eq!(id.step(0), ROTORID_OK);
        let export = id.export();
        for bit in 0..128 {
            id.flip(bit);
            let damaged = id.bytes();
            let h = id.h();
            let s = sample(1);
            let (mut out, mut state, mut k) = (
                rotorid_step_output_t::default(),
                rotorid_state_t::default(),
                0u32,
            );
            let mut buf = vec![0u8; export.len()];
            let mut len = 0usize;
            let sigma = [0.5f32; 3];
            // SAFETY: valid pointers; `h` points to damaged storage, which must be refused.
            let codes = unsafe {
                [
                    rotorid_info(h, &mut k, null_mut(), null_mut()),
                    rotorid_step(h, &s, &mut out, null_mut()),
                    rotorid_resume(h, &s, &mut state, null_mut()),
                    rotorid_predict(h, null(), &s, &mut state, null_mut()),
                    rotorid_export(h, buf.as_mut_ptr(), buf.len(), &mut len, null_mut()),
                    rotorid_import(h, export.as_ptr(), export.len(), null_mut()),
                    rotorid_compensate(h, sigma.as_ptr(), null_mut(), null_mut()),
                    rotorid_reset(h, null_mut()),
                ]
            };
            assert_eq!(
                codes, [ROTORID_E_NOT_INITIALISED; 8],
                "kind {kind}, bit {bit}"
            );
            assert!(
                id.bytes() == damaged,
                "kind {kind}, bit {bit}: storage changed"
            );
            assert_eq!((k, len), (0, 0));
            id.flip(bit);
        }
        assert_eq!(id.step(1), ROTORID_OK);
    }
}

/// A storage copied to another aligned place keeps working there, with the same bits as one
/// that never moved (the header holds no address).
#[test]
fn a_moved_storage_keeps_working() {
    let mut still = Prepared::new(ROTORID_KIND_FLIGHT);
    let mut moved = Prepared::new(ROTORID_KIND_FLIGHT);
    for k in 0..50 {
        assert_eq!(still.step(k), ROTORID_OK);
        assert_eq!(moved.step(k), ROTORID_OK);
    }
    let mut elsewhere = Prepared {
        storage: vec![0u64; moved.storage.len() + 3],
        kind: moved.kind,
    };
    elsewhere.storage.drain(..3);
    elsewhere.storage.copy_from_slice(&moved.storage);
    moved.storage.fill(0);
    for k in 50..100 {
        assert_eq!(still.step(k), ROTORID_OK);
        assert_eq!(elsewhere.step(k), ROTORID_OK);
    }
    assert_eq!(still.export(), elsewhere.export());
}

/// Every single bit flipped anywhere in an export (header, values, CRC) is refused with
/// `ROTORID_E_INCOMPATIBLE`, and the import changes nothing; the intact export imports.
#[test]
fn every_export_bit_flip_is_refused() {
    for kind in [ROTORID_KIND_PAPER_PLAIN, ROTORID_KIND_FLIGHT] {
        let mut id = Prepared::new(kind);
        for k in 0..100 {
            assert_eq!(id.step(k), ROTORID_OK);
        }
        let mut export = id.export();
        let mut target = Prepared::new(kind);
        let before = target.bytes();
        let h = target.h();
        for bit in 0..export.len() * 8 {
            export[bit / 8] ^= 1 << (bit % 8);
            let mut err = rotorid_error_t::default();
            // SAFETY: valid pointers.
            let rc = unsafe { rotorid_import(h, export.as_ptr(), export.len(), &mut err) };
            assert_eq!(rc, ROTORID_E_INCOMPATIBLE, "kind {kind}, bit {bit}");
            assert!(
                target.bytes() == before,
                "kind {kind}, bit {bit}: storage changed"
            );
            export[bit / 8] ^= 1 << (bit % 8);
        }
        // SAFETY: valid pointers.
        let rc = unsafe { rotorid_import(h, export.as_ptr(), export.len(), null_mut()) };
        assert_eq!(rc, ROTORID_OK);
        assert_eq!(target.export(), export);
    }
}

/// A refused call writes none of its outputs (only the error detail).
#[test]
fn refused_calls_leave_outputs_untouched() {
    let mut id = Prepared::new(ROTORID_KIND_FLIGHT);
    assert_eq!(id.step(0), ROTORID_OK);
    let h = id.h();
    let mut bad = sample(1);
    bad.rates[1] = f32::NAN;
    let sentinel = rotorid_state_t {
        velocity: [1.0, 2.0, 3.0],
        rates: [4.0, 5.0, 6.0],
    };
    let mut out = rotorid_step_output_t {
        prediction: sentinel,
        innovation: sentinel,
        has_innovation: 7,
    };
    let mut state = sentinel;
    let mut err = rotorid_error_t::default();
    // SAFETY: valid pointers.
    unsafe {
        assert_eq!(
            rotorid_step(h, &bad, &mut out, &mut err),
            ROTORID_E_NON_FINITE
        );
        assert_eq!((err.quantity, err.index), (ROTORID_QUANTITY_RATE, 1));
        assert_eq!(
            out,
            rotorid_step_output_t {
                prediction: sentinel,
                innovation: sentinel,
                has_innovation: 7
            }
        );
        assert_eq!(
            rotorid_resume(h, &bad, &mut state, null_mut()),
            ROTORID_E_NON_FINITE
        );
        assert_eq!(
            rotorid_predict(h, null(), &bad, &mut state, null_mut()),
            ROTORID_E_NON_FINITE
        );
        assert_eq!(state, sentinel);
        let mut late = sample(100);
        late.time_us += 5_000_000;
        assert_eq!(
            rotorid_step(h, &late, &mut out, &mut err),
            ROTORID_E_TIME_STEP
        );
        assert_eq!(out.has_innovation, 7);
        let mut buf = vec![0x5au8; ROTORID_FLIGHT_EXPORT_SIZE];
        let mut len = 12345usize;
        let rc = rotorid_export(h, buf.as_mut_ptr(), buf.len() - 1, &mut len, null_mut());
        assert_eq!((rc, len), (ROTORID_E_BUFFER_SIZE, 12345));
        assert!(buf.iter().all(|&b| b == 0x5a));
        let sigma = [f32::NAN, 0.0, 0.0];
        let mut count = 99u32;
        let rc = rotorid_compensate(h, sigma.as_ptr(), &mut count, &mut err);
        assert_eq!((rc, count), (ROTORID_E_CONFIG_GYRO_NOISE, 99));
        // On success the detail is not written.
        let mut err = rotorid_error_t {
            code: 77,
            ..Default::default()
        };
        assert_eq!(
            rotorid_info(h, null_mut(), null_mut(), &mut err),
            ROTORID_OK
        );
        assert_eq!(err.code, 77);
    }
}

/// Bad settings give `CONFIG_*` codes, never `OUT_OF_RANGE` with the quantity CONFIG.
/// A quaternion sample (`ROTORID_ATTITUDE_QUATERNION`) steps every kind exactly as the core's
/// quaternion path does, bit for bit; a form that is not a `ROTORID_ATTITUDE_*` and a quaternion
/// off unit norm are refused with their quantity, and change nothing.
#[test]
fn quaternion_samples_step_as_the_core_and_wrong_ones_are_refused() {
    use rotorid::hover::{flight_sets, AnyAttitude, Attitude, HoverSample, Quaternion};
    let mut core =
        rotorid::FlightIdentifier::<f32>::flight(rotorid::HoverConfig::default(), flight_sets())
            .expect("the flight default");
    for kind in KINDS {
        let mut id = Prepared::new(kind);
        for k in 0..60 {
            let mut s = sample(k);
            let q = Quaternion::from_euler(&Attitude {
                roll: s.roll,
                pitch: s.pitch,
                yaw: s.yaw,
            });
            s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
            s.q = q.to_array();
            let mut out = rotorid_step_output_t::default();
            // SAFETY: valid pointers.
            let rc = unsafe { rotorid_step(id.h(), &s, &mut out, null_mut()) };
            assert_eq!(rc, ROTORID_OK, "kind {kind}, sample {k}");
            let taken: HoverSample<f32, AnyAttitude<f32>> =
                HoverSample::try_from(&s).expect("a known form");
            assert_eq!(taken.attitude, AnyAttitude::Quaternion(q));
            if kind == ROTORID_KIND_FLIGHT {
                // The core stepped directly with the same quaternion: the same bits.
                let want =
                    rotorid_step_output_t::from(core.step(&taken.with_attitude(q)).expect("legal"));
                let bits = |o: &rotorid_step_output_t| {
                    let p = o.prediction;
                    [p.velocity, p.rates].map(|v| v.map(f32::to_bits))
                };
                assert_eq!(bits(&out), bits(&want), "sample {k}");
            }
        }
        let before = id.bytes();
        let mut bad = sample(60);
        bad.attitude_form = 7;
        let mut err = rotorid_error_t::default();
        let mut out = rotorid_step_output_t::default();
        // SAFETY: valid pointers.
        let rc = unsafe { rotorid_step(id.h(), &bad, &mut out, &mut err) };
        assert_eq!(
            (rc, err.quantity),
            (ROTORID_E_OUT_OF_RANGE, ROTORID_QUANTITY_ATTITUDE_FORM)
        );
        bad.attitude_form = ROTORID_ATTITUDE_QUATERNION;
        bad.q = [1.02, 0.0, 0.0, 0.0];
        // SAFETY: valid pointers.
        let rc = unsafe { rotorid_step(id.h(), &bad, &mut out, &mut err) };
        assert_eq!(
            (rc, err.quantity, err.index),
            (ROTORID_E_OUT_OF_RANGE, ROTORID_QUANTITY_QUATERNION, 4)
        );
        bad.q = [f32::NAN, 0.0, 0.0, 1.0];
        // SAFETY: valid pointers.
        let rc = unsafe { rotorid_step(id.h(), &bad, &mut out, &mut err) };
        assert_eq!(
            (rc, err.quantity, err.index),
            (ROTORID_E_NON_FINITE, ROTORID_QUANTITY_QUATERNION, 0)
        );
        assert!(
            id.bytes() == before,
            "kind {kind}: a refused sample changed the storage"
        );
    }
}

#[test]
fn configuration_errors_have_config_codes() {
    let mut base = rotorid_config_t::from(rotorid::HoverConfig::<f32>::default());
    // SAFETY: valid pointer.
    assert_eq!(unsafe { rotorid_config_default(&mut base) }, ROTORID_OK);
    type Change = fn(&mut rotorid_config_t);
    let cases: [(Change, i32); 6] = [
        (|c| c.algorithm = 7, ROTORID_E_CONFIG_ALGORITHM),
        (|c| c.scaling = 9, ROTORID_E_CONFIG_SCALING),
        (
            |c| c.initial_covariance = f32::NAN,
            ROTORID_E_CONFIG_INITIAL_COVARIANCE,
        ),
        (|c| c.forgetting = 0.5, ROTORID_E_CONFIG_FORGETTING),
        (|c| c.max_trace = -1.0, ROTORID_E_CONFIG_FORGETTING),
        (
            |c| c.period_tolerance_us = c.sample_period_us,
            ROTORID_E_CONFIG_SAMPLE_PERIOD,
        ),
    ];
    for (i, (change, code)) in cases.into_iter().enumerate() {
        let mut c = base;
        change(&mut c);
        let mut storage = vec![0u64; ROTORID_FLIGHT_STORAGE_SIZE / 8];
        let (mut h, mut err) = (null_mut(), rotorid_error_t::default());
        // SAFETY: valid pointers.
        let rc = unsafe {
            rotorid_init_flight(
                storage.as_mut_ptr().cast(),
                ROTORID_FLIGHT_STORAGE_SIZE,
                &c,
                null(),
                &mut h,
                &mut err,
            )
        };
        assert_eq!((rc, err.code), (code, code), "case {i}");
        assert_ne!(err.quantity, ROTORID_QUANTITY_CONFIG, "case {i}");
        assert!(storage.iter().all(|&w| w == 0), "case {i}: storage written");
    }
    let mut id = Prepared::new(ROTORID_KIND_FLIGHT);
    for sigma in [
        [-1.0f32, 0.0, 0.0],
        [0.0, 2001.0, 0.0],
        [0.0, 0.0, f32::INFINITY],
    ] {
        // SAFETY: valid pointers.
        let rc = unsafe { rotorid_compensate(id.h(), sigma.as_ptr(), null_mut(), null_mut()) };
        assert_eq!(rc, ROTORID_E_CONFIG_GYRO_NOISE);
    }
}

/// `rotorid_compensate_each` is the core's `compensate_each`, bit for bit; with the damping
/// term's choice on every rate it is `rotorid_compensate`; a choice that is not a
/// `ROTORID_COMPENSATION_*` is refused (its rate in `index`) and changes nothing.
#[test]
fn a_compensation_per_rate_is_the_cores_and_a_bad_choice_changes_nothing() {
    use rotorid::hover::GyroCompensation::{Damping, Full};
    // `sample`'s flight with rates that respond to its sticks (damped second-order
    // dynamics: a pure sinusoid would be marginally stable, which the full compensation
    // refuses) and gyro noise: uniform, ±0.3 deg/s, from a xorshift generator.
    let trained = || {
        let mut id = Prepared::new(ROTORID_KIND_FLIGHT);
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let (mut rate, mut before) = ([0.0f32; 3], [0.0f32; 3]);
        for k in 0..3000 {
            let mut s = sample(k);
            let [_, ped, lon, lat] = s.controls;
            for ((w, b), u) in rate.iter_mut().zip(&mut before).zip([lon, ped, lat]) {
                let next = 1.6 * *w - 0.7 * *b + 20.0 * u;
                (*b, *w) = (*w, next);
            }
            for (measured, &w) in s.rates.iter_mut().zip(&rate) {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                *measured = w + 0.6 * ((x >> 40) as f32 / (1u64 << 24) as f32 - 0.5);
            }
            let mut out = rotorid_step_output_t::default();
            // SAFETY: valid pointers.
            let rc = unsafe { rotorid_step(id.h(), &s, &mut out, null_mut()) };
            assert_eq!(rc, ROTORID_OK);
        }
        id
    };
    // The noise's σ: 0.6/√12 deg/s.
    let sigma = [0.17f32; 3];
    let (full, damping) = (ROTORID_COMPENSATION_FULL, ROTORID_COMPENSATION_DAMPING);
    let each = |id: &mut Prepared, how: [u32; 3], err: &mut rotorid_error_t| {
        let mut count = 99u32;
        // SAFETY: valid pointers.
        let rc = unsafe {
            rotorid_compensate_each(id.h(), sigma.as_ptr(), how.as_ptr(), &mut count, err)
        };
        (rc, count)
    };
    let mut err = rotorid_error_t::default();
    let mut mixed = trained();
    let (rc, count) = each(&mut mixed, [full, damping, full], &mut err);
    assert_eq!(rc, ROTORID_OK);
    assert!(count > 0 && count < 99, "{count}");
    let mut core = trained();
    // SAFETY: a handle from rotorid_init.
    let id = unsafe { ident_mut(core.h()) }.unwrap();
    id.compensate_each(&sigma, [Full, Damping, Full]).unwrap();
    assert_eq!(mixed.export(), core.export());

    let mut all_damping = trained();
    assert_eq!(each(&mut all_damping, [damping; 3], &mut err).0, ROTORID_OK);
    let mut plain = trained();
    // SAFETY: valid pointers.
    let rc = unsafe { rotorid_compensate(plain.h(), sigma.as_ptr(), null_mut(), null_mut()) };
    assert_eq!(rc, ROTORID_OK);
    assert_eq!(all_damping.export(), plain.export());
    // The choice matters on this flight (else the checks above could not fail).
    assert!(mixed.export() != all_damping.export());

    let mut refused = trained();
    let before = refused.bytes();
    let (rc, count) = each(&mut refused, [damping, 2, full], &mut err);
    assert_eq!((rc, count), (ROTORID_E_CONFIG_GYRO_COMPENSATION, 99));
    assert_eq!(
        (err.code, err.index),
        (ROTORID_E_CONFIG_GYRO_COMPENSATION, 1)
    );
    assert_eq!(refused.bytes(), before);
    // SAFETY: valid pointers but `how`, which is NULL.
    let rc = unsafe {
        rotorid_compensate_each(refused.h(), sigma.as_ptr(), null(), null_mut(), null_mut())
    };
    assert_eq!(rc, ROTORID_E_NULL);
    assert_eq!(refused.bytes(), before);
}

/// `rotorid_init_flight_per_model`: four times the unscheduled sets is the plain kind bit
/// for bit, four times the defaults is `rotorid_init_flight`; NULL sets and bad sets are
/// refused without writing the storage.
#[test]
fn per_model_sets_init_the_flight_kind_as_its_models_ask() {
    let (mut unscheduled, mut defaults) = Default::default();
    // SAFETY: valid pointers.
    unsafe {
        assert_eq!(
            rotorid_flight_sets_unscheduled(&mut unscheduled),
            ROTORID_OK
        );
        assert_eq!(rotorid_flight_sets_default(&mut defaults), ROTORID_OK);
    }
    for (sets, twin) in [
        ([unscheduled; 4], ROTORID_KIND_FLIGHT_PLAIN),
        ([defaults; 4], ROTORID_KIND_FLIGHT),
    ] {
        let (rc, h, _, _storage) = init_per_model(sets.as_ptr());
        assert_eq!(rc, ROTORID_OK);
        let mut other = Prepared::new(twin);
        for k in 0..200 {
            let (mut a, mut b) = (
                rotorid_step_output_t::default(),
                rotorid_step_output_t::default(),
            );
            // SAFETY: valid pointers.
            unsafe {
                assert_eq!(rotorid_step(h, &sample(k), &mut a, null_mut()), ROTORID_OK);
                assert_eq!(
                    rotorid_step(other.h(), &sample(k), &mut b, null_mut()),
                    ROTORID_OK
                );
            }
            let bits = |o: &rotorid_step_output_t| {
                let p = o.prediction;
                [p.velocity, p.rates].map(|v| v.map(f32::to_bits))
            };
            assert_eq!(bits(&a), bits(&b), "kind {twin}, sample {k}");
        }
    }
    let mut bad = [defaults; 4];
    bad[3].spread[1] = 0.0;
    for (sets, code) in [
        (null(), ROTORID_E_NULL),
        (bad.as_ptr(), ROTORID_E_CONFIG_MEMBERSHIP),
    ] {
        let (rc, h, err, storage) = init_per_model(sets);
        assert_eq!((rc, err.code), (code, code));
        assert!(h.is_null() && storage.iter().all(|&w| w == 0));
    }
}

/// `rotorid_init_flight_per_model` with `sets` (NULL or four) in zeroed storage of its own:
/// the code, the handle, the error and the storage (which the handle points into).
fn init_per_model(
    sets: *const rotorid_flight_sets_t,
) -> (i32, *mut rotorid_ident_t, rotorid_error_t, Vec<u64>) {
    let mut storage = vec![0u64; ROTORID_FLIGHT_STORAGE_SIZE / 8];
    let (mut h, mut err) = (null_mut(), rotorid_error_t::default());
    // SAFETY: aligned storage of the flight kind's size; valid pointers; NULL or four sets.
    let rc = unsafe {
        rotorid_init_flight_per_model(
            storage.as_mut_ptr().cast(),
            ROTORID_FLIGHT_STORAGE_SIZE,
            null(),
            sets,
            &mut h,
            &mut err,
        )
    };
    (rc, h, err, storage)
}

/// `rotorid_init_flight_scheduled`: the speed four times is `rotorid_init_flight_per_model`
/// bit for bit; other speeds build the core's `FlightIdentifier::flight_scheduled` (the
/// record it writes, configuration hash included, is the core's byte for byte, and not the
/// per-model identifier's); a code that is none, the velocity model on the side speed and
/// NULLs are refused without writing the storage.
#[test]
fn scheduled_inits_build_the_cores_scheduled_flight_identifier() {
    use rotorid::hover::{flight_sets, Scheduling};
    use rotorid::{record, FlightIdentifier, HoverConfig};

    use crate::record::{rotorid_record_info_t, rotorid_record_write};

    let mut defaults = rotorid_flight_sets_t::default();
    // SAFETY: a valid pointer.
    assert_eq!(
        unsafe { rotorid_flight_sets_default(&mut defaults) },
        ROTORID_OK
    );
    let sets = [defaults; 4];
    let (rc, h, _, _storage) = init_scheduled(sets.as_ptr(), [ROTORID_SCHEDULE_SPEED; 4].as_ptr());
    assert_eq!(rc, ROTORID_OK);
    let (rc, twin, _, _twin_storage) = init_per_model(sets.as_ptr());
    assert_eq!(rc, ROTORID_OK);
    for k in 0..200 {
        let (mut a, mut b) = Default::default();
        // SAFETY: valid pointers.
        unsafe {
            assert_eq!(rotorid_step(h, &sample(k), &mut a, null_mut()), ROTORID_OK);
            assert_eq!(
                rotorid_step(twin, &sample(k), &mut b, null_mut()),
                ROTORID_OK
            );
        }
        let bits = |o: &rotorid_step_output_t| {
            let p = o.prediction;
            [p.velocity, p.rates].map(|v| v.map(f32::to_bits))
        };
        assert_eq!(bits(&a), bits(&b), "sample {k}");
    }

    let codes = [
        ROTORID_SCHEDULE_VERTICAL_SPEED,
        ROTORID_SCHEDULE_SIDE_SPEED,
        ROTORID_SCHEDULE_SPEED,
        ROTORID_SCHEDULE_VERTICAL_SPEED,
    ];
    let (rc, h, _, _storage) = init_scheduled(sets.as_ptr(), codes.as_ptr());
    assert_eq!(rc, ROTORID_OK);
    let mut from_c = vec![0u8; 8192];
    let mut info = rotorid_record_info_t::default();
    // SAFETY: a handle from an init; both slots erased (NULL); a buffer of its length.
    let rc = unsafe {
        rotorid_record_write(
            h,
            null(),
            0,
            null(),
            0,
            from_c.as_mut_ptr(),
            from_c.len(),
            &mut info,
            null_mut(),
        )
    };
    assert_eq!(rc, ROTORID_OK);
    from_c.truncate(info.length);
    let core_record = |id: FlightIdentifier<f32>| {
        let mut out = vec![0u8; 8192];
        let n = record::encode(&id, ROTORID_KIND_FLIGHT, info.sequence, &mut out).unwrap();
        out.truncate(n);
        out
    };
    let config = HoverConfig::default();
    let on = [
        Scheduling::VerticalSpeed,
        Scheduling::SideSpeed,
        Scheduling::Speed,
        Scheduling::VerticalSpeed,
    ];
    let scheduled =
        FlightIdentifier::flight_scheduled(config, core::array::from_fn(|_| flight_sets()), on)
            .unwrap();
    assert_eq!(from_c, core_record(scheduled));
    let per_model =
        FlightIdentifier::flight_per_model(config, core::array::from_fn(|_| flight_sets()))
            .unwrap();
    assert_ne!(from_c, core_record(per_model));

    let mut velocity_sideways = codes;
    velocity_sideways[0] = ROTORID_SCHEDULE_SIDE_SPEED;
    let mut unknown = codes;
    unknown[3] = 3;
    for (sets, codes, code) in [
        (null(), codes.as_ptr(), ROTORID_E_NULL),
        (sets.as_ptr(), null(), ROTORID_E_NULL),
        (sets.as_ptr(), unknown.as_ptr(), ROTORID_E_ARGUMENT),
        (
            sets.as_ptr(),
            velocity_sideways.as_ptr(),
            ROTORID_E_CONFIG_DIMENSIONS,
        ),
    ] {
        let (rc, h, err, storage) = init_scheduled(sets, codes);
        assert_eq!((rc, err.code), (code, code));
        assert!(h.is_null() && storage.iter().all(|&w| w == 0));
    }
}

/// `rotorid_init_flight_scheduled` with `sets` and `schedules` (NULL or four each) in zeroed
/// storage of its own: the code, the handle, the error and the storage.
fn init_scheduled(
    sets: *const rotorid_flight_sets_t,
    schedules: *const u32,
) -> (i32, *mut rotorid_ident_t, rotorid_error_t, Vec<u64>) {
    let mut storage = vec![0u64; ROTORID_FLIGHT_STORAGE_SIZE / 8];
    let (mut h, mut err) = (null_mut(), rotorid_error_t::default());
    // SAFETY: aligned storage of the flight kind's size; valid pointers; NULL or four each.
    let rc = unsafe {
        rotorid_init_flight_scheduled(
            storage.as_mut_ptr().cast(),
            ROTORID_FLIGHT_STORAGE_SIZE,
            null(),
            sets,
            schedules,
            &mut h,
            &mut err,
        )
    };
    (rc, h, err, storage)
}

/// The worked example of `docs/c-interface.md` ("The export format"): the export of a
/// `ROTORID_KIND_PAPER_PLAIN` identifier after 20 samples, as a hex dump with the fields
/// named. The section between its markers must be what this test prints; regenerate it with
/// `ROTORID_BLESS=1 cargo test --manifest-path core/ffi/Cargo.toml export_format_example`.
#[test]
fn export_format_example() {
    let mut id = Prepared::new(ROTORID_KIND_PAPER_PLAIN);
    for k in 0..20 {
        assert_eq!(id.step(k), ROTORID_OK);
    }
    let bytes = id.export();
    let mut text = String::from(
        "```text\n\
         offset  bytes (hex)                  field\n",
    );
    let word =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let hex = |at: usize, n: usize| -> String {
        bytes[at..at + n]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut line = |at: usize, n: usize, what: String| {
        text.push_str(&format!("{at:>6}  {:<27}  {what}\n", hex(at, n)));
    };
    line(0, 4, String::from("magic \"RIDX\""));
    line(4, 4, format!("format version {}", word(4)));
    line(8, 4, format!("kind {} (ROTORID_KIND_PAPER_PLAIN)", word(8)));
    // The sizes from the core: an estimator is algorithm, updates, θ (N), then the packed
    // factor (N(N+1)/2, column by column: entry (i, j), i ≤ j; U-D: D on the diagonal).
    let mut at = 12;
    let models = ["velocity", "q̂", "r̂", "p̂"];
    let sizes = paper_plain_sizes();
    for (model, n) in models.iter().zip(sizes) {
        let ud = word(at) == 1;
        line(
            at,
            4,
            format!("{model}: algorithm {} (0 covariance, 1 U-D)", word(at)),
        );
        line(at + 4, 4, format!("{model}: updates {}", word(at + 4)));
        at += 8;
        for i in 0..n {
            line(
                at,
                4,
                format!("{model}: θ[{i}] = {:e}", f32::from_bits(word(at))),
            );
            at += 4;
        }
        for j in 0..n {
            for i in 0..=j {
                let name = match (ud, i == j) {
                    (true, true) => format!("D_{j}"),
                    (true, false) => format!("U_{i}{j}"),
                    (false, _) => format!("P_{i}{j}"),
                };
                let value = f32::from_bits(word(at));
                line(at, 4, format!("{model}: {name} = {value:e}"));
                at += 4;
            }
        }
    }
    line(
        at,
        4,
        format!("CRC-32 of bytes 0..{at}: 0x{:08x}", word(at)),
    );
    assert_eq!(at + 4, bytes.len());
    text.push_str("```\n");
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/c-interface.md");
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    let (begin, end) = (
        "<!-- export example: begin -->\n",
        "<!-- export example: end -->",
    );
    let (Some(b), Some(e)) = (doc.find(begin), doc.find(end)) else {
        panic!("docs/c-interface.md has no export example markers");
    };
    let current = &doc[b + begin.len()..e];
    if std::env::var_os("ROTORID_BLESS").is_some() {
        let new = format!("{}{text}{}", &doc[..b + begin.len()], &doc[e..]);
        std::fs::write(path, new).unwrap();
    } else {
        assert!(
            current == text,
            "docs/c-interface.md's export example is stale: ROTORID_BLESS=1 cargo test \
             --manifest-path core/ffi/Cargo.toml export_format_example\n{text}"
        );
    }
}

/// N of each model of the paper's plain identifier, from the core.
fn paper_plain_sizes() -> [usize; 4] {
    let id =
        rotorid::PaperPlainIdentifier::<f32>::paper_plain(rotorid::HoverConfig::default()).unwrap();
    let mut n = [0usize; 4];
    id.for_each_rls(|m, _, v| n[usize::from(m.index())] = v.len());
    n
}
