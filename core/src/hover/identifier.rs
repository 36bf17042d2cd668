//! The hover identifier: one translational and three angular models fed one sample at a time.

use crate::error::{Error, Quantity};
use crate::hover::attitude::AttitudeInput;
use crate::hover::config::{HoverConfig, RegressorScaling};
use crate::hover::models::{BodyFrame, GyroCompensation, Premise, SharedStrengths, StateModel};
use crate::hover::sample::{Controls, HoverSample, HoverState, SampleLimits};
use crate::rls::{Compensation, RlsView};
use crate::rule_base::{same_sets, PremiseSets};
use crate::scalar::Real;

/// What one [`HoverIdentifier::step`] reports.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StepOutput<T> {
    /// One-step prediction of the next sample's state, made with the updated parameters.
    pub prediction: HoverState<T>,
    /// Prior innovations `Δy − ξᵀθ(k)` of the update this step made (the error of the
    /// previous step's prediction, up to rounding); `None` when the step only started a
    /// sample chain (first sample, or after [`HoverIdentifier::resume`]).
    pub innovation: Option<HoverState<T>>,
}

/// The four models of a [`HoverIdentifier`], in export order.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ModelId {
    /// The translational model (Eq. 27): `[v_x v_y v_z]`.
    Velocity,
    /// The q̂ model (Eq. 28).
    Pitch,
    /// The r̂ model (Eq. 29).
    Yaw,
    /// The p̂ model (Eq. 30).
    Roll,
}

impl ModelId {
    /// The four, in export order.
    pub const ALL: [ModelId; 4] = [Self::Velocity, Self::Pitch, Self::Yaw, Self::Roll];

    /// Position in export order (0 velocity, 1 q̂, 2 r̂, 3 p̂), the model number of the
    /// telemetry messages.
    pub const fn index(self) -> u8 {
        match self {
            Self::Velocity => 0,
            Self::Pitch => 1,
            Self::Yaw => 2,
            Self::Roll => 3,
        }
    }
}

/// The four model types of a [`HoverIdentifier`], by name: for code that must name one
/// model's state type, such as a firmware that stages an import one model at a time
/// (`<<I as HoverModels>::Velocity as StateModel<f32>>::State`) instead of restating its sizes.
pub trait HoverModels {
    /// The translational model.
    type Velocity;
    /// The q̂ model.
    type Pitch;
    /// The r̂ model.
    type Yaw;
    /// The p̂ model.
    type Roll;
}

impl<T, Vm, Qm, Rm, Pm> HoverModels for HoverIdentifier<T, Vm, Qm, Rm, Pm> {
    type Velocity = Vm;
    type Pitch = Qm;
    type Yaw = Rm;
    type Roll = Pm;
}

/// Everything a [`HoverIdentifier`] has learnt (warm start across flights).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct HoverSnapshot<Vs, Qs, Rs, Ps> {
    /// Translational model.
    pub velocity: Vs,
    /// q̂ model.
    pub pitch: Qs,
    /// r̂ model.
    pub yaw: Rs,
    /// p̂ model.
    pub roll: Ps,
}

/// Online identifier of the hover dynamics (paper Section 5): takes one sample per step,
/// learns all four models from the previous sample to this one, and predicts the next.
///
/// `Vm` is the translational model, `Qm`, `Rm`, `Pm` the q̂, r̂, p̂ models (`m` for model: `R`
/// and `P` elsewhere count rules and packed entries). The paper's two
/// configurations are the aliases [`PaperFuzzyIdentifier`](super::PaperFuzzyIdentifier) and [`PaperPlainIdentifier`](super::PaperPlainIdentifier); since
/// they share this API, Table 4's comparison is a change of type.
///
/// Every call that returns `Err` leaves the identifier exactly as it was.
#[derive(Clone, Debug, PartialEq)]
pub struct HoverIdentifier<T, Vm, Qm, Rm, Pm> {
    pub(super) velocity: Vm,
    pub(super) pitch: Qm,
    pub(super) yaw: Rm,
    pub(super) roll: Pm,
    /// The settings that are not the models' own (the RLS settings are: see
    /// [`HoverIdentifier::config`]).
    pub(super) settings: Settings,
    /// The end of the current sample chain (valid when `timing.chained`).
    pub(super) chain: Chain<T>,
}

