//! Identifiers in caller-provided storage: kinds, sizes, handles and the calls on them.
//!
//! Storage layout: a tag word, the kind code, then the core's identifier (`HoverIdentifier`),
//! as one `repr(C)` struct. The handle the caller gets back is the storage's address.

use core::mem::{align_of, size_of};

use rotorid::hover::{flight_sets, table3, StateModel};
use rotorid::membership::MembershipFunction;
use rotorid::{
    Error, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier,
    FlightIdentifier, FlightPlainIdentifier, HoverConfig, HoverIdentifier, HoverSample, HoverState,
    PaperFuzzyIdentifier, PaperLocalIdentifier, PaperPlainIdentifier,
};

use crate::error::*;
use crate::export::{self, Wire};
use crate::types::*;

/// The flight default: three forward-speed rules per model, local learning, the extended
/// flight structures (`rotorid::FlightIdentifier`).
pub const ROTORID_KIND_FLIGHT: u32 = 1;
/// The flight structures with one rule (`rotorid::FlightPlainIdentifier`).
pub const ROTORID_KIND_FLIGHT_PLAIN: u32 = 2;
/// The paper's fuzzy identifier (Table 3 sets, global RLS; `rotorid::PaperFuzzyIdentifier`).
pub const ROTORID_KIND_PAPER_FUZZY: u32 = 3;
/// The paper's plain identifier (one rule; `rotorid::PaperPlainIdentifier`).
pub const ROTORID_KIND_PAPER_PLAIN: u32 = 4;
/// Extended structures, Table 3 sets, global RLS (`rotorid::ExtendedFuzzyIdentifier`).
pub const ROTORID_KIND_EXTENDED_FUZZY: u32 = 5;
/// Extended structures, one rule (`rotorid::ExtendedPlainIdentifier`).
pub const ROTORID_KIND_EXTENDED_PLAIN: u32 = 6;
/// The paper's structures and sets, learnt locally (`rotorid::PaperLocalIdentifier`).
pub const ROTORID_KIND_PAPER_LOCAL: u32 = 7;
/// Extended structures, Table 3 sets, learnt locally (`rotorid::ExtendedLocalIdentifier`).
pub const ROTORID_KIND_EXTENDED_LOCAL: u32 = 8;

/// Alignment every identifier's storage needs (bytes).
pub const ROTORID_STORAGE_ALIGN: usize = 8;

/// Storage bytes of `ROTORID_KIND_FLIGHT`.
pub const ROTORID_FLIGHT_STORAGE_SIZE: usize = 2832;
/// Storage bytes of `ROTORID_KIND_FLIGHT_PLAIN`.
pub const ROTORID_FLIGHT_PLAIN_STORAGE_SIZE: usize = 1488;
/// Storage bytes of `ROTORID_KIND_PAPER_FUZZY`.
pub const ROTORID_PAPER_FUZZY_STORAGE_SIZE: usize = 11272;
/// Storage bytes of `ROTORID_KIND_PAPER_PLAIN`.
pub const ROTORID_PAPER_PLAIN_STORAGE_SIZE: usize = 880;
/// Storage bytes of `ROTORID_KIND_EXTENDED_FUZZY`.
pub const ROTORID_EXTENDED_FUZZY_STORAGE_SIZE: usize = 27240;
/// Storage bytes of `ROTORID_KIND_EXTENDED_PLAIN`.
pub const ROTORID_EXTENDED_PLAIN_STORAGE_SIZE: usize = 1232;
/// Storage bytes of `ROTORID_KIND_PAPER_LOCAL`.
pub const ROTORID_PAPER_LOCAL_STORAGE_SIZE: usize = 3760;
/// Storage bytes of `ROTORID_KIND_EXTENDED_LOCAL`.
pub const ROTORID_EXTENDED_LOCAL_STORAGE_SIZE: usize = 5184;

/// Export bytes of `ROTORID_KIND_FLIGHT`.
pub const ROTORID_FLIGHT_EXPORT_SIZE: usize = 1788;
/// Export bytes of `ROTORID_KIND_FLIGHT_PLAIN`.
pub const ROTORID_FLIGHT_PLAIN_EXPORT_SIZE: usize = 604;
/// Export bytes of `ROTORID_KIND_PAPER_FUZZY`.
pub const ROTORID_PAPER_FUZZY_EXPORT_SIZE: usize = 10520;
/// Export bytes of `ROTORID_KIND_PAPER_PLAIN`.
pub const ROTORID_PAPER_PLAIN_EXPORT_SIZE: usize = 124;
/// Export bytes of `ROTORID_KIND_EXTENDED_FUZZY`.
pub const ROTORID_EXTENDED_FUZZY_EXPORT_SIZE: usize = 26432;
/// Export bytes of `ROTORID_KIND_EXTENDED_PLAIN`.
pub const ROTORID_EXTENDED_PLAIN_EXPORT_SIZE: usize = 424;
/// Export bytes of `ROTORID_KIND_PAPER_LOCAL`.
pub const ROTORID_PAPER_LOCAL_EXPORT_SIZE: usize = 1776;
/// Export bytes of `ROTORID_KIND_EXTENDED_LOCAL`.
pub const ROTORID_EXTENDED_LOCAL_EXPORT_SIZE: usize = 3624;

