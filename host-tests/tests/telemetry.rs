//! Property tests of `rotorid_link` framing.

use proptest::prelude::*;
use rotorid_link::msg::Payload;
use rotorid_link::{
    encode_frame, FrameDecoder, FrameError, MAX_ENCODED_LEN, MAX_PAYLOAD, MAX_WIRE_LEN,
};

fn wire(t: u8, seq: u16, p: &[u8]) -> Vec<u8> {
    let mut w = [0u8; MAX_WIRE_LEN];
    let n = encode_frame(t, seq, p, &mut w).expect("fits");
    w[..n].to_vec()
}

/// Every frame and error the decoder yields for `bytes`, frames as owned tuples.
#[allow(clippy::type_complexity)]
fn decode_all(dec: &mut FrameDecoder, bytes: &[u8]) -> (Vec<(u8, u16, Vec<u8>)>, Vec<FrameError>) {
    let (mut frames, mut errors) = (Vec::new(), Vec::new());
    for &b in bytes {
        match dec.push(b) {
            Some(Ok(f)) => frames.push((f.msg_type, f.seq, f.payload.to_vec())),
            Some(Err(e)) => errors.push(e),
            None => {}
        }
    }
    (frames, errors)
}

fn payload() -> impl Strategy<Value = Vec<u8>> {
    // Bias towards zeros so COBS blocks are short and varied.
    prop::collection::vec(prop_oneof![Just(0u8), any::<u8>()], 0..=MAX_PAYLOAD)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn roundtrip_stream(frames in prop::collection::vec((any::<u8>(), payload()), 1..8),
                        start in any::<u16>(), chunk in 1usize..64) {
        let mut stream = Vec::new();
        for (i, (t, p)) in frames.iter().enumerate() {
            stream.extend(wire(*t, start.wrapping_add(i as u16), p));
        }
        // Feed in arbitrary slices through the slice API.
        let mut dec: FrameDecoder = FrameDecoder::new();
        let mut got = Vec::new();
        for piece in stream.chunks(chunk) {
            let mut rest = piece;
            loop {
                match dec.feed(rest) {
                    rotorid_link::Feed::Consumed => break,
                    rotorid_link::Feed::Frame { frame, remaining } => {
                        got.push((frame.msg_type, frame.seq, frame.payload.to_vec()));
                        rest = remaining;
                    }
                    rotorid_link::Feed::Error { error, .. } => {
                        prop_assert!(false, "unexpected {error}")
                    }
                }
            }
        }
        let want: Vec<_> = frames.iter().enumerate()
            .map(|(i, (t, p))| (*t, start.wrapping_add(i as u16), p.clone())).collect();
        prop_assert_eq!(got, want);
        prop_assert_eq!(dec.stats().lost_frames, 0);
        prop_assert_eq!(dec.stats().bytes as usize, stream.len());
    }

    #[test]
    fn any_single_bit_flip_is_rejected(t in any::<u8>(), seq in any::<u16>(), p in payload(),
                                       pos in any::<prop::sample::Index>(), bit in 0u8..8) {
        let mut w = wire(t, seq, &p);
        // Flip anywhere, the delimiter included.
        let i = pos.index(w.len());
        w[i] ^= 1 << bit;
        let mut dec: FrameDecoder = FrameDecoder::new();
        let (frames, _) = decode_all(&mut dec, &w);
        prop_assert!(frames.is_empty());
        // And the next good frame still comes through.
        let (frames, _) = decode_all(&mut dec, &[&[0u8][..], &wire(1, 2, b"ok")].concat());
        prop_assert_eq!(frames, vec![(1u8, 2u16, b"ok".to_vec())]);
    }

    /// Random bytes never produce a frame: a random chunk passes the CRC with probability
    /// 2^-32 (and only after also being valid COBS of 8..=248 bytes), so across this test's
    /// few thousand chunks a false accept has odds below 10^-6; a failure would print the
    /// (reproducible) input.
    #[test]
    fn random_bytes_never_yield_a_frame(bytes in prop::collection::vec(any::<u8>(), 0..2000)) {
        let mut dec: FrameDecoder = FrameDecoder::new();
        let (frames, errors) = decode_all(&mut dec, &bytes);
        prop_assert!(frames.is_empty(), "{frames:?}");
        prop_assert_eq!(errors.len() as u32, dec.stats().rejected());
    }

    #[test]
    fn truncation_and_oversize_are_counted_then_recovered(p in payload(), cut in any::<prop::sample::Index>(),
                                                         junk in 250usize..1000) {
        let w = wire(5, 10, &p);
        let cut = 1 + cut.index(w.len() - 2); // keep at least one byte, drop at least one
        let mut stream = w[..cut].to_vec();
        stream.push(0);
        stream.extend(std::iter::repeat_n(0x5A, junk));
        stream.push(0);
        stream.extend(wire(6, 11, b"next"));
        let mut dec = FrameDecoder::<MAX_ENCODED_LEN>::new();
        let (frames, errors) = decode_all(&mut dec, &stream);
        prop_assert_eq!(frames, vec![(6u8, 11u16, b"next".to_vec())]);
        prop_assert_eq!(errors.len(), 2);
        prop_assert_eq!(errors[1], FrameError::Oversized);
        // A cut frame is either bad COBS, too short or fails the CRC, never accepted.
        let first_ok = matches!(errors[0], FrameError::Cobs | FrameError::TooShort { .. } | FrameError::Crc);
        prop_assert!(first_ok, "{:?}", errors[0]);
        let s = dec.stats();
        prop_assert_eq!((s.oversized, s.frames_ok, s.rejected()), (1, 1, 2));
    }

    #[test]
    fn lost_frames_are_counted(drops in prop::collection::vec(any::<bool>(), 2..40)) {
        let mut stream = Vec::new();
        let mut sent = Vec::new();
        for (i, &drop) in drops.iter().enumerate() {
            if !drop || i == 0 {
                stream.extend(wire(1, i as u16, &[]));
                sent.push(i);
            }
        }
        let expected_lost = sent.last().map_or(0, |&l| l + 1 - sent.len());
        let mut dec: FrameDecoder = FrameDecoder::new();
        decode_all(&mut dec, &stream);
        prop_assert_eq!(dec.stats().lost_frames as usize, expected_lost);
    }
}

