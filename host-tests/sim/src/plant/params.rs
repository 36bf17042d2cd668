//! Physical parameters of a miniature helicopter of the Gavrilets model family
//! ([`Helicopter`]) and the stick-to-blade-pitch map.
//!
//! [`Helicopter::default`] (alias [`XCell60`]) is the published MIT X-Cell 60 (Gavrilets,
//! Mettler, Feron, AIAA 2001-4333; Gavrilets, Handbook of UAVs 2015) as listed in
//! `shared/plant/xcell60.md`; [`Helicopter::flybarless_600`] is the second plant, derived from
//! it (see there). All SI.

use serde::{Deserialize, Serialize};

/// Blade-element / momentum description of one rotor (main or tail).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RotorBlades {
    /// Rotor radius `R` (m).
    pub radius: f64,
    /// Blade chord `c` (m).
    pub chord: f64,
    /// Number of blades.
    pub blades: f64,
    /// Blade lift-curve slope `a` (1/rad).
    pub lift_slope: f64,
    /// Blade profile drag coefficient `C_D0` (–).
    pub cd0: f64,
    /// Thrust coefficient limit `C_T,max` (–); `C_T` is clamped to `±C_T,max`.
    pub ct_max: f64,
    /// Wake factor `η_w` (–) in `λ0 = C_T / (2 η_w sqrt(μ² + (λ0 − μ_z)²))`.
    pub eta_w: f64,
}

impl RotorBlades {
    /// Solidity `σ = N c / (π R)` (–).
    pub fn solidity(&self) -> f64 {
        self.blades * self.chord / (core::f64::consts::PI * self.radius)
    }

    /// Disc area `π R²` (m²).
    pub fn disc_area(&self) -> f64 {
        core::f64::consts::PI * self.radius * self.radius
    }
}

/// The X-Cell 60: [`Helicopter::default`], the published parameters.
pub type XCell60 = Helicopter;

/// Parameters of one helicopter (SI units). [`Default`] gives the published X-Cell 60 values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Helicopter {
    /// Mass `m` (kg).
    pub mass: f64,
    /// Roll moment of inertia `I_xx` (kg·m²), body FRD.
    pub ixx: f64,
    /// Pitch moment of inertia `I_yy` (kg·m²).
    pub iyy: f64,
    /// Yaw moment of inertia `I_zz` (kg·m²).
    pub izz: f64,
    /// Air density `ρ` (kg/m³).
    pub rho: f64,
    /// Gravity `g` (m/s²).
    pub g: f64,

    /// Main rotor blades (R = 0.775 m, c = 0.058 m, a = 5.5, C_D0 = 0.024, C_T,max = 0.0055).
    pub main: RotorBlades,
    /// Nominal main-rotor speed `Ω` (rad/s), held by a perfect governor.
    pub omega: f64,
    /// Hub torsional stiffness `K_β` (N·m/rad).
    pub k_beta: f64,
    /// Main-rotor hub height above the CG `h_mr` (m).
    pub h_mr: f64,

    /// Lock number of what sets the flapping speed, `γ_fb` (–): the stabiliser bar's on a
    /// flybarred rotor, the blades' on a flybarless one; sets `τ_e = 16 / (γ_fb Ω)`.
    pub gamma_fb: f64,
    /// Longitudinal cyclic-to-flapping gain `A_lon` (rad/rad).
    pub a_lon: f64,
    /// Lateral cyclic-to-flapping gain `B_lat` (rad/rad).
    pub b_lat: f64,
    /// Scaling of the flapping speed derivatives `K_μ` (–).
    pub k_mu: f64,

    /// Tail rotor blades (R_tr = 0.13 m, c = 0.029 m, a = 5.0, C_T,max = 0.05).
    pub tail: RotorBlades,
    /// Tail gear ratio `n_tr = Ω_tr / Ω` (–).
    pub n_tr: f64,
    /// Tail rotor hub distance behind the CG `l_tr` (m).
    pub l_tr: f64,
    /// Tail rotor hub height above the CG `h_tr` (m).
    pub h_tr: f64,
    /// Tail blade pitch offset `θ_tr,0` (rad): tail pitch at centred pedal.
    pub tail_pitch_offset: f64,

    /// Vertical fin area `S_vf` (m²), placed at the tail-rotor hub.
    pub vfin_area: f64,
    /// Vertical fin lift slope `C_Lα,vf` (1/rad).
    pub vfin_lift_slope: f64,
    /// Fraction of the vertical fin in the tail-rotor wash `ε_vf` (–).
    pub vfin_wash_fraction: f64,
    /// Horizontal fin area `S_ht` (m²).
    pub hfin_area: f64,
    /// Horizontal fin lift slope `C_Lα,ht` (1/rad).
    pub hfin_lift_slope: f64,
    /// Horizontal fin distance behind the CG `l_ht` (m). It lies inside the rotor radius, so it
    /// sits in the main-rotor downwash.
    pub l_ht: f64,

    /// Fuselage drag area along body x, `S_x` (m²).
    pub fus_sx: f64,
    /// Fuselage drag area along body y, `S_y` (m²).
    pub fus_sy: f64,
    /// Fuselage drag area along body z, `S_z` (m²).
    pub fus_sz: f64,

    /// Linear map from normalised sticks to blade pitch.
    pub sticks: StickMap,
}

