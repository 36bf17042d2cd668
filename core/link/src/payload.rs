//! Little-endian payload writer and reader over byte slices.
//!
//! Floats travel as their IEEE-754 bit patterns (`to_bits`/`from_bits`), so a value read back
//! is bit-identical to the value written, NaN payloads and signed zeros included.

use core::fmt;

/// Why a payload could not be written or read.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PayloadError {
    /// The writer's buffer is full.
    Overflow {
        /// Bytes the failed put needed.
        needed: usize,
        /// Bytes that were left.
        remaining: usize,
    },
    /// The reader ran out of bytes.
    Underflow {
        /// Bytes the failed get needed.
        needed: usize,
        /// Bytes that were left.
        remaining: usize,
    },
    /// The payload is longer than the message it should hold.
    TrailingBytes {
        /// Bytes left over.
        extra: usize,
    },
    /// A field holds a value the message does not allow (e.g. an unknown enum code).
    InvalidValue,
}

impl fmt::Display for PayloadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Overflow { needed, remaining } => {
                write!(f, "payload full: need {needed} B, {remaining} B left")
            }
            Self::Underflow { needed, remaining } => {
                write!(f, "payload too short: need {needed} B, {remaining} B left")
            }
            Self::TrailingBytes { extra } => write!(f, "{extra} unexpected trailing payload bytes"),
            Self::InvalidValue => f.write_str("invalid field value"),
        }
    }
}

impl core::error::Error for PayloadError {}

/// Appends little-endian values to a byte slice. A failed put writes nothing.
#[derive(Debug)]
pub struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
}

impl<'a> Writer<'a> {
    /// Writes from the start of `buf`.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    /// Bytes written so far.
    pub fn len(&self) -> usize {
        self.pos
    }

    /// True if nothing was written.
    pub fn is_empty(&self) -> bool {
        self.pos == 0
    }

    /// Bytes still free.
    pub fn remaining(&self) -> usize {
        self.buf.len().saturating_sub(self.pos)
    }

    /// The bytes written so far.
    pub fn written(&self) -> &[u8] {
        self.buf.get(..self.pos).unwrap_or_default()
    }

    /// Consumes the writer, returning the written prefix of the buffer.
    pub fn into_written(self) -> &'a [u8] {
        let pos = self.pos;
        let buf: &'a [u8] = self.buf;
        buf.get(..pos).unwrap_or_default()
    }

    /// Appends raw bytes.
    pub fn put_bytes(&mut self, bytes: &[u8]) -> Result<(), PayloadError> {
        let remaining = self.remaining();
        let dst = self
            .pos
            .checked_add(bytes.len())
            .and_then(|end| self.buf.get_mut(self.pos..end))
            .ok_or(PayloadError::Overflow {
                needed: bytes.len(),
                remaining,
            })?;
        // Element by element: `copy_from_slice` keeps a length check (a panic path) that the
        // compiler cannot drop although `dst` has exactly `bytes.len()` entries.
        for (d, &b) in dst.iter_mut().zip(bytes) {
            *d = b;
        }
        self.pos += bytes.len();
        Ok(())
    }

    /// Appends a `u8`.
    pub fn put_u8(&mut self, v: u8) -> Result<(), PayloadError> {
        self.put_bytes(&[v])
    }

    /// Appends an `i8`.
    pub fn put_i8(&mut self, v: i8) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends a little-endian `u16`.
    pub fn put_u16(&mut self, v: u16) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends a little-endian `i16`.
    pub fn put_i16(&mut self, v: i16) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends a little-endian `u32`.
    pub fn put_u32(&mut self, v: u32) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends a little-endian `i32`.
    pub fn put_i32(&mut self, v: i32) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends a little-endian `u64`.
    pub fn put_u64(&mut self, v: u64) -> Result<(), PayloadError> {
        self.put_bytes(&v.to_le_bytes())
    }

    /// Appends an `f32` as its little-endian IEEE-754 bit pattern.
    pub fn put_f32(&mut self, v: f32) -> Result<(), PayloadError> {
        self.put_u32(v.to_bits())
    }

    /// Appends an `f64` as its little-endian IEEE-754 bit pattern.
    pub fn put_f64(&mut self, v: f64) -> Result<(), PayloadError> {
        self.put_u64(v.to_bits())
    }
}

