//! The paper's Table 3: centres and spreads of the membership functions.
//!
//! Velocities in m/s, rates in deg/s. Each linguistic variable has a left shoulder, a centre
//! Gaussian and a right shoulder; `(*)` entries (a set or variable that takes no part) are
//! left out. The hover ("centre") sets are wide so that they dominate near hover; the
//! shoulders describe the helicopter outside the hover region. Note how narrow most shoulder
//! spreads are (0.01–0.03 deg/s for the rates): below the noise of a real gyro, so a noisy
//! rate near a shoulder's centre switches that rule on and off. They are the paper's values,
//! kept as the default to reproduce it; see the crate docs for choosing sets.

use heapless::Vec;

use crate::error::Error;
use crate::membership::MembershipFunction::{self, Gaussian, LeftShoulder, RightShoulder};
use crate::rule_base::{PremiseSets, RuleBase};
use crate::scalar::Real;

/// Left shoulder, centre and right shoulder from `(c^l, σ^l), (c, σ), (c^r, σ^r)`.
// Inlined: each call's literals become f32 constants (no f64 conversion code in an f32
// firmware; the same values).
#[inline(always)]
pub fn three_sets<T: Real>(
    left: (f64, f64),
    centre: (f64, f64),
    right: (f64, f64),
) -> PremiseSets<T> {
    sets(&[
        LeftShoulder {
            centre: T::lit(left.0),
            spread: T::lit(left.1),
        },
        Gaussian {
            centre: T::lit(centre.0),
            spread: T::lit(centre.1),
        },
        RightShoulder {
            centre: T::lit(right.0),
            spread: T::lit(right.1),
        },
    ])
}

/// Left shoulder, Gaussian and right shoulder from their centres and spreads, in that order
/// (the premise variable's unit): the three sets of a flight model's speed, as the C
/// interface and the link carry them. Unchecked: [`RuleBase::new`] checks them.
#[inline(always)]
pub fn shoulder_sets<T: Real>(centre: [T; 3], spread: [T; 3]) -> PremiseSets<T> {
    let [c0, c1, c2] = centre;
    let [s0, s1, s2] = spread;
    sets(&[
        LeftShoulder {
            centre: c0,
            spread: s0,
        },
        Gaussian {
            centre: c1,
            spread: s1,
        },
        RightShoulder {
            centre: c2,
            spread: s2,
        },
    ])
}

/// Copies up to [`MAX_SETS`](crate::rule_base::MAX_SETS) sets (extra ones are ignored; the rule
/// count check of [`RuleBase::new`] then reports the mismatch).
pub fn sets<T: Real>(list: &[MembershipFunction<T>]) -> PremiseSets<T> {
    let mut v = Vec::new();
    for &mf in list {
        if v.push(mf).is_err() {
            break;
        }
    }
    v
}

/// Translational model (Eq. 27): premise `(ṽ_x, ṽ_y, ṽ_z)` (m/s), 27 rules.
pub fn velocity<T: Real>() -> Result<RuleBase<T, 3, 27>, Error> {
    RuleBase::new([
        three_sets((-0.5, 0.01), (0.0, 1.0), (0.5, 0.01)),
        three_sets((-1.0, 0.03), (0.0, 3.0), (1.0, 0.03)),
        three_sets((-1.0, 0.3), (0.0, 0.3), (1.0, 0.3)),
    ])
}

/// Table 3's `ṽ_y` sets alone (3 rules): the premise of the extended fuzzy translational
/// model, whose thrust gain varies with the vertical inflow.
pub fn vertical_velocity<T: Real>() -> Result<RuleBase<T, 3, 3>, Error> {
    RuleBase::new([
        Vec::new(),
        three_sets((-1.0, 0.03), (0.0, 3.0), (1.0, 0.03)),
        Vec::new(),
    ])
}

/// q̂ model (Eq. 28): premise `(q̃, r̃, p̃)` (deg/s); p̃ has only its shoulders: 18 rules.
pub fn pitch_rate<T: Real>() -> Result<RuleBase<T, 3, 18>, Error> {
    RuleBase::new([
        three_sets((-1.5, 0.01), (0.0, 6.0), (1.5, 0.01)),
        three_sets((-4.0, 0.01), (0.0, 8.0), (4.0, 0.01)),
        sets(&[
            LeftShoulder {
                centre: T::lit(-0.5),
                spread: T::lit(1.0),
            },
            RightShoulder {
                centre: T::lit(0.5),
                spread: T::lit(1.0),
            },
        ]),
    ])
}

/// r̂ model (Eq. 29): premise `(r̃, p̃)` (deg/s), q̃ takes no part: 9 rules.
pub fn yaw_rate<T: Real>() -> Result<RuleBase<T, 3, 9>, Error> {
    RuleBase::new([
        Vec::new(),
        three_sets((-0.5, 0.01), (0.0, 8.0), (0.5, 0.01)),
        three_sets((-1.5, 0.03), (0.0, 6.0), (1.5, 0.03)),
    ])
}

/// p̂ model (Eq. 30): premise `(q̃, r̃)` (deg/s), p̃ takes no part: 9 rules.
pub fn roll_rate<T: Real>() -> Result<RuleBase<T, 3, 9>, Error> {
    RuleBase::new([
        three_sets((-2.0, 0.03), (0.0, 6.0), (2.0, 0.03)),
        three_sets((-0.5, 0.01), (0.0, 8.0), (0.5, 0.01)),
        Vec::new(),
    ])
}
