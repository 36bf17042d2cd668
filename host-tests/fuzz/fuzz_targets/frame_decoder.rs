//! Arbitrary bytes into the frame decoder: it never panics, every delivered frame re-encodes
//! to a frame that decodes to itself, and the statistics account for every byte.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_link::{encode_frame, FrameDecoder, MAX_WIRE_LEN};

fuzz_target!(|data: &[u8]| {
    let mut rx: FrameDecoder = FrameDecoder::new();
    let mut wire = [0u8; MAX_WIRE_LEN];
    for &b in data {
        if let Some(Ok(f)) = rx.push(b) {
            let (t, s, p) = (f.msg_type, f.seq, f.payload.to_vec());
            let n = encode_frame(t, s, &p, &mut wire).expect("a delivered frame re-encodes");
            let mut again: FrameDecoder = FrameDecoder::new();
            let mut back = None;
            for &c in &wire[..n] {
                if let Some(Ok(g)) = again.push(c) {
                    back = Some((g.msg_type, g.seq, g.payload.to_vec()));
                }
            }
            assert_eq!(back, Some((t, s, p)));
        }
    }
    assert_eq!(rx.stats().bytes as usize, data.len());
});
