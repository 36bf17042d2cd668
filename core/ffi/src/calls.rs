//! The calls on a prepared identifier: step, predict, resume, reset, info, export, import.

use rotorid::hover::{AnyAttitude, AttitudeInput, GyroCompensation};
use rotorid::{DynIdentifier, Error, HoverSample, HoverState, Quantity};

use crate::error::*;
use crate::handle::{ident, ident_mut, kind_of, rotorid_ident_t};
use crate::ptr::{get, put};
use crate::types::*;

/// Takes sample k+1: learns every model from sample k to it and predicts sample k+2
/// (`rotorid::HoverIdentifier::step`).
///
/// Required: `h`, `sample`, `out`. Optional: `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; NON_FINITE, OUT_OF_RANGE (a sample field,
/// or a target/innovation beyond the estimator's limits), TIME_STEP, NON_MONOTONIC_TIME,
/// NUMERICAL (a guard: no accepted state reaches it).
/// On success: `*out` and the identifier. On an error: only `*error` (when given); the
/// identifier and `*out` are unchanged, whatever an import brought in. After TIME_STEP
/// (a gap or jitter beyond the tolerance) call `rotorid_resume` with the same sample: it
/// restarts the chain there; dropping the sample instead leaves the chain at the last
/// accepted one, and every later step fails the same way.
///
/// # Safety
/// `h` is NULL or a handle from `rotorid_init*`; `sample` is NULL or valid for reads; `out`
/// and `error` are NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn rotorid_step(
    h: *mut rotorid_ident_t,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_step_output_t,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { step_with::<AnyAttitude<f32>, _>(|| ident_mut(h), sample, out, error) }
}

/// One-step prediction of the state after `sample` with the current parameters; changes
/// nothing. `before`: the state of the sample before `sample` (measured, or the model's own
/// estimate in a simulation), read only by the flight structures' second-order rate terms and
/// horizontal drag; NULL at the start of a chain.
///
/// Required: `h`, `sample`, `out`. Optional: `before`, `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; NON_FINITE, OUT_OF_RANGE (a field of
/// `sample` or `before`), NUMERICAL (a guard). On success: `*out`. On an error: only
/// `*error`. Never changes the identifier.
///
/// # Safety
/// As `rotorid_step`; `before` is NULL or valid for reads.
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
            let sample = get(sample)?;
            let before = before.as_ref().map(HoverState::from);
            if out.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let id = ident(h)?;
            let p = id.predict_after(before.as_ref(), &HoverSample::try_from(&sample)?)?;
            put(out, p.into())
        })();
        report(result, error)
    }
}

/// Starts a new sample chain at `sample` without learning (after a gap or a time jump) and
/// writes the prediction from it to `out`.
///
/// Required: `h`, `sample`, `out`. Optional: `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; NON_FINITE, OUT_OF_RANGE (a sample field),
/// NUMERICAL (a guard). On success: `*out` and the identifier's chain. On an error: only
/// `*error`; the identifier and `*out` are unchanged.
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
    unsafe { resume_with::<AnyAttitude<f32>, _>(|| ident_mut(h), sample, out, error) }
}

/// The body of `rotorid_step` and of every `rotorid_lean_step_<kind>`: reads the sample,
/// checks `out`, finds the identifier (`find`: before the sample's attitude form is read, so
/// that a damaged handle is always NOT_INITIALISED), converts the sample to the form `A` the
/// identifier takes, steps, writes `out`, and reports.
///
/// # Safety
/// As `rotorid_step`; `find` only dereferences a handle the caller's contract covers.
pub(crate) unsafe fn step_with<'a, A, I>(
    find: impl FnOnce() -> Result<&'a mut I, rotorid_error_t>,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_step_output_t,
    error: *mut rotorid_error_t,
) -> i32
where
    A: AttitudeInput<f32>,
    I: DynIdentifier<A> + ?Sized + 'a,
    for<'s> HoverSample<f32, A>: TryFrom<&'s rotorid_sample_t, Error = rotorid_error_t>,
{
    // SAFETY: the caller's contract.
    unsafe { with_sample(find, sample, out, error, |id, s| Ok(id.step(s)?.into())) }
}

/// The body of `rotorid_resume` and of every `rotorid_lean_resume_<kind>`, as
/// [`step_with`]'s.
///
/// # Safety
/// As `rotorid_resume`; `find` as in [`step_with`].
pub(crate) unsafe fn resume_with<'a, A, I>(
    find: impl FnOnce() -> Result<&'a mut I, rotorid_error_t>,
    sample: *const rotorid_sample_t,
    out: *mut rotorid_state_t,
    error: *mut rotorid_error_t,
) -> i32
where
    A: AttitudeInput<f32>,
    I: DynIdentifier<A> + ?Sized + 'a,
    for<'s> HoverSample<f32, A>: TryFrom<&'s rotorid_sample_t, Error = rotorid_error_t>,
{
    // SAFETY: the caller's contract.
    unsafe { with_sample(find, sample, out, error, |id, s| Ok(id.resume(s)?.into())) }
}

