//! The hover identifier: one translational and three angular models fed one sample at a time.

use crate::error::{ConfigError, Error};
use crate::hover::models::{
    BodyFrame, Premise, RateAxis, RateModel, RateStructure, StateModel, VelocityModel,
    VelocityStructure,
};
use crate::hover::sample::{HoverSample, HoverState, SampleLimits};
use crate::hover::table3;
use crate::learning::TsEstimator;
use crate::local::LocalTsRls;
use crate::rls::RlsConfig;
use crate::rule_base::{PremiseSets, RuleBase};
use crate::scalar::Real;
use crate::ts::{Scaling, TsRls};

/// Whether the models divide their terms by nominal scales (see [`crate::ts::Scaling`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RegressorScaling {
    /// Raw physical units, as the paper: bit-identical to an implementation without scaling.
    None,
    /// The nominal miniature-helicopter scales of
    /// [`VelocityStructure::helicopter_scaling`] and [`RateStructure::helicopter_scaling`]:
    /// a well-conditioned problem in f32. Parameters are still reported in physical units by
    /// [`TsRls::physical_parameter`](crate::TsRls::physical_parameter).
    Helicopter,
}

/// Settings shared by the four models of a [`HoverIdentifier`].
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HoverConfig<T> {
    /// Estimator settings of every model.
    pub rls: RlsConfig<T>,
    /// Nominal sample period ΔT (µs). The identified parameters are per-step quantities
    /// (Eqs. 22–25 contain ΔT), so a model is only valid at the rate it was learnt at.
    pub sample_period_us: u32,
    /// Accepted deviation of one interval from ΔT (µs), for timing jitter.
    pub period_tolerance_us: u32,
    /// Regressor scaling of every model.
    pub scaling: RegressorScaling,
}

impl<T: Real> Default for HoverConfig<T> {
    /// The flight settings: robust (U-D) RLS with α = 10⁶, helicopter regressor scaling,
    /// 50 Hz (20 000 µs) ± 50 %.
    fn default() -> Self {
        Self {
            rls: RlsConfig::default(),
            sample_period_us: 20_000,
            period_tolerance_us: 10_000,
            scaling: RegressorScaling::Helicopter,
        }
    }
}

impl<T: Real> HoverConfig<T> {
    /// The paper's settings: covariance-form RLS, λ = 1, α = 10⁶, no scaling, 50 Hz ± 50 %.
    pub fn paper() -> Self {
        Self {
            rls: RlsConfig::paper(T::lit(1e6)),
            scaling: RegressorScaling::None,
            ..Self::default()
        }
    }

    /// The paper's estimator computed robustly: U-D RLS, α = 10⁶, no scaling.
    pub fn paper_robust() -> Self {
        Self {
            scaling: RegressorScaling::None,
            ..Self::default()
        }
    }

    pub(crate) fn velocity_scaling<const D: usize>(&self, s: VelocityStructure) -> Scaling<T, D> {
        match self.scaling {
            RegressorScaling::None => Scaling::unit(),
            RegressorScaling::Helicopter => s.helicopter_scaling(),
        }
    }

    pub(crate) fn rate_scaling<const D: usize>(&self, s: RateStructure) -> Scaling<T, D> {
        match self.scaling {
            RegressorScaling::None => Scaling::unit(),
            RegressorScaling::Helicopter => s.helicopter_scaling(),
        }
    }

    fn validate(&self) -> Result<(), Error> {
        self.rls.validate()?;
        if self.sample_period_us == 0 || self.period_tolerance_us >= self.sample_period_us {
            return Err(ConfigError::SamplePeriod.into());
        }
        Ok(())
    }
}

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

/// Everything a [`HoverIdentifier`] has learnt (warm start across flights).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct HoverSnapshot<V, Q, R, P> {
    /// Translational model.
    pub velocity: V,
    /// q̂ model.
    pub pitch: Q,
    /// r̂ model.
    pub yaw: R,
    /// p̂ model.
    pub roll: P,
}

