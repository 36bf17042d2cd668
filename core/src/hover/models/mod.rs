//! The four state models of the hover identifier: thin wrappers that turn a [`HoverSample`]
//! into the premise and consequent terms of a TS estimator
//! ([`TsEstimator`](crate::learning::TsEstimator)).
//!
//! * [`velocity`]: the translational model (Eq. 27) and its structures.
//! * [`rate`]: the three angular models (Eqs. 28–30) and their structures.

use crate::error::{ConfigError, Error};
use crate::hover::sample::{HoverSample, HoverState};
use crate::learning::TsEstimator;
use crate::rls::{Compensation, RlsConfig};
use crate::rule_base::{PremiseSets, RuleBase};
use crate::scalar::Real;

/// The [`StateModel`] methods that [`RateModel`] and [`VelocityModel`] forward to their TS
/// estimator `self.ts` (scheduled on `self.premise`), written once. `$scaling` names the
/// [`HoverConfig`](crate::hover::HoverConfig) method that gives the model's scales for its
/// structure, and `$axis` the field it also needs, if any (a rate model's axis): the only
/// difference between the two.
macro_rules! forward_to_estimator {
    ($scaling:ident $(, $axis:ident)?) => {
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
                .reconfigure(config.rls, config.$scaling::<D>(self.structure $(, self.$axis)?))
        }

        fn rls_config(&self) -> &RlsConfig<T> {
            self.ts.config()
        }

        fn for_each_rls(&self, f: &mut dyn FnMut(crate::rls::RlsView<'_, T>)) {
            self.ts.for_each_rls(f)
        }

        fn premise_sets(&self) -> (Premise, &[crate::rule_base::PremiseSets<T>]) {
            (self.premise, self.ts.rules().variables())
        }
    };
}

mod rate;
#[cfg(test)]
mod tests;
mod velocity;

pub use crate::hover::frame::{right_axis, rotor_axis, BodyFrame};
pub use rate::{GyroCompensation, RateAxis, RateModel, RateStructure};
pub use velocity::{VelocityModel, VelocityStructure};

/// The identifier's speed-ups, in a private module so that nothing outside the crate can call
/// or implement them (and so [`StateModel`] is sealed).
pub(crate) mod sealed {
    use super::{BodyFrame, SharedStrengths};
    use crate::error::Error;
    use crate::hover::sample::{HoverSample, HoverState};
    use crate::scalar::Real;

    /// The sealed part of [`StateModel`].
    pub trait StepParts<T: Real> {
        /// A checked update, ready to apply.
        type Prepared;

        /// [`prepare`](StateModel::prepare) with `from`'s body frame already computed (the identifier
        /// keeps it from the previous step) and the state `[v^s, ω]` of the sample before `from`
        /// (`before`; `from`'s own state when there is none), for the structures that read it
        /// ([`RateStructure::Flight`]'s second-order term, [`VelocityStructure::Flight`]'s drag).
        /// [`prepare`](StateModel::prepare) is this with `before = from.state()`.
        ///
        /// Only `from_frame` is read of `from`'s attitude, and nothing of `to`'s: the attitude may
        /// come in any form.
        fn prepare_in<A, B>(
            &self,
            from: &HoverSample<T, A>,
            from_frame: &BodyFrame<T>,
            before: &HoverState<T>,
            to: &HoverSample<T, B>,
        ) -> Result<Self::Prepared, Error>;

        /// [`predict`](StateModel::predict) with `from`'s body frame already computed and the state of
        /// the sample before `from` (see [`prepare_in`](Self::prepare_in)).
        fn predict_in<A>(
            &self,
            from: &HoverSample<T, A>,
            from_frame: &BodyFrame<T>,
            before: &HoverState<T>,
            next: &mut HoverState<T>,
        ) -> Result<(), Error>;

        /// [`predict_in`](Self::predict_in) from `&mut self`: the same prediction, and the
        /// estimator may keep what the update from `from` at the next step reuses (the local
        /// one keeps its firing strengths and block products, see
        /// [`LocalTsRls::predict_keep`](crate::ts::local::LocalTsRls::predict_keep)). `shared`: firing
        /// strengths another model computed at `from`, which this one takes if they are its own
        /// (see [`SharedStrengths`]).
        fn predict_keep<A>(
            &mut self,
            from: &HoverSample<T, A>,
            from_frame: &BodyFrame<T>,
            before: &HoverState<T>,
            shared: Option<&SharedStrengths<'_, T>>,
            next: &mut HoverState<T>,
        ) -> Result<(), Error>;

        /// The firing strengths the last [`predict_keep`](Self::predict_keep) used, to offer to
        /// the other models, if the estimator kept them (and has not learnt since).
        fn kept_strengths(&self) -> Option<SharedStrengths<'_, T>> {
            None
        }
    }
}

