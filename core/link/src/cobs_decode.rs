//! COBS decoding without a panic path (encoding stays with the `cobs` crate).

/// COBS-decodes `buf` (up to its first `0x00`, if any) in place; returns the decoded length,
/// `None` for an empty or invalid chunk (a block that runs past the end).
///
/// The same result as `cobs::decode_in_place` (the `cobs` crate still encodes), written here
/// with checked accesses only: the crate's decoder indexes the buffer, which leaves a bounds
/// check, i.e. a panic path, in every firmware's receive loop (found by the firmware's ELF
/// inspection, `scripts/no_panic.py`).
pub(crate) fn cobs_decode_in_place(buf: &mut [u8]) -> Option<usize> {
    if buf.is_empty() {
        return None;
    }
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    let (mut src, mut dst) = (0usize, 0usize);
    while src < end {
        let code = usize::from(*buf.get(src)?);
        if src + code > end && code != 1 {
            return None;
        }
        src += 1;
        for _ in 1..code {
            let b = *buf.get(src)?;
            *buf.get_mut(dst)? = b;
            src += 1;
            dst += 1;
        }
        if code != 0xFF && src < end {
            *buf.get_mut(dst)? = 0;
            dst += 1;
        }
    }
    Some(dst)
}

#[cfg(test)]
mod tests {
    #[test]
    fn own_cobs_decoder_agrees_with_the_cobs_crate() {
        extern crate std;
        // Every chunk of up to 3 bytes, and pseudo-random longer ones.
        let mut chunks: std::vec::Vec<std::vec::Vec<u8>> = std::vec::Vec::new();
        for a in 0..=255u8 {
            chunks.push(std::vec![a]);
            for b in [0u8, 1, 2, 3, 254, 255] {
                chunks.push(std::vec![a, b]);
                for c in [0u8, 1, 2, 255] {
                    chunks.push(std::vec![a, b, c]);
                }
            }
        }
        let mut x = 0x1234_5678u32;
        for len in 1..300 {
            let mut v = std::vec::Vec::new();
            for _ in 0..len {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                v.push(if x.is_multiple_of(7) {
                    (x >> 8) as u8 % 4
                } else {
                    (x >> 8) as u8
                });
            }
            chunks.push(v);
        }
        for c in chunks {
            let (mut a, mut b) = (c.clone(), c.clone());
            let theirs = cobs::decode_in_place(&mut a).ok();
            let ours = super::cobs_decode_in_place(&mut b);
            assert_eq!(ours, theirs, "{c:?}");
            if let Some(n) = ours {
                assert_eq!(a[..n], b[..n], "{c:?}");
            }
        }
    }
}
