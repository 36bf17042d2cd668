//! The frame's fixed sizes, version and CRC: what the framing layer and the messages share,
//! below both (see the crate docs for the frame layout and the CRC's choice).

/// Protocol version carried in byte 0 of every raw frame. Frames with another version and a
/// valid CRC are rejected and counted as [`FrameError::UnknownVersion`](crate::frame::FrameError::UnknownVersion). 2 since export and
/// import carry the core's snapshot (`docs/protocol.md`, "Versions").
pub const VERSION: u8 = 2;
/// Largest payload of one frame, in bytes.
pub const MAX_PAYLOAD: usize = 240;
/// Header bytes before the payload: version, message type, sequence number (2).
pub const HEADER_LEN: usize = 4;
/// Bytes of the CRC trailer.
pub const CRC_LEN: usize = 4;
/// Smallest raw (decoded) frame: header and CRC with an empty payload, in bytes.
pub const MIN_RAW_LEN: usize = HEADER_LEN + CRC_LEN;
/// Largest raw (decoded) frame, in bytes.
pub const MAX_RAW_LEN: usize = HEADER_LEN + MAX_PAYLOAD + CRC_LEN;
/// Largest COBS-encoded frame without its delimiter, in bytes (raw + 1 for frames < 254 B).
pub const MAX_ENCODED_LEN: usize = cobs::max_encoding_length(MAX_RAW_LEN);
/// Largest wire frame including the trailing `0x00` delimiter, in bytes. A buffer of this size
/// always fits [`encode_frame`](crate::frame::encode_frame)'s output.
pub const MAX_WIRE_LEN: usize = MAX_ENCODED_LEN + 1;
/// Frame delimiter on the wire.
pub const DELIMITER: u8 = 0x00;

/// Wire length (bytes, delimiter included) of a frame with `payload_len` payload bytes.
pub const fn wire_len(payload_len: usize) -> usize {
    cobs::max_encoding_length(HEADER_LEN + payload_len + CRC_LEN) + 1
}

/// The CRC used by every frame; see the crate docs for the choice.
pub(crate) const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);
