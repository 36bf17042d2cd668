//! Identifiers in caller-provided storage: the layout, the `rotorid_init*` calls that prepare
//! it, and the checked way back from a handle to the identifier.
//!
//! Storage layout: a header (tag word, kind code, and the function that views the rest as the
//! kind's identifier), then the core's `HoverIdentifier`, as one `repr(C)` struct. The handle
//! the caller gets back is the storage's address. Because each kind's init stores its own view
//! function, every later call reaches the identifier without a match over all kinds: a
//! firmware that calls only `rotorid_init_flight` links the flight identifier's code only.

use core::mem::size_of;

use rotorid::HoverConfig;

use crate::error::*;
use crate::kinds::*;
use crate::types::*;

/// An identifier in caller-provided storage (opaque; the storage's address).
pub struct rotorid_ident_t {
    _private: [u8; 0],
}

/// Written by `rotorid_init*` at the start of the storage: "RDI1".
const TAG: u32 = u32::from_le_bytes(*b"RDI1");

/// The start of every prepared storage. Aligned to 8 so that the identifier starts at the
/// same offset (16) on every target, whatever its own alignment and the size of a function
/// pointer: the storage sizes of `kinds` are then the same on the host and the MCU.
#[repr(C, align(8))]
pub(crate) struct Header {
    tag: u32,
    kind: u32,
    /// The identifier behind this header, as a trait object.
    view: unsafe fn(*mut Header) -> *mut dyn Ident,
}

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
unsafe fn view<I: Ident + 'static>(h: *mut Header) -> *mut dyn Ident {
    // SAFETY: the caller's contract.
    unsafe { core::ptr::addr_of_mut!((*h.cast::<Slot<I>>()).ident) }
}

/// Reads `*p`, or reports `ROTORID_E_NULL`.
///
/// # Safety
/// `p` is NULL or valid for one read of a `T`.
pub(crate) unsafe fn get<T: Copy>(p: *const T) -> Result<T, rotorid_error_t> {
    // SAFETY: the caller's contract.
    unsafe { p.as_ref() }
        .copied()
        .ok_or(rotorid_error_t::interface(ROTORID_E_NULL))
}

/// Writes `value` to `out`, or reports `ROTORID_E_NULL`.
///
/// # Safety
/// `out` is NULL or valid for one write of a `T`.
pub(crate) unsafe fn put<T>(out: *mut T, value: T) -> Result<(), rotorid_error_t> {
    // SAFETY: the caller's contract.
    match unsafe { out.as_mut() } {
        Some(out) => {
            *out = value;
            Ok(())
        }
        None => Err(rotorid_error_t::interface(ROTORID_E_NULL)),
    }
}

/// Prepares an identifier of type `I` (kind code `kind`) in `storage`: the body of every
/// `rotorid_init*`. Never inlined: each kind gets its own stack frame, so that a call pays for
/// its own kind only.
///
/// # Safety
/// As `rotorid_init`.
#[inline(never)]
unsafe fn init<I: Build + Ident + 'static>(
    kind: u32,
    storage: *mut core::ffi::c_void,
    storage_size: usize,
    config: *const rotorid_config_t,
    sets: *const rotorid_flight_sets_t,
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
    if !sets.is_null() && kind != ROTORID_KIND_FLIGHT {
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
        I::build_into(
            config,
            sets.as_ref(),
            core::ptr::addr_of_mut!((*slot).ident),
        )?;
        core::ptr::addr_of_mut!((*slot).header).write(Header {
            tag: TAG,
            kind,
            view: view::<I>,
        });
        handle.write(storage.cast());
    }
    Ok(())
}