/// What [`step_with`] and [`resume_with`] share: reads the sample, checks `out`, finds the
/// identifier, converts the sample to the form `A`, runs `call`, writes its answer to `out`,
/// and reports. Nothing is written but `*error` when any part fails.
///
/// # Safety
/// As `rotorid_step`, with `out` valid for a write of `O`; `find` as in [`step_with`].
unsafe fn with_sample<'a, A, I, O>(
    find: impl FnOnce() -> Result<&'a mut I, rotorid_error_t>,
    sample: *const rotorid_sample_t,
    out: *mut O,
    error: *mut rotorid_error_t,
    call: impl FnOnce(&mut I, &HoverSample<f32, A>) -> Result<O, rotorid_error_t>,
) -> i32
where
    A: AttitudeInput<f32>,
    I: ?Sized + 'a,
    for<'s> HoverSample<f32, A>: TryFrom<&'s rotorid_sample_t, Error = rotorid_error_t>,
{
    // SAFETY: the caller's contract.
    unsafe {
        let result = (|| {
            let sample = get(sample)?;
            if out.is_null() {
                return Err(rotorid_error_t::interface(ROTORID_E_NULL));
            }
            let id = find()?;
            let answer = call(id, &HoverSample::<f32, A>::try_from(&sample)?)?;
            put(out, answer)
        })();
        report(result, error)
    }
}

/// Forgets everything learnt: θ = 0, P = αI, no previous sample.
///
/// Required: `h`. Optional: `error`. Codes: OK; NULL, MISALIGNED, NOT_INITIALISED (then
/// nothing is written but `*error`).
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

/// Replaces the rate models' parameters by those compensated for the gyros' white noise
/// (`rotorid::HoverIdentifier::compensate`): the parameters to simulate (free-run) with, while
/// the learnt ones are the better one-step predictor, so compensate a second identifier
/// imported from this one's export and keep learning on this one. Only the flight kinds' rate
/// models are compensated.
/// `gyro_noise`: 3 floats, σ of q, r, p (deg/s; finite, ≥ 0, ≤ 2000; 0 compensates nothing).
/// `compensated`: receives how many rules were compensated (a rule that saw fewer samples
/// than it has parameters, or whose rate hardly moved, keeps its parameters).
///
/// Required: `h`, `gyro_noise`. Optional: `compensated`, `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; CONFIG_GYRO_NOISE. On success: the
/// identifier's rate parameters and `*compensated`. On an error: only `*error`; the
/// identifier and `*compensated` are unchanged.
///
/// # Safety
/// As `rotorid_step`; `gyro_noise` is NULL or points to 3 floats; `compensated` is NULL or
/// valid for writes.
#[no_mangle]
pub unsafe extern "C" fn rotorid_compensate(
    h: *mut rotorid_ident_t,
    gyro_noise: *const f32,
    compensated: *mut u32,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        report(
            compensate_as(
                h,
                gyro_noise,
                Ok([GyroCompensation::Damping; 3]),
                compensated,
            ),
            error,
        )
    }
}

/// `rotorid_compensate_each`'s choice for a rate: the damping term's noise, as
/// `rotorid_compensate` (`rotorid::hover::GyroCompensation::Damping`).
pub const ROTORID_COMPENSATION_DAMPING: u32 = 0;
/// `rotorid_compensate_each`'s choice for a rate: the damping and the second-order terms'
/// noise (`rotorid::hover::GyroCompensation::Full`; a rule where the pair cannot be
/// compensated gets the damping term's).
pub const ROTORID_COMPENSATION_FULL: u32 = 1;

