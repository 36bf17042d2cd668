//! The four state models of the hover identifier: thin wrappers that turn a [`HoverSample`]
//! into the premise and consequent terms of a [`TsRls`].

use crate::error::{ConfigError, Error};
use crate::hover::sample::{Attitude, HoverSample, HoverState};
use crate::learning::{Learning, TsEstimator};
use crate::rls::RlsConfig;
use crate::rule_base::RuleBase;
use crate::scalar::Real;
use crate::ts::{Prepared, Scaling};

/// What a [`HoverIdentifier`](crate::hover::HoverIdentifier) needs of each of its models.
///
/// Learning is split in two so that the identifier can check all four models before it
/// changes any: [`prepare`](Self::prepare) checks and computes, [`apply`](Self::apply) writes.
pub trait StateModel<T: Real> {
    /// A checked update, ready to apply.
    type Prepared;
    /// What [`export`](Self::export) returns and [`import`](Self::import) takes.
    type State: Copy;

    /// Checks and computes the update from sample k (`from`) to sample k+1 (`to`).
    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error>;
    /// Learns from a prepared update; writes the prior innovations of this model's outputs
    /// into `innovation` (the other entries are left alone).
    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>);
    /// Writes this model's one-step prediction of sample k+1 from sample k into `next`.
    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error>;
    /// Back to θ(0) = 0, P(0) = αI.
    fn reset(&mut self);
    /// Everything learnt.
    fn export(&self) -> Self::State;
    /// Warm start from an exported state. On `Err` nothing changed.
    fn import(&mut self, state: &Self::State) -> Result<(), Error>;
    /// The checks of [`import`](Self::import), without importing.
    fn check_import(&self, state: &Self::State) -> Result<(), Error>;
    /// New estimator settings (and the scales they imply), in place, starting afresh.
    fn reconfigure(&mut self, config: &crate::hover::HoverConfig<T>) -> Result<(), Error>;
    /// The estimator settings.
    fn rls_config(&self) -> &RlsConfig<T>;

    /// [`prepare`](Self::prepare) with `from`'s body frame already computed (the identifier
    /// keeps it from the previous step) and the body rates `[q r p]` of the sample before
    /// `from` (`before`; `from`'s own rates when there is none), for structures with a
    /// second-order term ([`RateStructure::Flight`]). [`prepare`](Self::prepare) is this with
    /// `before = from.rates`.
    fn prepare_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        before: &[T; 3],
        to: &HoverSample<T>,
    ) -> Result<Self::Prepared, Error> {
        let _ = (from_frame, before);
        self.prepare(from, to)
    }

    /// [`predict`](Self::predict) with `from`'s body frame already computed and the rates of
    /// the sample before `from` (see [`prepare_in`](Self::prepare_in)).
    fn predict_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        before: &[T; 3],
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let _ = (from_frame, before);
        self.predict(from, next)
    }
}

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
    /// [`Extended`](Self::Extended) with the drag in the aircraft's heading frame instead of
    /// the inertial axes: `[α1, α2, d_f, d_r, d_u, σ0, σ1]` with
    /// `… + d_f u_f f + d_r u_r r + d_u v_y e2 + …`, where `f` and `r` are the heading's
    /// forward and right unit vectors and `u_f`, `u_r` the velocity along them (m/s). A
    /// fuselage's drag differs along and across it; in inertial axes those two mix as the
    /// heading turns, so that one set of `d_x, d_z` fits only one heading. `D = 7`.
    Flight,
}

impl VelocityStructure {
    /// Consequent terms per rule.
    pub const fn terms(self) -> usize {
        match self {
            Self::Paper => 2,
            Self::Extended | Self::Flight => 7,
        }
    }

    /// Nominal scales for a miniature helicopter at 50 Hz (see [`Scaling`]): thrust term
    /// `e·u_col` 0.5, constants and axes 1, velocities 1 m/s, `u_ped` terms 0.3; target `Δv`
    /// 0.05 m/s per step.
    pub fn helicopter_scaling<T: Real, const D: usize>(self) -> Scaling<T, D> {
        let nominal: &[f64] = match self {
            Self::Paper => &[0.5, 1.0],
            Self::Extended | Self::Flight => &[0.5, 1.0, 1.0, 1.0, 1.0, 1.0, 0.3],
        };
        let mut terms = [T::one(); D];
        for (t, &n) in terms.iter_mut().zip(nominal) {
            *t = T::lit(n);
        }
        Scaling {
            terms,
            target: T::lit(0.05),
        }
    }
}

