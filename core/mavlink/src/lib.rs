//! MAVLink 2 telemetry for rotorid: what the identifier learns, in messages every ground station
//! already reads.
//!
//! `no_std`, no allocation, no panic: [`Encoder`] writes whole MAVLink 2 frames (unsigned,
//! common-dialect message ids and CRCs) into a caller's buffer. The messages
//! (docs/protocol.md, section "MAVLink 2", has the full field mapping):
//!
//! | message | id | what |
//! |---|---|---|
//! | `HEARTBEAT` | 0 | the component is alive ([`Encoder::heartbeat`]) |
//! | `DEBUG_FLOAT_ARRAY` | 350 | prediction + innovation of a step ([`Encoder::step`]), θ chunks ([`Encoder::theta`]); `array_id` scheme in [`array_id`] |
//! | `NAMED_VALUE_FLOAT` | 251 | convergence ratios and mask ([`Encoder::convergence`]) |
//! | `STATUSTEXT` | 253 | a rejected sample and why ([`Encoder::rejected`]) |
//!
//! # Why a dialect of our own, generated and committed
//!
//! The `mavlink` crate 0.21 only has `DEBUG_FLOAT_ARRAY.data` (an extension field) with its
//! `mav2-message-extensions` feature, which pulls in `std`. So `dialect/rotorid.xml` copies the
//! four messages and their enums unchanged from the upstream `minimal.xml`/`common.xml` (same
//! ids and CRC_EXTRA: a stock common-dialect decoder reads our frames), `mavlink-bindgen`
//! generates [`dialect`] from it with extensions on, and only `mavlink-core` (feature
//! `embedded`, no `std`) is a dependency. The generated file is committed (see
//! `tests/generated.rs`, which checks it is current) so that a firmware build compiles no XML
//! parser or code generator. pymavlink's `mavgen` reads the same XML (the round-trip test in
//! host-tests).
//!
//! Floats are f32 on the wire (MAVLink's `float`): an f64 identifier's outputs are converted
//! by the caller (`as f32`).

#![no_std]
#![deny(missing_docs)]

pub mod array_id;
#[allow(non_camel_case_types)]
pub mod dialect;
mod encoder;

pub use array_id::{chunk_count, ArrayId, ArrayKind, Model, Sender, ARRAY_LEN};
pub use dialect::MavState;
pub use encoder::Encoder;

/// Largest MAVLink 2 frame (signed, full payload), in bytes: a buffer this long fits any frame
/// the [`Encoder`] writes (a full `DEBUG_FLOAT_ARRAY` is 264 bytes).
pub const MAX_FRAME_LEN: usize = mavlink_core::consts::MAX_FRAME_SIZE;

/// Why a frame was not written.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EncodeError {
    /// The output buffer is shorter than the frame.
    BufferTooSmall {
        /// Bytes the frame needs.
        needed: usize,
        /// Bytes the buffer had.
        available: usize,
    },
    /// Slot over 15, or a tag that is empty, longer than 3 bytes or not `[A-Za-z0-9_]`.
    InvalidSender,
    /// A θ chunk past the end of the vector (or a vector over 256 chunks).
    ChunkOutOfRange,
    /// A convergence indicator over more than 24 outputs (its mask would not be exact in f32).
    TooManyOutputs,
}

impl core::fmt::Display for EncodeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EncodeError::BufferTooSmall { needed, available } => {
                write!(
                    f,
                    "MAVLink frame needs {needed} bytes, buffer has {available}"
                )
            }
            EncodeError::InvalidSender => f.write_str("identifier slot > 15 or bad tag"),
            EncodeError::ChunkOutOfRange => f.write_str("parameter chunk out of range"),
            EncodeError::TooManyOutputs => f.write_str("more than 24 convergence outputs"),
        }
    }
}

impl core::error::Error for EncodeError {}