/// The end of a sample chain: the sample the next step learns from, its body frame, and what
/// the models read of the sample before it ([`Before`]).
///
/// Laid out for the 11 KiB target of the paper fuzzy identifier (f32): no `Option`s (the
/// flag of a valid chain lives in [`Settings`]'s padding), and the sample's fields kept apart,
/// its time stamp as two 32-bit words, so that the chain is 4-byte aligned and packs with
/// the models (a `u64` would pad it to 8).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Chain<T> {
    /// The sample's time stamp (µs): high and low 32 bits.
    time_us: [u32; 2],
    velocity: [T; 3],
    rates: [T; 3],
    controls: Controls<T>,
    frame: BodyFrame<T>,
    before: Before<T>,
}

impl<T: Real> Chain<T> {
    pub(super) fn empty() -> Self {
        Self::new(
            &HoverSample::<T>::default(),
            BodyFrame::identity(),
            &HoverState::default(),
        )
    }

    /// The chain ending at `sample` (whose body frame is `frame`), with `before` the state
    /// of the sample before it.
    fn new<A>(sample: &HoverSample<T, A>, frame: BodyFrame<T>, before: &HoverState<T>) -> Self {
        let t = sample.time_us;
        Self {
            time_us: [(t >> 32) as u32, t as u32],
            velocity: sample.velocity,
            rates: sample.rates,
            controls: sample.controls,
            frame,
            before: Before::of(before),
        }
    }

    /// The sample the chain ends at, without its attitude: the models read the chain's
    /// [`frame`](Self::frame) instead (and a smaller copy stays in registers on an MCU).
    #[inline(always)]
    fn sample(&self) -> HoverSample<T, ()> {
        let [high, low] = self.time_us;
        HoverSample {
            time_us: (u64::from(high) << 32) | u64::from(low),
            attitude: (),
            velocity: self.velocity,
            rates: self.rates,
            controls: self.controls,
        }
    }
}

/// What the models read of the sample before the chain's last: its rates (the second-order
/// term of [`RateStructure::Flight`](super::RateStructure::Flight)) and its horizontal velocity
/// (the drag of [`VelocityStructure::Flight`](super::VelocityStructure::Flight)). Its vertical
/// velocity is not kept: no model reads it (the heave damping is on `v_y(k)`), and without
/// those 4 bytes the paper fuzzy identifier stays within 11 KiB.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Before<T> {
    rates: [T; 3],
    v_x: T,
    v_z: T,
}

impl<T: Real> Before<T> {
    fn of(state: &HoverState<T>) -> Self {
        let [v_x, _, v_z] = state.velocity;
        Self {
            rates: state.rates,
            v_x,
            v_z,
        }
    }

    /// The state the models are given for the sample before `from`: the kept rates and
    /// horizontal velocity, and `from`'s own `v_y` in the slot no model reads.
    fn state_before<A>(&self, from: &HoverSample<T, A>) -> HoverState<T> {
        HoverState {
            velocity: [self.v_x, from.velocity[1], self.v_z],
            rates: self.rates,
        }
    }
}

/// [`HoverConfig`] less the RLS settings, which each model keeps (not stored twice: the
/// identifier's `size_of` is held to 11 KiB), and two flags kept in its padding: whether a
/// chain is open, and the [`Sharing`] cache.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct Settings {
    sample_period_us: u32,
    period_tolerance_us: u32,
    scaling: RegressorScaling,
    /// Whether `chain` holds a sample. Its `before` is then valid too: a chain's first sample
    /// stands in for the sample before it.
    chained: bool,
    sharing: Sharing,
}