/// Online identifier of the hover dynamics (paper Section 5): takes one sample per step,
/// learns all four models from the previous sample to this one, and predicts the next.
///
/// `V` is the translational model, `Q`, `R`, `P` the q̂, r̂, p̂ models. The paper's two
/// configurations are the aliases [`PaperFuzzyIdentifier`] and [`PaperPlainIdentifier`]; since
/// they share this API, Table 4's comparison is a change of type.
///
/// Every call that returns `Err` leaves the identifier exactly as it was.
#[derive(Clone, Debug, PartialEq)]
pub struct HoverIdentifier<T, V, Q, R, P> {
    velocity: V,
    pitch: Q,
    yaw: R,
    roll: P,
    /// The settings that are not the models' own (the RLS settings are: see
    /// [`HoverIdentifier::config`]).
    timing: Timing,
    /// The end of the current sample chain (how much of it is valid: `timing.links`).
    chain: Chain<T>,
}

/// The end of a sample chain: the sample the next step learns from, its body frame, and the
/// body rates `[q r p]` of the sample before it (for second-order rate terms,
/// [`RateStructure::Flight`]). Kept without `Option`s, the count of valid links living in
/// [`Timing`]'s padding, so that the paper fuzzy identifier stays within 11 KiB.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Chain<T> {
    sample: HoverSample<T>,
    frame: BodyFrame<T>,
    before: [T; 3],
}

impl<T: Real> Chain<T> {
    fn empty() -> Self {
        Self {
            sample: HoverSample::default(),
            frame: BodyFrame::identity(),
            before: [T::zero(); 3],
        }
    }
}

/// The paper's Takagi-Sugeno identifier with Table 3's sets: 27 + 18 + 9 + 9 rules,
/// 54 + 36 + 18 + 18 parameters.
pub type PaperFuzzyIdentifier<T> = HoverIdentifier<
    T,
    GlobalVelocityModel<T, 27, 2, 54, 1485>,
    GlobalRateModel<T, 18, 2, 36, 666>,
    GlobalRateModel<T, 9, 2, 18, 171>,
    GlobalRateModel<T, 9, 2, 18, 171>,
>;

/// The paper's plain-RLS baseline (Eqs. 19 and 26): the same models with a single rule.
pub type PaperPlainIdentifier<T> = HoverIdentifier<
    T,
    GlobalVelocityModel<T, 1, 2, 2, 3>,
    GlobalRateModel<T, 1, 2, 2, 3>,
    GlobalRateModel<T, 1, 2, 2, 3>,
    GlobalRateModel<T, 1, 2, 2, 3>,
>;

/// The extended structure (damping and trim terms, [`RateStructure::Extended`],
/// [`VelocityStructure::Extended`]) with fuzzy rule bases: Table 3's sets for the rates
/// (18, 9, 9 rules × 5 terms) and Table 3's `ṽ_y` sets for the velocity (3 rules × 7 terms;
/// the thrust per unit collective varies with the vertical inflow, while drag is linear).
pub type ExtendedFuzzyIdentifier<T> = HoverIdentifier<
    T,
    GlobalVelocityModel<T, 3, 7, 21, 231>,
    GlobalRateModel<T, 18, 5, 90, 4095>,
    GlobalRateModel<T, 9, 5, 45, 1035>,
    GlobalRateModel<T, 9, 5, 45, 1035>,
>;

/// The extended structure with a single rule per model (a linear model with damping and trim).
pub type ExtendedPlainIdentifier<T> = HoverIdentifier<
    T,
    GlobalVelocityModel<T, 1, 7, 7, 28>,
    GlobalRateModel<T, 1, 5, 5, 15>,
    GlobalRateModel<T, 1, 5, 5, 15>,
    GlobalRateModel<T, 1, 5, 5, 15>,
>;

