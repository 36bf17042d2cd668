//! One measurement sample and the state vector the identifier predicts.

use crate::error::{check, Error, SampleField};
use crate::hover::attitude::{self, Attitude, AttitudeInput};
use crate::scalar::Real;

/// The four normalised controls (−1…1).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Controls<T> {
    /// Main-rotor collective `u_col`; the models multiply by it as a stand-in for thrust
    /// (Eq. 10), so at hover it must sit well above zero (for example near 0.5).
    pub col: T,
    /// Tail-rotor collective (pedal) `u_ped`.
    pub ped: T,
    /// Longitudinal cyclic `u_lon`.
    pub lon: T,
    /// Lateral cyclic `u_lat`.
    pub lat: T,
}

impl<T: Real> Controls<T> {
    /// `[u_col u_ped u_lon u_lat]`.
    pub fn to_array(&self) -> [T; 4] {
        [self.col, self.ped, self.lon, self.lat]
    }
}

/// The six states the identifier predicts: `v^s` (m/s) and `[q r p]` (deg/s).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HoverState<T> {
    /// `[v_x v_y v_z]` (m/s), paper inertial axes.
    pub velocity: [T; 3],
    /// `[q r p]` (deg/s).
    pub rates: [T; 3],
}

impl<T: Real> HoverState<T> {
    /// `[v_x v_y v_z q r p]`.
    pub fn to_array(&self) -> [T; 6] {
        let [a, b, c] = self.velocity;
        let [q, r, p] = self.rates;
        [a, b, c, q, r, p]
    }

    /// From `[v_x v_y v_z q r p]`.
    pub fn from_array([a, b, c, q, r, p]: [T; 6]) -> Self {
        Self {
            velocity: [a, b, c],
            rates: [q, r, p],
        }
    }
}

/// One sample at time step k (paper axes and units, see [`crate::hover`]).
///
/// `A` is the form of the attitude: ZYX Euler angles ([`Attitude`], the default), a
/// [`Quaternion`](crate::hover::Quaternion) or a [`RotationMatrix`](crate::hover::RotationMatrix)
/// (both without trigonometry in the step; see [`crate::hover::AttitudeInput`]).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HoverSample<T, A = Attitude<T>> {
    /// Time stamp (µs, monotonic). Integer so that hours of flight lose no resolution.
    pub time_us: u64,
    /// Attitude.
    pub attitude: A,
    /// Inertial velocity `v^s` (m/s).
    pub velocity: [T; 3],
    /// Body rates `[q r p]` (deg/s).
    pub rates: [T; 3],
    /// Controls applied from this sample until the next.
    pub controls: Controls<T>,
}

impl<T: Real, A> HoverSample<T, A> {
    /// The measured state of this sample.
    pub fn state(&self) -> HoverState<T> {
        HoverState {
            velocity: self.velocity,
            rates: self.rates,
        }
    }

    /// The same sample with another attitude (the time stamp, state and controls kept).
    pub fn with_attitude<B>(&self, attitude: B) -> HoverSample<T, B> {
        HoverSample {
            time_us: self.time_us,
            attitude,
            velocity: self.velocity,
            rates: self.rates,
            controls: self.controls,
        }
    }
}

impl<T: Real> HoverSample<T> {
    /// The same sample in another precision, e.g. an `f32` flight log replayed in `f64`
    /// (exact from `f32` to `f64`; rounded to nearest the other way).
    pub fn cast<U: Real>(&self) -> HoverSample<U> {
        let c = |x: T| U::lit(x.to_f64());
        let (a, u) = (&self.attitude, &self.controls);
        HoverSample {
            time_us: self.time_us,
            attitude: Attitude {
                roll: c(a.roll),
                pitch: c(a.pitch),
                yaw: c(a.yaw),
            },
            velocity: self.velocity.map(c),
            rates: self.rates.map(c),
            controls: Controls {
                col: c(u.col),
                ped: c(u.ped),
                lon: c(u.lon),
                lat: c(u.lat),
            },
        }
    }
}