/// Which rate models are scheduled on the velocity model's premise with its sets, and so take
/// its firing strengths ([`SharedStrengths`]) without comparing the sets at every sample; and
/// which of the yaw and roll models, not sharing the velocity model's, take the pitch model's
/// (the flight identifier's rates are scheduled on the forward speed, its translational model
/// on the horizontal speed).
/// Found at the first prediction, and again after a model was handed out mutably (which could
/// replace it). One byte in [`Settings`]'s padding.
///
/// A cache, not state: it changes no result, and takes no part in equality.
#[derive(Copy, Clone, Debug)]
struct Sharing(u8);

impl Sharing {
    /// Not found yet.
    const UNKNOWN: Self = Self(0);
    const KNOWN: u8 = 1;

    fn of<T: Real>(
        velocity: &impl StateModel<T>,
        rates: [(Premise, &[PremiseSets<T>]); 3],
    ) -> Self {
        let (premise, sets) = velocity.premise_sets();
        let (pitch_premise, pitch_sets) = rates[0];
        let mut bits = Self::KNOWN;
        for (i, (p, s)) in rates.into_iter().enumerate() {
            if p == premise && same_sets(s, sets) {
                bits |= 2 << i;
            } else if i > 0 && p == pitch_premise && same_sets(s, pitch_sets) {
                bits |= 16 << i;
            }
        }
        Self(bits)
    }

    fn known(self) -> bool {
        self.0 & Self::KNOWN != 0
    }

    /// Whether rate model `i` (0 q̂, 1 r̂, 2 p̂) takes the velocity model's strengths.
    fn takes(self, i: u8) -> bool {
        self.0 & (2 << i) != 0
    }

    /// Whether rate model `i` (1 r̂, 2 p̂) takes the pitch model's strengths.
    fn takes_pitch(self, i: u8) -> bool {
        self.0 & (16 << i) != 0
    }
}

