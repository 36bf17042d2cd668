//! Identifiers in caller-provided storage: the layout, the `rotorid_init*` calls that prepare
//! it, and the checked way back from a handle to the identifier.
//!
//! Storage layout: a 16-byte header, then the core's `HoverIdentifier`, as one `repr(C)`
//! struct. The handle the caller gets back is the storage's address.
//!
//! The header holds no address, only words that every call checks before it trusts anything
//! else: a magic word, the kind code, the layout version and a check word (the CRC-32 of the
//! other three and of the kind's storage size). The check word of each kind is a constant
//! (`CHECKS`, computed at compile time), so the check costs four comparisons; a damaged
//! header (any single bit, and all but a 2⁻³² share of other damage) returns
//! `ROTORID_E_NOT_INITIALISED`, never a call into a wrong identifier.
//!
//! Dispatch is by the checked kind, through a table in the library's own memory (`VIEWS`)
//! that each kind's init fills with that kind's view function: a firmware that calls only
//! `rotorid_init_flight` still links the flight identifier's code only, and a kind whose init
//! never ran in this program is refused (`NOT_INITIALISED`) even with an intact header.
//! That view is a table of every method of the kind, so the full init links them all; the
//! lean init (`crate::lean`) registers none and only sets the kind's bit in `PREPARED`, which
//! the lean calls check instead (with the same header checks, `typed_mut`).
//!
//! Because the storage holds no address (neither into itself nor into code), a prepared
//! storage may be moved (copied to another suitably aligned place, the old copy no longer
//! used) and keeps working at its new address. It must not be saved and reloaded by another
//! build of the library: the identifier's layout is the compiler's, and only the layout
//! version (not the build) is checked. Warm starts across builds or flights go through
//! `rotorid_export` / `rotorid_import`.

use core::mem::{align_of, size_of};
use core::sync::atomic::{AtomicPtr, AtomicU32, Ordering};

use rotorid::hover::AnyAttitude;
use rotorid::{
    DynIdentifier, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier,
    FlightIdentifier, FlightPlainIdentifier, HoverConfig, PaperFuzzyIdentifier,
    PaperLocalIdentifier, PaperPlainIdentifier,
};

use crate::error::*;
use crate::kinds::*;
use crate::ptr::get;
use crate::types::*;

/// An identifier in caller-provided storage (opaque; the storage's address).
pub struct rotorid_ident_t {
    _private: [u8; 0],
}

/// Written by `rotorid_init*` at the start of the storage: "RDI2" (2: the header without a
/// function pointer).
const MAGIC: u32 = u32::from_le_bytes(*b"RDI2");

/// Version of the storage layout (header and identifiers); raised whenever either changes.
pub const ROTORID_LAYOUT_VERSION: u32 = 2;

/// The start of every prepared storage. Aligned to 8 so that the identifier starts at the
/// same offset (16) on every target, whatever its own alignment: the storage sizes of `kinds`
/// are then the same on the host and the MCU.
#[repr(C, align(8))]
#[derive(Copy, Clone, PartialEq, Eq)]
pub(crate) struct Header {
    magic: u32,
    kind: u32,
    layout: u32,
    /// [`check_word`] of the three words above.
    check: u32,
}

/// The header checksum: CRC-32 (IEEE, as `crate::crc32`) over magic, kind, layout version
/// and the kind's storage size, all little-endian. A single flipped bit anywhere in the
/// header changes either a checked constant or this word's relation to them.
const fn check_word(kind: u32, storage_size: usize) -> u32 {
    let [m0, m1, m2, m3] = MAGIC.to_le_bytes();
    let [k0, k1, k2, k3] = kind.to_le_bytes();
    let [l0, l1, l2, l3] = ROTORID_LAYOUT_VERSION.to_le_bytes();
    let [s0, s1, s2, s3] = (storage_size as u32).to_le_bytes();
    crate::export::CRC32.checksum(&[
        m0, m1, m2, m3, k0, k1, k2, k3, l0, l1, l2, l3, s0, s1, s2, s3,
    ])
}

/// Kinds are 1..=`KINDS`.
const KINDS: usize = 8;