/// An identifier in caller-provided storage (opaque; the storage's address).
pub struct rotorid_ident_t {
    _private: [u8; 0],
}

/// Written by `rotorid_init` in front of the identifier: "RDI1".
const TAG: u32 = u32::from_le_bytes(*b"RDI1");

/// What the storage holds.
#[repr(C)]
struct Slot<I> {
    tag: u32,
    kind: u32,
    ident: I,
}

/// The calls the C interface makes on any identifier kind.
trait Ident {
    fn step(&mut self, s: &HoverSample<f32>) -> Result<rotorid_step_output_t, Error>;
    fn predict(
        &self,
        before: Option<&HoverState<f32>>,
        s: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, Error>;
    fn resume(&mut self, s: &HoverSample<f32>) -> Result<HoverState<f32>, Error>;
    fn reset(&mut self);
    fn config(&self) -> HoverConfig<f32>;
    fn export(&self, kind: u32, out: &mut [u8]) -> Result<usize, ()>;
    fn import(&mut self, kind: u32, bytes: &[u8]) -> Result<(), Error>;
}

/// The export size of an identifier type.
trait ExportSize {
    const EXPORT_SIZE: usize;
}

impl<V, Q, R, P> ExportSize for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32, State: Wire>,
    Q: StateModel<f32, State: Wire>,
    R: StateModel<f32, State: Wire>,
    P: StateModel<f32, State: Wire>,
{
    const EXPORT_SIZE: usize = export::export_size::<V, Q, R, P>();
}

impl<V, Q, R, P> Ident for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32, State: Wire>,
    Q: StateModel<f32, State: Wire>,
    R: StateModel<f32, State: Wire>,
    P: StateModel<f32, State: Wire>,
{
    fn step(&mut self, s: &HoverSample<f32>) -> Result<rotorid_step_output_t, Error> {
        HoverIdentifier::step(self, s).map(Into::into)
    }
    fn predict(
        &self,
        before: Option<&HoverState<f32>>,
        s: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, Error> {
        self.predict_after(before, s)
    }
    fn resume(&mut self, s: &HoverSample<f32>) -> Result<HoverState<f32>, Error> {
        HoverIdentifier::resume(self, s)
    }
    fn reset(&mut self) {
        HoverIdentifier::reset(self)
    }
    fn config(&self) -> HoverConfig<f32> {
        HoverIdentifier::config(self)
    }
    fn export(&self, kind: u32, out: &mut [u8]) -> Result<usize, ()> {
        export::export(self, kind, out)
    }
    fn import(&mut self, kind: u32, bytes: &[u8]) -> Result<(), Error> {
        export::import(self, kind, bytes)
    }
}

/// Calls `$body` with `$I` the identifier type of kind code `$kind` (`$none` for an unknown
/// code): the one list of kinds every call dispatches through.
macro_rules! for_kind {
    ($kind:expr, $I:ident => $body:expr, _ => $none:expr) => {
        match $kind {
            ROTORID_KIND_FLIGHT => {
                type $I = FlightIdentifier<f32>;
                $body
            }
            ROTORID_KIND_FLIGHT_PLAIN => {
                type $I = FlightPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_FUZZY => {
                type $I = PaperFuzzyIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_PLAIN => {
                type $I = PaperPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_FUZZY => {
                type $I = ExtendedFuzzyIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_PLAIN => {
                type $I = ExtendedPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_LOCAL => {
                type $I = PaperLocalIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_LOCAL => {
                type $I = ExtendedLocalIdentifier<f32>;
                $body
            }
            _ => $none,
        }
    };
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

/// Bytes of an export of `kind` (0 for an unknown kind).
#[no_mangle]
pub extern "C" fn rotorid_export_size(kind: u32) -> usize {
    for_kind!(kind, I => <I as ExportSize>::EXPORT_SIZE, _ => 0)
}

/// Writes `value` to `out`, or reports `ROTORID_E_NULL`.
///
/// # Safety
/// `out` is NULL or valid for one write of a `T`.
unsafe fn put<T>(out: *mut T, value: T) -> Result<(), rotorid_error_t> {
    // SAFETY: the caller's contract.
    match unsafe { out.as_mut() } {
        Some(out) => {
            *out = value;
            Ok(())
        }
        None => Err(rotorid_error_t::interface(ROTORID_E_NULL)),
    }
}

/// Reads `*p`, or reports `ROTORID_E_NULL`.
///
/// # Safety
/// `p` is NULL or valid for one read of a `T`.
unsafe fn get<T: Copy>(p: *const T) -> Result<T, rotorid_error_t> {
    // SAFETY: the caller's contract.
    unsafe { p.as_ref() }
        .copied()
        .ok_or(rotorid_error_t::interface(ROTORID_E_NULL))
}

/// The flight settings (`rotorid::HoverConfig::default()`): U-D RLS, α = 10⁶, λ = 1,
/// helicopter scaling, 50 Hz ± 50 %. Returns `ROTORID_E_NULL` when `out` is NULL.
///
/// # Safety
/// `out` is NULL or points to a writable `rotorid_config_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_config_default(out: *mut rotorid_config_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        report(
            put(out, HoverConfig::<f32>::default().into()),
            core::ptr::null_mut(),
        )
    }
}

/// The paper's settings (`rotorid::HoverConfig::paper()`): covariance-form RLS, α = 10⁶,
/// λ = 1, no scaling, 50 Hz ± 50 %.
///
/// # Safety
/// As `rotorid_config_default`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_config_paper(out: *mut rotorid_config_t) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        report(
            put(out, HoverConfig::<f32>::paper().into()),
            core::ptr::null_mut(),
        )
    }
}

/// The default forward-speed sets of `ROTORID_KIND_FLIGHT` (`rotorid::hover::flight_sets`).
///
/// # Safety
/// `out` is NULL or points to a writable `rotorid_flight_sets_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_flight_sets_default(out: *mut rotorid_flight_sets_t) -> i32 {
    let mut sets = rotorid_flight_sets_t {
        centre: [0.0; 3],
        spread: [0.0; 3],
    };
    for (i, mf) in flight_sets::<f32>().iter().enumerate() {
        if let (Some(c), Some(s)) = (sets.centre.get_mut(i), sets.spread.get_mut(i)) {
            (*c, *s) = mf.parameters();
        }
    }
    // SAFETY: the caller's contract.
    unsafe { report(put(out, sets), core::ptr::null_mut()) }
}

fn premise_sets(s: &rotorid_flight_sets_t) -> rotorid::rule_base::PremiseSets<f32> {
    let [c0, c1, c2] = s.centre;
    let [s0, s1, s2] = s.spread;
    table3::sets(&[
        MembershipFunction::LeftShoulder {
            centre: c0,
            spread: s0,
        },
        MembershipFunction::Gaussian {
            centre: c1,
            spread: s1,
        },
        MembershipFunction::RightShoulder {
            centre: c2,
            spread: s2,
        },
    ])
}

/// Builds an identifier of type `I` and moves it into `storage`. Never inlined: each kind gets
/// its own stack frame, so that a call pays for its own kind only (dispatching all eight in
/// one frame would reserve the largest two times over).
///
/// # Safety
/// `storage` is aligned to `ROTORID_STORAGE_ALIGN` and valid for writes of
/// `size_of::<Slot<I>>()` bytes.
#[inline(never)]
unsafe fn place<I: Build>(
    storage: *mut u8,
    kind: u32,
    config: HoverConfig<f32>,
    sets: Option<&rotorid_flight_sets_t>,
) -> Result<(), rotorid_error_t> {
    let ident = I::build(config, sets)?;
    // SAFETY: the caller's contract.
    unsafe {
        storage.cast::<Slot<I>>().write(Slot {
            tag: TAG,
            kind,
            ident,
        })
    };
    Ok(())
}

/// How each kind is built from the C settings.
trait Build: Sized {
    fn build(
        config: HoverConfig<f32>,
        sets: Option<&rotorid_flight_sets_t>,
    ) -> Result<Self, rotorid_error_t>;
}

/// Kinds without premise sets of their own (`rotorid_init` refuses sets for them).
macro_rules! build_without_sets {
    ($($I:ty => $new:path),* $(,)?) => {$(
        impl Build for $I {
            fn build(
                config: HoverConfig<f32>,
                _: Option<&rotorid_flight_sets_t>,
            ) -> Result<Self, rotorid_error_t> {
                Ok($new(config)?)
            }
        }
    )*};
}

build_without_sets! {
    FlightPlainIdentifier<f32> => FlightPlainIdentifier::flight_plain,
    PaperFuzzyIdentifier<f32> => PaperFuzzyIdentifier::paper_fuzzy,
    PaperPlainIdentifier<f32> => PaperPlainIdentifier::paper_plain,
    ExtendedFuzzyIdentifier<f32> => ExtendedFuzzyIdentifier::extended_fuzzy,
    ExtendedPlainIdentifier<f32> => ExtendedPlainIdentifier::extended_plain,
    PaperLocalIdentifier<f32> => PaperLocalIdentifier::paper_local,
    ExtendedLocalIdentifier<f32> => ExtendedLocalIdentifier::extended_local,
}

impl Build for FlightIdentifier<f32> {
    fn build(
        config: HoverConfig<f32>,
        sets: Option<&rotorid_flight_sets_t>,
    ) -> Result<Self, rotorid_error_t> {
        let sets = match sets {
            Some(s) => premise_sets(s),
            None => flight_sets(),
        };
        Ok(FlightIdentifier::flight(config, sets)?)
    }
}

/// Prepares an identifier of `kind` in `storage` (`storage_size` bytes, aligned to
/// `ROTORID_STORAGE_ALIGN`) and writes its handle to `*handle`.
///
/// `config`: the settings (NULL: `rotorid_config_default`). `sets`: the forward-speed sets of
/// `ROTORID_KIND_FLIGHT` (NULL: `rotorid_flight_sets_default`); must be NULL for the other
/// kinds. On an error the storage is not written. Building the identifier uses about its
/// storage size of stack. Calling it again on the same storage starts afresh.
///
/// Errors: NULL, MISALIGNED, STORAGE_SIZE, KIND, ARGUMENT, and the core's CONFIG_* codes.
///
/// # Safety
/// `storage` is NULL or valid for writes of `storage_size` bytes and not used for anything
/// else while the identifier lives; `config`, `sets`, `handle`, `error` are NULL or valid.
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
    let result = (|| {
        let storage = storage.cast::<u8>();
        if storage.is_null() || handle.is_null() {
            return Err(rotorid_error_t::interface(ROTORID_E_NULL));
        }
        if !(storage as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
            return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
        }
        let needed = rotorid_storage_size(kind);
        if needed == 0 {
            return Err(rotorid_error_t::interface(ROTORID_E_KIND));
        }
        if storage_size < needed {
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
        // SAFETY: NULL or valid by the caller's contract.
        let sets = unsafe { sets.as_ref() };
        // SAFETY: `storage` is aligned and holds `size_of::<Slot<I>>()` bytes (checked
        // above), and the caller gave it to the identifier.
        for_kind!(kind, I => unsafe { place::<I>(storage, kind, config, sets)? },
            _ => return Err(rotorid_error_t::interface(ROTORID_E_KIND)));
        // SAFETY: checked not NULL above.
        unsafe { handle.write(storage.cast()) };
        Ok(())
    })();
    // SAFETY: the caller's contract.
    unsafe { report(result, error) }
}

/// The identifier behind a handle, after checking it.
///
/// # Safety
/// `h` is NULL or points to at least 8 readable bytes, and, when they hold the tag that
/// `rotorid_init` writes, to the storage `rotorid_init` prepared.
unsafe fn ident<'a>(h: *const rotorid_ident_t) -> Result<&'a dyn Ident, rotorid_error_t> {
    // SAFETY: the caller's contract; the header is checked before the identifier is read.
    unsafe {
        let (kind, p) = header(h)?;
        for_kind!(kind, I => Ok(&(*p.cast::<Slot<I>>()).ident as &dyn Ident),
            _ => Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED)))
    }
}