/// The paper's structure and Table 3's sets, every rule learnt locally (see
/// [`crate::local`]): 27 + 18 + 9 + 9 rules of 2 terms.
pub type PaperLocalIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 27, 2, 3>,
    LocalRateModel<T, 18, 2, 3>,
    LocalRateModel<T, 9, 2, 3>,
    LocalRateModel<T, 9, 2, 3>,
>;

/// [`ExtendedFuzzyIdentifier`]'s structure and sets, every rule learnt locally.
pub type ExtendedLocalIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 3, 7, 28>,
    LocalRateModel<T, 18, 5, 15>,
    LocalRateModel<T, 9, 5, 15>,
    LocalRateModel<T, 9, 5, 15>,
>;

/// **The identifier to fly**: the extended structure, each model scheduled on the forward
/// speed (the heading-frame velocity of [`Premise::HeadingVelocity`], sets on its first
/// component only) with three rules learnt locally. See [`FlightIdentifier::flight`] and
/// [`flight_sets`].
///
/// Why (docs/results.md has the evidence): a helicopter's rate and velocity dynamics change
/// mainly with airspeed, so that is what the rules are scheduled on; local learning makes
/// each rule a local linear model that stays sane where it is rarely visited; three rules of
/// 7 and 5 terms keep the step cheap and the identifier small (f32: under 3 KiB).
pub type FlightIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 3, 7, 28>,
    LocalRateModel<T, 3, 7, 28>,
    LocalRateModel<T, 3, 7, 28>,
    LocalRateModel<T, 3, 7, 28>,
>;

/// [`FlightIdentifier`]'s terms with one rule per model (local learning of one rule is the
/// global one, bit for bit): the baseline that shows what the rules themselves add.
pub type FlightPlainIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 1, 7, 28>,
    LocalRateModel<T, 1, 7, 28>,
    LocalRateModel<T, 1, 7, 28>,
    LocalRateModel<T, 1, 7, 28>,
>;

/// The default forward-speed sets of [`FlightIdentifier`] (m/s): a left shoulder at hover
/// (c = 0, σ = 2.5; it also takes backward flight), a Gaussian at 5 m/s (σ = 2.5) and a right
/// shoulder from 10 m/s (σ = 2.5): a miniature helicopter's low-speed envelope in three
/// regions that overlap at about μ = 0.6. For another aircraft or envelope, place them from a
/// training flight with [`crate::premise::quantile_sets`] (`rotorid identify` does).
pub fn flight_sets<T: Real>() -> PremiseSets<T> {
    table3::three_sets((0.0, 2.5), (5.0, 2.5), (10.0, 2.5))
}

/// A translational model learnt globally (the paper's RLS over `N = R·D` parameters, `NP`
/// packed covariance entries).
pub type GlobalVelocityModel<T, const R: usize, const D: usize, const N: usize, const NP: usize> =
    VelocityModel<T, R, D, TsRls<T, 3, R, D, N, NP>>;
/// An angular model learnt globally.
pub type GlobalRateModel<T, const R: usize, const D: usize, const N: usize, const NP: usize> =
    RateModel<T, R, D, TsRls<T, 3, R, D, N, NP>>;
/// A translational model learnt locally (each of the `R` rules its own RLS of `DP = D(D+1)/2`
/// packed covariance entries).
pub type LocalVelocityModel<T, const R: usize, const D: usize, const DP: usize> =
    VelocityModel<T, R, D, LocalTsRls<T, 3, R, D, DP>>;
/// An angular model learnt locally.
pub type LocalRateModel<T, const R: usize, const D: usize, const DP: usize> =
    RateModel<T, R, D, LocalTsRls<T, 3, R, D, DP>>;

/// [`HoverConfig`] less the RLS settings, which each model keeps (not stored twice: the
/// identifier's `size_of` is held to 11 KiB).
#[derive(Copy, Clone, Debug, PartialEq)]
struct Timing {
    sample_period_us: u32,
    period_tolerance_us: u32,
    scaling: RegressorScaling,
    /// Samples of the current chain the identifier knows: 0 (none), 1 (`chain.sample`) or 2
    /// (also `chain.before`).
    links: u8,
}

