//! The link at scale: random valid frames through a channel with bit errors (rate 1e-3),
//! truncations and bursts of random bytes. No corrupted frame is accepted, every lost frame
//! is counted, and the receiver resynchronises at the next intact frame.
//!
//! CI runs 100 000 frames in release builds (20 000 in debug builds); the full campaign (1 000 000 and more) is
//! `ROTORID_LINK_FRAMES=1000000 cargo test --release -p host-tests --test integration link_at_scale:: -- --nocapture`.

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorid_link::{FrameDecoder, FrameEncoder, MAX_PAYLOAD, MAX_WIRE_LEN};

/// Bit error rate of the channel.
const BER: f64 = 1e-3;
/// Probability that a frame is cut short (its tail, delimiter included, never arrives).
const TRUNCATION: f64 = 0.01;
/// Probability of a burst of random bytes (any value, 0x00 included) after a frame.
const GARBAGE: f64 = 0.005;

struct Sent {
    msg_type: u8,
    seq: u16,
    payload: Vec<u8>,
    /// Offset of its first byte in the channel stream.
    start: usize,
    /// Whether its bytes (delimiter included) crossed the channel untouched.
    intact: bool,
}

fn frames() -> usize {
    std::env::var("ROTORID_LINK_FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(if cfg!(debug_assertions) {
            20_000
        } else {
            100_000
        })
}

#[test]
fn no_corrupted_frame_is_accepted_every_loss_is_counted_and_the_link_resynchronises() {
    let n = frames();
    let mut rng = ChaCha8Rng::seed_from_u64(0x0001_14e5_ca1e);
    let mut tx = FrameEncoder::new();
    let mut wire = [0u8; MAX_WIRE_LEN];
    let mut channel: Vec<u8> = Vec::new();
    let mut sent: Vec<Sent> = Vec::with_capacity(n);
    let (mut flipped_bits, mut truncated, mut bursts) = (0u64, 0u64, 0u64);
    for k in 0..n {
        let len = rng.random_range(0..=MAX_PAYLOAD);
        let payload: Vec<u8> = (0..len).map(|_| rng.random()).collect();
        let msg_type = rng.random_range(1..=0x7f);
        let seq = tx.next_seq();
        let mut bytes = tx.encode(msg_type, &payload, &mut wire).unwrap().to_vec();
        // The first and last frames cross cleanly (the first sets the receiver's baseline), so
        // that every loss between them is visible in `seq`.
        let last = k == 0 || k + 1 == n;
        let mut intact = true;
        if !last {
            if rng.random_bool(TRUNCATION) {
                bytes.truncate(rng.random_range(0..bytes.len()));
                truncated += 1;
                intact = false;
            }
            for b in &mut bytes {
                for bit in 0..8 {
                    if rng.random_bool(BER) {
                        *b ^= 1 << bit;
                        flipped_bits += 1;
                        intact = false;
                    }
                }
            }
        }
        sent.push(Sent {
            msg_type,
            seq,
            payload,
            start: channel.len(),
            intact,
        });
        channel.extend_from_slice(&bytes);
        if !last && rng.random_bool(GARBAGE) {
            let burst = rng.random_range(1..300);
            channel.extend((0..burst).map(|_| rng.random::<u8>()));
            bursts += 1;
        }
    }

    let mut rx: FrameDecoder = FrameDecoder::new();
    let mut delivered: Vec<usize> = Vec::new();
    let mut next = 0usize; // index of the first sent frame not yet matched
    let mut corrupted_accepted = 0u64;
    for &b in &channel {
        if let Some(Ok(f)) = rx.push(b) {
            // A delivered frame must be one of those sent, in order: the first later frame
            // with its sequence number, with exactly its type and payload.
            let found = (next..sent.len().min(next + 60_000)).find(|&i| sent[i].seq == f.seq);
            match found {
                Some(i) if sent[i].msg_type == f.msg_type && sent[i].payload == f.payload => {
                    delivered.push(i);
                    next = i + 1;
                }
                _ => corrupted_accepted += 1,
            }
        }
    }
    let stats = *rx.stats();
    let lost = n - delivered.len();
    eprintln!(
        "{n} frames, {} bytes: {flipped_bits} bits flipped, {truncated} truncated, {bursts} garbage bursts; \
         delivered {}, lost {lost}; stats {stats:?}",
        channel.len(),
        delivered.len()
    );
    assert_eq!(corrupted_accepted, 0, "corrupted frames accepted");
    assert_eq!(stats.frames_ok as usize, delivered.len());
    // Every loss is counted: the sequence numbers account for each frame that did not arrive
    // (the first and last frames arrived, and no gap reaches half the sequence space).
    assert_eq!(delivered.first(), Some(&0));
    assert_eq!(delivered.last(), Some(&(n - 1)));
    assert_eq!(stats.lost_frames as usize, lost);
    assert_eq!(stats.seq_resets, 0);
    // Every undelivered frame left a rejected chunk behind (or merged into one).
    let rejected = stats.cobs_errors + stats.crc_errors + stats.too_short + stats.oversized;
    assert!(rejected > 0 && (rejected as usize) <= lost + bursts as usize * 300);
    // Resynchronisation: every frame that crossed intact right after a delimiter arrived.
    for (i, s) in sent.iter().enumerate() {
        let after_delimiter = s.start == 0 || channel[s.start - 1] == 0;
        if s.intact && after_delimiter {
            assert!(delivered.binary_search(&i).is_ok(), "intact frame {i} lost");
        }
    }
    // The channel really was hostile.
    assert!(lost > n / 4, "only {lost} of {n} lost");
}

#[test]
fn random_bytes_alone_never_make_a_frame() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut rx: FrameDecoder = FrameDecoder::new();
    let mut accepted = 0;
    let n = if cfg!(debug_assertions) {
        400_000
    } else {
        2_000_000
    };
    for _ in 0..n {
        if let Some(Ok(_)) = rx.push(rng.next_u32() as u8) {
            accepted += 1;
        }
    }
    assert_eq!(accepted, 0, "{:?}", rx.stats());
}
