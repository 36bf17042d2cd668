//! The identifiers to use: the paper's (fuzzy and plain), the extended structures, local
//! learning, and the flight default, as type aliases of [`HoverIdentifier`] with their
//! constructors.

use crate::error::{ConfigError, Error};
use crate::hover::config::HoverConfig;
use crate::hover::identifier::{Chain, HoverIdentifier, Settings};
use crate::hover::models::{
    Premise, RateAxis, RateModel, RateStructure, VelocityModel, VelocityStructure,
};
use crate::hover::table3;
use crate::learning::TsEstimator;
use crate::rule_base::{PremiseSets, RuleBase};
use crate::scalar::Real;
use crate::ts::local::LocalTsRls;
use crate::ts::TsRls;

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
/// [`crate::ts::local`]): 27 + 18 + 9 + 9 rules of 2 terms.
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

/// **The identifier to fly**: the extended structure, each model with three rules learnt
/// locally, the rates' scheduled on the forward speed (the heading-frame velocity of
/// [`Premise::HeadingVelocity`]) and the translational model's on the horizontal speed in
/// any direction ([`Premise::HorizontalSpeed`]), with the same sets on the first premise
/// variable only. See [`FlightIdentifier::flight`] and [`flight_sets`].
///
/// Why (docs/results.md has the evidence): a helicopter's rate and velocity dynamics change
/// mainly with airspeed, so that is what the rules are scheduled on (the rotor's thrust with
/// the speed in any direction, the fin's and tail rotor's moments with its direction too); local learning makes
/// each rule a local linear model that stays sane where it is rarely visited; three rules of
/// 8 (velocity) and 7 (rates) terms keep the step cheap and the identifier small (f32: under 3 KiB).
pub type FlightIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 3, 8, 36>,
    LocalRateModel<T, 3, 7, 28>,
    LocalRateModel<T, 3, 7, 28>,
    LocalRateModel<T, 3, 7, 28>,
>;

/// [`FlightIdentifier`]'s terms with one rule per model (local learning of one rule is the
/// global one, bit for bit): the baseline that shows what the rules themselves add.
pub type FlightPlainIdentifier<T> = HoverIdentifier<
    T,
    LocalVelocityModel<T, 1, 8, 36>,
    LocalRateModel<T, 1, 7, 28>,
    LocalRateModel<T, 1, 7, 28>,
    LocalRateModel<T, 1, 7, 28>,
>;

/// The default speed sets of [`FlightIdentifier`] (m/s; the rates' forward speed, the
/// translational model's horizontal speed): a left shoulder at hover
/// (c = 0, σ = 2.5; it also takes backward flight), a Gaussian at 5 m/s (σ = 2.5) and a right
/// shoulder from 10 m/s (σ = 2.5): a miniature helicopter's low-speed envelope in three
/// regions that overlap at about μ = 0.6. For another aircraft or envelope, place them from a
/// training flight with [`crate::premise::quantile_sets`] (`rotorid identify` does).
pub fn flight_sets<T: Real>() -> PremiseSets<T> {
    table3::three_sets((0.0, 2.5), (5.0, 2.5), (10.0, 2.5))
}

/// Three sets under which a three-rule model is its one-rule form: a left shoulder whose
/// membership is 1 at every premise value a sample can carry (centre 10⁵, beyond
/// [`SampleLimits`](crate::hover::SampleLimits)' speeds and rates), then a Gaussian and a right
/// shoulder whose memberships are exactly 0 there (centres 10⁶ and 2·10⁶, σ = 1: `exp` of
/// about −5·10¹¹ is 0 in f32 and f64). So the first rule fires with ξ = 1 at every sample and
/// the others never: the first rule learns alone, with the plain model's weights and
/// forgetting, and the model predicts and learns bit for bit as the one-rule model
/// ([`FlightPlainIdentifier`]'s, for the flight structure) on every sample both accept. The
/// idle rules cost their memory and little time (they are never updated).
///
/// What it is for: a model whose dynamics the data show not to change with the speed (or
/// that the data cannot resolve per region) keeps its sizes, its snapshot format and its
/// place among the flight identifier's four models, but is not scheduled
/// ([`FlightIdentifier::flight_per_model`]; `rotorid identify` chooses this per model from the
/// training data).
pub fn unscheduled_sets<T: Real>() -> PremiseSets<T> {
    table3::three_sets((1e5, 1.0), (1e6, 1.0), (2e6, 1.0))
}

