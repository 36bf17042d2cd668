//! The body axes of one attitude: what the models read of it, whatever its form (the
//! constructors from each form are beside the forms, in `attitude.rs`).

use crate::scalar::Real;

/// The body axes of one attitude, in paper axes (x east, y up, z south): the rotor axis `j_b`,
/// the right axis `i_b`, and the heading's sine and cosine `(sψ, cψ)`. What the models read of
/// an attitude, whatever its form ([`AttitudeInput`](crate::hover::AttitudeInput)).
///
/// From Euler angles: one `libm` `sincos` per angle (bit-identical to separate `sin` and
/// `cos`). From a quaternion or a rotation matrix: the matrix's columns, and the heading
/// normalised from the forward axis's horizontal part (no trigonometry). The identifier
/// computes it once per sample and keeps the previous sample's.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BodyFrame<T> {
    up: [T; 3],
    right: [T; 3],
    pub(crate) sp: T,
    pub(crate) cp: T,
}

/// Below this `cos²θ` (pitch within about 0.06° of ±90°) the heading of a quaternion or a
/// matrix is read from the right axis: the forward axis is then vertical and its horizontal
/// part is rounding.
const VERTICAL_NOSE_COS2: f64 = 1e-6;

impl<T: Real> BodyFrame<T> {
    /// The frame of roll, pitch, yaw (rad).
    #[inline]
    pub fn new(roll: T, pitch: T, yaw: T) -> Self {
        let (sf, cf) = roll.sin_cos_libm();
        let (st, ct) = pitch.sin_cos_libm();
        let (sp, cp) = yaw.sin_cos_libm();
        Self::of_sines_cosines(sf, cf, st, ct, sp, cp)
    }

    /// The frame of zero roll, pitch and yaw (no trigonometry).
    #[inline]
    pub fn identity() -> Self {
        let (zero, one) = (T::zero(), T::one());
        Self::of_sines_cosines(zero, one, zero, one, zero, one)
    }

    /// The columns of the paper's R from `(sφ, cφ, sθ, cθ, sψ, cψ)`.
    #[inline(always)]
    fn of_sines_cosines(sf: T, cf: T, st: T, ct: T, sp: T, cp: T) -> Self {
        Self {
            up: [sf * cp - cf * st * sp, cf * ct, sf * sp + cf * st * cp],
            right: [cf * cp + sf * st * sp, -(sf * ct), cf * sp - sf * st * cp],
            sp,
            cp,
        }
    }

    /// From the rows (north, east, down) of a body-FRD-to-NED matrix. Paper axes are
    /// (east, −down, −north): up = −(down column), right = right column.
    #[inline(always)]
    pub(crate) fn of_rows(r: &[[T; 3]; 3]) -> Self {
        let [[r00, r01, r02], [r10, r11, r12], [_, r21, r22]] = *r;
        let (sp, cp) = heading(r00, r10, r01, r11);
        Self {
            up: [-r12, r22, r02],
            right: [r11, -r21, -r01],
            sp,
            cp,
        }
    }

    /// The body "up" axis `j_b` in inertial paper axes (see [`rotor_axis`]).
    #[inline]
    pub fn rotor_axis(&self) -> [T; 3] {
        self.up
    }

    /// The body's right axis `i_b` in inertial paper axes (see [`right_axis`]).
    #[inline]
    pub fn right_axis(&self) -> [T; 3] {
        self.right
    }

    /// `[j_b, i_b, sψ, cψ]`: every value the frame holds (for bit-exact comparisons).
    pub fn to_array(&self) -> [T; 8] {
        let ([a, b, c], [d, e, f]) = (self.up, self.right);
        [a, b, c, d, e, f, self.sp, self.cp]
    }

    /// `(sin ψ, cos ψ)` of the heading ψ (clockwise from north).
    #[inline]
    pub fn heading(&self) -> (T, T) {
        (self.sp, self.cp)
    }
}

/// `(sψ, cψ)` from a body-to-NED matrix: the forward axis's horizontal part `(r00, r10) =
/// cos θ (cψ, sψ)` normalised; with the nose vertical, the right axis's `(r11, −r01)` (the
/// heading at zero roll: at ±90° pitch only ψ ∓ φ is defined).
#[inline(always)]
fn heading<T: Real>(r00: T, r10: T, r01: T, r11: T) -> (T, T) {
    let h2 = r00 * r00 + r10 * r10;
    let (c, s, n2) = if h2 >= T::lit(VERTICAL_NOSE_COS2) {
        (r00, r10, h2)
    } else {
        (r11, -r01, r11 * r11 + r01 * r01)
    };
    if n2 > T::zero() {
        let n = n2.sqrt_ieee();
        (s / n, c / n)
    } else {
        // Not an orthonormal matrix (refused by its check); north keeps this finite.
        (T::zero(), T::one())
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