impl Default for Helicopter {
    fn default() -> Self {
        Self {
            mass: 8.2,
            ixx: 0.18,
            iyy: 0.34,
            izz: 0.28,
            rho: 1.225,
            g: 9.81,
            main: RotorBlades {
                radius: 0.775,
                chord: 0.058,
                blades: 2.0,
                lift_slope: 5.5,
                cd0: 0.024,
                ct_max: 0.0055,
                eta_w: 0.9,
            },
            omega: 167.0,
            k_beta: 54.0,
            h_mr: 0.235,
            gamma_fb: 0.8,
            a_lon: 4.2,
            b_lat: 4.2,
            k_mu: 0.2,
            tail: RotorBlades {
                radius: 0.13,
                chord: 0.029,
                blades: 2.0,
                lift_slope: 5.0,
                // Not published for the tail; the main-rotor value is used.
                cd0: 0.024,
                ct_max: 0.05,
                // The spec gives one wake factor; the same momentum model is used for both rotors.
                eta_w: 0.9,
            },
            n_tr: 4.66,
            l_tr: 0.91,
            h_tr: 0.08,
            tail_pitch_offset: 0.1,
            vfin_area: 0.012,
            vfin_lift_slope: 2.0,
            vfin_wash_fraction: 0.2,
            hfin_area: 0.01,
            hfin_lift_slope: 3.0,
            l_ht: 0.71,
            fus_sx: 0.1,
            fus_sy: 0.22,
            fus_sz: 0.15,
            sticks: StickMap::default(),
        }
    }
}

impl Helicopter {
    /// Effective flapping time constant `τ_e = 16 / (γ_fb Ω)` (s), ≈ 0.12 s on the X-Cell.
    pub fn tau_e(&self) -> f64 {
        16.0 / (self.gamma_fb * self.omega)
    }

    /// Tail-rotor speed `Ω_tr = n_tr Ω` (rad/s).
    pub fn omega_tr(&self) -> f64 {
        self.n_tr * self.omega
    }

    /// Combined flapping-moment stiffness `K_β + T h_mr` (N·m/rad) at thrust `T` (N).
    pub fn flap_moment_gain(&self, thrust: f64) -> f64 {
        self.k_beta + thrust * self.h_mr
    }
}

/// Linear map from normalised sticks in [−1, 1] to blade pitch (rad).
///
/// * collective `θ0 = col_offset + col_gain · u_col`. Default `0 + 0.2 u_col`: ±0.2 rad
///   (±11.5°, an aerobatic collective range). Zero stick is zero pitch, so at hover the
///   thrust is close to proportional to `u_col` (the paper's `T_M = K_M u_col`), and hover
///   (θ0 ≈ 0.10 rad) sits at `u_col ≈ 0.5`, clearly positive as the identified model needs.
/// * tail `θ_tr = θ_tr,0 + ped_gain · u_ped` with the published offset `θ_tr,0 = 0.1 rad` and
///   default gain 0.25 rad: range −0.15 … 0.35 rad, hover (≈ 0.2 rad) at `u_ped ≈ 0.4`.
///   Positive pedal = more tail thrust = nose right (positive `r`).
/// * cyclic `δ_lon = lon_gain · u_lon`, `δ_lat = lat_gain · u_lat`, default 0.05 rad, which
///   `A_lon = B_lat = 4.2` turns into ±0.21 rad of steady flapping. Positive `u_lon` tilts the
///   tip-path plane back (`a1 > 0`, nose up, `q > 0`); positive `u_lat` tilts it right
///   (`b1 > 0`, roll right, `p > 0`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StickMap {
    /// Collective pitch at centred stick (rad).
    pub col_offset: f64,
    /// Collective pitch per unit stick (rad).
    pub col_gain: f64,
    /// Tail pitch per unit pedal (rad); the offset is [`Helicopter::tail_pitch_offset`].
    pub ped_gain: f64,
    /// Longitudinal cyclic pitch per unit stick (rad).
    pub lon_gain: f64,
    /// Lateral cyclic pitch per unit stick (rad).
    pub lat_gain: f64,
}

impl Default for StickMap {
    fn default() -> Self {
        Self {
            col_offset: 0.0,
            col_gain: 0.2,
            ped_gain: 0.25,
            lon_gain: 0.05,
            lat_gain: 0.05,
        }
    }
}

impl Helicopter {
    /// The same helicopter Froude-scaled by the length ratio `s`: lengths ∝ s, areas ∝ s²,
    /// mass ∝ s³, hub stiffness (a moment per radian) ∝ s⁴, inertia ∝ s⁵, rotor speed ∝ s^−½
    /// (so time ∝ s^½ and `τ_e` with it); air, gravity, every coefficient, gain and angle
    /// unchanged. Hover thrust `C_T ρ (ΩR)² π R²` then scales as s³ like the weight, so the trim
    /// `C_T`, blade pitch and sticks are the same, and the non-dimensional dynamics too.
    pub fn froude_scaled(&self, s: f64) -> Self {
        let (s2, s3, s4, s5) = (s * s, s * s * s, s * s * s * s, s * s * s * s * s);
        let blades = |b: &RotorBlades| RotorBlades {
            radius: b.radius * s,
            chord: b.chord * s,
            ..*b
        };
        Self {
            mass: self.mass * s3,
            ixx: self.ixx * s5,
            iyy: self.iyy * s5,
            izz: self.izz * s5,
            main: blades(&self.main),
            omega: self.omega / s.sqrt(),
            k_beta: self.k_beta * s4,
            h_mr: self.h_mr * s,
            tail: blades(&self.tail),
            l_tr: self.l_tr * s,
            h_tr: self.h_tr * s,
            vfin_area: self.vfin_area * s2,
            hfin_area: self.hfin_area * s2,
            l_ht: self.l_ht * s,
            fus_sx: self.fus_sx * s2,
            fus_sy: self.fus_sy * s2,
            fus_sz: self.fus_sz * s2,
            ..*self
        }
    }
}