/// What a [`HoverIdentifier`](crate::hover::HoverIdentifier) needs of each of its models.
///
/// Learning is split in two so that the identifier can check all four models before it
/// changes any: [`prepare`](Self::prepare) checks and computes, [`apply`](Self::apply) writes.
///
/// Sealed: only the crate's [`VelocityModel`] and [`RateModel`] implement it (an identifier's
/// speed-ups, such as sharing firing strengths between the models, live in its sealed part).
pub trait StateModel<T: Real>: sealed::StepParts<T> {
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
    /// The premise the rules are scheduled on and each premise variable's sets (an empty
    /// list: the variable does not take part), as a tool writes them next to an export so
    /// that a firmware can rebuild the same rule base.
    fn premise_sets(&self) -> (Premise, &[PremiseSets<T>]);
    /// Calls `f` with a view of each of the model's RLS estimators, in export order (see
    /// [`TsEstimator::for_each_rls`](crate::learning::TsEstimator::for_each_rls)).
    fn for_each_rls(&self, f: &mut dyn FnMut(crate::rls::RlsView<'_, T>));

    /// Replaces the parameters by their estimates with the gyro noise's bias removed, for a
    /// model whose terms the noise biases (see [`RateModel::compensate`]); `gyro_noise`: the
    /// standard deviation of the white noise of each rate `[q r p]` (deg/s, finite, ≥ 0,
    /// checked by the caller); `how`: which terms' noise, per rate `[q r p]` (a rate model
    /// reads its own axis's). Other models have nothing to compensate.
    fn compensate(&mut self, gyro_noise: &[T; 3], how: &[GyroCompensation; 3]) -> Compensation {
        let _ = (gyro_noise, how);
        Compensation::default()
    }
}

/// Normalised firing strengths ξ that one model computed at a sample, offered to the others:
/// a model scheduled on the same premise with the same sets (as the flight identifier's three
/// rate models are, on the forward speed) takes them instead of computing them again. The
/// same premise of the same sample and the same sets give the same ξ, bit for bit, so sharing
/// changes no result, only the cost.
#[derive(Copy, Clone, Debug)]
pub struct SharedStrengths<'a, T> {
    premise: Premise,
    sets: &'a [PremiseSets<T>],
    strengths: &'a [T],
    /// The caller compared the sets of the model it hands these to (see
    /// [`for_rules`](Self::for_rules)).
    sets_checked: bool,
}

impl<'a, T: Real> SharedStrengths<'a, T> {
    /// The strengths of the rule base `rules` at `premise` of one sample.
    pub fn new<const V: usize, const R: usize>(
        premise: Premise,
        rules: &'a RuleBase<T, V, R>,
        strengths: &'a [T; R],
    ) -> Self {
        Self {
            premise,
            sets: rules.variables(),
            strengths,
            sets_checked: false,
        }
    }

    /// The same strengths, for a model whose premise and sets the caller has compared with
    /// these (the identifier does so once, not at every sample: see its `Sharing`).
    pub(crate) fn with_sets_checked(self) -> Self {
        Self {
            sets_checked: true,
            ..self
        }
    }

    /// The strengths, if a model on `premise` with the rule base `rules` would compute the
    /// same at this sample: the same premise variables and the same sets, bit for bit
    /// ([`RuleBase::has_sets`]).
    pub fn for_rules<const V: usize, const R: usize>(
        &self,
        premise: Premise,
        rules: &RuleBase<T, V, R>,
    ) -> Option<&'a [T; R]> {
        if premise != self.premise || !(self.sets_checked || rules.has_sets(self.sets)) {
            return None;
        }
        self.strengths.try_into().ok()
    }
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
    /// The horizontal speed first, `[|v_h|, v_up, 0]` (m/s): `|v_h| = √(v_x² + v_z²)` in any
    /// direction (ground speed, which is airspeed in still air), then the vertical velocity
    /// (up) and a zero (no third variable). What changes the rotor's thrust and in-plane force
    /// is the advance ratio `μ = |v_h| / ΩR`, whatever the direction of flight: translational
    /// lift (the induced inflow falls as the rotor moves into clean air) raises the thrust per
    /// collective as much flying sideways as forwards. Scheduled on the forward speed, a
    /// translational model takes sideways flight at 5 m/s for hover and predicts too little
    /// thrust there (docs/results.md, "Where the trim is wrong"). The fin, the tail rotor
    /// and the stabiliser do depend on the direction: the rate models stay on
    /// [`HeadingVelocity`](Self::HeadingVelocity).
    HorizontalSpeed,
}

impl Premise {
    /// The premise vector of sample `s` (whose body frame is `frame`).
    #[inline]
    pub fn of<T: Real, A>(self, s: &HoverSample<T, A>, frame: &BodyFrame<T>) -> [T; 3] {
        match self {
            Self::Velocity => s.velocity,
            Self::Rates => s.rates,
            Self::HeadingVelocity => {
                // Paper axes: x east, y up, z south; ψ from north towards east.
                let [x, y, z] = s.velocity;
                let (sp, cp) = (frame.sp, frame.cp);
                [x * sp - z * cp, x * cp + z * sp, y]
            }
            Self::HorizontalSpeed => {
                let [x, y, z] = s.velocity;
                [(x * x + z * z).sqrt_ieee(), y, T::zero()]
            }
        }
    }
}

/// The strengths the estimator `ts` of a model on `premise` kept from its last prediction,
/// offered to the other models (`StepParts::kept_strengths`).
pub(crate) fn kept_by<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>>(
    premise: Premise,
    ts: &E,
) -> Option<SharedStrengths<'_, T>> {
    Some(SharedStrengths::new(
        premise,
        ts.rules(),
        ts.kept_strengths()?,
    ))
}

pub(crate) fn check_terms(needed: usize, found: usize) -> Result<(), Error> {
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
