//! Frame encoder, streaming decoder and error kinds.

use core::fmt;

use crate::cobs_decode::cobs_decode_in_place;
use crate::stats::{LinkStats, SeqTracker};

use crate::wire::{
    CRC, CRC_LEN, DELIMITER, HEADER_LEN, MAX_ENCODED_LEN, MAX_PAYLOAD, MAX_RAW_LEN, MIN_RAW_LEN,
    VERSION,
};

/// Why a frame could not be encoded.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncodeError {
    /// The payload is longer than [`MAX_PAYLOAD`](crate::wire::MAX_PAYLOAD) bytes.
    PayloadTooLarge {
        /// Payload length that was asked for, in bytes.
        len: usize,
    },
    /// The output buffer cannot hold the encoded frame and its delimiter.
    BufferTooSmall {
        /// Bytes the wire frame needs.
        needed: usize,
        /// Bytes the buffer offered.
        available: usize,
    },
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::PayloadTooLarge { len } => {
                write!(f, "payload of {len} B exceeds the {MAX_PAYLOAD} B limit")
            }
            Self::BufferTooSmall { needed, available } => {
                write!(f, "frame needs {needed} B but the buffer has {available} B")
            }
        }
    }
}

impl core::error::Error for EncodeError {}

/// Why a received frame (the bytes between two delimiters) was rejected.
///
/// Each kind has its own counter in [`LinkStats`].
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameError {
    /// The bytes are not valid COBS (a block length runs past the delimiter), which is what a
    /// frame cut short inside a block or most line noise looks like.
    Cobs,
    /// Valid COBS but the CRC does not match: corruption.
    Crc,
    /// Valid COBS but shorter than header + CRC.
    TooShort {
        /// Decoded length, in bytes.
        len: usize,
    },
    /// More bytes than the decoder buffer (or than a legal frame) before the next delimiter;
    /// the decoder dropped them and resynchronised at that delimiter.
    Oversized,
    /// Intact frame (CRC valid) of a protocol version this build does not speak.
    UnknownVersion {
        /// Version byte that was received.
        version: u8,
    },
}

impl FrameError {
    /// Counts this rejected chunk under its kind in `stats`.
    fn count_in(self, stats: &mut LinkStats) {
        let c = match self {
            Self::Cobs => &mut stats.cobs_errors,
            Self::Crc => &mut stats.crc_errors,
            Self::TooShort { .. } => &mut stats.too_short,
            Self::Oversized => &mut stats.oversized,
            Self::UnknownVersion { .. } => &mut stats.unknown_version,
        };
        *c = c.wrapping_add(1);
    }
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Cobs => f.write_str("invalid COBS encoding"),
            Self::Crc => f.write_str("CRC mismatch"),
            Self::TooShort { len } => {
                write!(
                    f,
                    "frame of {len} B is shorter than the {MIN_RAW_LEN} B minimum"
                )
            }
            Self::Oversized => f.write_str("frame longer than the receive buffer"),
            Self::UnknownVersion { version } => {
                write!(f, "unknown protocol version {version} (expected {VERSION})")
            }
        }
    }
}

impl core::error::Error for FrameError {}

/// One valid frame, borrowed from the decoder's buffer until the next byte is fed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Frame<'a> {
    /// Message type byte (the catalogue, `msg::MsgType`, names the known ones).
    pub msg_type: u8,
    /// Sender's sequence number (wrapping, one counter per direction).
    pub seq: u16,
    /// Payload, at most [`MAX_PAYLOAD`](crate::wire::MAX_PAYLOAD) bytes.
    pub payload: &'a [u8],
}

