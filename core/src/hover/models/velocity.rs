//! The translational model (Eq. 27): `Δv^s` from the thrust direction, gravity and drag.

use crate::error::Error;
use crate::hover::sample::{HoverSample, HoverState};
use crate::learning::{Learning, TsEstimator};
use crate::rls::RlsConfig;
use crate::rule_base::RuleBase;
use crate::scalar::Real;
use crate::ts::{Prepared, Scaling};

use super::sealed::{self, StepParts};
use super::{check_terms, kept_by, BodyFrame, Premise, SharedStrengths, StateModel};

/// Consequent structure of the translational model.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum VelocityStructure {
    /// Eq. 27: per rule `α1` (thrust along the rotor axis `R e2`, all three outputs) and `α2`
    /// (weight, `v_y` only). `D = 2`, terms `[e·u_col, 1]`.
    Paper,
    /// Eq. 27 plus per-axis drag and the tail rotor's side force: per rule
    /// `[α1, α2, d_x, d_y, d_z, σ0, σ1]` with
    /// `v̂(k+1) = v + α1 (R e2) u_col + α2 e2 + diag(d_x, d_y, d_z) v + (σ0 + σ1 u_ped) R e1`.
    /// `R e1` is the body's right axis in inertial axes (the first column of the paper's R).
    /// The drag terms model fuselage and rotor damping. The side-force terms are Eq. 13's tail
    /// rotor thrust `T_T = K_T u_ped` along `−i_b`, which Eq. 15 neglects: in hover it balances
    /// the trim roll against the tail rotor, and without it Eq. 27 leaves a bias that turns
    /// with the heading (an affine term fixed in the body frame, not the inertial one). `D = 7`.
    Extended,
    /// [`Extended`](Self::Extended) with the horizontal drag in the aircraft's heading frame
    /// instead of the inertial axes, on the velocity of the sample before, and the main
    /// rotor's thrust affine in the collective: `[α1, α2, d_f, d_r, d_u, σ0, σ1, α0]` with
    /// `v̂(k+1) = v + (α1 u_col + α0) R e2 + α2 e2 + d_f u_f(k−1) f + d_r u_r(k−1) r +
    /// d_u v_y(k) e2 + (σ0 + σ1 u_ped) R e1`, where `f` and `r` are the heading's forward and
    /// right unit vectors at sample k and `u_f`, `u_r` the velocity along them (m/s).
    ///
    /// * Affine thrust `(α1 u_col + α0) R e2`: Eq. 13's `T_M = K_M u_col` makes the thrust
    ///   zero at zero stick, but a rotor's thrust is zero at its zero-lift blade pitch, which a
    ///   stick mapping need not put at zero, and the induced inflow, which grows with the
    ///   thrust, makes the thrust's slope in the collective (what a climb responds with)
    ///   differ from its ratio to the collective at trim (what tilting the disc turns into
    ///   horizontal acceleration, `≈ g` per radian at hover). With `α1` alone the two compete
    ///   for one parameter and every tilt is over- or under-predicted; `α0` is the thrust at
    ///   zero collective, along the rotor axis like the rest of it (the tail rotor's side
    ///   force has its constant `σ0` for the same reason). The weight `α2 e2` stays: gravity
    ///   is vertical whatever the attitude.
    /// * Heading frame: a fuselage's drag differs along and across it; in inertial axes those
    ///   two mix as the heading turns, so that one set of `d_x, d_z` fits only one heading.
    /// * Sample k−1: the measurement noise of `v(k)` is in the target `Δv = v(k+1) − v(k)` too,
    ///   with the opposite sign, and a least-squares fit on `v(k)` reads it as drag (errors in
    ///   variables): a bias of about `−σ²/var(v)` per step, σ the sensor's noise. The noise of
    ///   `v(k−1)` is independent of the target's, and drag, with time constants of seconds,
    ///   does not change in one 20 ms sample. The bias matters where the real drag is small and
    ///   the speed little excited: horizontally in hover, where GPS/INS noise of 0.02 m/s makes
    ///   a fit on `v(k)` learn several times the real drag (docs/results.md, "What limits the
    ///   flight default"), a model that damps the noise well one step ahead and drifts in a
    ///   free run. The heave damping is large and the vertical speed well excited by the
    ///   collective, so the bias is a few per cent of it, and `d_u` stays on `v_y(k)` (keeping
    ///   `v_y(k−1)` as well would take the paper fuzzy identifier over its 11 KiB). Some of that
    ///   bias reaches the horizontal drag through the parameters the three outputs share
    ///   (`core/tests/extended.rs` measures both). The structure needs the sample before, which the
    ///   identifier keeps.
    ///
    /// `D = 8`.
    Flight,
}