impl PartialEq for Sharing {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Settings {
    pub(super) fn of<T>(config: &HoverConfig<T>) -> Self {
        Self {
            sample_period_us: config.sample_period_us,
            period_tolerance_us: config.period_tolerance_us,
            scaling: config.scaling,
            chained: false,
            sharing: Sharing::UNKNOWN,
        }
    }
}

impl<T, Vm, Qm, Rm, Pm> HoverIdentifier<T, Vm, Qm, Rm, Pm>
where
    T: Real,
    Vm: StateModel<T>,
    Qm: StateModel<T>,
    Rm: StateModel<T>,
    Pm: StateModel<T>,
{
    /// An identifier from four models (translational, q̂, r̂, p̂). `config` gives the sample
    /// period and its tolerance; the models keep the RLS settings and scales they were built
    /// with.
    pub fn new(
        velocity: Vm,
        pitch: Qm,
        yaw: Rm,
        roll: Pm,
        config: HoverConfig<T>,
    ) -> Result<Self, Error> {
        config.validate()?;
        Ok(Self {
            velocity,
            pitch,
            yaw,
            roll,
            settings: Settings::of(&config),
            chain: Chain::empty(),
        })
    }

    /// The settings: sample period, tolerance and scaling as given to the constructor or to
    /// [`reconfigure`](Self::reconfigure), and the RLS settings of the translational model
    /// (the four models share them, unless one was reconfigured on its own through
    /// [`velocity_model_mut`](Self::velocity_model_mut) and the like).
    pub fn config(&self) -> HoverConfig<T> {
        HoverConfig {
            rls: *self.velocity.rls_config(),
            sample_period_us: self.settings.sample_period_us,
            period_tolerance_us: self.settings.period_tolerance_us,
            scaling: self.settings.scaling,
        }
    }

    /// The translational model.
    pub fn velocity_model(&self) -> &Vm {
        &self.velocity
    }

    /// The q̂ model.
    pub fn pitch_model(&self) -> &Qm {
        &self.pitch
    }

    /// The r̂ model.
    pub fn yaw_model(&self) -> &Rm {
        &self.yaw
    }

    /// The p̂ model.
    pub fn roll_model(&self) -> &Pm {
        &self.roll
    }

    /// Calls `f` with every RLS estimator of the four models, in export order: the model, the
    /// estimator's index within it (0 when learnt globally; the rule when learnt locally) and
    /// a size-erased view ([`RlsView`]). One routine that sends, stores or
    /// prints estimators then serves every identifier.
    pub fn for_each_rls(&self, mut f: impl FnMut(ModelId, usize, RlsView<'_, T>)) {
        for model in ModelId::ALL {
            let mut index = 0;
            let mut visit = |v: RlsView<'_, T>| {
                f(model, index, v);
                index += 1;
            };
            match model {
                ModelId::Velocity => self.velocity.for_each_rls(&mut visit),
                ModelId::Pitch => self.pitch.for_each_rls(&mut visit),
                ModelId::Yaw => self.yaw.for_each_rls(&mut visit),
                ModelId::Roll => self.roll.for_each_rls(&mut visit),
            }
        }
    }

    /// The sample the next step will learn from, if any, its attitude as the body frame the
    /// models read (whatever form the sample's attitude came in).
    pub fn previous_sample(&self) -> Option<HoverSample<T, BodyFrame<T>>> {
        self.settings
            .chained
            .then(|| self.chain.sample().with_attitude(self.chain.frame))
    }

    /// Takes sample k+1: learns every model from (sample k → sample k+1), then predicts the
    /// state at k+2.
    ///
    /// Errors (nothing changes on any of them): a field out of range or not finite
    /// ([`SampleLimits`]), a time stamp that does not increase, an interval outside
    /// `sample_period_us ± period_tolerance_us` (after a gap, call [`resume`](Self::resume)),
    /// or an update beyond the estimator's numeric limits. Every error is found before anything
    /// is written, whatever state an [`import`](Self::import) brought in: an import bounds
    /// every parameter and every factor entry (see [`Rls::check_import`](crate::rls::Rls::check_import)),
    /// the covariance form skips (and counts) an update that would take a parameter past them,
    /// the U-D form's gain is bounded by `√P_ii/(2√λ)` (`P_ii` stays within its import bound),
    /// and with such parameters a prediction from a sample that passed [`SampleLimits`] is
    /// finite, so the prediction after the update cannot fail.
    ///
    /// The attitude may come as Euler angles, a quaternion or a rotation matrix
    /// ([`AttitudeInput`]); the latter two need no trigonometry.
    pub fn step<A: AttitudeInput<T>>(
        &mut self,
        sample: &HoverSample<T, A>,
    ) -> Result<StepOutput<T>, Error> {
        SampleLimits::check(sample)?;
        let mut innovation = None;
        let mut before = sample.state();
        if self.settings.chained {
            let prev = self.chain.sample();
            let frame = &self.chain.frame;
            self.check_interval(prev.time_us, sample.time_us)?;
            let b = self.chain.before.state_before(&prev);
            // Check all four models before changing any.
            let v = self.velocity.prepare_in(&prev, frame, &b, sample)?;
            let q = self.pitch.prepare_in(&prev, frame, &b, sample)?;
            let r = self.yaw.prepare_in(&prev, frame, &b, sample)?;
            let p = self.roll.prepare_in(&prev, frame, &b, sample)?;
            let mut inn = HoverState::default();
            self.velocity.apply(&v, &mut inn);
            self.pitch.apply(&q, &mut inn);
            self.yaw.apply(&r, &mut inn);
            self.roll.apply(&p, &mut inn);
            innovation = Some(inn);
            before = prev.state();
        }
        let frame = sample.attitude.frame();
        self.chain = Chain::new(sample, frame, &before);
        self.settings.chained = true;
        // The sample passed SampleLimits, which bounds every regressor, and the parameters are
        // bounded (see the docs above): this prediction is finite, so no error comes after the
        // update was written. (`predict_keep` keeps its `Result` for the models' own checks,
        // which the same sample passed in `prepare_in`.)
        let prediction = self.predict_keep(sample, &frame, &before)?;
        Ok(StepOutput {
            prediction,
            innovation,
        })
    }

    /// One-step prediction of the state after `sample`, with the current parameters, as the
    /// first sample of a chain (a second-order term sees no earlier sample); changes nothing.
    /// To verify a frozen model or simulate it forward, use
    /// [`predict_after`](Self::predict_after).
    pub fn predict<A: AttitudeInput<T>>(
        &self,
        sample: &HoverSample<T, A>,
    ) -> Result<HoverState<T>, Error> {
        self.predict_after(None, sample)
    }

    /// One-step prediction of the state after `sample`, given the state of the sample before
    /// it (`before`: measured, or the model's own estimate in a simulation; `None` at the
    /// start of a chain; then `sample`'s own state stands in). Only the terms that read the
    /// sample before read it: the second-order term of
    /// [`RateStructure::Flight`](super::RateStructure::Flight) and the drag of
    /// [`VelocityStructure::Flight`](super::VelocityStructure::Flight). Changes nothing.
    pub fn predict_after<A: AttitudeInput<T>>(
        &self,
        before: Option<&HoverState<T>>,
        sample: &HoverSample<T, A>,
    ) -> Result<HoverState<T>, Error> {
        SampleLimits::check(sample)?;
        let before = match before {
            Some(b) => {
                SampleLimits::check_state(b)?;
                *b
            }
            None => sample.state(),
        };
        self.predict_in(sample, &sample.attitude.frame(), &before)
    }

    fn predict_in<A>(
        &self,
        sample: &HoverSample<T, A>,
        frame: &BodyFrame<T>,
        before: &HoverState<T>,
    ) -> Result<HoverState<T>, Error> {
        let mut next = HoverState::default();
        self.velocity.predict_in(sample, frame, before, &mut next)?;
        self.pitch.predict_in(sample, frame, before, &mut next)?;
        self.yaw.predict_in(sample, frame, before, &mut next)?;
        self.roll.predict_in(sample, frame, before, &mut next)?;
        finite(next)
    }

    /// [`predict_in`](Self::predict_in) from the end of the chain: the same prediction, and
    /// each model may keep what its update from `sample` at the next step reuses.
    fn predict_keep<A>(
        &mut self,
        sample: &HoverSample<T, A>,
        frame: &BodyFrame<T>,
        before: &HoverState<T>,
    ) -> Result<HoverState<T>, Error> {
        let mut next = HoverState::default();
        self.velocity
            .predict_keep(sample, frame, before, None, &mut next)?;
        // The rate models take the velocity model's firing strengths where their premise and
        // sets are the same, and the yaw and roll models the pitch model's where theirs are
        // (the flight identifier's): each set of strengths computed once per sample.
        if !self.settings.sharing.known() {
            let rates = [
                self.pitch.premise_sets(),
                self.yaw.premise_sets(),
                self.roll.premise_sets(),
            ];
            self.settings.sharing = Sharing::of(&self.velocity, rates);
        }
        let sharing = self.settings.sharing;
        let shared = self
            .velocity
            .kept_strengths()
            .map(SharedStrengths::with_sets_checked);
        let to = |i| shared.as_ref().filter(|_| sharing.takes(i));
        self.pitch
            .predict_keep(sample, frame, before, to(0), &mut next)?;
        let pitch = self
            .pitch
            .kept_strengths()
            .map(SharedStrengths::with_sets_checked);
        let to = |i| to(i).or_else(|| pitch.as_ref().filter(|_| sharing.takes_pitch(i)));
        self.yaw
            .predict_keep(sample, frame, before, to(1), &mut next)?;
        self.roll
            .predict_keep(sample, frame, before, to(2), &mut next)?;
        finite(next)
    }

    /// Starts a new sample chain at `sample` without learning (after a gap, a time jump, or
    /// between concatenated manoeuvres). Returns the prediction from it.
    pub fn resume<A: AttitudeInput<T>>(
        &mut self,
        sample: &HoverSample<T, A>,
    ) -> Result<HoverState<T>, Error> {
        SampleLimits::check(sample)?;
        let frame = sample.attitude.frame();
        let prediction = self.predict_keep(sample, &frame, &sample.state())?;
        self.chain = Chain::new(sample, frame, &sample.state());
        self.settings.chained = true;
        Ok(prediction)
    }

    /// Replaces the rate models' parameters by their estimates with the bias of the gyros'
    /// white noise removed (bias-compensated least squares, see
    /// [`RateModel::gyro_noise`](super::RateModel::gyro_noise) and
    /// [`Rls::bias_compensated`](crate::rls::Rls::bias_compensated)): the model to *simulate*
    /// (free-run) with. The least-squares parameters the identifier learns are the better
    /// one-step predictor from noisy measurements, so compensate a copy and keep learning on
    /// the original (learning on from compensated parameters returns to least squares).
    ///
    /// `gyro_noise`: standard deviation σ of each rate's white noise `[q r p]` (deg/s), from
    /// the gyro's data sheet or a flight ([`RateNoise`](super::RateNoise)); 0 compensates
    /// nothing. Only [`RateStructure::Flight`](super::RateStructure::Flight) models learnt in
    /// the U-D form are compensated; a rule whose rate hardly moved (the noise is half its
    /// information or more) or that saw fewer samples than it has parameters keeps its
    /// parameters, and the result counts it. On `Err` (σ not finite, negative or above
    /// [`SampleLimits::RATE`]) nothing changed.
    pub fn compensate(&mut self, gyro_noise: &[T; 3]) -> Result<Compensation, Error> {
        self.compensate_with(gyro_noise, GyroCompensation::Damping)
    }

    /// [`compensate`](Self::compensate), removing the noise `how` says
    /// ([`GyroCompensation::Full`]: the second-order term's too) on every rate.
    pub fn compensate_with(
        &mut self,
        gyro_noise: &[T; 3],
        how: GyroCompensation,
    ) -> Result<Compensation, Error> {
        self.compensate_each(gyro_noise, [how; 3])
    }

    /// [`compensate`](Self::compensate), removing on each rate `[q r p]` the noise its entry
    /// of `how` says: the choice a selection made per axis from the data (a structure the
    /// full compensation suits on one axis may not suit on another).
    pub fn compensate_each(
        &mut self,
        gyro_noise: &[T; 3],
        how: [GyroCompensation; 3],
    ) -> Result<Compensation, Error> {
        for &sigma in gyro_noise {
            if !sigma.is_finite() {
                return Err(Error::NonFinite(Quantity::Config));
            }
            if !(sigma >= T::zero() && sigma <= T::lit(SampleLimits::RATE)) {
                return Err(Error::OutOfRange(Quantity::Config));
            }
        }
        Ok(self
            .velocity
            .compensate(gyro_noise, &how)
            .and(self.pitch.compensate(gyro_noise, &how))
            .and(self.yaw.compensate(gyro_noise, &how))
            .and(self.roll.compensate(gyro_noise, &how)))
    }

    /// Forgets everything learnt: θ = 0, P = αI, no previous sample.
    pub fn reset(&mut self) {
        self.velocity.reset();
        self.pitch.reset();
        self.yaw.reset();
        self.roll.reset();
        self.end_chain_in_place();
    }

    /// Everything learnt, for a warm start on the next flight.
    pub fn export(&self) -> HoverSnapshot<Vm::State, Qm::State, Rm::State, Pm::State> {
        HoverSnapshot {
            velocity: self.velocity.export(),
            pitch: self.pitch.export(),
            yaw: self.yaw.export(),
            roll: self.roll.export(),
        }
    }

    /// Warm start from an exported snapshot. The sample chain restarts (the next step only
    /// anchors). All four states are checked before any is written; on `Err` nothing changed.
    /// The checks bound every word of every state (θ, and every entry of the covariance or
    /// U-D factor, not only its diagonal), so that an accepted state cannot make a later
    /// [`step`](Self::step) or [`resume`](Self::resume) fail after writing.
    pub fn import(
        &mut self,
        snapshot: &HoverSnapshot<Vm::State, Qm::State, Rm::State, Pm::State>,
    ) -> Result<(), Error> {
        self.velocity.check_import(&snapshot.velocity)?;
        self.pitch.check_import(&snapshot.pitch)?;
        self.yaw.check_import(&snapshot.yaw)?;
        self.roll.check_import(&snapshot.roll)?;
        self.velocity.import(&snapshot.velocity)?;
        self.pitch.import(&snapshot.pitch)?;
        self.yaw.import(&snapshot.yaw)?;
        self.roll.import(&snapshot.roll)?;
        self.end_chain_in_place();
        Ok(())
    }

    /// Ends the sample chain without learning: the next step only anchors, as after
    /// [`import`](Self::import). A firmware that imports one model at a time (through
    /// [`velocity_model_mut`](Self::velocity_model_mut) etc.) calls it once it starts.
    pub fn end_chain(&mut self) {
        self.end_chain_in_place();
    }

    /// Forgets the chain (cleared too, so that an identifier compares equal to a fresh one).
    fn end_chain_in_place(&mut self) {
        self.chain = Chain::empty();
        self.settings.chained = false;
    }

    /// Mutable access to the translational model, for importing one model at a time (a
    /// firmware can stage one model's state instead of a whole snapshot). Importing a model
    /// does not restart the sample chain.
    pub fn velocity_model_mut(&mut self) -> &mut Vm {
        self.settings.sharing = Sharing::UNKNOWN;
        &mut self.velocity
    }

    /// Mutable access to the q̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn pitch_model_mut(&mut self) -> &mut Qm {
        self.settings.sharing = Sharing::UNKNOWN;
        &mut self.pitch
    }