/// The check word of each kind code (index 0 unused), computed at compile time (an index out
/// of range would fail the build, not a call).
#[allow(clippy::indexing_slicing)]
const CHECKS: [u32; KINDS + 1] = {
    let mut c = [0u32; KINDS + 1];
    let mut k = 1;
    while k <= KINDS {
        c[k] = check_word(k as u32, storage_size_of(k as u32));
        k += 1;
    }
    c
};

/// The storage size of a kind code, as a constant expression (0 for an unknown code).
const fn storage_size_of(kind: u32) -> usize {
    for_kind!(kind, I => size_of::<Slot<I>>(), _ => 0)
}

/// The view function of each kind, filled by that kind's init (null until then).
static VIEWS: [AtomicPtr<()>; KINDS + 1] =
    [const { AtomicPtr::new(core::ptr::null_mut()) }; KINDS + 1];

/// Bit `k` set: an init of kind `k` (full or lean) ran in this program. The lean calls check
/// it instead of [`VIEWS`], which only the full init fills (filling it links every method).
static PREPARED: AtomicU32 = AtomicU32::new(0);

/// What each kind stores in [`VIEWS`].
type ViewFn = unsafe fn(*mut Header) -> *mut AnyKind;

/// What the storage holds.
#[repr(C)]
pub(crate) struct Slot<I> {
    header: Header,
    ident: I,
}

/// The view function of kind `I`.
///
/// # Safety
/// `h` points to a `Slot<I>`.
unsafe fn view<I: DynIdentifier<AnyAttitude<f32>> + 'static>(h: *mut Header) -> *mut AnyKind {
    // SAFETY: the caller's contract.
    unsafe { core::ptr::addr_of_mut!((*h.cast::<Slot<I>>()).ident) }
}

/// Records kind `kind`'s view function (idempotent: the same function every time).
fn register<I: DynIdentifier<AnyAttitude<f32>> + 'static>(kind: u32) {
    let f: ViewFn = view::<I>;
    if let Some(slot) = VIEWS.get(kind as usize) {
        slot.store(f as *mut (), Ordering::Release);
    }
}

/// The view function registered for `kind`, if its init ran.
fn registered(kind: u32) -> Option<ViewFn> {
    let p = VIEWS.get(kind as usize)?.load(Ordering::Acquire);
    if p.is_null() {
        return None;
    }
    // SAFETY: the only non-null values stored in VIEWS are `ViewFn`s (`register`), and a
    // function pointer round-trips through a data pointer on every target Rust supports.
    Some(unsafe { core::mem::transmute::<*mut (), ViewFn>(p) })
}

/// Prepares an identifier of type `I` (kind code `kind`) in `storage` for every call: the
/// body of every full `rotorid_init*` ([`prepare`], then the kind's view for the generic
/// calls, which links every method of the kind).
///
/// # Safety
/// As `rotorid_init`.
unsafe fn init<I: Build + DynIdentifier<AnyAttitude<f32>> + 'static>(
    kind: u32,
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: Sets<'_>,
    handle: *mut *mut rotorid_ident_t,
) -> Result<(), rotorid_error_t> {
    // SAFETY: the caller's contract.
    unsafe { prepare::<I>(kind, storage, storage_size, config, sets, handle) }?;
    register::<I>(kind);
    Ok(())
}