/// The body axes of one attitude, kept as the sines and cosines of roll, pitch and yaw: one
/// `libm` `sincos` per angle (bit-identical to separate `sin` and `cos`), shared by both axes.
///
/// The identifier computes it once per sample and keeps the previous sample's (the
/// transcendental functions are the most expensive part of a plain step on an MCU without a
/// double-precision FPU).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BodyFrame<T> {
    sf: T,
    cf: T,
    st: T,
    ct: T,
    sp: T,
    cp: T,
}

impl<T: Real> BodyFrame<T> {
    /// The frame of an attitude.
    #[inline]
    pub fn of(a: &Attitude<T>) -> Self {
        Self::new(a.roll, a.pitch, a.yaw)
    }

    /// The frame of roll, pitch, yaw (rad).
    #[inline]
    pub fn new(roll: T, pitch: T, yaw: T) -> Self {
        let (sf, cf) = roll.sin_cos_libm();
        let (st, ct) = pitch.sin_cos_libm();
        let (sp, cp) = yaw.sin_cos_libm();
        Self {
            sf,
            cf,
            st,
            ct,
            sp,
            cp,
        }
    }

    /// The frame of zero roll, pitch and yaw (no trigonometry).
    #[inline]
    pub fn identity() -> Self {
        let (zero, one) = (T::zero(), T::one());
        Self {
            sf: zero,
            cf: one,
            st: zero,
            ct: one,
            sp: zero,
            cp: one,
        }
    }

    /// [`rotor_axis`] of this attitude.
    #[inline]
    pub fn rotor_axis(&self) -> [T; 3] {
        let Self {
            sf,
            cf,
            st,
            ct,
            sp,
            cp,
        } = *self;
        [sf * cp - cf * st * sp, cf * ct, sf * sp + cf * st * cp]
    }

    /// [`right_axis`] of this attitude.
    #[inline]
    pub fn right_axis(&self) -> [T; 3] {
        let Self {
            sf,
            cf,
            st,
            ct,
            sp,
            cp,
        } = *self;
        [cf * cp + sf * st * sp, -(sf * ct), cf * sp - sf * st * cp]
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

/// The premise variables a model's rules are scheduled on.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Premise {
    /// The paper's choice for Eq. 27: the inertial velocity `v^s = [v_x v_y v_z]` (m/s).
    Velocity,
    /// The paper's choice for Eqs. 28–30: the body rates `[q r p]` (deg/s).
    Rates,
    /// The velocity in the heading frame, `[forward, right, up]` (m/s): `v^s` turned by the
    /// yaw ψ (ground speed, which is airspeed in still air). A helicopter's dynamics change
    /// with airspeed (speed stability, the fin's and the stabiliser's damping, translational
    /// lift, the tail rotor's effectiveness), and they do so in the aircraft's own axes; the
    /// inertial velocity would split one physical regime over several headings.
    HeadingVelocity,
}

impl Premise {
    /// The premise vector of sample `s` (whose body frame is `frame`).
    #[inline]
    pub fn of<T: Real>(self, s: &HoverSample<T>, frame: &BodyFrame<T>) -> [T; 3] {
        match self {
            Self::Velocity => s.velocity,
            Self::Rates => s.rates,
            Self::HeadingVelocity => {
                // Paper axes: x east, y up, z south; ψ from north towards east.
                let [x, y, z] = s.velocity;
                let (sp, cp) = (frame.sp, frame.cp);
                [x * sp - z * cp, x * cp + z * sp, y]
            }
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

    /// The consequent terms `Δ` of the outputs `v_x, v_y, v_z` at sample k.
    pub fn terms(&self, s: &HoverSample<T>) -> [[T; D]; 3] {
        self.terms_in(s, &BodyFrame::of(&s.attitude))
    }

    /// [`terms`](Self::terms) with the sample's body frame already computed.
    pub fn terms_in(&self, s: &HoverSample<T>, trig: &BodyFrame<T>) -> [[T; D]; 3] {
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
                let [vx, _, vz] = s.velocity;
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
            // Slots [α1, α2, d_x, d_y, d_z, σ0, σ1]: α2 only in v_y, each drag in its own
            // output (the flight structure: forward and right drag in x and z, vertical in
            // y), the side force in all three.
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
                }
            }
        }
        terms
    }
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> StateModel<T>
    for VelocityModel<T, R, D, E>
{
    type Prepared = Prepared<T, R, D, 3>;
    type State = E::State;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        self.prepare_in(from, &BodyFrame::of(&from.attitude), &from.rates, to)
    }

