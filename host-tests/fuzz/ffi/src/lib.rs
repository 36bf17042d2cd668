//! `core/ffi/src` compiled as an rlib with `std` (see `Cargo.toml`): the modules of
//! `core/ffi/src/lib.rs` at the same paths, so that their `crate::` paths resolve, plus the
//! call-sequence driver `sequences` that the fuzz target `c_interface` runs.
#![allow(non_camel_case_types)]

#[path = "../../../../core/ffi/src/calls.rs"]
pub mod calls;
#[path = "../../../../core/ffi/src/error.rs"]
pub mod error;
#[path = "../../../../core/ffi/src/export.rs"]
pub mod export;
#[path = "../../../../core/ffi/src/frames.rs"]
pub mod frames;
#[path = "../../../../core/ffi/src/handle.rs"]
pub mod handle;
#[path = "../../../../core/ffi/src/kinds.rs"]
pub mod kinds;
#[path = "../../../../core/ffi/src/lean.rs"]
pub mod lean;
#[path = "../../../../core/ffi/src/ptr.rs"]
mod ptr;
#[path = "../../../../core/ffi/src/record.rs"]
pub mod record;
#[path = "../../../../core/ffi/src/sequences.rs"]
pub mod sequences;
#[path = "../../../../core/ffi/src/sweep.rs"]
pub mod sweep;
#[path = "../../../../core/ffi/src/types.rs"]
pub mod types;
