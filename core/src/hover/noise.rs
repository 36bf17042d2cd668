//! The white noise of the gyro rates, estimated from a flight.

use crate::error::SampleField;
use crate::error::{Error, Quantity};
use crate::hover::sample::SampleLimits;
use crate::scalar::Real;

/// Estimates the standard deviation σ of each rate's white noise `[q r p]` (deg/s) from a
/// stream of samples, for [`HoverIdentifier::compensate`](super::HoverIdentifier::compensate).
///
/// The third difference `Δ³ω(k) = ω(k) − 3ω(k−1) + 3ω(k−2) − ω(k−3)` of a rate that is
/// smooth at the sample scale is almost all noise: of white noise it has the variance
/// `(1 + 9 + 9 + 1) σ² = 20 σ²`, so `σ̂² = mean(Δ³ω²) / 20`. What the rate itself adds to
/// `Δ³ω` makes σ̂ an over-estimate, small when the sample rate is well above the dynamics
/// (50 Hz for a helicopter's body rates; `rotorid identify` reports σ̂ of each flight).
///
/// 52 bytes in f32; the identifier does not keep one (a firmware runs it beside the
/// identifier, or takes σ from the gyro's data sheet).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RateNoise<T> {
    /// The last three rates, newest first.
    recent: [[T; 3]; 3],
    /// How many of `recent` are filled (0–3).
    held: u8,
    /// `Σ Δ³ω²` per rate.
    sum: [T; 3],
    /// Third differences summed.
    count: u32,
}

impl<T: Real> Default for RateNoise<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> RateNoise<T> {
    /// Nothing seen yet.
    pub fn new() -> Self {
        Self {
            recent: [[T::zero(); 3]; 3],
            held: 0,
            sum: [T::zero(); 3],
            count: 0,
        }
    }

    /// Takes the rates `[q r p]` (deg/s) of the next sample (equally spaced in time from the
    /// previous one; after a gap call [`restart`](Self::restart) first). A rate that is not
    /// finite or beyond [`SampleLimits::RATE`] is refused, and nothing changes.
    pub fn push(&mut self, rates: &[T; 3]) -> Result<(), Error> {
        let limit = T::lit(SampleLimits::RATE);
        for (i, &w) in rates.iter().enumerate() {
            let at = Quantity::Sample(SampleField::Rate(i as u8));
            if !w.is_finite() {
                return Err(Error::NonFinite(at));
            }
            if w.abs() > limit {
                return Err(Error::OutOfRange(at));
            }
        }
        if self.held == 3 {
            let [a, b, c] = self.recent;
            let three = T::lit(3.0);
            for (i, sum) in self.sum.iter_mut().enumerate() {
                let x = |r: &[T; 3]| r.get(i).copied().unwrap_or_else(T::zero);
                let d3 = x(rates) - three * x(&a) + three * x(&b) - x(&c);
                *sum += d3 * d3;
            }
            self.count = self.count.saturating_add(1);
        } else {
            self.held += 1;
        }
        let [newest, older, _] = self.recent;
        self.recent = [*rates, newest, older];
        Ok(())
    }

    /// The next sample does not follow the last one (a gap): the next three only refill the
    /// window. What was summed is kept.
    pub fn restart(&mut self) {
        self.held = 0;
    }

    /// How many third differences the estimate is made of.
    pub fn differences(&self) -> u32 {
        self.count
    }

    /// σ̂ of each rate `[q r p]` (deg/s); `None` before the first third difference.
    pub fn std_dev(&self) -> Option<[T; 3]> {
        if self.count == 0 {
            return None;
        }
        let n = T::lit(f64::from(self.count)) * T::lit(20.0);
        Some(self.sum.map(|s| (s / n).sqrt_ieee()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_white_noise_on_a_smooth_rate() {
        // A 0.5 Hz sine of 20 deg/s at 50 Hz plus uniform noise of σ = 0.3 deg/s.
        let sigma = 0.3f64;
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        let mut noise = RateNoise::<f64>::new();
        assert_eq!(noise.std_dev(), None);
        for k in 0..20_000 {
            let t = f64::from(k) / 50.0;
            let smooth = 20.0 * libm::sin(core::f64::consts::PI * t);
            let rates = [0, 1, 2].map(|_| smooth + sigma * 3f64.sqrt() * uniform());
            noise.push(&rates).unwrap();
        }
        assert_eq!(noise.differences(), 20_000 - 3);
        for s in noise.std_dev().unwrap() {
            assert!((s - sigma).abs() < 0.02 * sigma, "σ̂ = {s}");
        }
    }

    #[test]
    fn refuses_bad_rates_and_restarts_after_a_gap() {
        let mut noise = RateNoise::<f32>::new();
        for k in 0..5 {
            noise.push(&[k as f32, 0.0, 0.0]).unwrap();
        }
        // A ramp has no third difference.
        assert_eq!(noise.std_dev(), Some([0.0; 3]));
        let before = noise;
        assert!(noise.push(&[f32::NAN, 0.0, 0.0]).is_err());
        assert!(noise.push(&[0.0, 2001.0, 0.0]).is_err());
        assert_eq!(noise, before);
        noise.restart();
        for _ in 0..3 {
            noise.push(&[100.0, 0.0, 0.0]).unwrap();
        }
        assert_eq!(noise.differences(), before.differences());
    }
}
