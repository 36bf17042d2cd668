//! Membership functions of the paper's Table 1.
//!
//! All three are Gaussian bells `exp(−½((x − c)/σ)²)`; the shoulders saturate at 1 beyond
//! their centre so that the outermost sets cover everything outside the hover region.

use crate::scalar::Real;

/// One fuzzy set's membership function `μ(x) ∈ [0, 1]` (paper Table 1).
///
/// `centre` (c) and `spread` (σ) are in the premise variable's own unit (m/s for velocities,
/// deg/s for rates in the helicopter models). A [`RuleBase`](crate::rule_base::RuleBase)
/// checks every set when it is built: c finite, σ finite and > 0.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MembershipFunction<T> {
    /// `μ(x) = exp(−½((x − c)/σ)²)`: the "Centers" column of Table 1.
    Gaussian {
        /// Centre c.
        centre: T,
        /// Spread σ (> 0).
        spread: T,
    },
    /// `μ(x) = 1` for `x ≤ c`, the Gaussian above: the "Left" column of Table 1.
    LeftShoulder {
        /// Centre c^l.
        centre: T,
        /// Spread σ^l (> 0).
        spread: T,
    },
    /// `μ(x) = 1` for `x ≥ c`, the Gaussian below: the "Right" column of Table 1.
    RightShoulder {
        /// Centre c^r.
        centre: T,
        /// Spread σ^r (> 0).
        spread: T,
    },
}

impl<T: Real> MembershipFunction<T> {
    /// Centre c and spread σ.
    pub fn parameters(&self) -> (T, T) {
        match *self {
            Self::Gaussian { centre, spread }
            | Self::LeftShoulder { centre, spread }
            | Self::RightShoulder { centre, spread } => (centre, spread),
        }
    }

    /// Whether `other` is the same kind of set with the same centre and spread, bit for bit
    /// (then it gives the same degrees, bit for bit).
    #[inline]
    pub fn same_bits(&self, other: &Self) -> bool {
        let ((c, s), (oc, os)) = (self.parameters(), other.parameters());
        core::mem::discriminant(self) == core::mem::discriminant(other)
            && c.to_bits_u64() == oc.to_bits_u64()
            && s.to_bits_u64() == os.to_bits_u64()
    }

    /// Whether c is finite and σ is finite and strictly positive.
    pub fn is_valid(&self) -> bool {
        let (c, s) = self.parameters();
        c.is_finite() && s.is_finite() && s > T::zero()
    }

    /// The exponent `−½((x − c)/σ)²` (≤ 0), or 0 where a shoulder saturates.
    ///
    /// `degree(x) == exp(log_degree(x))`; the rule base falls back to this log form when every
    /// product of degrees underflows.
    #[inline]
    pub fn log_degree(&self, x: T) -> T {
        let (c, s) = self.parameters();
        let saturated = match self {
            Self::Gaussian { .. } => false,
            Self::LeftShoulder { .. } => x <= c,
            Self::RightShoulder { .. } => x >= c,
        };
        if saturated {
            return T::zero();
        }
        let z = (x - c) / s;
        -(z * z) * T::lit(0.5)
    }

    /// Degree of membership `μ(x)` in [0, 1] (through `libm`'s `exp`).
    #[inline]
    pub fn degree(&self, x: T) -> T {
        let l = self.log_degree(x);
        if l == T::zero() {
            T::one()
        } else {
            l.exp()
        }
    }
}
