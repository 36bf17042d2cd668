//! The attitude a sample carries, in the form the flight stack holds it: ZYX Euler angles
//! ([`Attitude`]), a unit quaternion ([`Quaternion`], PX4's `vehicle_attitude.q`) or a rotation
//! matrix ([`RotationMatrix`], ArduPilot's DCM).
//!
//! The models read an attitude only through its body frame ([`BodyFrame`]: the rotor axis, the
//! right axis and the heading). From Euler angles that takes three `sincos`; on a Cortex-M4F
//! (no double-precision FPU, and `libm`'s `sincosf` computes in `f64`) they are about 4 000
//! instructions of a step. A quaternion or a matrix gives the same axes with a dozen
//! multiplications, one division and one square root (see [`BodyFrame`]).
//!
//! **How the three relate.** For the same attitude the three forms give the same body frame up
//! to rounding: each axis component within a few units in the last place of `T`, and the
//! heading's sine and cosine within about `ε / cos θ` (they are normalised from the forward
//! axis's horizontal part). Predictions from the three forms therefore differ in their last
//! bits, never more: the tests bound the difference over a flight. Each form on its own gives
//! the same bits on every target.

use crate::error::{check, Error, SampleField};
use crate::hover::frame::BodyFrame;
use crate::scalar::Real;

/// The bounds of each form (the values of [`SampleLimits`](crate::hover::SampleLimits)'
/// attitude constants, which document them).
pub(crate) mod limits {
    pub const ROLL: f64 = 3.2;
    pub const PITCH: f64 = 1.6;
    pub const YAW: f64 = 6.3;
    pub const QUATERNION_NORM: f64 = 0.01;
    pub const MATRIX_ORTHONORMALITY: f64 = 0.01;
}

/// ZYX Euler angles (rad): roll φ, pitch θ, yaw ψ.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Attitude<T> {
    /// Roll φ (rad), right wing down positive.
    pub roll: T,
    /// Pitch θ (rad), nose up positive.
    pub pitch: T,
    /// Yaw ψ (rad), clockwise from north seen from above.
    pub yaw: T,
}

/// A unit quaternion `q = [w x y z]` (Hamilton convention) that rotates forward-right-down
/// body vectors into north-east-down: PX4's `vehicle_attitude.q` as it stands.
///
/// It must be normalised to within [`SampleLimits::QUATERNION_NORM`](crate::hover::SampleLimits::QUATERNION_NORM) (`|‖q‖² − 1|`); the
/// frame divides by `‖q‖²`, so small drifts of the norm do not tilt the axes. `q` and `−q`
/// are the same attitude.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Quaternion<T> {
    /// Scalar part.
    pub w: T,
    /// Vector part, north.
    pub x: T,
    /// Vector part, east.
    pub y: T,
    /// Vector part, down.
    pub z: T,
}

impl<T: Real> Default for Quaternion<T> {
    /// The identity (level, heading north).
    fn default() -> Self {
        Self {
            w: T::one(),
            x: T::zero(),
            y: T::zero(),
            z: T::zero(),
        }
    }
}

/// A rotation matrix `R` that rotates forward-right-down body vectors into north-east-down:
/// rows north, east, down; columns the body's forward, right and down axes. ArduPilot's
/// `AP_AHRS::get_rotation_body_to_ned()` (its DCM) as it stands.
///
/// Its columns must be orthonormal to within [`SampleLimits::MATRIX_ORTHONORMALITY`](crate::hover::SampleLimits::MATRIX_ORTHONORMALITY) (every
/// `|cᵢ·cⱼ − δᵢⱼ|`).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RotationMatrix<T> {
    /// `rows[i][j]`: row i (north, east, down), column j (forward, right, down).
    pub rows: [[T; 3]; 3],
}

impl<T: Real> Default for RotationMatrix<T> {
    /// The identity (level, heading north).
    fn default() -> Self {
        let (o, l) = (T::zero(), T::one());
        Self {
            rows: [[l, o, o], [o, l, o], [o, o, l]],
        }
    }
}

