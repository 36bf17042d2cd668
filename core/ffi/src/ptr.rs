//! Reading the caller's inputs and writing its outputs through raw pointers: NULL is
//! `ROTORID_E_NULL`, never a dereference.

use crate::error::*;

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