/// As [`ident`], mutably.
///
/// # Safety
/// As [`ident`], and nothing else refers to the storage during the call.
unsafe fn ident_mut<'a>(h: *mut rotorid_ident_t) -> Result<&'a mut dyn Ident, rotorid_error_t> {
    // SAFETY: as in `ident`.
    unsafe {
        let (kind, p) = header(h)?;
        let p = p.cast_mut();
        for_kind!(kind, I => Ok(&mut (*p.cast::<Slot<I>>()).ident as &mut dyn Ident),
            _ => Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED)))
    }
}

/// Checks a handle's pointer and tag; returns its kind and address.
///
/// # Safety
/// As [`ident`].
unsafe fn header(h: *const rotorid_ident_t) -> Result<(u32, *const u8), rotorid_error_t> {
    let p = h.cast::<u8>();
    if p.is_null() {
        return Err(rotorid_error_t::interface(ROTORID_E_NULL));
    }
    if !(p as usize).is_multiple_of(ROTORID_STORAGE_ALIGN) {
        return Err(rotorid_error_t::interface(ROTORID_E_MISALIGNED));
    }
    // SAFETY: aligned and readable by the caller's contract; every Slot starts with these two
    // words.
    let (tag, kind) = unsafe { (p.cast::<u32>().read(), p.cast::<u32>().add(1).read()) };
    if tag != TAG {
        return Err(rotorid_error_t::interface(ROTORID_E_NOT_INITIALISED));
    }
    Ok((kind, p))
}