/// The speed a flight model's three rules are scheduled on (m/s), for
/// [`FlightIdentifier::flight_scheduled`]: which premise variable of the model's premise
/// carries its three sets.
///
/// The flight default schedules every model on a speed of forward flight; the rotors'
/// inflow, and so the forces and moments per control, also change with sideways flight (the
/// tail rotor's thrust and the fin's side force) and with climb and descent (a rotor
/// descending into its own wake loses thrust). Which one changes a helicopter's dynamics
/// most is for its data to say (`rotorid identify`'s `flight selected` chooses per model).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Scheduling {
    /// The flight default's: the forward speed for a rate model, the horizontal speed
    /// `|v_h|` for the translational model ([`Premise::HeadingVelocity`]'s and
    /// [`Premise::HorizontalSpeed`]'s first variable).
    #[default]
    Speed,
    /// The rightward speed in the heading frame ([`Premise::HeadingVelocity`]'s second
    /// variable). Rate models only: the translational model's premise has no side speed
    /// ([`ConfigError::Dimensions`]).
    SideSpeed,
    /// The vertical speed, up ([`Premise::HeadingVelocity`]'s third variable,
    /// [`Premise::HorizontalSpeed`]'s second).
    VerticalSpeed,
}

impl Scheduling {
    /// Index of the premise variable this schedules on, in the translational model's premise
    /// (`rate` false) or a rate model's; `None` where the premise has no such variable.
    pub const fn variable(self, rate: bool) -> Option<usize> {
        match (self, rate) {
            (Self::Speed, _) => Some(0),
            (Self::SideSpeed, true) => Some(1),
            (Self::SideSpeed, false) => None,
            (Self::VerticalSpeed, true) => Some(2),
            (Self::VerticalSpeed, false) => Some(1),
        }
    }
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

/// What a variant's four models are besides their rule bases and estimators: the structures
/// and the premises (translational, then the same premise for q̂, r̂ and p̂).
#[derive(Copy, Clone)]
struct Design {
    velocity: VelocityStructure,
    rate: RateStructure,
    velocity_premise: Premise,
    rate_premise: Premise,
}

impl Design {
    /// The paper's: Eqs. 27–30, `v^s` for the velocity, `[q r p]` for the rates.
    const PAPER: Self = Self {
        velocity: VelocityStructure::Paper,
        rate: RateStructure::Paper,
        velocity_premise: Premise::Velocity,
        rate_premise: Premise::Rates,
    };
    /// The extended structures on the paper's premises.
    const EXTENDED: Self = Self {
        velocity: VelocityStructure::Extended,
        rate: RateStructure::Extended,
        ..Self::PAPER
    };
    /// The flight structures: the translational model scheduled on the horizontal speed
    /// (the rotor's thrust changes with it in any direction), the rates on the heading-frame
    /// velocity (the fin and the tail rotor see the direction too).
    const FLIGHT: Self = Self {
        velocity: VelocityStructure::Flight,
        rate: RateStructure::Flight,
        velocity_premise: Premise::HorizontalSpeed,
        rate_premise: Premise::HeadingVelocity,
    };
}

/// The four rule bases (translational, q̂, r̂, p̂) of an identifier.
type Rules<T, const RV: usize, const RQ: usize, const RR: usize, const RP: usize> = (
    RuleBase<T, 3, RV>,
    RuleBase<T, 3, RQ>,
    RuleBase<T, 3, RR>,
    RuleBase<T, 3, RP>,
);

/// Table 3's rule bases: the given velocity sets' (the paper's `v^s` or the `ṽ_y` ones) and
/// the three rates', made in that order. Always inlined, as is [`four`]: out of line (a C
/// library built for size leaves them so) the rule bases were moved through the stack, and
/// the C firmware's stack for `ExtendedLocalIdentifier` was 16.8 KB instead of 7.2
/// (docs/c-interface.md).
#[inline(always)]
fn table3_rules<T: Real, const RV: usize>(
    velocity: fn() -> Result<RuleBase<T, 3, RV>, Error>,
) -> Result<Rules<T, RV, 18, 9, 9>, Error> {
    Ok((
        velocity()?,
        table3::pitch_rate()?,
        table3::yaw_rate()?,
        table3::roll_rate()?,
    ))
}

/// Four rule bases made alike by `base`, one model after the other.
#[inline(always)]
fn four<T: Real, const R: usize>(
    base: impl Fn() -> Result<RuleBase<T, 3, R>, Error>,
) -> Result<Rules<T, R, R, R, R>, Error> {
    Ok((base()?, base()?, base()?, base()?))
}

/// Builds the four models of an identifier from rule bases and its design. Always inlined,
/// as the constructors that call it: the C interface builds an identifier straight into its
/// storage only when the whole construction is one body (the flight kind's, called from
/// `flight_per_model` and `flight_scheduled` and left out of line, took its C init from
/// 4 284 to 13 384 B of stack: the identifier copied through temporaries).
#[allow(clippy::type_complexity)]
#[inline(always)]
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
    rules: Rules<T, RV, RQ, RR, RP>,
    design: Design,
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
    let (velocity, rate) = (design.velocity, design.rate);
    let c = config.rls;
    let rs = |axis| config.rate_scaling::<DA>(rate, axis);
    let (rq, rr, rp) = (rs(RateAxis::Pitch), rs(RateAxis::Yaw), rs(RateAxis::Roll));
    let vs = config.velocity_scaling::<DV>(velocity);
    let (pv, pr) = (design.velocity_premise, design.rate_premise);
    // Everything is checked first; then the identifier is built as one expression from
    // inlined infallible constructors, so the compiler writes the ~11 KB of arrays straight
    // into the result instead of moving models through the stack.
    config.validate()?;
    VelocityModel::<T, RV, DV, EV>::check_new(velocity, &c, &vs)?;
    RateModel::<T, RQ, DA, EQ>::check_new(rate, &c, &rq)?;
    RateModel::<T, RR, DA, ER>::check_new(rate, &c, &rr)?;
    RateModel::<T, RP, DA, EP>::check_new(rate, &c, &rp)?;
    Ok(HoverIdentifier {
        velocity: VelocityModel::with_scaling_unchecked(rules.0, velocity, pv, c, vs),
        pitch: RateModel::with_scaling_unchecked(RateAxis::Pitch, rules.1, rate, pr, c, rq),
        yaw: RateModel::with_scaling_unchecked(RateAxis::Yaw, rules.2, rate, pr, c, rr),
        roll: RateModel::with_scaling_unchecked(RateAxis::Roll, rules.3, rate, pr, c, rp),
        settings: Settings::of(&config),
        chain: Chain::empty(),
    })
}

