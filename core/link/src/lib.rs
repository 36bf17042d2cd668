//! rotorid's telemetry link: framing, payload codec and message catalogue shared by a
//! firmware and its host.
//!
//! A crate of its own so that a flight stack that links the identifier (`rotorid`) does not
//! carry a protocol it does not speak. It depends on `rotorid` (the types it carries), `crc`
//! and `cobs`, and nothing depends on it but firmwares and host tools.
//!
//! Everything here is `no_std`, allocation-free and total: no input (random bytes, truncated or
//! corrupted frames, oversized bursts) can make it panic, and nothing corrupted is ever handed
//! to the application. The wire format is specified in `docs/protocol.md`; in short:
//!
//! ```text
//! raw frame   = version:u8 | msg_type:u8 | seq:u16 LE | payload (0..=240 bytes) | crc:u32 LE
//! wire frame  = COBS(raw frame) | 0x00
//! crc         = CRC-32/ISO-HDLC over version..payload (poly 0x04C11DB7 reflected, init/xorout !0)
//! ```
//!
//! One frame through the wire, including a corrupted copy that is never delivered:
//!
//! ```
//! use rotorid_link::{FrameDecoder, FrameEncoder, MAX_WIRE_LEN};
//!
//! let mut tx = FrameEncoder::new();
//! let mut wire = [0u8; MAX_WIRE_LEN];
//! let bytes = tx.encode(0x02, b"ping", &mut wire)?.to_vec(); // Ping, seq 0
//!
//! let mut rx: FrameDecoder = FrameDecoder::new();
//! let mut corrupted = bytes.clone();
//! corrupted[3] ^= 0x10;
//! for &b in &corrupted {
//!     if let Some(r) = rx.push(b) {
//!         assert!(r.is_err()); // CRC (or COBS) error: counted, not delivered
//!     }
//! }
//! let mut got = None;
//! for &b in &bytes {
//!     if let Some(Ok(frame)) = rx.push(b) {
//!         got = Some((frame.msg_type, frame.seq, frame.payload.to_vec()));
//!     }
//! }
//! assert_eq!(got, Some((0x02, 0, b"ping".to_vec())));
//! assert_eq!(rx.stats().frames_ok, 1);
//! # Ok::<(), rotorid_link::EncodeError>(())
//! ```
//!
//! * [`encode_frame`] / [`FrameEncoder`] write one wire frame into a caller's buffer.
//! * [`FrameDecoder`] is a streaming decoder with a fixed buffer: feed it bytes one at a time
//!   ([`FrameDecoder::push`]) or in slices ([`FrameDecoder::feed`]); it yields complete valid
//!   [`Frame`]s, classifies and counts every rejected frame ([`LinkStats`]), resynchronises at
//!   the next `0x00` and counts sequence gaps (lost frames) of the direction it receives.
//! * [`Writer`] / [`Reader`] put and get little-endian scalars in payloads.
//! * [`Field`] is a fixed-size value in a payload (scalars, arrays).
//! * [`msg`] is the message catalogue above the framing: type codes and payload layouts
//!   ([`msg::Payload`]). The framing modules (`frame`, `stats`, `cobs_decode`, `payload`)
//!   import nothing from it: the arrow points from the catalogue to the framing only.
//!
//! # Why CRC-32/ISO-HDLC
//!
//! A raw frame is at most 248 bytes (1984 bits). CRC-32 (generator 0x04C11DB7) has Hamming
//! distance 5 up to 2974 data bits, so it detects every error of up to 4 flipped bits in any
//! frame we send, every burst up to 32 bits, and accepts random garbage with probability
//! 2^-32 per candidate frame. CRC-16 would give HD 4 but a 2^-16 false-accept rate on noise,
//! which at one garbage "frame" per second is one bogus accepted frame per 18 hours. The two
//! extra bytes are cheap and the `crc` crate's 1 KiB table costs ~20 instructions per byte on
//! a Cortex-M4. It is also the CRC every tool knows (zlib, Python `binascii.crc32`).
#![no_std]
#![forbid(unsafe_code)]
// No panic path: the workspace's lints (Cargo.toml) fail clippy and CI on any unwrap, expect,
// panic or unchecked index outside the tests.

mod cobs_decode;
mod frame;
pub mod msg;
mod payload;
mod sample_chain;
mod stats;
mod wire;

pub use frame::{
    encode_frame, encode_frame_vec, EncodeError, Feed, Frame, FrameDecoder, FrameEncoder,
    FrameError,
};
pub use payload::{Field, PayloadError, Reader, Writer};
pub use sample_chain::{Answer, SampleChain};
pub use stats::{LinkStats, SeqTracker};
pub use wire::{
    wire_len, CRC_LEN, DELIMITER, HEADER_LEN, MAX_ENCODED_LEN, MAX_PAYLOAD, MAX_RAW_LEN,
    MAX_WIRE_LEN, MIN_RAW_LEN, VERSION,
};
