//! A byte stream with file offsets and bounded look-ahead, under the ULog and DataFlash readers.
//!
//! Why not `std::io::BufReader` alone: the readers need a whole record (up to 3 + 65 535 bytes
//! for ULog) contiguous in memory, the byte offset of every record for their errors and notes,
//! and to scan forward byte by byte when resynchronising after corrupt data; `BufReader` cannot
//! guarantee `n` contiguous bytes. This keeps one fixed buffer of [`CAPACITY`] bytes: memory
//! stays bounded whatever the file's size.

use std::io::{ErrorKind, Read};

/// Largest buffer (bytes): the longest record either format can hold (3 + `u16::MAX`),
/// rounded up.
pub const CAPACITY: usize = 1 << 17;

/// First buffer size (bytes): the buffer grows to [`CAPACITY`] only when a record needs it,
/// so that a small input costs a small allocation.
const INITIAL: usize = 1 << 13;

/// Reads `inner` through a fixed buffer, counting the offset of the next unread byte.
#[derive(Debug)]
pub struct ByteStream<R> {
    inner: R,
    buf: Vec<u8>,
    start: usize,
    end: usize,
    offset: u64,
    eof: bool,
}

impl<R: Read> ByteStream<R> {
    /// A stream at offset 0 of `inner`.
    pub fn new(inner: R) -> Self {
        Self {
            inner,
            buf: vec![0; INITIAL],
            start: 0,
            end: 0,
            offset: 0,
            eof: false,
        }
    }

    /// Offset (bytes from the start of the input) of the next unread byte.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// The next `n` bytes (at most [`CAPACITY`]) without consuming them; fewer only at the
    /// end of the input.
    pub fn peek(&mut self, n: usize) -> std::io::Result<&[u8]> {
        let n = n.min(CAPACITY);
        if self.end - self.start < n && !self.eof {
            if self.start + n > self.buf.len() {
                self.buf.copy_within(self.start..self.end, 0);
                self.end -= self.start;
                self.start = 0;
            }
            if n > self.buf.len() {
                let grown = n.max(2 * self.buf.len()).min(CAPACITY);
                self.buf.resize(grown, 0);
            }
            while self.end - self.start < n {
                match self.inner.read(&mut self.buf[self.end..]) {
                    Ok(0) => {
                        self.eof = true;
                        break;
                    }
                    Ok(k) => self.end += k,
                    Err(e) if e.kind() == ErrorKind::Interrupted => {}
                    Err(e) => return Err(e),
                }
            }
        }
        let avail = (self.end - self.start).min(n);
        Ok(&self.buf[self.start..self.start + avail])
    }

    /// Consumes up to `n` bytes already made available by [`Self::peek`].
    pub fn consume(&mut self, n: usize) {
        let n = n.min(self.end - self.start);
        self.start += n;
        self.offset += n as u64;
    }

    /// Consumes `n` bytes, reading them as needed (for skipping a record whatever its size);
    /// returns how many were there before the end of the input.
    pub fn skip(&mut self, mut n: u64) -> std::io::Result<u64> {
        let mut done = 0;
        while n > 0 {
            let want = usize::try_from(n).unwrap_or(CAPACITY).min(CAPACITY);
            let got = self.peek(want)?.len();
            if got == 0 {
                break;
            }
            self.consume(got);
            done += got as u64;
            n -= got as u64;
        }
        Ok(done)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader that gives at most 3 bytes per call, as a pipe might.
    struct Trickle<'a>(&'a [u8]);
    impl Read for Trickle<'_> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            let n = self.0.len().min(out.len()).min(3);
            out[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    #[test]
    fn peeks_whole_windows_across_refills_and_counts_offsets() {
        let data: Vec<u8> = (0..3 * CAPACITY).map(|k| (k % 251) as u8).collect();
        let mut s = ByteStream::new(Trickle(&data));
        let mut at = 0usize;
        for step in [1usize, 70_000, CAPACITY, 5, CAPACITY - 3] {
            let w = s.peek(step).expect("reads").to_vec();
            assert_eq!(w.len(), step);
            assert_eq!(w, data[at..at + step]);
            s.consume(step);
            at += step;
            assert_eq!(s.offset(), at as u64);
        }
        let left = (data.len() - at) as u64;
        assert_eq!(s.skip(u64::MAX).expect("reads"), left);
        assert_eq!(s.offset(), data.len() as u64);
        assert!(s.peek(10).expect("reads").is_empty());
    }
}