/// Takes sample k+1: learns every model from sample k to it and predicts sample k+2
/// (`rotorid::HoverIdentifier::step`). A rejected sample changes nothing; after a
/// TIME_STEP error (a gap), call `rotorid_resume`.
///
/// # Safety
/// `h` comes from `rotorid_init` (or is NULL); `sample`, `out`, `error` are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_step(
    h: *mut rotorid_ident_t,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_step_output_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let sample = HoverSample::from(&get(sample)?);
            if out.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let o = ident_mut(h)?.step(&sample)?;
            put(out, o)
        })();
        report(result, error)
    }
}

/// One-step prediction of the state after `sample` with the current parameters; changes
/// nothing. `before`: the state of the sample before `sample` (measured, or the model's own
/// estimate in a simulation), read only by second-order terms; NULL at the start of a chain.
///
/// # Safety
/// As `rotorid_step`; `before` is NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_predict(
    h: *const rotorid_ident_t,
    before: *const rotorid_state_t,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_state_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let sample = HoverSample::from(&get(sample)?);
            let before = before.as_ref().map(HoverState::from);
            if out.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let p = ident(h)?.predict(before.as_ref(), &sample)?;
            put(out, p.into())
        })();
        report(result, error)
    }
}

/// Starts a new sample chain at `sample` without learning (after a gap or a time jump) and
/// writes the prediction from it to `out`.
///
/// # Safety
/// As `rotorid_step`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_resume(
    h: *mut rotorid_ident_t,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_state_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let sample = HoverSample::from(&get(sample)?);
            if out.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let p = ident_mut(h)?.resume(&sample)?;
            put(out, p.into())
        })();
        report(result, error)
    }
}

