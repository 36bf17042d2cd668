//! The body axes of one attitude.

use crate::hover::sample::Attitude;
use crate::scalar::Real;

/// The body axes of one attitude, kept as the sines and cosines of roll, pitch and yaw: one
/// `libm` `sincos` per angle (bit-identical to separate `sin` and `cos`), shared by both axes.
///
/// The identifier computes it once per sample and keeps the previous sample's (the
/// transcendental functions are the most expensive part of a plain step on an MCU without a
/// double-precision FPU).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BodyFrame<T> {
    sf: T,
    cf: T,
    st: T,
    ct: T,
    pub(super) sp: T,
    pub(super) cp: T,
}

impl<T: Real> BodyFrame<T> {
    /// The frame of an attitude.
    #[inline]
    pub fn of(a: &Attitude<T>) -> Self {
        Self::new(a.roll, a.pitch, a.yaw)
    }

    /// The frame of roll, pitch, yaw (rad).
    #[inline]
    pub fn new(roll: T, pitch: T, yaw: T) -> Self {
        let (sf, cf) = roll.sin_cos_libm();
        let (st, ct) = pitch.sin_cos_libm();
        let (sp, cp) = yaw.sin_cos_libm();
        Self {
            sf,
            cf,
            st,
            ct,
            sp,
            cp,
        }
    }

    /// The frame of zero roll, pitch and yaw (no trigonometry).
    #[inline]
    pub fn identity() -> Self {
        let (zero, one) = (T::zero(), T::one());
        Self {
            sf: zero,
            cf: one,
            st: zero,
            ct: one,
            sp: zero,
            cp: one,
        }
    }

    /// `(sφ, cφ, sθ, cθ, sψ, cψ)`: what both axes are written in.
    #[inline(always)]
    fn sines_cosines(&self) -> (T, T, T, T, T, T) {
        (self.sf, self.cf, self.st, self.ct, self.sp, self.cp)
    }

    /// [`rotor_axis`] of this attitude.
    #[inline]
    pub fn rotor_axis(&self) -> [T; 3] {
        let (sf, cf, st, ct, sp, cp) = self.sines_cosines();
        [sf * cp - cf * st * sp, cf * ct, sf * sp + cf * st * cp]
    }

    /// [`right_axis`] of this attitude.
    #[inline]
    pub fn right_axis(&self) -> [T; 3] {
        let (sf, cf, st, ct, sp, cp) = self.sines_cosines();
        [cf * cp + sf * st * sp, -(sf * ct), cf * sp - sf * st * cp]
    }
}

/// The body "up" axis `j_b` in inertial paper axes: `R e2 = [sφcψ − cφsθsψ, cφcθ, sφsψ + cφsθcψ]`
/// (the column of R that Eq. 27 uses; NOTES.md item 1).
pub fn rotor_axis<T: Real>(roll: T, pitch: T, yaw: T) -> [T; 3] {
    BodyFrame::new(roll, pitch, yaw).rotor_axis()
}

/// The body's right axis `i_b` in inertial paper axes: `R e1 = [cφcψ + sφsθsψ, −sφcθ,
/// cφsψ − sφsθcψ]` (the first column of the paper's R).
pub fn right_axis<T: Real>(roll: T, pitch: T, yaw: T) -> [T; 3] {
    BodyFrame::new(roll, pitch, yaw).right_axis()
}