/// Found by `scripts/fuzz.sh` (target `messages`): an `Estimate` whose `error` had code 0 (none)
/// with non-zero unused fields, and whose innovation floats were non-zero without the
/// innovation flag, parsed into a value that wrote back to other bytes. Only the canonical
/// encoding is accepted now.
#[test]
fn fuzz_regression_non_canonical_estimate_is_refused() {
    let hex = "01000000000000000000000000000000003100000000c7000000000000000000000000000000000000000000000000520000000000000000c7c7c7c7bfbfbfc7c7c7c7c7c7c72fc7c7c7c7c7c7c700000000000000000000000000a900000000000000000000ffffffffffffffffffffffffffff0000000000000000000000000000000000000000000000000000000000000000000000000000000000000003007a000000008e69000000";
    let bytes: Vec<u8> = (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
        .collect();
    assert!(rotorid_link::msg::Estimate::read(&bytes).is_err());
}

/// Found by `scripts/fuzz.sh` (target `messages`): a `ParamsChunk` of 287 bytes, more words than
/// a frame carries, parsed although no writer could send it. Chunks longer than a frame's
/// payload are refused now (`DataChunk` likewise).
#[test]
fn fuzz_regression_oversized_chunks_are_refused() {
    use rotorid_link::msg::ParamsChunk;
    // ident 1, model 0, field 0, index 0, total 0xffff; then 70 words, 58 fit a frame.
    let mut payload = vec![1u8, 0, 0, 0, 0, 0xff, 0xff];
    assert_eq!(payload.len(), ParamsChunk::HEADER);
    payload.extend(std::iter::repeat_n(
        0x75u8,
        4 * (ParamsChunk::MAX_WORDS + 12),
    ));
    assert!(ParamsChunk::read(&payload).is_err());
    payload.truncate(ParamsChunk::HEADER + 4 * ParamsChunk::MAX_WORDS);
    assert!(ParamsChunk::read(&payload).is_ok());
    let mut data = vec![0u8; 13];
    data[5..9].copy_from_slice(&u32::MAX.to_le_bytes()); // total
    data.extend(std::iter::repeat_n(
        0u8,
        rotorid_link::msg::DataChunk::MAX_DATA + 1,
    ));
    assert!(rotorid_link::msg::DataChunk::read(&data).is_err());
}