/// Forgets everything learnt: θ = 0, P = αI, no previous sample.
///
/// # Safety
/// As `rotorid_step`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_reset(
    h: *mut rotorid_ident_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = ident_mut(h).map(|id| id.reset());
        report(result, error)
    }
}

/// The settings of an identifier (as given to `rotorid_init`) and its kind.
///
/// # Safety
/// As `rotorid_step`; `kind` and `config` are NULL (not wanted) or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_info(
    h: *const rotorid_ident_t,
    kind: *mut u32,
    config: *mut rotorid_config_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let (k, _) = header(h)?;
            let c = ident(h)?.config();
            if let Some(kind) = kind.as_mut() {
                *kind = k;
            }
            if let Some(config) = config.as_mut() {
                *config = c.into();
            }
            Ok(())
        })();
        report(result, error)
    }
}

/// Writes everything the identifier has learnt into `buffer` (`capacity` bytes, at least
/// `ROTORID_<KIND>_EXPORT_SIZE`; format in the crate docs of `rotorid-ffi`, module `export`)
/// and its length to `*length`.
///
/// # Safety
/// As `rotorid_step`; `buffer` is NULL or valid for writes of `capacity` bytes; `length`
/// is NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn rotorid_export(
    h: *const rotorid_ident_t,
    buffer: *mut u8,
    capacity: usize,
    length: *mut usize,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            if buffer.is_null() || length.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let (kind, _) = header(h)?;
            let id = ident(h)?;
            let out = core::slice::from_raw_parts_mut(buffer, capacity);
            let n = id
                .export(kind, out)
                .map_err(|()| rotorid_error_t::interface(ROTORID_E_BUFFER_SIZE))?;
            put(length, n)
        })();
        report(result, error)
    }
}

/// Warm start from an export of the same kind (`length` bytes at `buffer`). Everything is
/// checked before anything is written: on an error nothing changed. The sample chain
/// restarts (the next step only anchors).
///
/// # Safety
/// As `rotorid_step`; `buffer` is NULL or valid for reads of `length` bytes.
#[no_mangle]
pub unsafe extern "C" fn rotorid_import(
    h: *mut rotorid_ident_t,
    buffer: *const u8,
    length: usize,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            if buffer.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let (kind, _) = header(h)?;
            let bytes = core::slice::from_raw_parts(buffer, length);
            ident_mut(h)?.import(kind, bytes)?;
            Ok(())
        })();
        report(result, error)
    }
}