/// Any of the three forms, chosen at run time: for an interface that takes the form as a
/// value (the C interface's `attitude_form`). One instantiation of the step serves all three;
/// each form gives exactly the bits it gives on its own.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AnyAttitude<T> {
    /// ZYX Euler angles.
    Euler(Attitude<T>),
    /// A unit quaternion, body FRD to NED.
    Quaternion(Quaternion<T>),
    /// A rotation matrix, body FRD to NED.
    Matrix(RotationMatrix<T>),
}

impl<T: Real> Default for AnyAttitude<T> {
    /// Zero Euler angles.
    fn default() -> Self {
        Self::Euler(Attitude::default())
    }
}

impl<T> From<Attitude<T>> for AnyAttitude<T> {
    fn from(a: Attitude<T>) -> Self {
        Self::Euler(a)
    }
}

impl<T> From<Quaternion<T>> for AnyAttitude<T> {
    fn from(q: Quaternion<T>) -> Self {
        Self::Quaternion(q)
    }
}

impl<T> From<RotationMatrix<T>> for AnyAttitude<T> {
    fn from(m: RotationMatrix<T>) -> Self {
        Self::Matrix(m)
    }
}

impl<T: Real> AttitudeInput<T> for AnyAttitude<T> {
    fn check(&self) -> Result<(), Error> {
        match self {
            Self::Euler(a) => a.check(),
            Self::Quaternion(q) => q.check(),
            Self::Matrix(m) => m.check(),
        }
    }

    #[inline]
    fn frame(&self) -> BodyFrame<T> {
        match self {
            Self::Euler(a) => a.frame(),
            Self::Quaternion(q) => q.frame(),
            Self::Matrix(m) => m.frame(),
        }
    }
}

mod sealed {
    pub trait Sealed {}
    impl<T> Sealed for super::AnyAttitude<T> {}
    impl<T> Sealed for super::Attitude<T> {}
    impl<T> Sealed for super::Quaternion<T> {}
    impl<T> Sealed for super::RotationMatrix<T> {}
}

/// A form of the attitude a [`HoverSample`](super::HoverSample) can carry: [`Attitude`] (Euler
/// angles, the default), [`Quaternion`] or [`RotationMatrix`]. Sealed: the identifier relies on
/// the checks and frames below.
pub trait AttitudeInput<T: Real>: Copy + sealed::Sealed {
    /// Checks the attitude: `NonFinite` for NaN/±∞, `OutOfRange` beyond [`SampleLimits`](crate::hover::SampleLimits).
    fn check(&self) -> Result<(), Error>;
    /// The body frame of an attitude that passed [`check`](Self::check) (finite for any
    /// finite input).
    fn frame(&self) -> BodyFrame<T>;
}

impl<T: Real> AttitudeInput<T> for Attitude<T> {
    fn check(&self) -> Result<(), Error> {
        check(self.roll, limits::ROLL, SampleField::Roll.into())?;
        check(self.pitch, limits::PITCH, SampleField::Pitch.into())?;
        check(self.yaw, limits::YAW, SampleField::Yaw.into())
    }

    #[inline]
    fn frame(&self) -> BodyFrame<T> {
        BodyFrame::of(self)
    }
}

impl<T: Real> AttitudeInput<T> for Quaternion<T> {
    fn check(&self) -> Result<(), Error> {
        for (i, c) in self.to_array().into_iter().enumerate() {
            if !c.is_finite() {
                return Err(Error::NonFinite(SampleField::Quaternion(i as u8).into()));
            }
        }
        // Each component is finite, so |c| ≤ 2 (checked first) keeps the squares finite.
        let n2 = self.norm_squared();
        if (n2 - T::one()).abs() > T::lit(limits::QUATERNION_NORM) {
            return Err(Error::OutOfRange(SampleField::QuaternionNorm.into()));
        }
        Ok(())
    }

    #[inline]
    fn frame(&self) -> BodyFrame<T> {
        BodyFrame::from_quaternion(self)
    }
}