/// Prepares an identifier of type `I` (kind code `kind`) in `storage` for the lean calls of
/// its kind (`crate::lean`): the storage and its header, and the kind's bit in [`PREPARED`];
/// no view (that is [`init`]'s). Never inlined: each kind gets its own stack frame, so that a
/// call pays for its own kind only.
///
/// # Safety
/// As `rotorid_init`.
#[inline(never)]
pub(crate) unsafe fn prepare<I: Build + 'static>(
    kind: u32,
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: Sets<'_>,
    handle: *mut *mut rotorid_ident_t,
) -> Result<(), rotorid_error_t> {
    let storage = storage.cast::<u8>();
    if storage.is_null() || handle.is_null() {
        return Err(rotorid_error_t::interface(ROTORID_E_NULL));
    }
    if !(storage as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
        return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
    }
    if storage_size < size_of::<Slot<I>>() {
        return Err(rotorid_error_t::interface(ROTORID_E_STORAGE_SIZE));
    }
    if !matches!(sets, Sets::Default) && kind != ROTORID_KIND_FLIGHT {
        return Err(rotorid_error_t::interface(ROTORID_E_ARGUMENT));
    }
    let config = if config.is_null() {
        HoverConfig::default()
    } else {
        // SAFETY: not NULL, and valid by the caller's contract.
        HoverConfig::try_from(&unsafe { get(config)? })?
    };
    let slot = storage.cast::<Slot<I>>();
    // SAFETY: `storage` is aligned and holds a `Slot<I>` (checked above), and the caller gave
    // it to the identifier; `sets` is NULL or valid; `handle` is not NULL. The identifier is
    // built in place (written only once it is built: on an error the storage is untouched),
    // then its header.
    unsafe {
        I::build_into(config, sets, core::ptr::addr_of_mut!((*slot).ident))?;
        core::ptr::addr_of_mut!((*slot).header).write(Header {
            magic: MAGIC,
            kind,
            layout: ROTORID_LAYOUT_VERSION,
            // The compile-time constant (a CRC at run time would bring its table along).
            check: CHECKS.get(kind as usize).copied().unwrap_or(0),
        });
        handle.write(storage.cast());
    }
    PREPARED.fetch_or(1u32.checked_shl(kind).unwrap_or(0), Ordering::Release);
    Ok(())
}

/// Prepares an identifier of `kind` (`ROTORID_KIND_*`) in `storage` and writes its handle to
/// `*handle`. This call links the code of every kind; `rotorid_init_<kind>` links one.
///
/// Required: `storage` (at least `rotorid_storage_size(kind)` bytes, given in `storage_size`,
/// aligned to `ROTORID_STORAGE_ALIGN`, used for nothing else while the identifier lives;
/// calling an init again on it starts afresh), `handle`. Optional (NULL allowed): `config`
/// (NULL: `rotorid_config_default`), `sets` (the speed sets of `ROTORID_KIND_FLIGHT`;
/// NULL: the defaults; must be NULL for every other kind), `error` (NULL: no detail).
///
/// Codes: OK; NULL, MISALIGNED, STORAGE_SIZE, KIND, ARGUMENT; CONFIG_ALGORITHM,
/// CONFIG_SCALING, CONFIG_INITIAL_COVARIANCE, CONFIG_FORGETTING, CONFIG_SAMPLE_PERIOD,
/// CONFIG_MEMBERSHIP (sets). On success: the storage and `*handle` are written. On an error:
/// only `*error` (when given); the storage and `*handle` are not written.
///
/// The identifier is built in place; the storage holds no address (it may be moved, not
/// saved across builds: see `docs/c-interface.md`). Stack and flash per kind: the size table
/// of `docs/c-interface.md`, measured by `core/ffi/tests/c_interface.rs`:
///
/// | kind | storage (B) | export (B) | stack (B) | firmware text (B) |
/// |---|---|---|---|---|
/// | `ROTORID_KIND_FLIGHT` (the flight default) | 2 984 | 1 900 | 4 292 | 54 534 |
/// | `ROTORID_KIND_FLIGHT_PLAIN` | 1 664 | 644 | 3 324 | 53 598 |
/// | `ROTORID_KIND_PAPER_FUZZY` | 11 280 | 10 524 | 12 780 | 55 262 |
/// | `ROTORID_KIND_PAPER_PLAIN` | 880 | 128 | 2 584 | 47 022 |
/// | `ROTORID_KIND_EXTENDED_FUZZY` | 27 248 | 26 436 | not measured (see below) |  |
/// | `ROTORID_KIND_EXTENDED_PLAIN` | 1 240 | 428 | 3 144 | 49 422 |
/// | `ROTORID_KIND_PAPER_LOCAL` | 3 104 | 1 780 | 5 580 | 55 406 |
/// | `ROTORID_KIND_EXTENDED_LOCAL` | 4 872 | 3 628 | 5 964 | 56 678 |
/// | `ROTORID_KIND_FLIGHT` through `rotorid_init_flight_scheduled` | 2 984 | 1 900 | 4 708 | 54 734 |
///
/// # Safety
/// `storage` is NULL or valid for writes of `storage_size` bytes; `config` and `sets` are
/// NULL or valid for reads; `handle` and `error` are NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    kind: u32,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    let result = for_kind!(kind, I => unsafe { init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle) },
        _ => Err(rotorid_error_t::interface(ROTORID_E_KIND)));
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