/// `rotorid_compensate` with a choice per rate (`rotorid::HoverIdentifier::compensate_each`):
/// `how`, 3 codes for q, r, p, each `ROTORID_COMPENSATION_DAMPING` or
/// `ROTORID_COMPENSATION_FULL`; `rotorid identify` names the rates its `flight selected` flies
/// fully compensated (`metrics.json`'s `verdict.full_compensation`).
///
/// Required: `h`, `gyro_noise`, `how`. Optional: `compensated`, `error`.
/// Codes: those of `rotorid_compensate`, and CONFIG_GYRO_COMPENSATION (`index`: the rate
/// whose code is not a `ROTORID_COMPENSATION_*`). On an error: only `*error`; the identifier
/// and `*compensated` are unchanged.
///
/// # Safety
/// As `rotorid_compensate`; `how` is NULL or points to 3 `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn rotorid_compensate_each(
    h: *mut rotorid_ident_t,
    gyro_noise: *const f32,
    how: *const u32,
    compensated: *mut u32,
    error: *mut rotorid_error_t,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe {
        let how = get(how.cast::<[u32; 3]>()).and_then(|codes| {
            let mut choice = [GyroCompensation::Damping; 3];
            for (index, (c, &code)) in choice.iter_mut().zip(&codes).enumerate() {
                *c = match code {
                    ROTORID_COMPENSATION_DAMPING => GyroCompensation::Damping,
                    ROTORID_COMPENSATION_FULL => GyroCompensation::Full,
                    _ => {
                        return Err(rotorid_error_t {
                            index: index as u32,
                            ..rotorid_error_t::interface(ROTORID_E_CONFIG_GYRO_COMPENSATION)
                        })
                    }
                };
            }
            Ok(choice)
        });
        report(compensate_as(h, gyro_noise, how, compensated), error)
    }
}

/// The body of `rotorid_compensate` and `rotorid_compensate_each`: `how` is the choice per
/// rate, or the error reading it gave (reported after σ's and the handle's checks).
///
/// # Safety
/// As `rotorid_compensate`.
unsafe fn compensate_as(
    h: *mut rotorid_ident_t,
    gyro_noise: *const f32,
    how: Result<[GyroCompensation; 3], rotorid_error_t>,
    compensated: *mut u32,
) -> Result<(), rotorid_error_t> {
    // SAFETY: the caller's contract.
    let sigma = unsafe { get(gyro_noise.cast::<[f32; 3]>()) }?;
    // SAFETY: the caller's contract.
    let id = unsafe { ident_mut(h) }?;
    let outcome = id.compensate_each(&sigma, how?).map_err(|e| match e {
        // The core names σ a configuration value; here it has its own code.
        Error::NonFinite(Quantity::Config) | Error::OutOfRange(Quantity::Config) => {
            rotorid_error_t::interface(ROTORID_E_CONFIG_GYRO_NOISE)
        }
        e => e.into(),
    })?;
    if !compensated.is_null() {
        // SAFETY: the caller's contract.
        unsafe { put(compensated, u32::from(outcome.compensated)) }?;
    }
    Ok(())
}

/// The settings of an identifier (as given to `rotorid_init`) and its kind.
///
/// Required: `h`. Optional: `kind`, `config`, `error` (NULL: not wanted).
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED. On success: `*kind`, `*config` (those
/// given). On an error: only `*error`.
///
/// # Safety
/// As `rotorid_step`; `kind` and `config` are NULL or valid for writes.
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
            let k = kind_of(h)?;
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
/// `ROTORID_<KIND>_EXPORT_SIZE`; the format, with its version and CRC-32, in
/// `docs/c-interface.md`) and its length to `*length`.
///
/// Required: `h`, `buffer`, `length`. Optional: `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED, BUFFER_SIZE. On success: the first
/// `*length` bytes of `buffer` and `*length`. On an error: only `*error`; `buffer` and
/// `*length` are not written. Never changes the identifier.
///
/// # Safety
/// As `rotorid_step`; `buffer` is NULL or valid for writes of `capacity` bytes; `length`
/// is NULL or valid for writes.
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
            let kind = kind_of(h)?;
            let id = ident(h)?;
            let out = core::slice::from_raw_parts_mut(buffer, capacity);
            let n = id
                .write_snapshot(kind, out)
                .map_err(|_| rotorid_error_t::interface(ROTORID_E_BUFFER_SIZE))?;
            put(length, n)
        })();
        report(result, error)
    }
}

/// Warm start from an export of the same kind (`length` bytes at `buffer`). Everything is
/// checked before anything is written: the length, the CRC-32, the header (magic, version,
/// kind) and every value (θ and every covariance or U-D factor entry bounded and finite).
/// The sample chain restarts (the next step only anchors).
///
/// Required: `h`, `buffer`. Optional: `error`.
/// Codes: OK; NULL, MISALIGNED, NOT_INITIALISED; INCOMPATIBLE (length, CRC, header, or the
/// algorithm of an estimator), NON_FINITE, OUT_OF_RANGE (a value: quantity PARAMETER or
/// COVARIANCE, index its position). On success: the identifier. On an error: only
/// `*error`; the identifier is unchanged.
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
            let kind = kind_of(h)?;
            let bytes = core::slice::from_raw_parts(buffer, length);
            ident_mut(h)?.read_snapshot(kind, bytes)?;
            Ok(())
        })();
        report(result, error)
    }
}