    fn prepare_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        _before: &[T; 3],
        to: &HoverSample<T>,
    ) -> Result<Self::Prepared, Error> {
        let [x0, y0, z0] = from.velocity;
        let [x1, y1, z1] = to.velocity;
        self.ts.prepare(
            &self.premise.of(from, from_frame),
            &self.terms_in(from, from_frame),
            &[x1 - x0, y1 - y0, z1 - z0],
        )
    }

    fn predict_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        _before: &[T; 3],
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let increments = self.ts.predict_many(
            &self.premise.of(from, from_frame),
            &self.terms_in(from, from_frame),
        )?;
        let mut out = from.velocity;
        for (o, &d) in out.iter_mut().zip(increments.iter()) {
            *o += d;
        }
        next.velocity = out;
        Ok(())
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        innovation.velocity = prepared.innovations;
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        self.predict_in(from, &BodyFrame::of(&from.attitude), &from.rates, next)
    }

    fn reset(&mut self) {
        self.ts.reset();
    }

    fn export(&self) -> Self::State {
        self.ts.export()
    }

    fn import(&mut self, state: &Self::State) -> Result<(), Error> {
        self.ts.import(state)
    }

    fn check_import(&self, state: &Self::State) -> Result<(), Error> {
        self.ts.check_import(state)
    }

    fn reconfigure(&mut self, config: &crate::hover::HoverConfig<T>) -> Result<(), Error> {
        self.ts
            .reconfigure(config.rls, config.velocity_scaling::<D>(self.structure))
    }

    fn rls_config(&self) -> &RlsConfig<T> {
        self.ts.config()
    }
}

fn check_terms(needed: usize, found: usize) -> Result<(), Error> {
    if needed == found {
        Ok(())
    } else {
        Err(ConfigError::ConsequentTerms {
            needed: needed as u8,
            found: found as u8,
        }
        .into())
    }
}

/// Which body rate an angular model predicts.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RateAxis {
    /// q̂, Eq. 28: `Δ = [r·p, u_lon·u_col]`.
    Pitch,
    /// r̂, Eq. 29: `Δ = [q·p, u_ped]`.
    Yaw,
    /// p̂, Eq. 30: `Δ = [q·r, u_lat·u_col]`.
    Roll,
}

impl RateAxis {
    /// Index of this rate in `[q r p]`.
    pub const fn index(self) -> usize {
        match self {
            Self::Pitch => 0,
            Self::Yaw => 1,
            Self::Roll => 2,
        }
    }
}

/// Consequent structure of an angular model.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RateStructure {
    /// Eqs. 28–30: per rule an inertia-coupling coefficient `𝕀^i` (gyroscopic product of
    /// the other two rates) and a control gain `γ^i`. `D = 2`.
    Paper,
    /// Eqs. 28–30 plus a damping term in the model's own rate, the collective term `B′u_col`
    /// of Eq. 20 that Eq. 26 drops, and an affine (trim) term: per rule `[𝕀, γ, δ, β, c]`,
    /// e.g. `q̂(k+1) = q + 𝕀 r p + γ u_lon u_col + δ q + β u_col + c`. Rotorcraft damp their
    /// rates strongly (rotor flapping, Eqs. 6–7), which the paper's structure can only fold
    /// into the control gain; the main rotor's torque changes with collective, which drives
    /// yaw; the affine term absorbs trim moments. `D = 5`.
    Extended,
    /// [`Extended`](Self::Extended) plus the speed-stability term of the model's own axis and
    /// a second-order term: `[𝕀, γ, δ, β, c, κ, η]`, e.g.
    /// `q̂(k+1) = q + … + κ u + η (q(k) − q(k−1))`.
    ///
    /// * `κ u` for q̂ (`M_u`: forward speed flaps the disc back and pitches the nose up) and
    ///   `κ v` for r̂ and p̂ (`N_v`: the fin's weathercock moment; `L_v`: the disc's dihedral
    ///   effect), `u`, `v` being the forward and rightward speed in the heading frame (m/s):
    ///   the velocity derivatives of every linear helicopter model, and they grow with
    ///   airspeed.
    /// * `η Δω(k)`, the previous increment of the rate: the rotor's flapping and inflow are
    ///   fast states that no sample records (flapping settles in ≈ 3 samples at 50 Hz), so
    ///   the rate responds as a second-order system at the sample scale; an ARX model of order
    ///   2 in the rate (as PX4's `ArxRls<2, …>`) accounts for them. It makes the rate models
    ///   need the sample before: see [`StateModel::prepare_in`].
    ///
    /// `D = 7`.
    Flight,
}