impl Timing {
    fn of<T>(config: &HoverConfig<T>) -> Self {
        Self {
            sample_period_us: config.sample_period_us,
            period_tolerance_us: config.period_tolerance_us,
            scaling: config.scaling,
            links: 0,
        }
    }
}

/// The premises of the four models (translational, q̂, r̂, p̂).
#[derive(Copy, Clone)]
struct Premises {
    velocity: Premise,
    rates: Premise,
}

impl Premises {
    /// The paper's: `v^s` for the velocity, `[q r p]` for the rates.
    const PAPER: Self = Self {
        velocity: Premise::Velocity,
        rates: Premise::Rates,
    };
}

/// Builds the four models of an identifier from rule bases, structures and premises.
#[allow(clippy::type_complexity)]
fn build<
    T: Real,
    const RV: usize,
    const DV: usize,
    const RQ: usize,
    const RR: usize,
    const RP: usize,
    const DA: usize,
    EV: TsEstimator<T, 3, RV, DV>,
    EQ: TsEstimator<T, 3, RQ, DA>,
    ER: TsEstimator<T, 3, RR, DA>,
    EP: TsEstimator<T, 3, RP, DA>,
>(
    config: HoverConfig<T>,
    rules: (
        RuleBase<T, 3, RV>,
        RuleBase<T, 3, RQ>,
        RuleBase<T, 3, RR>,
        RuleBase<T, 3, RP>,
    ),
    velocity: VelocityStructure,
    rate: RateStructure,
    premises: Premises,
) -> Result<
    HoverIdentifier<
        T,
        VelocityModel<T, RV, DV, EV>,
        RateModel<T, RQ, DA, EQ>,
        RateModel<T, RR, DA, ER>,
        RateModel<T, RP, DA, EP>,
    >,
    Error,
> {
    let c = config.rls;
    let rs = config.rate_scaling::<DA>(rate);
    let vs = config.velocity_scaling::<DV>(velocity);
    let (pv, pr) = (premises.velocity, premises.rates);
    // Everything is checked first; then the identifier is built as one expression from
    // inlined infallible constructors, so the compiler writes the ~11 KB of arrays straight
    // into the result instead of moving models through the stack.
    config.validate()?;
    VelocityModel::<T, RV, DV, EV>::check_new(velocity, &c, &vs)?;
    RateModel::<T, RQ, DA, EQ>::check_new(rate, &c, &rs)?;
    RateModel::<T, RR, DA, ER>::check_new(rate, &c, &rs)?;
    RateModel::<T, RP, DA, EP>::check_new(rate, &c, &rs)?;
    Ok(HoverIdentifier {
        velocity: VelocityModel::with_scaling_unchecked(rules.0, velocity, pv, c, vs),
        pitch: RateModel::with_scaling_unchecked(RateAxis::Pitch, rules.1, rate, pr, c, rs),
        yaw: RateModel::with_scaling_unchecked(RateAxis::Yaw, rules.2, rate, pr, c, rs),
        roll: RateModel::with_scaling_unchecked(RateAxis::Roll, rules.3, rate, pr, c, rs),
        timing: Timing::of(&config),
        chain: Chain::empty(),
    })
}

impl<T: Real> PaperFuzzyIdentifier<T> {
    /// The paper's fuzzy identifier: Eqs. 27–30 with Table 3's sets.
    pub fn paper_fuzzy(config: HoverConfig<T>) -> Result<Self, Error> {
        let rules = (
            table3::velocity()?,
            table3::pitch_rate()?,
            table3::yaw_rate()?,
            table3::roll_rate()?,
        );
        build(
            config,
            rules,
            VelocityStructure::Paper,
            RateStructure::Paper,
            Premises::PAPER,
        )
    }
}