/// The ranges a [`HoverSample`] must lie in to be accepted.
///
/// They are physical sanity bounds for a miniature helicopter, and they also guarantee that
/// no regressor product can leave the estimator's numeric limits
/// ([`REGRESSOR_LIMIT`](crate::rls::REGRESSOR_LIMIT)).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SampleLimits;

impl SampleLimits {
    /// |φ| ≤ 3.2 rad (π plus margin).
    pub const ROLL: f64 = attitude::limits::ROLL;
    /// |θ| ≤ 1.6 rad (π/2 plus margin).
    pub const PITCH: f64 = attitude::limits::PITCH;
    /// |ψ| ≤ 6.3 rad (2π plus margin: both ±π and 0…2π conventions pass).
    pub const YAW: f64 = attitude::limits::YAW;
    /// Each |v_i| ≤ 100 m/s.
    pub const VELOCITY: f64 = 100.0;
    /// Each |ω_i| ≤ 2000 deg/s (a common gyro range).
    pub const RATE: f64 = 2000.0;
    /// Each |u_i| ≤ 1.
    pub const CONTROL: f64 = 1.0;
    /// `|‖q‖² − 1| ≤ 0.01` for an attitude quaternion (a flight stack renormalises its
    /// quaternion at every step; 0.01 is far beyond its rounding and short of a wrong input).
    pub const QUATERNION_NORM: f64 = attitude::limits::QUATERNION_NORM;
    /// `|cᵢ·cⱼ − δᵢⱼ| ≤ 0.01` for the columns of an attitude rotation matrix (a DCM is
    /// re-orthonormalised at every step).
    pub const MATRIX_ORTHONORMALITY: f64 = attitude::limits::MATRIX_ORTHONORMALITY;

    /// Checks body rates `[q r p]` (deg/s) against [`RATE`](Self::RATE).
    pub fn check_rates<T: Real>(rates: &[T; 3]) -> Result<(), Error> {
        for (i, &w) in rates.iter().enumerate() {
            check(w, Self::RATE, SampleField::Rate(i as u8).into())?;
        }
        Ok(())
    }

    /// Checks a state `[v^s, ω]` (a sample's, or a model's own estimate) against
    /// [`VELOCITY`](Self::VELOCITY) and [`RATE`](Self::RATE).
    pub fn check_state<T: Real>(state: &HoverState<T>) -> Result<(), Error> {
        for (i, &v) in state.velocity.iter().enumerate() {
            check(v, Self::VELOCITY, SampleField::Velocity(i as u8).into())?;
        }
        Self::check_rates(&state.rates)
    }

    /// Checks every field of a sample: `NonFinite` for NaN/±∞, `OutOfRange` beyond the limits.
    pub fn check<T: Real, A: AttitudeInput<T>>(s: &HoverSample<T, A>) -> Result<(), Error> {
        s.attitude.check()?;
        Self::check_state(&s.state())?;
        for (i, u) in s.controls.to_array().into_iter().enumerate() {
            check(u, Self::CONTROL, SampleField::Control(i as u8).into())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cast_to_f64_and_back_keeps_every_bit() {
        let s = HoverSample::<f32> {
            time_us: 123_456_789,
            attitude: Attitude {
                roll: 0.1,
                pitch: -0.2,
                yaw: 3.1,
            },
            velocity: [1.5, -0.25, 1e-7],
            rates: [12.3, -45.6, 0.001],
            controls: Controls {
                col: 0.51,
                ped: -0.07,
                lon: 0.03,
                lat: -0.3,
            },
        };
        let wide: HoverSample<f64> = s.cast();
        assert_eq!(wide.rates[0], f64::from(12.3f32));
        let back: HoverSample<f32> = wide.cast();
        let bits = |s: &HoverSample<f32>| {
            let a = &s.attitude;
            let c = s.controls.to_array();
            [a.roll, a.pitch, a.yaw]
                .iter()
                .chain(&s.velocity)
                .chain(&s.rates)
                .chain(&c)
                .map(|x| x.to_bits())
                .collect::<heapless::Vec<u32, 13>>()
        };
        assert_eq!(bits(&back), bits(&s));
        assert_eq!(back.time_us, s.time_us);
    }
}
