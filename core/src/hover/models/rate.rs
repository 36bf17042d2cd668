//! The angular models (Eqs. 28–30): `Δq`, `Δr`, `Δp` from the controls and the rates.

use crate::error::Error;
use crate::hover::sample::{HoverSample, HoverState};
use crate::learning::{Learning, TsEstimator};
use crate::rls::{Compensation, PairedNoise, RegressorNoise, RlsConfig};
use crate::rule_base::RuleBase;
use crate::scalar::Real;
use crate::ts::{Prepared, Scaling};

use super::sealed::{self, StepParts};
use super::{check_terms, kept_by, BodyFrame, Premise, SharedStrengths, StateModel};

/// Which body rate an angular model predicts.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RateAxis {
    /// q̂, Eq. 28: `Δ = [r·p, u_lon·u_col]`.
    Pitch,
    /// r̂, Eq. 29: `Δ = [q·p, u_ped]` (with [`RateStructure::Flight`]: `[|v|, u_ped]`).
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

/// Which gyro noise [`RateModel::compensate`] removes from a [`RateStructure::Flight`] model.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum GyroCompensation {
    /// The noise of the damping term's `ω(k)` and its correlation with the target's and the
    /// second-order term's (the default; see [`RateModel::gyro_noise`]).
    #[default]
    Damping,
    /// [`Damping`](Self::Damping) and the second-order term's own noise: `Δω(k−1)` has
    /// variance `2σ²` and covariance `σ²` with `ω(k)`'s. The consistent bias-compensated
    /// estimate when the structure holds. A rule where the pair cannot be compensated (the
    /// noise is half its information or more, or the compensated rate would be unstable)
    /// gets [`Damping`](Self::Damping)'s compensation. Measured against the default in
    /// docs/full-compensation.md.
    Full,
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
    /// * For r̂, `𝕀 |v|` in place of the gyroscopic product `q p`: a yaw moment **even** in
    ///   the rightward speed `v` (m/s). Sideways flight in either direction changes the main
    ///   rotor's torque (its induced power falls with airspeed) and the tail rotor's thrust
    ///   (the flow through its disc), which `κ v`, odd in `v`, cannot represent; the product
    ///   `q p`, scaled by `(I_xx − I_yy)/I_zz` and two small rates, is the smallest term of
    ///   yaw. On the envelope flights the yaw model's one-step prediction showed a bias of the
    ///   same sign to either side (docs/results.md, "Where the trim is wrong") that this term
    ///   takes up.
    /// * `η Δω(k)`, the previous increment of the rate: the rotor's flapping and inflow are
    ///   fast states that no sample records (flapping settles in ≈ 3 samples at 50 Hz), so
    ///   the rate responds as a second-order system at the sample scale; an ARX model of order
    ///   2 in the rate (as PX4's `ArxRls<2, …>`) accounts for them. It makes the rate models
    ///   need the sample before, which the identifier keeps.
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

    /// Nominal scales for a miniature helicopter at 50 Hz of the model of `axis` (see
    /// [`Scaling`]): rate products 100 (deg/s)², control products 0.05, rates 10 deg/s,
    /// collective 0.5, constants 1, speeds 5 m/s (the yaw model's `|v|` of
    /// [`Flight`](Self::Flight) too), rate increments 1 deg/s; target `Δω` 1 deg/s per step.
    pub fn helicopter_scaling<T: Real, const D: usize>(self, axis: RateAxis) -> Scaling<T, D> {
        // Each literal converted where it stands (a constant for f32: no f64 conversion code
        // in an f32 firmware); the tail of a shorter structure is 1, as `terms` starts.
        let l = T::lit;
        let one = T::one();
        let nominal: [T; 7] = match (self, axis) {
            (Self::Paper, _) => [l(100.0), l(0.05), one, one, one, one, one],
            (Self::Extended, _) => [l(100.0), l(0.05), l(10.0), l(0.5), one, one, one],
            (Self::Flight, RateAxis::Yaw) => [l(5.0), l(0.05), l(10.0), l(0.5), one, l(5.0), one],
            (Self::Flight, _) => [l(100.0), l(0.05), l(10.0), l(0.5), one, l(5.0), one],
        };
        let mut terms = [T::one(); D];
        for (t, &n) in terms.iter_mut().zip(&nominal) {
            *t = n;
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
    pub fn terms_in<A>(
        &self,
        s: &HoverSample<T, A>,
        frame: &BodyFrame<T>,
        before: &[T; 3],
    ) -> [T; D] {
        let [q, r, p] = s.rates;
        let u = &s.controls;
        let flight = self.structure == RateStructure::Flight;
        let [forward, right, _] = if flight {
            Premise::HeadingVelocity.of(s, frame)
        } else {
            [T::zero(); 3]
        };
        let [cross, control] = match self.axis {
            RateAxis::Pitch => [r * p, u.lon * u.col],
            RateAxis::Yaw if flight => [right.abs(), u.ped],
            RateAxis::Yaw => [q * p, u.ped],
            RateAxis::Roll => [q * r, u.lat * u.col],
        };
        let (speed, increment) = if flight {
            let speed = match self.axis {
                RateAxis::Pitch => forward,
                RateAxis::Yaw | RateAxis::Roll => right,
            };
            let earlier = before.get(self.axis.index()).copied();
            (
                speed,
                self.rate(s) - earlier.unwrap_or_else(|| self.rate(s)),
            )
        } else {
            (T::zero(), T::zero())
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

    /// Writes this model's rate `ω(k) + Δω̂` into `next`.
    fn advance<A>(&self, from: &HoverSample<T, A>, increment: T, next: &mut HoverState<T>) {
        if let Some(slot) = next.rates.get_mut(self.axis.index()) {
            *slot = self.rate(from) + increment;
        }
    }

    /// The white noise of the model's own gyro rate (standard deviation σ, deg/s) as the
    /// estimator sees it, in its scaled units, for [`RateStructure::Flight`] (`None` for the
    /// others):
    ///
    /// * the damping term's regressor ω(k) carries the noise n(k) (variance `σ²/S_δ²`);
    /// * the target `ω(k+1) − ω(k)` carries `−n(k)`, which correlates with the damping term's
    ///   noise (`−σ²/(S_δ S_y)`) and with the second-order term's `n(k) − n(k−1)`
    ///   (`−σ²/(S_η S_y)`);
    /// * the affine term (always 1) counts the samples.
    ///
    /// The second-order term's own noise variance is left out: in hover most of that term's
    /// information is noise (its signal is the small increment of a rate at 50 Hz), and
    /// removing it would divide by the small remainder, amplifying the estimate's variance. The [`RateStructure::Extended`] structure is not compensated: it is first
    /// order in a rate that responds as a second-order system, and the noise's bias partly
    /// stands in for the missing term.
    pub fn gyro_noise(&self, sigma: T) -> Option<RegressorNoise<T, D>> {
        self.gyro_noise_as(sigma, GyroCompensation::Damping)
    }

    /// [`gyro_noise`](Self::gyro_noise), with the second-order term's own noise as well for
    /// [`GyroCompensation::Full`] (its variance `2σ²/S_η²`, its covariance `σ²/(S_δ S_η)`
    /// with the damping term's, and the factors that turn the scaled δ and η into the rate's
    /// own dynamics, so that an unstable compensation is refused).
    pub fn gyro_noise_as(&self, sigma: T, how: GyroCompensation) -> Option<RegressorNoise<T, D>> {
        const DAMPING: usize = 2;
        const AFFINE: usize = 4;
        const SECOND_ORDER: usize = 6;
        if self.structure != RateStructure::Flight {
            return None;
        }
        let scaling = self.ts.scaling();
        let scale = |j: usize| scaling.terms.get(j).copied();
        let (s_damping, s_affine, s_second) =
            (scale(DAMPING)?, scale(AFFINE)?, scale(SECOND_ORDER)?);
        let variance = sigma * sigma;
        let mut with_target = [T::zero(); D];
        *with_target.get_mut(DAMPING)? = -variance / (s_damping * scaling.target);
        *with_target.get_mut(SECOND_ORDER)? = -variance / (s_second * scaling.target);
        Some(RegressorNoise {
            noisy: DAMPING,
            variance: variance / (s_damping * s_damping),
            with_target,
            unit: AFFINE,
            unit_value: T::one() / s_affine,
            paired: match how {
                GyroCompensation::Damping => None,
                GyroCompensation::Full => Some(PairedNoise {
                    index: SECOND_ORDER,
                    variance: T::lit(2.0) * variance / (s_second * s_second),
                    covariance: variance / (s_damping * s_second),
                    dynamics: [scaling.target / s_damping, scaling.target / s_second],
                }),
            },
        })
    }

    fn rate<A>(&self, s: &HoverSample<T, A>) -> T {
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

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> sealed::StepParts<T>
    for RateModel<T, R, D, E>
{
    type Prepared = Prepared<T, R, D, 1>;

    fn prepare_in<A, B>(
        &self,
        from: &HoverSample<T, A>,
        from_frame: &BodyFrame<T>,
        before: &HoverState<T>,
        to: &HoverSample<T, B>,
    ) -> Result<Self::Prepared, Error> {
        self.ts.prepare(
            &self.premise.of(from, from_frame),
            &[self.terms_in(from, from_frame, &before.rates)],
            &[self.rate(to) - self.rate(from)],
        )
    }

    fn predict_in<A>(
        &self,
        from: &HoverSample<T, A>,
        from_frame: &BodyFrame<T>,
        before: &HoverState<T>,
        next: &mut HoverState<T>,
    ) -> Result<(), Error> {
        let [increment] = self.ts.predict_many(
            &self.premise.of(from, from_frame),
            &[self.terms_in(from, from_frame, &before.rates)],
        )?;
        self.advance(from, increment, next);
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
        let terms = [self.terms_in(from, from_frame, &before.rates)];
        let [increment] = self.ts.predict_keep(&premise, strengths, &terms)?;
        self.advance(from, increment, next);
        Ok(())
    }

    fn kept_strengths(&self) -> Option<SharedStrengths<'_, T>> {
        kept_by(self.premise, &self.ts)
    }
}

impl<T: Real, const R: usize, const D: usize, E: TsEstimator<T, 3, R, D>> StateModel<T>
    for RateModel<T, R, D, E>
{
    type State = E::State;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        self.prepare_in(from, &self.frame_for(from), &from.state(), to)
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        if let Some(slot) = innovation.rates.get_mut(self.axis.index()) {
            let [e] = prepared.innovations;
            *slot = e;
        }
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        self.predict_in(from, &self.frame_for(from), &from.state(), next)
    }

    /// Compensates the rules for the noise of this axis's gyro ([`gyro_noise_as`](Self::gyro_noise_as)).
    fn compensate(&mut self, gyro_noise: &[T; 3], how: &[GyroCompensation; 3]) -> Compensation {
        let axis = self.axis.index();
        let (sigma, how) = (gyro_noise.get(axis).copied(), how.get(axis).copied());
        match sigma
            .zip(how)
            .and_then(|(sigma, how)| self.gyro_noise_as(sigma, how))
        {
            Some(noise) => self.ts.compensate(&noise),
            None => Compensation::default(),
        }
    }

    forward_to_estimator!(rate_scaling, axis);
}