// The eight `rotorid_init_<kind>` below are written out, not generated by a macro: cbindgen
// reads the source as written (expanding macros needs a nightly compiler), and each is one
// call of `init::<I>`.

/// `rotorid_init` for `ROTORID_KIND_FLIGHT`, linking that kind only. `sets`: NULL for the
/// defaults (`rotorid_flight_sets_default`). Every `rotorid_init_<kind>` takes the same
/// arguments, pointers and codes as `rotorid_init` (but KIND); `sets` must be NULL for the
/// kinds without premise sets of their own.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_flight(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::FlightIdentifier<f32>;
    let kind = ROTORID_KIND_FLIGHT;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init_flight` with speed sets of its own for each of the four models: `sets`
/// points to an array of four, in the order velocity, q̂, r̂, p̂
/// (`rotorid::FlightIdentifier::flight_per_model`). A model whose sets are
/// `rotorid_flight_sets_unscheduled` has one rule in effect: what `rotorid identify`'s
/// `flight selected` names `p: rules` (those sets in its `params-*.json`). `sets` is required
/// (NULL: `ROTORID_E_NULL`); the other arguments, pointers and codes as `rotorid_init`.
///
/// # Safety
/// As `rotorid_init`, and `sets` is NULL or valid for reads of four `rotorid_flight_sets_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_flight_per_model(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::FlightIdentifier<f32>;
    let kind = ROTORID_KIND_FLIGHT;
    // SAFETY: the caller's contract: four sets where `sets` points.
    let Some(each) = (unsafe { sets.cast::<[rotorid_flight_sets_t; 4]>().as_ref() }) else {
        // SAFETY: the caller's contract.
        return unsafe { report(Err(rotorid_error_t::interface(ROTORID_E_NULL)), error) };
    };
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(
                kind,
                storage,
                storage_size,
                config,
                Sets::PerModel(each),
                handle,
            ),
            error,
        )
    }
}

