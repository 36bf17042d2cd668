//! Independent `f64` reference of the paper's equations and a naive dense RLS: the yardsticks
//! the `rotorid` core is tested (agreement, properties) and benchmarked ([`dense_rls`]) against.
//!
//! May depend on `std`, `nalgebra` and `rand` (the benchmark's seeded stream) only, never on
//! `rotorid` or the simulator: an error in the core must not be able to hide in its yardstick.
//!
//! The reference is written straight
//! from the paper ("System Identification for a Miniature Helicopter at Hover Using Fuzzy
//! Models", `/work/shared/paper/ts-fuzzy-rls-helicopter-hover.txt`, Sections 4–5, Tables 1
//! and 3) and the reading notes (`NOTES.md`), with plain loops, heap vectors and full
//! (row-major, `n × n`) matrices. It deliberately shares no code with the core and favours
//! transparency over speed: nothing here is meant to match the core bit for bit, only to the
//! accuracy of `f64` arithmetic.
//!
//! Contents:
//!
//! - [`MembershipFunction`]: the three Gaussian shapes of Table 1.
//! - [`table3`]: the centres and spreads of Table 3, with units, in one place.
//! - [`RuleBase`]: product t-norm rule base and normalised firing strengths `ξ_i` (Section 4).
//! - [`ts_regressor`]: the regressor `ξ(k)` of Section 4, `[Δ₁ξ₁ … Δ₁ξ_R, Δ₂ξ₁ … Δ₂ξ_R]`.
//! - [`Rls`]: the full-matrix RLS of Section 4 (optionally with a forgetting factor `λ`).
//! - [`ModelKind`], [`ReferenceModel`]: the four models of Section 5 (Eqs. 27–30) and their
//!   single-rule baselines (Eqs. 19, 26).
//! - [`ReferenceHover`]: all eight models fed one [`HoverSample`] at a time, recording every
//!   step ([`HoverStep`]).
//!
//! # Axes and units (NOTES.md, X-Plane conventions)
//!
//! Inertial frame: `j_s` up, so `v^s = [v_x, v_y, v_z]` has `v_y` up (m/s). Body rates
//! `ω^b = [q, r, p]` (pitch, yaw, roll) in **deg/s**: Table 3's centres and spreads for `q̃, r̃,
//! p̃` are in deg/s and the products `r·p`, `q·p`, `q·r` of Eqs. 28–30 are formed in (deg/s)².
//! Attitude: roll `φ`, pitch `θ`, yaw `ψ` in rad. Controls `u = [u_col, u_ped, u_lon, u_lat]`
//! (normalised; the collective stays clearly positive at hover, see NOTES.md).

pub mod dense_rls;
mod hover;
mod membership;
mod rls;
mod rule_base;

pub use hover::*;
pub use membership::*;
pub use rls::*;
pub use rule_base::*;