impl<T: Real> PaperPlainIdentifier<T> {
    /// The paper's plain-RLS baseline: Eqs. 19 and 26, one rule per model.
    pub fn paper_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        let one = || RuleBase::single_rule();
        let rules = (one()?, one()?, one()?, one()?);
        build(
            config,
            rules,
            VelocityStructure::Paper,
            RateStructure::Paper,
            Premises::PAPER,
        )
    }
}

impl<T: Real> ExtendedFuzzyIdentifier<T> {
    /// The extended fuzzy identifier (see [`ExtendedFuzzyIdentifier`]).
    pub fn extended_fuzzy(config: HoverConfig<T>) -> Result<Self, Error> {
        let rules = (
            table3::vertical_velocity()?,
            table3::pitch_rate()?,
            table3::yaw_rate()?,
            table3::roll_rate()?,
        );
        build(
            config,
            rules,
            VelocityStructure::Extended,
            RateStructure::Extended,
            Premises::PAPER,
        )
    }
}

impl<T: Real> ExtendedPlainIdentifier<T> {
    /// The extended single-rule identifier (see [`ExtendedPlainIdentifier`]).
    pub fn extended_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        let one = || RuleBase::single_rule();
        let rules = (one()?, one()?, one()?, one()?);
        build(
            config,
            rules,
            VelocityStructure::Extended,
            RateStructure::Extended,
            Premises::PAPER,
        )
    }
}

impl<T: Real> PaperLocalIdentifier<T> {
    /// The paper's structure and sets, learnt locally.
    pub fn paper_local(config: HoverConfig<T>) -> Result<Self, Error> {
        let rules = (
            table3::velocity()?,
            table3::pitch_rate()?,
            table3::yaw_rate()?,
            table3::roll_rate()?,
        );
        build(
            config,
            rules,
            VelocityStructure::Paper,
            RateStructure::Paper,
            Premises::PAPER,
        )
    }
}

impl<T: Real> ExtendedLocalIdentifier<T> {
    /// The extended structure with [`ExtendedFuzzyIdentifier`]'s sets, learnt locally.
    pub fn extended_local(config: HoverConfig<T>) -> Result<Self, Error> {
        let rules = (
            table3::vertical_velocity()?,
            table3::pitch_rate()?,
            table3::yaw_rate()?,
            table3::roll_rate()?,
        );
        build(
            config,
            rules,
            VelocityStructure::Extended,
            RateStructure::Extended,
            Premises::PAPER,
        )
    }
}

impl<T: Real> FlightIdentifier<T> {
    /// The flight identifier with the given forward-speed sets (m/s; three sets, e.g. from
    /// [`flight_sets`] or [`crate::premise::quantile_sets`]) for all four models.
    pub fn flight(config: HoverConfig<T>, forward: PremiseSets<T>) -> Result<Self, Error> {
        let base = || RuleBase::new([forward.clone(), PremiseSets::new(), PremiseSets::new()]);
        let rules = (base()?, base()?, base()?, base()?);
        build(
            config,
            rules,
            VelocityStructure::Flight,
            RateStructure::Flight,
            Premises {
                velocity: Premise::HeadingVelocity,
                rates: Premise::HeadingVelocity,
            },
        )
    }
}

impl<T: Real> FlightPlainIdentifier<T> {
    /// [`FlightIdentifier`]'s terms and premise with a single rule per model.
    pub fn flight_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        let one = || RuleBase::single_rule();
        build(
            config,
            (one()?, one()?, one()?, one()?),
            VelocityStructure::Flight,
            RateStructure::Flight,
            Premises {
                velocity: Premise::HeadingVelocity,
                rates: Premise::HeadingVelocity,
            },
        )
    }
}