// Each constructor below is its type's rule bases and design; `build` does the rest. The
// rule bases are made before the configuration is checked, as they always were, so the same
// error comes first.

impl<T: Real> PaperFuzzyIdentifier<T> {
    /// The paper's fuzzy identifier: Eqs. 27–30 with Table 3's sets.
    pub fn paper_fuzzy(config: HoverConfig<T>) -> Result<Self, Error> {
        build(config, table3_rules(table3::velocity)?, Design::PAPER)
    }
}

impl<T: Real> PaperPlainIdentifier<T> {
    /// The paper's plain-RLS baseline: Eqs. 19 and 26, one rule per model.
    pub fn paper_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        build(config, four(RuleBase::single_rule)?, Design::PAPER)
    }
}

impl<T: Real> ExtendedFuzzyIdentifier<T> {
    /// The extended fuzzy identifier (see [`ExtendedFuzzyIdentifier`]).
    pub fn extended_fuzzy(config: HoverConfig<T>) -> Result<Self, Error> {
        build(
            config,
            table3_rules(table3::vertical_velocity)?,
            Design::EXTENDED,
        )
    }
}

impl<T: Real> ExtendedPlainIdentifier<T> {
    /// The extended single-rule identifier (see [`ExtendedPlainIdentifier`]).
    pub fn extended_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        build(config, four(RuleBase::single_rule)?, Design::EXTENDED)
    }
}