/// Reads little-endian values from a byte slice. A failed get consumes nothing.
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    buf: &'a [u8],
}

impl<'a> Reader<'a> {
    /// Reads from the start of `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        Self { buf }
    }

    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.buf.len()
    }

    /// The unread bytes.
    pub fn rest(&self) -> &'a [u8] {
        self.buf
    }

    /// Succeeds only if every byte was read (messages have fixed layouts).
    pub fn finish(&self) -> Result<(), PayloadError> {
        match self.buf.len() {
            0 => Ok(()),
            extra => Err(PayloadError::TrailingBytes { extra }),
        }
    }

    /// Takes the next `n` bytes.
    pub fn get_bytes(&mut self, n: usize) -> Result<&'a [u8], PayloadError> {
        if n > self.buf.len() {
            return Err(PayloadError::Underflow {
                needed: n,
                remaining: self.buf.len(),
            });
        }
        let (head, tail) = self.buf.split_at(n);
        self.buf = tail;
        Ok(head)
    }

    fn get_array<const K: usize>(&mut self) -> Result<[u8; K], PayloadError> {
        let remaining = self.buf.len();
        let (head, tail) = self
            .buf
            .split_first_chunk::<K>()
            .ok_or(PayloadError::Underflow {
                needed: K,
                remaining,
            })?;
        self.buf = tail;
        Ok(*head)
    }

    /// Reads a `u8`.
    pub fn get_u8(&mut self) -> Result<u8, PayloadError> {
        self.get_array::<1>().map(u8::from_le_bytes)
    }

    /// Reads an `i8`.
    pub fn get_i8(&mut self) -> Result<i8, PayloadError> {
        self.get_array::<1>().map(i8::from_le_bytes)
    }

    /// Reads a little-endian `u16`.
    pub fn get_u16(&mut self) -> Result<u16, PayloadError> {
        self.get_array().map(u16::from_le_bytes)
    }

    /// Reads a little-endian `i16`.
    pub fn get_i16(&mut self) -> Result<i16, PayloadError> {
        self.get_array().map(i16::from_le_bytes)
    }

    /// Reads a little-endian `u32`.
    pub fn get_u32(&mut self) -> Result<u32, PayloadError> {
        self.get_array().map(u32::from_le_bytes)
    }

    /// Reads a little-endian `i32`.
    pub fn get_i32(&mut self) -> Result<i32, PayloadError> {
        self.get_array().map(i32::from_le_bytes)
    }

    /// Reads a little-endian `u64`.
    pub fn get_u64(&mut self) -> Result<u64, PayloadError> {
        self.get_array().map(u64::from_le_bytes)
    }

    /// Reads an `f32` from its little-endian bit pattern.
    pub fn get_f32(&mut self) -> Result<f32, PayloadError> {
        self.get_u32().map(f32::from_bits)
    }

    /// Reads an `f64` from its little-endian bit pattern.
    pub fn get_f64(&mut self) -> Result<f64, PayloadError> {
        self.get_u64().map(f64::from_bits)
    }
}

/// A value with a fixed-size little-endian layout inside a payload: the building block of the
/// message layouts (a message's field list is a sequence of `Field`s).
pub trait Field: Sized {
    /// Encoded size, in bytes.
    const LEN: usize;
    /// Appends the value.
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError>;
    /// Reads a value; [`PayloadError::InvalidValue`] if the bytes are not one this type allows.
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError>;
}