impl<T, V, Q, R, P> HoverIdentifier<T, V, Q, R, P>
where
    T: Real,
    V: StateModel<T>,
    Q: StateModel<T>,
    R: StateModel<T>,
    P: StateModel<T>,
{
    /// An identifier from four models (translational, q̂, r̂, p̂). `config` gives the sample
    /// period and its tolerance; the models keep the RLS settings and scales they were built
    /// with.
    pub fn new(
        velocity: V,
        pitch: Q,
        yaw: R,
        roll: P,
        config: HoverConfig<T>,
    ) -> Result<Self, Error> {
        config.validate()?;
        Ok(Self {
            velocity,
            pitch,
            yaw,
            roll,
            timing: Timing::of(&config),
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
            sample_period_us: self.timing.sample_period_us,
            period_tolerance_us: self.timing.period_tolerance_us,
            scaling: self.timing.scaling,
        }
    }

    /// The translational model.
    pub fn velocity_model(&self) -> &V {
        &self.velocity
    }

    /// The q̂ model.
    pub fn pitch_model(&self) -> &Q {
        &self.pitch
    }

    /// The r̂ model.
    pub fn yaw_model(&self) -> &R {
        &self.yaw
    }

    /// The p̂ model.
    pub fn roll_model(&self) -> &P {
        &self.roll
    }

    /// The sample the next step will learn from, if any.
    pub fn previous_sample(&self) -> Option<&HoverSample<T>> {
        (self.timing.links > 0).then_some(&self.chain.sample)
    }

    /// Takes sample k+1: learns every model from (sample k → sample k+1), then predicts the
    /// state at k+2.
    ///
    /// Errors (nothing changes on any of them): a field out of range or not finite
    /// ([`SampleLimits`]), a time stamp that does not increase, an interval outside
    /// `sample_period_us ± period_tolerance_us` (after a gap, call [`resume`](Self::resume)),
    /// or an update beyond the estimator's numeric limits. One exception to "nothing changes":
    /// [`Error::Numerical`] after learning means the prediction from the updated parameters
    /// overflowed (possible only with parameters far beyond anything learning produces, such
    /// as an absurd imported state); the sample was learnt, and the identifier should be
    /// [`reset`](Self::reset).
    pub fn step(&mut self, sample: &HoverSample<T>) -> Result<StepOutput<T>, Error> {
        SampleLimits::check(sample)?;
        let mut innovation = None;
        let mut before = sample.rates;
        if self.timing.links > 0 {
            let Chain {
                sample: prev,
                frame,
                before: earlier,
            } = &self.chain;
            self.check_interval(prev, sample)?;
            let b = if self.timing.links > 1 {
                earlier
            } else {
                &prev.rates
            };
            // Check all four models before changing any.
            let v = self.velocity.prepare_in(prev, frame, b, sample)?;
            let q = self.pitch.prepare_in(prev, frame, b, sample)?;
            let r = self.yaw.prepare_in(prev, frame, b, sample)?;
            let p = self.roll.prepare_in(prev, frame, b, sample)?;
            let mut inn = HoverState::default();
            self.velocity.apply(&v, &mut inn);
            self.pitch.apply(&q, &mut inn);
            self.yaw.apply(&r, &mut inn);
            self.roll.apply(&p, &mut inn);
            innovation = Some(inn);
            before = prev.rates;
        }
        let frame = BodyFrame::of(&sample.attitude);
        self.chain = Chain {
            sample: *sample,
            frame,
            before,
        };
        self.timing.links = if self.timing.links > 0 { 2 } else { 1 };
        // The sample passed SampleLimits, which bounds every regressor; only parameters beyond
        // any learnt ones could make this fail (see the docs above).
        let prediction = self.predict_in(sample, &frame, &before)?;
        Ok(StepOutput {
            prediction,
            innovation,
        })
    }

    /// One-step prediction of the state after `sample`, with the current parameters, as the
    /// first sample of a chain (a second-order term sees no earlier sample); changes nothing.
    /// To verify a frozen model or simulate it forward, use
    /// [`predict_after`](Self::predict_after).
    pub fn predict(&self, sample: &HoverSample<T>) -> Result<HoverState<T>, Error> {
        self.predict_after(None, sample)
    }

    /// One-step prediction of the state after `sample`, given the state of the sample before
    /// it (`before`: measured, or the model's own estimate in a simulation; `None` at the
    /// start of a chain). Only second-order terms ([`RateStructure::Flight`]) read it.
    /// Changes nothing.
    pub fn predict_after(
        &self,
        before: Option<&HoverState<T>>,
        sample: &HoverSample<T>,
    ) -> Result<HoverState<T>, Error> {
        SampleLimits::check(sample)?;
        let before = match before {
            Some(b) => {
                SampleLimits::check_rates(&b.rates)?;
                b.rates
            }
            None => sample.rates,
        };
        self.predict_in(sample, &BodyFrame::of(&sample.attitude), &before)
    }

    fn predict_in(
        &self,
        sample: &HoverSample<T>,
        frame: &BodyFrame<T>,
        before: &[T; 3],
    ) -> Result<HoverState<T>, Error> {
        let mut next = HoverState::default();
        self.velocity.predict_in(sample, frame, before, &mut next)?;
        self.pitch.predict_in(sample, frame, before, &mut next)?;
        self.yaw.predict_in(sample, frame, before, &mut next)?;
        self.roll.predict_in(sample, frame, before, &mut next)?;
        // Never a non-finite number out of an `Ok`: parameters far beyond anything learning
        // produces (an absurd imported state, say) could overflow a prediction.
        if next.to_array().iter().all(|x| x.is_finite()) {
            Ok(next)
        } else {
            Err(Error::Numerical)
        }
    }

    /// Starts a new sample chain at `sample` without learning (after a gap, a time jump, or
    /// between concatenated manoeuvres). Returns the prediction from it.
    pub fn resume(&mut self, sample: &HoverSample<T>) -> Result<HoverState<T>, Error> {
        SampleLimits::check(sample)?;
        let frame = BodyFrame::of(&sample.attitude);
        let prediction = self.predict_in(sample, &frame, &sample.rates)?;
        self.chain = Chain {
            sample: *sample,
            frame,
            before: sample.rates,
        };
        self.timing.links = 1;
        Ok(prediction)
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
    pub fn export(&self) -> HoverSnapshot<V::State, Q::State, R::State, P::State> {
        HoverSnapshot {
            velocity: self.velocity.export(),
            pitch: self.pitch.export(),
            yaw: self.yaw.export(),
            roll: self.roll.export(),
        }
    }

    /// Warm start from an exported snapshot. The sample chain restarts (the next step only
    /// anchors). All four states are checked before any is written; on `Err` nothing changed.
    pub fn import(
        &mut self,
        snapshot: &HoverSnapshot<V::State, Q::State, R::State, P::State>,
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
        self.timing.links = 0;
    }

    /// Mutable access to the translational model, for importing one model at a time (a
    /// firmware can stage one model's state instead of a whole snapshot). Importing a model
    /// does not restart the sample chain.
    pub fn velocity_model_mut(&mut self) -> &mut V {
        &mut self.velocity
    }

    /// Mutable access to the q̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn pitch_model_mut(&mut self) -> &mut Q {
        &mut self.pitch
    }

    /// Mutable access to the r̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn yaw_model_mut(&mut self) -> &mut R {
        &mut self.yaw
    }

    /// Mutable access to the p̂ model (see [`velocity_model_mut`](Self::velocity_model_mut)).
    pub fn roll_model_mut(&mut self) -> &mut P {
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
        self.timing = Timing::of(&config);
        self.end_chain_in_place();
        Ok(())
    }

    fn check_interval(&self, prev: &HoverSample<T>, next: &HoverSample<T>) -> Result<(), Error> {
        if next.time_us <= prev.time_us {
            return Err(Error::NonMonotonicTime);
        }
        let dt = next.time_us - prev.time_us;
        let nominal = u64::from(self.timing.sample_period_us);
        let tol = u64::from(self.timing.period_tolerance_us);
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