    /// Mutable access to the r̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn yaw_model_mut(&mut self) -> &mut Rm {
        self.settings.sharing = Sharing::UNKNOWN;
        &mut self.yaw
    }

    /// Mutable access to the p̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn roll_model_mut(&mut self) -> &mut Pm {
        self.settings.sharing = Sharing::UNKNOWN;
        &mut self.roll
    }

    /// New settings (RLS form, α, λ, scaling, sample period), in place: every model starts
    /// afresh. Unlike building a new identifier this moves nothing, so a firmware needs no
    /// second copy of the identifier on its stack. On `Err` nothing changed.
    pub fn reconfigure(&mut self, config: HoverConfig<T>) -> Result<(), Error> {
        config.validate()?;
        // Every model validates the same RLS settings and its own scales, which are fixed
        // constants: after the check above none of these can fail.
        self.velocity.reconfigure(&config)?;
        self.pitch.reconfigure(&config)?;
        self.yaw.reconfigure(&config)?;
        self.roll.reconfigure(&config)?;
        self.settings = Settings::of(&config);
        self.end_chain_in_place();
        Ok(())
    }

    /// Whether a sample at `next_us` follows one at `prev_us` (µs) at the sample period, within
    /// its tolerance.
    pub(super) fn check_interval(&self, prev_us: u64, next_us: u64) -> Result<(), Error> {
        if next_us <= prev_us {
            return Err(Error::NonMonotonicTime);
        }
        let dt = next_us - prev_us;
        let nominal = u64::from(self.settings.sample_period_us);
        let tol = u64::from(self.settings.period_tolerance_us);
        let (min, max) = (nominal - tol, nominal + tol);
        if dt < min || dt > max {
            return Err(Error::TimeStep {
                dt_us: dt,
                min_us: min,
                max_us: max,
            });
        }
        Ok(())
    }
}

/// Never a non-finite number out of an `Ok`: parameters far beyond anything learning produces
/// (an absurd imported state, say) could overflow a prediction.
fn finite<T: Real>(next: HoverState<T>) -> Result<HoverState<T>, Error> {
    if next.to_array().iter().all(|x| x.is_finite()) {
        Ok(next)
    } else {
        Err(Error::Numerical)
    }
}
