//! Plant variations: other helicopters of the same kind, drawn at random around an airframe.
//!
//! rotorid is judged on helicopters it was not developed on. Two airframes cannot show how a
//! modelling choice generalises; a family of plants whose parameters are spread as far as real
//! miniature helicopters differ can. [`Helicopter::varied`] multiplies each parameter that
//! sets the dynamics the models identify by its own random factor, log-uniform in
//! `[1/s, s]`, with `s` per parameter from [`SPREADS`]:
//!
//! | parameter | spread `s` | why that wide |
//! |---|---:|---|
//! | mass `m` | 1.15 | the rotor must still lift it at the same head speed and collective range |
//! | inertias `I_xx`, `I_yy`, `I_zz` (each on top of the mass's factor) | 1.6 | battery, tail boom and canopy layouts move them independently |
//! | hub stiffness `K_β`, hub height `h_mr` | 1.6 | dampers and head designs |
//! | flapping Lock number `γ_fb` | 1.6 | flybar paddles or blade weights: the flapping time constant `τ_e` |
//! | cyclic-to-flapping gains `A_lon`, `B_lat` | 1.6 | flybar mixing ratios, servo arms |
//! | flapping speed derivatives `K_μ` | 1.6 | not well known on any aircraft |
//! | tail arm `l_tr`, fin areas | 1.6 | boom lengths and fin sizes |
//! | fuselage drag areas `S_x`, `S_y`, `S_z` | 1.6 | canopy shapes |
//! | tail rotor radius | 1.15 | it must still balance the main rotor's torque |
//! | head speed `Ω` | 1.1 | governor settings within the blades' range |
//!
//! Everything else (blade aerodynamics, the stick map, gravity, air) is the airframe's. Some
//! draws cannot hover within the sticks' range; the trim then fails and the flight says so.
//! The same seed gives the same plant bit for bit (ChaCha8, the draws in the table's order).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::params::Helicopter;

/// The spread `s` of each varied parameter (factor log-uniform in `[1/s, s]`), in draw order.
pub const SPREADS: Spreads = Spreads {
    mass: 1.15,
    inertia: 1.6,
    hub: 1.6,
    flapping: 1.6,
    tail_and_fins: 1.6,
    fuselage: 1.6,
    tail_radius: 1.15,
    head_speed: 1.1,
};

/// The spreads of [`Helicopter::varied`], by group (see the module's table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spreads {
    /// Mass.
    pub mass: f64,
    /// Each moment of inertia, on top of the mass's factor.
    pub inertia: f64,
    /// Hub stiffness and hub height.
    pub hub: f64,
    /// Lock number, cyclic gains, flapping speed derivatives.
    pub flapping: f64,
    /// Tail arm and fin areas.
    pub tail_and_fins: f64,
    /// Fuselage drag areas.
    pub fuselage: f64,
    /// Tail rotor radius.
    pub tail_radius: f64,
    /// Main rotor speed.
    pub head_speed: f64,
}