impl<T: Real> Quaternion<T> {
    /// `[w x y z]`.
    pub fn to_array(&self) -> [T; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// `w² + x² + y² + z²`, or +∞ when a component's magnitude exceeds 2 (so that no
    /// square can overflow and no such quaternion passes the norm check).
    pub(crate) fn norm_squared(&self) -> T {
        let two = T::lit(2.0);
        if self.to_array().iter().any(|c| c.abs() > two) {
            return T::max_value().unwrap_or_else(T::one);
        }
        let Self { w, x, y, z } = *self;
        w * w + x * x + y * y + z * z
    }

    /// The quaternion of ZYX Euler angles (rad), computed in `T` with `libm`: for tests,
    /// simulators and logs that hold Euler angles.
    pub fn from_euler(a: &Attitude<T>) -> Self {
        let half = T::lit(0.5);
        let (sr, cr) = (a.roll * half).sin_cos_libm();
        let (sp, cp) = (a.pitch * half).sin_cos_libm();
        let (sy, cy) = (a.yaw * half).sin_cos_libm();
        Self {
            w: cr * cp * cy + sr * sp * sy,
            x: sr * cp * cy - cr * sp * sy,
            y: cr * sp * cy + sr * cp * sy,
            z: cr * cp * sy - sr * sp * cy,
        }
    }
}

impl<T: Real> AttitudeInput<T> for RotationMatrix<T> {
    fn check(&self) -> Result<(), Error> {
        for (i, &x) in self.rows.iter().flatten().enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFinite(SampleField::Matrix(i as u8).into()));
            }
            // Bounded first so that the products below stay finite.
            if x.abs() > T::lit(2.0) {
                return Err(Error::OutOfRange(SampleField::Matrix(i as u8).into()));
            }
        }
        let limit = T::lit(limits::MATRIX_ORTHONORMALITY);
        let col = |j: usize| self.rows.map(|r| r.get(j).copied().unwrap_or_else(T::zero));
        let cols = [col(0), col(1), col(2)];
        for (i, a) in cols.iter().enumerate() {
            for (j, b) in cols.iter().enumerate().skip(i) {
                let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                let target = if i == j { T::one() } else { T::zero() };
                if (dot - target).abs() > limit {
                    return Err(Error::OutOfRange(SampleField::MatrixOrthonormality.into()));
                }
            }
        }
        Ok(())
    }

    #[inline]
    fn frame(&self) -> BodyFrame<T> {
        BodyFrame::from_matrix(self)
    }
}

impl<T: Real> RotationMatrix<T> {
    /// The rotation matrix of a quaternion (exact up to rounding for a unit quaternion; the
    /// frame of either is computed without this step).
    pub fn from_quaternion(q: &Quaternion<T>) -> Self {
        let [r0, r1, r2] = quaternion_rows(q);
        Self { rows: [r0, r1, r2] }
    }
}

impl<T: Real> BodyFrame<T> {
    /// The frame of an attitude.
    #[inline]
    pub fn of(a: &Attitude<T>) -> Self {
        Self::new(a.roll, a.pitch, a.yaw)
    }

    /// The frame of a quaternion (see [`Quaternion`]): its rotation matrix's columns, without
    /// trigonometry.
    #[inline]
    pub fn from_quaternion(q: &Quaternion<T>) -> Self {
        Self::of_rows(&quaternion_rows(q))
    }

    /// The frame of a rotation matrix (see [`RotationMatrix`]).
    #[inline]
    pub fn from_matrix(m: &RotationMatrix<T>) -> Self {
        Self::of_rows(&m.rows)
    }
}

/// The rows of the rotation matrix of `q` (body FRD to NED), divided by `‖q‖²` so that a
/// quaternion slightly off unit norm still gives orthonormal axes.
#[inline(always)]
fn quaternion_rows<T: Real>(q: &Quaternion<T>) -> [[T; 3]; 3] {
    let Quaternion { w, x, y, z } = *q;
    let n2 = w * w + x * x + y * y + z * z;
    let one = T::one();
    // A zero quaternion is refused by its check; `s = 0` keeps this finite anyway.
    let s = if n2 > T::zero() {
        T::lit(2.0) / n2
    } else {
        T::zero()
    };
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    [
        [one - s * (yy + zz), s * (xy - wz), s * (xz + wy)],
        [s * (xy + wz), one - s * (xx + zz), s * (yz - wx)],
        [s * (xz - wy), s * (yz + wx), one - s * (xx + yy)],
    ]
}
