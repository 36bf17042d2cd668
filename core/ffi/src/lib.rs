//! C interface to [`rotorid`]: a `no_std` static library and its header `include/rotorid.h`.
//!
//! A C or C++ autopilot (PX4, ArduPilot, Betaflight, ...) links `librotorid_ffi.a` (built for
//! the host or for `thumbv7em-none-eabihf`) and includes the header, which `cbindgen` generates
//! from this crate (`tests/header.rs` fails when the committed header is stale). It depends on
//! `rotorid` only and adds no number of its own: a C program gets the bits the Rust API gives.
//!
//! - **Storage**: every identifier lives in memory the caller provides (no `malloc`): at least
//!   `ROTORID_<KIND>_STORAGE_SIZE` bytes aligned to [`ROTORID_STORAGE_ALIGN`]. The handle is a
//!   pointer into it, checked on every call (null, alignment, and a 16-byte header of magic,
//!   kind, layout version and CRC-32 check word written by [`rotorid_init`]; see [`handle`]).
//!   The storage holds no address: it may be moved, not saved across builds.
//! - **Identifiers**: the flight default and the paper's variants (`ROTORID_KIND_*`), f32.
//! - **Errors**: every call returns [`ROTORID_OK`] or a code that names one core error
//!   ([`rotorid::Error`], [`rotorid::ConfigError`]) or one interface error (null pointer, small
//!   buffer, ...); [`rotorid_error_t`] gives the detail. A call that fails changes nothing and
//!   writes no output but the detail.
//! - **Export/import**: a documented byte format with a version and a CRC-32 (see [`export`]
//!   and `docs/c-interface.md`) for warm starts.
//! - **Sweeps**: Table 2's frequency sweeps and their schedule ([`sweep`]).
//! - **Frames**: samples from NED velocity and FRD rates in rad/s ([`frames`]).
//!
//! No panic: the library holds no `unwrap`, no unchecked index and no arithmetic that can
//! overflow (clippy denies them); on `no_std` targets the panic handler is an endless loop
//! that the link-time check of `.ci/run` proves unreachable.

#![no_std]
#![allow(non_camel_case_types)]
// No panic path: Cargo.toml's lints fail clippy and CI on any unwrap, expect, panic or
// unchecked index outside the tests.

pub mod calls;
pub mod error;
pub mod export;
pub mod frames;
pub mod handle;
pub mod kinds;
pub mod lean;
#[cfg(test)]
mod lean_tests;
#[cfg(test)]
mod promises;
mod ptr;
pub mod record;
#[cfg(test)]
mod record_tests;
#[cfg(test)]
mod sequences;
pub mod sweep;
pub mod types;

pub use calls::*;
pub use error::*;
pub use export::*;
pub use frames::*;
pub use handle::*;
pub use kinds::*;
pub use lean::*;
pub use record::*;
pub use sweep::*;
pub use types::*;

/// The library cannot panic (see the crate docs); a static library needs a handler all the
/// same. Test builds link `std`, which brings its own.
#[cfg(not(test))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}

/// On hosted targets Rust's precompiled `core` refers to the unwinder's personality routine
/// even when everything aborts on panic; this library never unwinds, so it is never called.
#[cfg(all(not(test), not(target_os = "none")))]
#[no_mangle]
pub extern "C" fn rust_eh_personality() {}