impl VelocityStructure {
    /// Consequent terms per rule.
    pub const fn terms(self) -> usize {
        match self {
            Self::Paper => 2,
            Self::Extended => 7,
            Self::Flight => 8,
        }
    }

    /// Nominal scales for a miniature helicopter at 50 Hz (see [`Scaling`]): thrust term
    /// `e·u_col` 0.5, constants and axes 1 (the flight structure's `R e2` of `α0` too),
    /// velocities 1 m/s, `u_ped` terms 0.3; target `Δv` 0.05 m/s per step.
    pub fn helicopter_scaling<T: Real, const D: usize>(self) -> Scaling<T, D> {
        // Each literal converted where it stands (a constant for f32: no f64 conversion code
        // in an f32 firmware); the tail of a shorter structure is 1, as `terms` starts.
        let one = T::one();
        let (half, u_ped) = (T::lit(0.5), T::lit(0.3));
        let nominal: [T; 8] = match self {
            Self::Paper => [half, one, one, one, one, one, one, one],
            Self::Extended | Self::Flight => [half, one, one, one, one, one, u_ped, one],
        };
        let mut terms = [T::one(); D];
        for (t, &n) in terms.iter_mut().zip(&nominal) {
            *t = n;
        }
        Scaling {
            terms,
            target: T::lit(0.05),
        }
    }
}