impl RateStructure {
    /// Consequent terms per rule.
    pub const fn terms(self) -> usize {
        match self {
            Self::Paper => 2,
            Self::Extended => 5,
            Self::Flight => 7,
        }
    }

    /// Nominal scales for a miniature helicopter at 50 Hz (see [`Scaling`]): rate products
    /// 100 (deg/s)², control products 0.05, rates 10 deg/s, collective 0.5, constants 1,
    /// speeds 5 m/s, rate increments 1 deg/s; target `Δω` 1 deg/s per step.
    pub fn helicopter_scaling<T: Real, const D: usize>(self) -> Scaling<T, D> {
        let nominal: &[f64] = match self {
            Self::Paper => &[100.0, 0.05],
            Self::Extended => &[100.0, 0.05, 10.0, 0.5, 1.0],
            Self::Flight => &[100.0, 0.05, 10.0, 0.5, 1.0, 5.0, 1.0],
        };
        let mut terms = [T::one(); D];
        for (t, &n) in terms.iter_mut().zip(nominal) {
            *t = T::lit(n);
        }
        Scaling {
            terms,
            target: T::one(),
        }
    }
}

/// An angular model (Eqs. 28–30): premise `[q r p](k)` (deg/s; or see [`Premise`]), one
/// output, learnt by the TS estimator `E` (global or local, see [`Learning`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RateModel<T, const R: usize, const D: usize, E> {
    ts: E,
    axis: RateAxis,
    structure: RateStructure,
    premise: Premise,
    _scalar: core::marker::PhantomData<T>,
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> RateModel<T, R, D, E> {
    /// A model of one body rate over the given rule base (premise `[q r p]`, deg/s), unscaled.
    pub fn new(
        axis: RateAxis,
        rules: RuleBase<T, 3, R>,
        structure: RateStructure,
        config: RlsConfig<T>,
    ) -> Result<Self, Error> {
        Self::with_scaling(
            axis,
            rules,
            structure,
            Premise::Rates,
            config,
            Scaling::unit(),
        )
    }

    /// A model over the given premise whose terms and target are divided by nominal scales
    /// (see [`Scaling`]).
    pub fn with_scaling(
        axis: RateAxis,
        rules: RuleBase<T, 3, R>,
        structure: RateStructure,
        premise: Premise,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Result<Self, Error> {
        Self::check_new(structure, &config, &scaling)?;
        Ok(Self::with_scaling_unchecked(
            axis, rules, structure, premise, config, scaling,
        ))
    }

    pub(crate) fn check_new(
        structure: RateStructure,
        config: &RlsConfig<T>,
        scaling: &Scaling<T, D>,
    ) -> Result<(), Error> {
        check_terms(structure.terms(), D)?;
        E::check_new(config, scaling)
    }

    #[inline(always)]
    pub(crate) fn with_scaling_unchecked(
        axis: RateAxis,
        rules: RuleBase<T, 3, R>,
        structure: RateStructure,
        premise: Premise,
        config: RlsConfig<T>,
        scaling: Scaling<T, D>,
    ) -> Self {
        Self {
            ts: E::build(rules, config, scaling),
            axis,
            structure,
            premise,
            _scalar: core::marker::PhantomData,
        }
    }

    /// The consequent structure.
    pub fn structure(&self) -> RateStructure {
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

    /// Which rate this model predicts.
    pub fn axis(&self) -> RateAxis {
        self.axis
    }

    /// The consequent terms `Δ` at sample k (with no sample before it: a second-order term
    /// is 0).
    pub fn terms(&self, s: &HoverSample<T>) -> [T; D] {
        self.terms_in(s, &self.frame_for(s), &s.rates)
    }

    /// [`terms`](Self::terms) with the sample's body frame already computed and the rates
    /// `[q r p]` of the sample before (deg/s).
    pub fn terms_in(&self, s: &HoverSample<T>, frame: &BodyFrame<T>, before: &[T; 3]) -> [T; D] {
        let [q, r, p] = s.rates;
        let u = &s.controls;
        let [cross, control] = match self.axis {
            RateAxis::Pitch => [r * p, u.lon * u.col],
            RateAxis::Yaw => [q * p, u.ped],
            RateAxis::Roll => [q * r, u.lat * u.col],
        };
        let (speed, increment) = match self.structure {
            RateStructure::Flight => {
                let [forward, right, _] = Premise::HeadingVelocity.of(s, frame);
                let speed = match self.axis {
                    RateAxis::Pitch => forward,
                    RateAxis::Yaw | RateAxis::Roll => right,
                };
                let earlier = before.get(self.axis.index()).copied();
                (
                    speed,
                    self.rate(s) - earlier.unwrap_or_else(|| self.rate(s)),
                )
            }
            _ => (T::zero(), T::zero()),
        };
        let all = [
            cross,
            control,
            self.rate(s),
            u.col,
            T::one(),
            speed,
            increment,
        ];
        let used = self.structure.terms();
        let mut terms = [T::zero(); D];
        for (t, &x) in terms.iter_mut().zip(all.iter().take(used)) {
            *t = x;
        }
        terms
    }

    fn rate(&self, s: &HoverSample<T>) -> T {
        s.rates
            .get(self.axis.index())
            .copied()
            .unwrap_or_else(T::zero)
    }

    /// The body frame, computed only for a premise or structure that needs it (the paper's
    /// do not: their step stays free of trigonometry when called without a frame).
    fn frame_for(&self, s: &HoverSample<T>) -> BodyFrame<T> {
        match (self.premise, self.structure) {
            (Premise::HeadingVelocity, _) | (_, RateStructure::Flight) => {
                BodyFrame::of(&s.attitude)
            }
            _ => BodyFrame::identity(),
        }
    }
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> StateModel<T>
    for RateModel<T, R, D, E>
{
    type Prepared = Prepared<T, R, D, 1>;
    type State = E::State;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        self.prepare_in(from, &self.frame_for(from), &from.rates, to)
    }

    fn prepare_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        before: &[T; 3],
        to: &HoverSample<T>,
    ) -> Result<Self::Prepared, Error> {
        self.ts.prepare(
            &self.premise.of(from, from_frame),
            &[self.terms_in(from, from_frame, before)],
            &[self.rate(to) - self.rate(from)],
        )
    }

    fn predict_in(
        &self,
        from: &HoverSample<T>,
        from_frame: &BodyFrame<T>,
        before: &[T; 3],
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let [increment] = self.ts.predict_many(
            &self.premise.of(from, from_frame),
            &[self.terms_in(from, from_frame, before)],
        )?;
        if let Some(slot) = next.rates.get_mut(self.axis.index()) {
            *slot = self.rate(from) + increment;
        }
        Ok(())
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        if let Some(slot) = innovation.rates.get_mut(self.axis.index()) {
            let [e] = prepared.innovations;
            *slot = e;
        }
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        self.predict_in(from, &self.frame_for(from), &from.rates, next)
    }

    fn reset(&mut self) {
        self.ts.reset();
    }

    fn export(&self) -> Self::State {
        self.ts.export()
    }

    fn import(&mut self, state: &Self::State) -> Result<(), Error> {
        self.ts.import(state)
    }

    fn check_import(&self, state: &Self::State) -> Result<(), Error> {
        self.ts.check_import(state)
    }

    fn reconfigure(&mut self, config: &crate::hover::HoverConfig<T>) -> Result<(), Error> {
        self.ts
            .reconfigure(config.rls, config.rate_scaling::<D>(self.structure))
    }

    fn rls_config(&self) -> &RlsConfig<T> {
        self.ts.config()
    }
}