/// `rotorid_init_flight_per_model` with each model's three sets on the speed `schedules`
/// names for it: four `ROTORID_SCHEDULE_*` codes in the same order (velocity, q̂, r̂, p̂),
/// `rotorid::FlightIdentifier::flight_scheduled`. What `rotorid identify`'s `flight selected`
/// flies when it moves a model's rules to another speed (`r: rules on the side speed` in its
/// verdict; in `params-flight-selected.json` the premise variable that carries a model's sets
/// names its speed, see `docs/c-interface.md`). With `ROTORID_SCHEDULE_SPEED` four times it
/// is `rotorid_init_flight_per_model`, bit for bit; a firmware that never calls it links
/// none of its choice.
///
/// Required: `storage`, `sets` (four), `schedules` (four), `handle` (NULL: `ROTORID_E_NULL`).
/// Codes: those of `rotorid_init_flight_per_model`, and ARGUMENT for a code that is not a
/// `ROTORID_SCHEDULE_*`, CONFIG_DIMENSIONS for the velocity model on
/// `ROTORID_SCHEDULE_SIDE_SPEED` (its premise has no side speed).
///
/// # Safety
/// As `rotorid_init_flight_per_model`, and `schedules` is NULL or valid for reads of four
/// `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_flight_scheduled(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    schedules: *const u32,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    let kind = ROTORID_KIND_FLIGHT;
    // SAFETY: the caller's contract: four sets where `sets` points, four codes where
    // `schedules` does.
    let (each, codes) = unsafe {
        (
            sets.cast::<[rotorid_flight_sets_t; 4]>().as_ref(),
            schedules.cast::<[u32; 4]>().as_ref(),
        )
    };
    let result = match (each, codes.map(scheduling)) {
        (Some(each), Some(Some(on))) => {
            // `ScheduledFlight` is the flight kind's identifier built by `flight_scheduled`
            // (the storage holds a `FlightIdentifier`; every other call takes it as one).
            // SAFETY: the caller's contract.
            let prepared = unsafe {
                prepare::<ScheduledFlight>(
                    kind,
                    storage,
                    storage_size,
                    config,
                    Sets::Scheduled(each, on),
                    handle,
                )
            };
            prepared.map(|()| register::<rotorid::FlightIdentifier<f32>>(kind))
        }
        (Some(_), Some(None)) => Err(rotorid_error_t::interface(ROTORID_E_ARGUMENT)),
        _ => Err(rotorid_error_t::interface(ROTORID_E_NULL)),
    };
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// `rotorid_init` for `ROTORID_KIND_FLIGHT_PLAIN`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_flight_plain(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::FlightPlainIdentifier<f32>;
    let kind = ROTORID_KIND_FLIGHT_PLAIN;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_PAPER_FUZZY`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_paper_fuzzy(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::PaperFuzzyIdentifier<f32>;
    let kind = ROTORID_KIND_PAPER_FUZZY;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_PAPER_PLAIN`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_paper_plain(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::PaperPlainIdentifier<f32>;
    let kind = ROTORID_KIND_PAPER_PLAIN;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_EXTENDED_FUZZY`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_extended_fuzzy(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::ExtendedFuzzyIdentifier<f32>;
    let kind = ROTORID_KIND_EXTENDED_FUZZY;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_EXTENDED_PLAIN`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_extended_plain(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::ExtendedPlainIdentifier<f32>;
    let kind = ROTORID_KIND_EXTENDED_PLAIN;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_PAPER_LOCAL`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_paper_local(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::PaperLocalIdentifier<f32>;
    let kind = ROTORID_KIND_PAPER_LOCAL;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// `rotorid_init` for `ROTORID_KIND_EXTENDED_LOCAL`, linking that kind only.
///
/// # Safety
/// As `rotorid_init`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_init_extended_local(
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
    handle: *mut *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    type I = rotorid::ExtendedLocalIdentifier<f32>;
    let kind = ROTORID_KIND_EXTENDED_LOCAL;
    // SAFETY: the caller's contract.
    unsafe {
        report(
            init::<I>(kind, storage, storage_size, config, Sets::of(sets), handle),
            error,
        )
    }
}

/// Checks a handle's pointer and header; returns the kind and its view function.
///
/// # Safety
/// `h` is NULL or points to at least `size_of::<Header>()` readable bytes, and, when they
/// hold a header that passes the checks below, to storage that `rotorid_init*` prepared (and
/// that only the library wrote since, or that was moved as the module docs allow).
unsafe fn header(h: *const rotorid_ident_t) -> Result<(u32, ViewFn), rotorid_error_t> {
    let p = h.cast::<Header>();
    if p.is_null() {
        return Err(rotorid_error_t::interface(ROTORID_E_NULL));
    }
    if !(p as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
        return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
    }
    // SAFETY: aligned and readable by the caller's contract; every word is checked before
    // anything else is trusted.
    let hd = unsafe { p.read() };
    let expected = CHECKS.get(hd.kind as usize).copied().unwrap_or(0);
    let intact = hd.magic == MAGIC
        && hd.layout == ROTORID_LAYOUT_VERSION
        && hd.kind != 0
        && hd.check == expected;
    let not_initialised = rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED);
    if !intact {
        return Err(not_initialised);
    }
    let view = registered(hd.kind).ok_or(not_initialised)?;
    Ok((hd.kind, view))
}

/// The identifier of type `I` (kind code `kind`) behind a handle, for the lean calls: the
/// same checks as [`header`] (a damaged header is `NOT_INITIALISED`), then the kind must be
/// `kind` (an intact header of another kind: `ROTORID_E_KIND`) and an init of it must have run
/// in this program (full or lean). Reads no table of code pointers: nothing but the caller's
/// own call is linked.
///
/// # Safety
/// As [`header`], `I` is kind `kind`'s type, and nothing else refers to the storage during
/// the call.
pub(crate) unsafe fn typed_mut<'a, I>(
    h: *mut rotorid_ident_t,
    kind: u32,
) -> Result<&'a mut I, rotorid_error_t> {
    let p = h.cast::<Header>();
    if p.is_null() {
        return Err(rotorid_error_t::interface(ROTORID_E_NULL));
    }
    if !(p as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
        return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
    }
    // SAFETY: aligned and readable by the caller's contract; checked before it is trusted.
    let hd = unsafe { p.read() };
    let intact = hd.magic == MAGIC
        && hd.layout == ROTORID_LAYOUT_VERSION
        && hd.kind != 0
        && hd.check == CHECKS.get(hd.kind as usize).copied().unwrap_or(0);
    if !intact {
        return Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED));
    }
    if hd.kind != kind {
        return Err(rotorid_error_t::interface(ROTORID_E_KIND));
    }
    let prepared = PREPARED.load(Ordering::Acquire);
    if prepared & 1u32.checked_shl(kind).unwrap_or(0) == 0 {
        return Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED));
    }
    // SAFETY: the header is intact and of kind `kind`, whose init ran in this program: the
    // storage is a `Slot<I>` (the caller's contract ties `I` to `kind`).
    Ok(unsafe { &mut *core::ptr::addr_of_mut!((*p.cast::<Slot<I>>()).ident) })
}

/// The kind code behind a handle, after checking it.
///
/// # Safety
/// As [`header`].
pub(crate) unsafe fn kind_of(h: *const rotorid_ident_t) -> Result<u32, rotorid_error_t> {
    // SAFETY: the caller's contract.
    unsafe { header(h) }.map(|(kind, _)| kind)
}

/// The identifier behind a handle, after checking it.
///
/// # Safety
/// As [`header`].
pub(crate) unsafe fn ident<'a>(h: *const rotorid_ident_t) -> Result<&'a AnyKind, rotorid_error_t> {
    // SAFETY: the caller's contract; `view` is the one registered for the checked kind.
    unsafe {
        let (_, view) = header(h)?;
        Ok(&*view(h.cast::<Header>().cast_mut()))
    }
}

/// As [`ident`], mutably.
///
/// # Safety
/// As [`header`], and nothing else refers to the storage during the call.
pub(crate) unsafe fn ident_mut<'a>(
    h: *mut rotorid_ident_t,
) -> Result<&'a mut AnyKind, rotorid_error_t> {
    // SAFETY: as in `ident`.
    unsafe {
        let (_, view) = header(h)?;
        Ok(&mut *view(h.cast::<Header>()))
    }
}

/// The documented sizes are the real ones (checked at compile time, on every target).
const _: () = {
    macro_rules! check {
        ($I:ty, $storage:expr, $export:expr) => {
            assert!(size_of::<Slot<$I>>() == $storage);
            assert!(align_of::<Slot<$I>>() <= ROTORID_STORAGE_ALIGN);
            assert!(<$I as ExportSize>::EXPORT_SIZE == $export);
        };
    }
    check!(
        FlightIdentifier<f32>,
        ROTORID_FLIGHT_STORAGE_SIZE,
        ROTORID_FLIGHT_EXPORT_SIZE
    );
    check!(
        FlightPlainIdentifier<f32>,
        ROTORID_FLIGHT_PLAIN_STORAGE_SIZE,
        ROTORID_FLIGHT_PLAIN_EXPORT_SIZE
    );
    check!(
        PaperFuzzyIdentifier<f32>,
        ROTORID_PAPER_FUZZY_STORAGE_SIZE,
        ROTORID_PAPER_FUZZY_EXPORT_SIZE
    );
    check!(
        PaperPlainIdentifier<f32>,
        ROTORID_PAPER_PLAIN_STORAGE_SIZE,
        ROTORID_PAPER_PLAIN_EXPORT_SIZE
    );
    check!(
        ExtendedFuzzyIdentifier<f32>,
        ROTORID_EXTENDED_FUZZY_STORAGE_SIZE,
        ROTORID_EXTENDED_FUZZY_EXPORT_SIZE
    );
    check!(
        ExtendedPlainIdentifier<f32>,
        ROTORID_EXTENDED_PLAIN_STORAGE_SIZE,
        ROTORID_EXTENDED_PLAIN_EXPORT_SIZE
    );
    check!(
        PaperLocalIdentifier<f32>,
        ROTORID_PAPER_LOCAL_STORAGE_SIZE,
        ROTORID_PAPER_LOCAL_EXPORT_SIZE
    );
    check!(
        ExtendedLocalIdentifier<f32>,
        ROTORID_EXTENDED_LOCAL_STORAGE_SIZE,
        ROTORID_EXTENDED_LOCAL_EXPORT_SIZE
    );
};

/// Storage bytes an identifier of `kind` needs (0 for an unknown kind).
#[no_mangle]
pub extern "C" fn rotorid_storage_size(kind: u32) -> usize {
    for_kind!(kind, I => size_of::<Slot<I>>(), _ => 0)
}