impl<T: Real> PaperLocalIdentifier<T> {
    /// The paper's structure and sets, learnt locally.
    pub fn paper_local(config: HoverConfig<T>) -> Result<Self, Error> {
        build(config, table3_rules(table3::velocity)?, Design::PAPER)
    }
}

impl<T: Real> ExtendedLocalIdentifier<T> {
    /// The extended structure with [`ExtendedFuzzyIdentifier`]'s sets, learnt locally.
    pub fn extended_local(config: HoverConfig<T>) -> Result<Self, Error> {
        build(
            config,
            table3_rules(table3::vertical_velocity)?,
            Design::EXTENDED,
        )
    }
}

impl<T: Real> FlightIdentifier<T> {
    /// The flight identifier with the given speed sets (m/s; three sets, e.g. from
    /// [`flight_sets`] or [`crate::premise::quantile_sets`]) for all four models: on the
    /// forward speed for the rates, on the horizontal speed for the translational model.
    pub fn flight(config: HoverConfig<T>, forward: PremiseSets<T>) -> Result<Self, Error> {
        Self::flight_per_model(config, core::array::from_fn(|_| forward.clone()))
    }

    /// The flight identifier with speed sets of its own for each model, in the order
    /// velocity, q̂, r̂, p̂ (m/s, three sets each; the premises as in
    /// [`flight`](Self::flight), which is this with the same sets four times). With
    /// [`unscheduled_sets`] a model is its one-rule form; the rate models that have the same
    /// sets still share their firing strengths.
    #[inline(always)] // see `build`: built in place by the C interface
    pub fn flight_per_model(
        config: HoverConfig<T>,
        sets: [PremiseSets<T>; 4],
    ) -> Result<Self, Error> {
        // Not `flight_scheduled` with the speed four times: the same identifier, but a
        // firmware that never schedules elsewhere links none of its choice.
        let [v, q, r, p] = sets;
        let rules = |s| RuleBase::new([s, PremiseSets::new(), PremiseSets::new()]);
        build(
            config,
            (rules(v)?, rules(q)?, rules(r)?, rules(p)?),
            Design::FLIGHT,
        )
    }

    /// [`flight_per_model`](Self::flight_per_model) with each model's three sets on the speed
    /// `on` names for it, in the same order (velocity, q̂, r̂, p̂; m/s). With
    /// [`Scheduling::Speed`] four times it is `flight_per_model`, bit for bit.
    ///
    /// # Errors
    ///
    /// Those of [`flight_per_model`](Self::flight_per_model), and
    /// [`ConfigError::Dimensions`] for the translational model on
    /// [`Scheduling::SideSpeed`] (its premise has none).
    pub fn flight_scheduled(
        config: HoverConfig<T>,
        sets: [PremiseSets<T>; 4],
        on: [Scheduling; 4],
    ) -> Result<Self, Error> {
        let [v, q, r, p] = sets;
        let [sv, sq, sr, sp] = on;
        let rules = |s: PremiseSets<T>, on: Scheduling, rate: bool| {
            let mut variables = [PremiseSets::new(), PremiseSets::new(), PremiseSets::new()];
            match on.variable(rate).and_then(|i| variables.get_mut(i)) {
                Some(slot) => *slot = s,
                None => return Err(ConfigError::Dimensions.into()),
            }
            RuleBase::new(variables)
        };
        build(
            config,
            (
                rules(v, sv, false)?,
                rules(q, sq, true)?,
                rules(r, sr, true)?,
                rules(p, sp, true)?,
            ),
            Design::FLIGHT,
        )
    }
}

impl<T: Real> FlightPlainIdentifier<T> {
    /// [`FlightIdentifier`]'s terms and premise with a single rule per model.
    pub fn flight_plain(config: HoverConfig<T>) -> Result<Self, Error> {
        build(config, four(RuleBase::single_rule)?, Design::FLIGHT)
    }
}