/// Writes the raw frame (header, payload, CRC) through COBS into `out`, then one delimiter.
///
/// Returns the number of bytes written (the wire length, delimiter included). The output is
/// exactly [`wire_len`](crate::wire::wire_len)`(payload.len())` bytes long.
pub fn encode_frame(
    msg_type: u8,
    seq: u16,
    payload: &[u8],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    if payload.len() > MAX_PAYLOAD {
        return Err(EncodeError::PayloadTooLarge { len: payload.len() });
    }
    let needed = crate::wire::wire_len(payload.len());
    if out.len() < needed {
        return Err(EncodeError::BufferTooSmall {
            needed,
            available: out.len(),
        });
    }
    let [s0, s1] = seq.to_le_bytes();
    let header = [VERSION, msg_type, s0, s1];
    let mut digest = CRC.digest();
    digest.update(&header);
    digest.update(payload);
    let crc = digest.finalize().to_le_bytes();

    let too_small = EncodeError::BufferTooSmall {
        needed,
        available: out.len(),
    };
    let (body, _) = out.split_at_mut(needed - 1);
    let mut enc = cobs::CobsEncoder::new(body);
    enc.push(&header).map_err(|_| too_small)?;
    enc.push(payload).map_err(|_| too_small)?;
    enc.push(&crc).map_err(|_| too_small)?;
    let n = enc.finalize();
    let delim = out.get_mut(n).ok_or(too_small)?;
    *delim = DELIMITER;
    Ok(n + 1)
}

/// [`encode_frame`] into a `heapless::Vec`, replacing its contents.
pub fn encode_frame_vec<const N: usize>(
    msg_type: u8,
    seq: u16,
    payload: &[u8],
    out: &mut heapless::Vec<u8, N>,
) -> Result<(), EncodeError> {
    out.clear();
    let needed = crate::wire::wire_len(payload.len().min(MAX_PAYLOAD));
    if out.resize(needed.min(N), 0).is_err() {
        // Unreachable: the length is clamped to the capacity.
        return Err(EncodeError::BufferTooSmall {
            needed,
            available: N,
        });
    }
    match encode_frame(msg_type, seq, payload, out.as_mut_slice()) {
        Ok(n) => {
            out.truncate(n);
            Ok(())
        }
        Err(e) => {
            out.clear();
            Err(e)
        }
    }
}

/// Encoder that owns the outgoing sequence counter of one direction.
#[derive(Clone, Debug, Default)]
pub struct FrameEncoder {
    next_seq: u16,
    frames: u32,
}

impl FrameEncoder {
    /// Starts at sequence number 0.
    pub const fn new() -> Self {
        Self {
            next_seq: 0,
            frames: 0,
        }
    }

    /// Encodes one frame with the next sequence number into `out`; returns the wire bytes.
    ///
    /// The sequence number is consumed only if encoding succeeds, so a failed encode does not
    /// look like a lost frame to the receiver.
    pub fn encode<'o>(
        &mut self,
        msg_type: u8,
        payload: &[u8],
        out: &'o mut [u8],
    ) -> Result<&'o [u8], EncodeError> {
        let n = encode_frame(msg_type, self.next_seq, payload, out)?;
        self.next_seq = self.next_seq.wrapping_add(1);
        self.frames = self.frames.wrapping_add(1);
        // `n <= out.len()` by construction of `encode_frame`; `get` keeps it panic-free.
        out.get(..n).ok_or(EncodeError::BufferTooSmall {
            needed: n,
            available: 0,
        })
    }

    /// Sequence number the next frame will carry.
    pub fn next_seq(&self) -> u16 {
        self.next_seq
    }

    /// Frames encoded so far (wrapping).
    pub fn frames(&self) -> u32 {
        self.frames
    }
}

/// Streaming frame decoder with an `N`-byte buffer for one encoded frame (delimiter excluded).
///
/// The default `N` = [`MAX_ENCODED_LEN`] accepts every legal frame. A smaller `N` rejects
/// frames with long payloads as [`FrameError::Oversized`]; a larger one gains nothing.
/// Empty chunks (consecutive delimiters) are idle fill and are ignored.
#[derive(Clone, Debug)]
pub struct FrameDecoder<const N: usize = MAX_ENCODED_LEN> {
    buf: [u8; N],
    len: usize,
    /// Set when the current chunk overflowed `buf`: drop bytes until the next delimiter.
    overflow: bool,
    stats: LinkStats,
    seq: SeqTracker,
}

impl<const N: usize> Default for FrameDecoder<N> {
    fn default() -> Self {
        Self::new()
    }
}