impl Helicopter {
    /// Another helicopter of this one's kind: the parameters of the module's table each
    /// multiplied by a factor drawn from `seed` (module docs). The airframe itself is not a
    /// variation; seed 0 is a variation like any other.
    pub fn varied(&self, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut factor = |spread: f64| -> f64 {
            let ln = spread.ln();
            rng.random_range(-ln..=ln).exp()
        };
        let s = SPREADS;
        let mut h = *self;
        let mass = factor(s.mass);
        h.mass *= mass;
        h.ixx *= mass * factor(s.inertia);
        h.iyy *= mass * factor(s.inertia);
        h.izz *= mass * factor(s.inertia);
        h.k_beta *= factor(s.hub);
        h.h_mr *= factor(s.hub);
        h.gamma_fb *= factor(s.flapping);
        h.a_lon *= factor(s.flapping);
        h.b_lat *= factor(s.flapping);
        h.k_mu *= factor(s.flapping);
        h.l_tr *= factor(s.tail_and_fins);
        h.vfin_area *= factor(s.tail_and_fins);
        h.hfin_area *= factor(s.tail_and_fins);
        h.fus_sx *= factor(s.fuselage);
        h.fus_sy *= factor(s.fuselage);
        h.fus_sz *= factor(s.fuselage);
        h.tail.radius *= factor(s.tail_radius);
        h.omega *= factor(s.head_speed);
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::params::XCell60;

    /// Each varied parameter's factor against the airframe's value.
    fn factors(a: &Helicopter, b: &Helicopter) -> Vec<(&'static str, f64, f64)> {
        let m = b.mass / a.mass;
        vec![
            ("mass", m, SPREADS.mass),
            ("ixx", b.ixx / a.ixx / m, SPREADS.inertia),
            ("iyy", b.iyy / a.iyy / m, SPREADS.inertia),
            ("izz", b.izz / a.izz / m, SPREADS.inertia),
            ("k_beta", b.k_beta / a.k_beta, SPREADS.hub),
            ("h_mr", b.h_mr / a.h_mr, SPREADS.hub),
            ("gamma_fb", b.gamma_fb / a.gamma_fb, SPREADS.flapping),
            ("a_lon", b.a_lon / a.a_lon, SPREADS.flapping),
            ("b_lat", b.b_lat / a.b_lat, SPREADS.flapping),
            ("k_mu", b.k_mu / a.k_mu, SPREADS.flapping),
            ("l_tr", b.l_tr / a.l_tr, SPREADS.tail_and_fins),
            ("vfin", b.vfin_area / a.vfin_area, SPREADS.tail_and_fins),
            ("hfin", b.hfin_area / a.hfin_area, SPREADS.tail_and_fins),
            ("fus_sx", b.fus_sx / a.fus_sx, SPREADS.fuselage),
            ("fus_sy", b.fus_sy / a.fus_sy, SPREADS.fuselage),
            ("fus_sz", b.fus_sz / a.fus_sz, SPREADS.fuselage),
            (
                "tail radius",
                b.tail.radius / a.tail.radius,
                SPREADS.tail_radius,
            ),
            ("omega", b.omega / a.omega, SPREADS.head_speed),
        ]
    }

    #[test]
    fn a_variation_is_reproducible_and_each_factor_within_its_spread() {
        let x = XCell60::default();
        for seed in 0..50 {
            let v = x.varied(seed);
            assert_eq!(v, x.varied(seed), "seed {seed} not reproducible");
            for (name, f, s) in factors(&x, &v) {
                // The inertias' factor is a product of two; the division gives it back to
                // within rounding.
                let eps = 1e-12;
                assert!(
                    f >= 1.0 / s - eps && f <= s + eps,
                    "seed {seed}: {name} factor {f} outside [1/{s}, {s}]"
                );
            }
            // What is not varied is the airframe's.
            assert_eq!(v.main, x.main);
            assert_eq!(v.sticks, x.sticks);
            assert_eq!((v.g, v.rho, v.n_tr), (x.g, x.rho, x.n_tr));
        }
    }

    #[test]
    fn variations_differ_and_spread_over_their_ranges() {
        let x = XCell60::default();
        let all: Vec<Vec<f64>> = (0..200)
            .map(|seed| factors(&x, &x.varied(seed)).iter().map(|f| f.1).collect())
            .collect();
        assert_ne!(all[0], all[1]);
        // Over 200 draws every factor reaches the outer fifths of its log range on both sides
        // (a draw that ignored a parameter, or a spread applied twice, would not).
        for (i, (name, _, s)) in factors(&x, &x.varied(0)).into_iter().enumerate() {
            let ln: Vec<f64> = all.iter().map(|f| f[i].ln() / s.ln()).collect();
            let (lo, hi) = ln
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            assert!(
                lo < -0.6 && hi > 0.6,
                "{name}: normalised log range {lo}..{hi}"
            );
        }
    }
}