/// Prepares an identifier of `kind` (`ROTORID_KIND_*`) in `storage` and writes its handle to
/// `*handle`. This call links the code of every kind; `rotorid_init_<kind>` links one.
///
/// `storage`: at least `rotorid_storage_size(kind)` bytes (`storage_size`), aligned to
/// `ROTORID_STORAGE_ALIGN`, used for nothing else while the identifier lives; calling an init
/// again on it starts afresh. `config`: the settings (NULL: `rotorid_config_default`).
/// `sets`: the forward-speed sets of `ROTORID_KIND_FLIGHT` (NULL: the defaults); must be NULL
/// for the other kinds. On an error the storage is not written.
///
/// The identifier is built in place. Stack, measured by the C firmware test over init, steps,
/// export and import (`docs/c-interface.md`): 4.3 KiB for `ROTORID_KIND_FLIGHT`, 13 KiB for
/// `ROTORID_KIND_PAPER_FUZZY`.
///
/// Errors: NULL, MISALIGNED, STORAGE_SIZE, KIND, ARGUMENT, and the core's CONFIG_* codes.
///
/// # Safety
/// `storage` is NULL or valid for writes of `storage_size` bytes; `config`, `sets`, `handle`
/// and `error` are NULL or valid.
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
    let result = for_kind!(kind, I => unsafe { init::<I>(kind, storage, storage_size, config, sets, handle) },
        _ => Err(rotorid_error_t::interface(ROTORID_E_KIND)));
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

// The eight `rotorid_init_<kind>` below are written out, not generated by a macro: cbindgen
// reads the source as written (expanding macros needs a nightly compiler), and each is one
// call of `init::<I>`.

/// `rotorid_init` for `ROTORID_KIND_FLIGHT`, linking that kind only. `sets`: NULL for the
/// defaults (`rotorid_flight_sets_default`). Every `rotorid_init_<kind>` takes the same
/// arguments; `sets` must be NULL for the kinds without premise sets of their own.
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
            error,
        )
    }
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
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
            init::<I>(kind, storage, storage_size, config, sets, handle),
            error,
        )
    }
}

/// Checks a handle's pointer and tag; returns its header.
///
/// # Safety
/// `h` is NULL or points to at least `size_of::<Header>()` readable bytes, and, when they
/// start with the tag that `rotorid_init*` writes, to storage that `rotorid_init*` prepared
/// and nothing else wrote since.
unsafe fn header<'a>(h: *const rotorid_ident_t) -> Result<&'a Header, rotorid_error_t> {
    let p = h.cast::<Header>();
    if p.is_null() {
        return Err(rotorid_error_t::interface(ROTORID_E_NULL));
    }
    if !(p as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
        return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
    }
    // SAFETY: aligned and readable by the caller's contract; the tag is read before anything
    // else is trusted.
    let tag = unsafe { p.cast::<u32>().read() };
    if tag != TAG {
        return Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED));
    }
    // SAFETY: tagged, so prepared by `init` (the caller's contract).
    Ok(unsafe { &*p })
}

/// The kind code behind a handle, after checking it.
///
/// # Safety
/// As [`header`].
pub(crate) unsafe fn kind_of(h: *const rotorid_ident_t) -> Result<u32, rotorid_error_t> {
    // SAFETY: the caller's contract.
    unsafe { header(h) }.map(|hd| hd.kind)
}

/// The identifier behind a handle, after checking it.
///
/// # Safety
/// As [`header`].
pub(crate) unsafe fn ident<'a>(
    h: *const rotorid_ident_t,
) -> Result<&'a dyn Ident, rotorid_error_t> {
    // SAFETY: the caller's contract; `view` is the one `init` stored for this storage.
    unsafe {
        let hd = header(h)?;
        Ok(&*(hd.view)(h.cast::<Header>().cast_mut()))
    }
}

/// As [`ident`], mutably.
///
/// # Safety
/// As [`header`], and nothing else refers to the storage during the call.
pub(crate) unsafe fn ident_mut<'a>(
    h: *mut rotorid_ident_t,
) -> Result<&'a mut dyn Ident, rotorid_error_t> {
    // SAFETY: as in `ident`.
    unsafe {
        let hd = header(h)?;
        Ok(&mut *(hd.view)(h.cast::<Header>()))
    }
}