/// `Field` for scalars through the matching `Writer::put_*` / `Reader::get_*` pair.
macro_rules! scalar_field {
    ($($t:ty: $put:ident, $get:ident;)+) => {$(
        impl Field for $t {
            const LEN: usize = core::mem::size_of::<$t>();
            fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
                w.$put(*self)
            }
            fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
                r.$get()
            }
        }
    )+};
}

scalar_field! {
    u8: put_u8, get_u8;
    i8: put_i8, get_i8;
    u16: put_u16, get_u16;
    i16: put_i16, get_i16;
    u32: put_u32, get_u32;
    i32: put_i32, get_i32;
    u64: put_u64, get_u64;
    f32: put_f32, get_f32;
    f64: put_f64, get_f64;
}

/// Arrays travel element by element, in index order.
impl<T: Field + Copy + Default, const N: usize> Field for [T; N] {
    const LEN: usize = N * T::LEN;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        self.iter().try_for_each(|v| v.put(w))
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        let mut a = [T::default(); N];
        for v in &mut a {
            *v = T::get(r)?;
        }
        Ok(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roundtrip_and_bounds() {
        let mut buf = [0u8; 25];
        let mut w = Writer::new(&mut buf);
        w.put_u8(0xAB).unwrap();
        w.put_u16(0x1234).unwrap();
        w.put_u32(0xDEAD_BEEF).unwrap();
        w.put_f32(-0.0).unwrap();
        w.put_f64(f64::from_bits(0x7FF8_0000_0000_1234)).unwrap();
        w.put_i16(-2).unwrap();
        w.put_i32(-3).unwrap();
        assert_eq!(w.remaining(), 0);
        assert_eq!(
            w.put_u8(1),
            Err(PayloadError::Overflow {
                needed: 1,
                remaining: 0
            })
        );
        let n = w.len();
        assert_eq!(&buf[..3], &[0xAB, 0x34, 0x12]);
        let mut r = Reader::new(&buf[..n]);
        assert_eq!(r.get_u8(), Ok(0xAB));
        assert_eq!(r.get_u16(), Ok(0x1234));
        assert_eq!(r.get_u32(), Ok(0xDEAD_BEEF));
        assert_eq!(r.get_f32().map(f32::to_bits), Ok((-0.0f32).to_bits()));
        assert_eq!(r.get_f64().map(f64::to_bits), Ok(0x7FF8_0000_0000_1234));
        assert_eq!(r.get_i16(), Ok(-2));
        assert_eq!(r.finish(), Err(PayloadError::TrailingBytes { extra: 4 }));
        assert_eq!(r.get_i32(), Ok(-3));
        assert_eq!(
            r.get_u16(),
            Err(PayloadError::Underflow {
                needed: 2,
                remaining: 0
            })
        );
        assert_eq!(r.finish(), Ok(()));
    }

    #[test]
    fn failed_put_writes_nothing() {
        let mut buf = [0u8; 3];
        let mut w = Writer::new(&mut buf);
        w.put_u16(7).unwrap();
        assert!(w.put_u32(9).is_err());
        assert_eq!(w.len(), 2);
        assert_eq!(w.into_written(), &[7, 0]);
    }

    #[test]
    fn fields_travel_in_order_little_endian() {
        assert_eq!(<[u16; 3]>::LEN, 6);
        assert_eq!(<[[f32; 2]; 2]>::LEN, 16);
        let mut buf = [0u8; 8];
        let mut w = Writer::new(&mut buf);
        [0x0102u16, 0x0304, 0x0506].put(&mut w).unwrap();
        0xABu8.put(&mut w).unwrap();
        assert_eq!(w.written(), &[2, 1, 4, 3, 6, 5, 0xAB]);
        // One byte left: a u16 array does not fit.
        assert!([1u16, 2].put(&mut w).is_err());
        let mut r = Reader::new(&buf[..7]);
        assert_eq!(<[u16; 3]>::get(&mut r), Ok([0x0102, 0x0304, 0x0506]));
        assert_eq!(u8::get(&mut r), Ok(0xAB));
        assert!(u8::get(&mut r).is_err());
    }
}