/// Result of [`FrameDecoder::feed`]: what happened and the input not yet consumed.
#[derive(Debug, PartialEq, Eq)]
pub enum Feed<'d, 'i> {
    /// All input was consumed without completing a chunk.
    Consumed,
    /// A valid frame; `remaining` is the input after its delimiter.
    Frame {
        /// The frame (borrowed from the decoder).
        frame: Frame<'d>,
        /// Input not yet fed.
        remaining: &'i [u8],
    },
    /// A rejected chunk (already counted); `remaining` is the input after its delimiter.
    Error {
        /// Why it was rejected.
        error: FrameError,
        /// Input not yet fed.
        remaining: &'i [u8],
    },
}

impl<const N: usize> FrameDecoder<N> {
    /// An empty decoder with zeroed counters.
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            len: 0,
            overflow: false,
            stats: LinkStats {
                frames_ok: 0,
                cobs_errors: 0,
                crc_errors: 0,
                too_short: 0,
                oversized: 0,
                unknown_version: 0,
                seq_gaps: 0,
                lost_frames: 0,
                seq_resets: 0,
                bytes: 0,
            },
            seq: SeqTracker::new(),
        }
    }

    /// Counters since creation (or the last [`FrameDecoder::reset_stats`]).
    pub fn stats(&self) -> &LinkStats {
        &self.stats
    }

    /// Zeroes the counters and forgets the expected sequence number.
    pub fn reset_stats(&mut self) {
        self.stats = LinkStats::default();
        self.seq = SeqTracker::new();
    }

    /// Bytes of an incomplete chunk currently buffered.
    pub fn pending(&self) -> usize {
        self.len
    }

    /// Feeds one byte. Returns `None` until a delimiter completes a non-empty chunk, then the
    /// frame or the (already counted) reason it was rejected.
    pub fn push(&mut self, byte: u8) -> Option<Result<Frame<'_>, FrameError>> {
        self.stats.bytes = self.stats.bytes.wrapping_add(1);
        if byte != DELIMITER {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = byte;
                self.len += 1;
            } else {
                self.overflow = true;
            }
            return None;
        }
        if self.len == 0 && !self.overflow {
            // Empty chunk (consecutive delimiters): idle fill, not an error.
            return None;
        }
        Some(self.finish_chunk())
    }

    /// Validates the buffered chunk after its delimiter and starts a new one.
    fn finish_chunk(&mut self) -> Result<Frame<'_>, FrameError> {
        let len = core::mem::take(&mut self.len);
        if core::mem::take(&mut self.overflow) {
            FrameError::Oversized.count_in(&mut self.stats);
            return Err(FrameError::Oversized);
        }
        match Self::check(self.buf.get_mut(..len).unwrap_or_default()) {
            Ok((msg_type, seq, payload)) => {
                self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                self.seq.observe(seq, &mut self.stats);
                Ok(Frame {
                    msg_type,
                    seq,
                    payload,
                })
            }
            Err(e) => {
                e.count_in(&mut self.stats);
                Err(e)
            }
        }
    }

    /// Feeds bytes until the first completed chunk (frame or error) or the end of `input`.
    ///
    /// Call again with `remaining` to continue; every byte is consumed exactly once.
    pub fn feed<'i>(&mut self, input: &'i [u8]) -> Feed<'_, 'i> {
        let mut rest = input;
        while let Some((&b, tail)) = rest.split_first() {
            rest = tail;
            if b == DELIMITER && (self.len != 0 || self.overflow) {
                self.stats.bytes = self.stats.bytes.wrapping_add(1);
                return match self.finish_chunk() {
                    Ok(frame) => Feed::Frame {
                        frame,
                        remaining: rest,
                    },
                    Err(error) => Feed::Error {
                        error,
                        remaining: rest,
                    },
                };
            }
            // A data byte or an idle delimiter: never completes a chunk.
            let _ = self.push(b);
        }
        Feed::Consumed
    }

    /// Decodes a delimiter-free chunk in place and validates it.
    fn check(chunk: &mut [u8]) -> Result<(u8, u16, &[u8]), FrameError> {
        let n = cobs_decode_in_place(chunk).ok_or(FrameError::Cobs)?;
        let raw = chunk.get(..n).ok_or(FrameError::Cobs)?;
        if raw.len() < MIN_RAW_LEN {
            return Err(FrameError::TooShort { len: raw.len() });
        }
        if raw.len() > MAX_RAW_LEN {
            return Err(FrameError::Oversized);
        }
        let (body, crc) = raw.split_at(raw.len() - CRC_LEN);
        let crc = u32::from_le_bytes(
            crc.try_into()
                .map_err(|_| FrameError::TooShort { len: raw.len() })?,
        );
        if CRC.checksum(body) != crc {
            return Err(FrameError::Crc);
        }
        let (header, payload) = body.split_at(HEADER_LEN);
        let &[version, msg_type, s0, s1] = header else {
            return Err(FrameError::TooShort { len: raw.len() });
        };
        if version != VERSION {
            return Err(FrameError::UnknownVersion { version });
        }
        Ok((msg_type, u16::from_le_bytes([s0, s1]), payload))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::{wire_len, MAX_WIRE_LEN};

    fn wire(msg_type: u8, seq: u16, payload: &[u8]) -> heapless::Vec<u8, MAX_WIRE_LEN> {
        let mut v = heapless::Vec::new();
        encode_frame_vec(msg_type, seq, payload, &mut v).unwrap();
        v
    }

    #[test]
    fn roundtrip_all_lengths() {
        let mut payload = [0u8; MAX_PAYLOAD];
        for (i, b) in payload.iter_mut().enumerate() {
            // Include zeros so COBS has work to do.
            *b = (i % 7) as u8;
        }
        let mut dec = FrameDecoder::<MAX_ENCODED_LEN>::new();
        for len in 0..=MAX_PAYLOAD {
            let w = wire(0x42, len as u16, &payload[..len]);
            assert_eq!(w.len(), wire_len(len));
            assert_eq!(w.iter().filter(|&&b| b == 0).count(), 1);
            let (last, head) = w.split_last().unwrap();
            for &b in head {
                assert!(dec.push(b).is_none());
            }
            let f = dec.push(*last).unwrap().unwrap();
            assert_eq!(
                (f.msg_type, f.seq, f.payload),
                (0x42, len as u16, &payload[..len])
            );
        }
        assert_eq!(dec.stats().frames_ok, MAX_PAYLOAD as u32 + 1);
        assert_eq!(dec.stats().rejected(), 0);
        assert_eq!(dec.stats().lost_frames, 0);
    }

    #[test]
    fn encode_errors() {
        let mut small = [0u8; 10];
        assert_eq!(
            encode_frame(1, 0, &[1, 2], &mut small),
            Err(EncodeError::BufferTooSmall {
                needed: 12,
                available: 10
            })
        );
        let big = [0u8; MAX_PAYLOAD + 1];
        let mut out = [0u8; 400];
        assert_eq!(
            encode_frame(1, 0, &big, &mut out),
            Err(EncodeError::PayloadTooLarge {
                len: MAX_PAYLOAD + 1
            })
        );
        let mut v: heapless::Vec<u8, 16> = heapless::Vec::new();
        assert!(encode_frame_vec(1, 0, &[7; 20], &mut v).is_err());
        assert!(v.is_empty());
        let mut enc = FrameEncoder::new();
        assert!(enc.encode(1, &[7; 20], &mut small).is_err());
        assert_eq!(enc.next_seq(), 0);
    }

    #[test]
    fn every_single_bit_flip_is_rejected() {
        let w = wire(3, 0xBEEF, b"\x00hello\x00\x00world\xff");
        for i in 0..w.len() - 1 {
            for bit in 0..8 {
                let mut bad = w.clone();
                bad[i] ^= 1 << bit;
                let mut dec = FrameDecoder::<MAX_ENCODED_LEN>::new();
                for &b in &bad {
                    if let Some(r) = dec.push(b) {
                        assert!(r.is_err(), "flip {i}.{bit} accepted");
                    }
                }
                assert_eq!(dec.stats().frames_ok, 0);
            }
        }
    }

    #[test]
    fn classification_and_resync() {
        let mut dec = FrameDecoder::<MAX_ENCODED_LEN>::new();
        let good = wire(2, 0, b"abc");
        // Oversized junk, then a good frame.
        for _ in 0..300 {
            assert!(dec.push(0x55).is_none());
        }
        assert_eq!(dec.push(0), Some(Err(FrameError::Oversized)));
        // Truncated frame: first 5 bytes then a delimiter (COBS block overruns).
        for &b in &good[..5] {
            dec.push(b);
        }
        assert_eq!(dec.push(0), Some(Err(FrameError::Cobs)));
        // Too short but valid COBS.
        for &b in &[3u8, 1, 2] {
            dec.push(b);
        }
        assert_eq!(dec.push(0), Some(Err(FrameError::TooShort { len: 2 })));
        // CRC error: flip a payload bit.
        let mut bad = good.clone();
        bad[6] ^= 0x10;
        let mut errs = 0;
        for &b in &bad {
            if let Some(r) = dec.push(b) {
                assert_eq!(r, Err(FrameError::Crc));
                errs += 1;
            }
        }
        assert_eq!(errs, 1);
        // Unknown version with a valid CRC.
        let mut raw = [9u8, 2, 0, 0, 0, 0, 0, 0];
        let crc = CRC.checksum(&raw[..4]).to_le_bytes();
        raw[4..].copy_from_slice(&crc);
        let mut enc = [0u8; 16];
        let n = cobs::encode(&raw, &mut enc);
        for &b in &enc[..n] {
            dec.push(b);
        }
        assert_eq!(
            dec.push(0),
            Some(Err(FrameError::UnknownVersion { version: 9 }))
        );
        // Empty chunks are idle fill.
        assert!(dec.push(0).is_none());
        // And the good frame still comes through.
        match dec.feed(&good) {
            Feed::Frame { frame, remaining } => {
                assert_eq!(frame.payload, b"abc");
                assert!(remaining.is_empty());
            }
            other => panic!("{other:?}"),
        }
        let s = *dec.stats();
        assert_eq!(
            (
                s.frames_ok,
                s.oversized,
                s.cobs_errors,
                s.too_short,
                s.crc_errors,
                s.unknown_version
            ),
            (1, 1, 1, 1, 1, 1)
        );
    }

    #[test]
    fn sequence_gaps() {
        let mut dec = FrameDecoder::<MAX_ENCODED_LEN>::new();
        let mut stream: heapless::Vec<u8, 2048> = heapless::Vec::new();
        for seq in [65533u16, 65534, 65535, 0, 3, 4, 9, 2] {
            stream.extend_from_slice(&wire(1, seq, &[])).unwrap();
        }
        let mut rest: &[u8] = &stream;
        let mut n = 0;
        loop {
            match dec.feed(rest) {
                Feed::Frame { remaining, .. } => {
                    n += 1;
                    rest = remaining;
                }
                Feed::Error { error, .. } => panic!("{error}"),
                Feed::Consumed => break,
            }
        }
        assert_eq!(n, 8);
        let s = dec.stats();
        // 0 -> 3 loses 2, 4 -> 9 loses 4; 9 -> 2 is a reset.
        assert_eq!((s.seq_gaps, s.lost_frames, s.seq_resets), (2, 6, 1));
        assert_eq!(s.bytes as usize, stream.len());
    }

    #[test]
    fn small_buffer_rejects_big_frames_then_recovers() {
        let mut dec = FrameDecoder::<16>::new();
        let big = wire(1, 0, &[0xAA; 40]);
        let small = wire(1, 1, &[0xBB; 4]);
        let mut got = 0;
        for &b in big.iter().chain(small.iter()) {
            match dec.push(b) {
                Some(Ok(f)) => {
                    assert_eq!(f.payload, &[0xBB; 4]);
                    got += 1;
                }
                Some(Err(e)) => assert_eq!(e, FrameError::Oversized),
                None => {}
            }
        }
        assert_eq!(got, 1);
        assert_eq!(dec.stats().oversized, 1);
    }
}
