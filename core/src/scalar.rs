//! The scalar types the core computes in.
//!
//! [`Real`] is implemented for `f32` (the flight type) and `f64` only. Its transcendental
//! functions come from [`nalgebra::RealField`], which this crate builds with nalgebra's
//! `libm-force` feature: `exp`, `sin`, `cos` and `sqrt` are the `libm` crate's software
//! implementations on every target, never the host's `std` maths. Together with IEEE-754
//! basic arithmetic (no fused multiply-add, fixed evaluation order) this is what makes a
//! result on x86_64 and on a Cortex-M4F identical to the last bit.

use nalgebra::RealField;

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// `f32` or `f64`: the scalar every estimator in this crate is generic over.
pub trait Real: RealField + Copy + Default + sealed::Sealed {
    /// Converts an `f64` constant (rounded to nearest for `f32`).
    fn lit(x: f64) -> Self;
    /// Widens to `f64` (exact for both implementors).
    fn to_f64(self) -> f64;
    /// The raw IEEE-754 bits, widened to `u64`, for bit-exact comparisons and golden files.
    fn to_bits_u64(self) -> u64;
    /// The smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// Number of bytes of one value (4 or 8), for serialisation.
    const BYTES: usize;
    /// Writes the little-endian bytes of `self` into `out[..Self::BYTES]`.
    /// Returns `false` (and writes nothing) when `out` is too short.
    fn write_le(self, out: &mut [u8]) -> bool;
    /// Reads a value from the little-endian bytes `bytes[..Self::BYTES]`.
    fn read_le(bytes: &[u8]) -> Option<Self>;
    /// `(sin x, cos x)` in one call of `libm`'s `sincosf`/`sincos`: one argument reduction
    /// for both, and bit-identical to `libm`'s separate `sin` and `cos` (same kernels).
    fn sin_cos_libm(self) -> (Self, Self);
}

impl Real for f32 {
    #[inline]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline]
    fn to_bits_u64(self) -> u64 {
        u64::from(self.to_bits())
    }
    const MIN_POSITIVE: Self = f32::MIN_POSITIVE;
    const BYTES: usize = 4;
    fn write_le(self, out: &mut [u8]) -> bool {
        match out.get_mut(..4) {
            Some(dst) => {
                dst.copy_from_slice(&self.to_le_bytes());
                true
            }
            None => false,
        }
    }
    fn read_le(bytes: &[u8]) -> Option<Self> {
        let b: [u8; 4] = bytes.get(..4)?.try_into().ok()?;
        Some(f32::from_le_bytes(b))
    }
    #[inline]
    fn sin_cos_libm(self) -> (Self, Self) {
        libm::sincosf(self)
    }
}

impl Real for f64 {
    #[inline]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn to_bits_u64(self) -> u64 {
        self.to_bits()
    }
    const MIN_POSITIVE: Self = f64::MIN_POSITIVE;
    const BYTES: usize = 8;
    fn write_le(self, out: &mut [u8]) -> bool {
        match out.get_mut(..8) {
            Some(dst) => {
                dst.copy_from_slice(&self.to_le_bytes());
                true
            }
            None => false,
        }
    }
    fn read_le(bytes: &[u8]) -> Option<Self> {
        let b: [u8; 8] = bytes.get(..8)?.try_into().ok()?;
        Some(f64::from_le_bytes(b))
    }
    #[inline]
    fn sin_cos_libm(self) -> (Self, Self) {
        libm::sincos(self)
    }
}

/// `|x| <= limit` and x finite, for a finite `limit`: one comparison, since a NaN compares
/// false and ±∞ exceeds any finite limit.
#[inline]
pub(crate) fn within<T: Real>(x: T, limit: T) -> bool {
    x.abs() <= limit
}
