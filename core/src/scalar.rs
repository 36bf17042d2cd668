//! The scalar types the core computes in.
//!
//! [`Real`] is implemented for `f32` (the flight type) and `f64` only. Its transcendental
//! functions come from [`nalgebra::RealField`], which this crate builds with nalgebra's
//! `libm-force` feature: `exp`, `sin` and `cos` are the `libm` crate's software
//! implementations on every target, never the host's `std` maths. The square root, which
//! IEEE 754 requires to be correctly rounded like `+` and `×`, is [`Real::sqrt_ieee`]: the
//! FPU's instruction where there is one. Together with IEEE-754 basic arithmetic (no fused
//! multiply-add, fixed evaluation order) this is what makes a result on x86_64 and on a
//! Cortex-M4F identical to the last bit.

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
    /// `√x`, correctly rounded (IEEE 754 requires it of every implementation, so every path
    /// below gives the same bits): the FPU's instruction where the target has one for this
    /// type (`vsqrt.f32` on an Arm with hard float, such as the Cortex-M4F; `libm` itself
    /// takes `sqrtss`/`sqrtsd` on x86_64), `libm`'s software routine elsewhere. On the
    /// Cortex-M4F the instruction replaces about 100 instructions and 480 B of flash
    /// (`libm`'s routine and its table). Negative x (which the core never passes) gives NaN.
    fn sqrt_ieee(self) -> Self;
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
    #[inline]
    fn sqrt_ieee(self) -> Self {
        sqrt_f32(self)
    }
}

/// [`Real::sqrt_ieee`] for `f32` on an Arm with hard float: every such FPU (VFPv2 and later,
/// the Cortex-M4F's FPv4-SP) has `vsqrt.f32`, correctly rounded to nearest as `libm`'s
/// `sqrtf` is. The operand travels through core registers and `s15` is saved and restored
/// around the instruction, because Rust cannot name the FPU's registers on this target
/// (its `sreg` class needs the `vfp2` feature, which rustc does not infer from the target's
/// FPU).
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline]
#[allow(unsafe_code)]
fn sqrt_f32(x: f32) -> f32 {
    let root: u32;
    // SAFETY: moves between core and FPU registers and one `vsqrt.f32`; `s15` holds its old
    // value again at the end, nothing else is written but the declared registers, and no
    // memory or stack is touched (the FPU's cumulative exception flags may be set, as any
    // arithmetic sets them). The hard-float ABI guarantees the FPU.
    unsafe {
        core::arch::asm!(
            "vmov {saved}, s15",
            "vmov s15, {x}",
            "vsqrt.f32 s15, s15",
            "vmov {root}, s15",
            "vmov s15, {saved}",
            x = in(reg) x.to_bits(),
            root = lateout(reg) root,
            saved = out(reg) _,
            options(pure, nomem, nostack),
        );
    }
    f32::from_bits(root)
}

/// [`Real::sqrt_ieee`] for `f32` elsewhere: `libm`'s (the hardware's on x86_64).
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    libm::sqrtf(x)
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
    #[inline]
    fn sqrt_ieee(self) -> Self {
        libm::sqrt(self)
    }
}

/// `|x| <= limit` and x finite, for a finite `limit`: one comparison, since a NaN compares
/// false and ±∞ exceeds any finite limit.
#[inline]
pub(crate) fn within<T: Real>(x: T, limit: T) -> bool {
    x.abs() <= limit
}