/// Translational model (Eq. 27): premise `v^s(k)` (or see [`Premise`]), three outputs
/// `v_x, v_y, v_z` sharing θ, learnt by the TS estimator `E` (global or local, see
/// [`Learning`]).
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityModel<T, const R: usize, const D: usize, E> {
    ts: E,
    structure: VelocityStructure,
    premise: Premise,
    _scalar: core::marker::PhantomData<T>,
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>>
    VelocityModel<T, R, D, E>
{
    /// A model over the given rule base (premise `[v_x v_y v_z]`, m/s), unscaled.
    pub fn new(
        rules: RuleBase<T, 3, R>,
        structure: VelocityStructure,
        config: RlsConfig<T>,
    ) -> Result<Self, Error> {
        Self::with_scaling(rules, structure, Premise::Velocity, config, Scaling::unit())
    }

    /// A model over the given premise whose terms and target are divided by nominal scales
    /// (see [`Scaling`]).
    pub fn with_scaling(
        rules: RuleBase<T, 3, R>,
        structure: VelocityStructure,
        premise: Premise,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Result<Self, Error> {
        Self::check_new(structure, &config, &scaling)?;
        Ok(Self::with_scaling_unchecked(
            rules, structure, premise, config, scaling,
        ))
    }

    pub(crate) fn check_new(
        structure: VelocityStructure,
        config: &RlsConfig<T>,
        scaling: &Scaling<T, D>,
    ) -> Result<(), Error> {
        check_terms(structure.terms(), D)?;
        E::check_new(config, scaling)
    }

    #[inline(always)]
    pub(crate) fn with_scaling_unchecked(
        rules: RuleBase<T, 3, R>,
        structure: VelocityStructure,
        premise: Premise,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Self {
        Self {
            ts: E::build(rules, config, scaling),
            structure,
            premise,
            _scalar: core::marker::PhantomData,
        }
    }

    /// The consequent structure.
    pub fn structure(&self) -> VelocityStructure {
        self.structure
    }

    /// The premise variables.
    pub fn premise(&self) -> Premise {
        self.premise
    }

    /// How the consequents are learnt.
    pub fn learning(&self) -> Learning {
        E::LEARNING
    }

    /// The underlying TS model (rule base, parameters, covariance).
    pub fn ts(&self) -> &E {
        &self.ts
    }

    /// The consequent terms `Δ` of the outputs `v_x, v_y, v_z` at sample k (with no sample
    /// before it: [`VelocityStructure::Flight`]'s drag takes sample k's own velocity).
    pub fn terms(&self, s: &HoverSample<T>) -> [[T; D]; 3] {
        self.terms_in(s, &BodyFrame::of(&s.attitude), &s.velocity)
    }

    /// [`terms`](Self::terms) with the sample's body frame already computed and the velocity
    /// `v^s` of the sample before (m/s; only [`VelocityStructure::Flight`] reads it, and only its
    /// horizontal components).
    pub fn terms_in<A>(
        &self,
        s: &HoverSample<T, A>,
        trig: &BodyFrame<T>,
        before: &[T; 3],
    ) -> [[T; D]; 3] {
        let mut terms = [[T::zero(); D]; 3];
        let e = trig.rotor_axis();
        // The right axis only enters the extended structure.
        let side = match self.structure {
            VelocityStructure::Paper => [T::zero(); 3],
            VelocityStructure::Extended | VelocityStructure::Flight => trig.right_axis(),
        };
        // Heading frame in paper axes (x east, y up, z south): forward f = [sψ, 0, −cψ],
        // right r = [cψ, 0, sψ]; with the velocity along them. Only the flight structure
        // needs them (the others skip the work).
        let heading = match self.structure {
            VelocityStructure::Flight => {
                let (sp, cp) = (trig.sp, trig.cp);
                let [vx, _, vz] = *before;
                let (u_f, u_r) = (vx * sp - vz * cp, vx * cp + vz * sp);
                [
                    [sp * u_f, cp * u_r],
                    [T::zero(), T::zero()],
                    [-cp * u_f, sp * u_r],
                ]
            }
            _ => [[T::zero(); 2]; 3],
        };
        let one = T::one();
        for (out, (t, ((&ei, &v), &si))) in terms
            .iter_mut()
            .zip(e.iter().zip(s.velocity.iter()).zip(side.iter()))
            .enumerate()
        {
            if let Some(x) = t.get_mut(0) {
                *x = ei * s.controls.col;
            }
            // Slots [α1, α2, d_x, d_y, d_z, σ0, σ1] (the flight structure: then α0): α2 only
            // in v_y, each drag in its own output (the flight structure: forward and right
            // drag in x and z, vertical in y), the side force and α0's thrust in all three.
            let mut set = |slot: usize, value: T| {
                if let Some(x) = t.get_mut(slot) {
                    *x = value;
                }
            };
            if out == 1 {
                set(1, one);
            }
            match self.structure {
                VelocityStructure::Paper => {}
                VelocityStructure::Extended => {
                    set(2 + out, v);
                    set(5, si);
                    set(6, si * s.controls.ped);
                }
                VelocityStructure::Flight => {
                    let [f, r] = heading.get(out).copied().unwrap_or([T::zero(); 2]);
                    set(2, f);
                    set(3, r);
                    set(4, if out == 1 { v } else { T::zero() });
                    set(5, si);
                    set(6, si * s.controls.ped);
                    set(7, ei);
                }
            }
        }
        terms
    }
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> sealed::StepParts<T>
    for VelocityModel<T, R, D, E>
{
    type Prepared = Prepared<T, R, D, 3>;

    fn prepare_in<A, B>(
        &self,
        from: &HoverSample<T, A>,
        from_frame: &BodyFrame<T>,
        before: &HoverState<T>,
        to: &HoverSample<T, B>,
    ) -> Result<Self::Prepared, Error> {
        let [x0, y0, z0] = from.velocity;
        let [x1, y1, z1] = to.velocity;
        self.ts.prepare(
            &self.premise.of(from, from_frame),
            &self.terms_in(from, from_frame, &before.velocity),
            &[x1 - x0, y1 - y0, z1 - z0],
        )
    }

    fn predict_in<A>(
        &self,
        from: &HoverSample<T, A>,
        from_frame: &BodyFrame<T>,
        before: &HoverState<T>,
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let increments = self.ts.predict_many(
            &self.premise.of(from, from_frame),
            &self.terms_in(from, from_frame, &before.velocity),
        )?;
        next.velocity = advance(from, &increments);
        Ok(())
    }

    fn predict_keep<A>(
        &mut self,
        from: &HoverSample<T, A>,
        from_frame: &BodyFrame<T>,
        before: &HoverState<T>,
        shared: Option<&SharedStrengths<'_, T>>,
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let premise = self.premise.of(from, from_frame);
        let strengths = shared.and_then(|s| s.for_rules(self.premise, self.ts.rules()));
        let terms = self.terms_in(from, from_frame, &before.velocity);
        let increments = self.ts.predict_keep(&premise, strengths, &terms)?;
        next.velocity = advance(from, &increments);
        Ok(())
    }

    fn kept_strengths(&self) -> Option<SharedStrengths<'_, T>> {
        kept_by(self.premise, &self.ts)
    }
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> StateModel<T>
    for VelocityModel<T, R, D, E>
{
    type State = E::State;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        self.prepare_in(from, &BodyFrame::of(&from.attitude), &from.state(), to)
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        innovation.velocity = prepared.innovations;
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        self.predict_in(from, &BodyFrame::of(&from.attitude), &from.state(), next)
    }

    forward_to_estimator!(velocity_scaling);
}

/// `v^s(k) + Δv̂`: the predicted velocity from the predicted increments.
fn advance<T: Real, A>(from: &HoverSample<T, A>, increments: &[T; 3]) -> [T; 3] {
    let mut out = from.velocity;
    for (o, &d) in out.iter_mut().zip(increments.iter()) {
        *o += d;
    }
    out
}
