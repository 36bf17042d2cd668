//! The identifier variants the tool compares, behind one object-safe [`Identifier`] trait
//! with parameter export/import as plain data.

use rotorid::hover::{
    flight_sets, BodyFrame, LocalRateModel, LocalVelocityModel, Premise, RateAxis, RateStructure,
    VelocityStructure,
};
use rotorid::hover::{
    GainSearch, HoverIdentifier, HoverSample, HoverSnapshot, HoverState, Observer, StateModel,
    StepOutput,
};
use rotorid::membership::MembershipFunction;
use rotorid::rls::{Algorithm, Compensation, RlsState};
use rotorid::rule_base::{PremiseSets, RuleBase};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier,
    FlightPlainIdentifier, HoverConfig, PaperFuzzyIdentifier, PaperLocalIdentifier,
    PaperPlainIdentifier,
};
use serde::{Deserialize, Serialize};

use super::error::ParametersError;

/// What the experiments need of an identifier: the core's [`HoverIdentifier`] API for `f32`,
/// object-safe, plus parameter export/import as plain data. Implemented for every
/// `HoverIdentifier<f32, …>` whose models hold [`RlsState`]s.
pub trait Identifier {
    /// [`HoverIdentifier::step`]: learn from the previous sample to this one, predict the next.
    fn step(&mut self, sample: &HoverSample<f32>) -> Result<StepOutput<f32>, rotorid::Error>;
    /// [`HoverIdentifier::predict`]: one-step prediction with frozen θ.
    fn predict(&self, sample: &HoverSample<f32>) -> Result<HoverState<f32>, rotorid::Error>;
    /// One-step prediction given the state of the sample before (see
    /// [`HoverIdentifier::predict_after`]).
    fn predict_after(
        &self,
        before: Option<&HoverState<f32>>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error>;
    /// [`HoverIdentifier::resume`]: restart the sample chain (after a gap).
    fn resume(&mut self, sample: &HoverSample<f32>) -> Result<HoverState<f32>, rotorid::Error>;
    /// A boxed copy (to verify a still-adapting copy next to the frozen one).
    fn boxed_clone(&self) -> Box<dyn Identifier>;
    /// θ and covariance factor of the four models (velocity, q̂, r̂, p̂), for warm start.
    fn parameters(&self) -> Vec<ModelParameters>;
    /// Warm start from [`parameters`](Self::parameters) output; on `Err` nothing changed.
    fn load(&mut self, parameters: &[ModelParameters]) -> Result<(), ParametersError>;
    /// [`HoverIdentifier::compensate`]: the parameters for a simulation, compensated for the
    /// gyros' white noise σ `[q r p]` (deg/s).
    fn compensate(&mut self, gyro_noise: &[f32; 3]) -> Result<Compensation, rotorid::Error>;
    /// [`Observer::predict`] with this identifier's parameters.
    fn observe(
        &self,
        observer: &mut Observer<f32>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error>;
    /// [`GainSearch::push`] with this identifier's parameters.
    fn search_gain(
        &self,
        search: &mut ObserverSearch,
        sample: &HoverSample<f32>,
    ) -> Result<(), rotorid::Error>;
}

/// Candidate gains of the observer's search: 0.1, 0.2, …, 1.0 ([`GainSearch::grid`]).
pub const OBSERVER_CANDIDATES: usize = 10;

/// The search for an observer's gain that the tool runs on the training logs.
pub type ObserverSearch = GainSearch<f32, OBSERVER_CANDIDATES>;

/// Exported state of one model (one [`RlsState`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelParameters {
    /// `velocity` (Eq. 27), `q`, `r` or `p` (Eqs. 28–30).
    pub model: String,
    /// `covariance` (the paper's form) or `ud` (Bierman U-D).
    pub algorithm: String,
    /// Consequent parameters θ, rule-major (`[α1 α2]` or `[𝕀 γ]` per rule).
    pub theta: Vec<f32>,
    /// Packed covariance P, or packed U with D on the diagonal.
    pub factor: Vec<f32>,
    /// Updates made (a locally learnt model: the sum over its rules).
    pub updates: u32,
    /// A locally learnt model: the updates of each rule (empty for a global model).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rule_updates: Vec<u32>,
    /// The premise the rules are scheduled on and each premise variable's sets, so that a
    /// firmware can rebuild the same rule base for a warm start (the C interface's
    /// `rotorid_flight_sets_t` takes the forward-speed sets of `premise: "heading-velocity"`).
    /// Absent for a model with one rule.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub premise: Option<PremiseParameters>,
}

/// A model's premise and sets, as written next to its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PremiseParameters {
    /// `velocity` (`[v_x v_y v_z]`, m/s), `rates` (`[q r p]`, deg/s) or `heading-velocity`
    /// (`[forward right up]`, m/s).
    pub kind: String,
    /// Each premise variable's sets in rule order (an empty list: the variable takes no part).
    pub variables: Vec<Vec<SetParameters>>,
}

/// One membership function: `μ(x) = exp(−½((x − c)/σ)²)`, held at 1 below the centre for a
/// `left` shoulder and above it for a `right` one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetParameters {
    /// `left`, `gaussian` or `right`.
    pub shape: String,
    /// Centre c (the premise variable's unit).
    pub centre: f32,
    /// Spread σ (same unit, > 0).
    pub spread: f32,
}

impl PremiseParameters {
    /// A model's premise and sets (`None` for a model whose rule base has one rule).
    pub fn of<M: StateModel<f32>>(model: &M) -> Option<Self> {
        let (premise, variables) = model.premise_sets();
        if variables.iter().all(|v| v.is_empty()) {
            return None;
        }
        let kind = match premise {
            Premise::Velocity => "velocity",
            Premise::Rates => "rates",
            Premise::HeadingVelocity => "heading-velocity",
            _ => "unknown",
        };
        let set = |mf: &MembershipFunction<f32>| {
            let (shape, (centre, spread)) = match mf {
                MembershipFunction::LeftShoulder { .. } => ("left", mf.parameters()),
                MembershipFunction::Gaussian { .. } => ("gaussian", mf.parameters()),
                MembershipFunction::RightShoulder { .. } => ("right", mf.parameters()),
            };
            SetParameters {
                shape: shape.to_string(),
                centre,
                spread,
            }
        };
        Some(Self {
            kind: kind.to_string(),
            variables: variables
                .iter()
                .map(|v| v.iter().map(set).collect())
                .collect(),
        })
    }
}

/// Conversion of one model's [`RlsState`] to and from [`ModelParameters`].
pub trait ModelStateIo: Sized {
    /// To plain data.
    fn to_parameters(&self, model: &str) -> ModelParameters;
    /// From plain data (sizes and algorithm checked here, values by the core's `import`).
    fn from_parameters(p: &ModelParameters) -> Result<Self, ParametersError>;
}

impl<const N: usize, const NP: usize> ModelStateIo for RlsState<f32, N, NP> {
    fn to_parameters(&self, model: &str) -> ModelParameters {
        ModelParameters {
            model: model.to_string(),
            algorithm: match self.algorithm {
                Algorithm::Covariance => "covariance",
                Algorithm::UdFactor => "ud",
            }
            .to_string(),
            theta: self.theta.to_vec(),
            factor: self.factor.to_vec(),
            updates: self.updates,
            rule_updates: Vec::new(),
            premise: None,
        }
    }

    fn from_parameters(p: &ModelParameters) -> Result<Self, ParametersError> {
        let algorithm = match p.algorithm.as_str() {
            "covariance" => Algorithm::Covariance,
            "ud" => Algorithm::UdFactor,
            other => {
                return Err(ParametersError::UnknownAlgorithm {
                    model: p.model.clone(),
                    algorithm: other.to_string(),
                })
            }
        };
        Ok(Self {
            algorithm,
            theta: sized(p, &p.theta, "parameters")?,
            factor: sized(p, &p.factor, "covariance entries")?,
            updates: p.updates,
        })
    }
}

/// `values` as an array of this model's size `M`; `what` they are, for the error.
fn sized<const M: usize>(
    p: &ModelParameters,
    values: &[f32],
    what: &'static str,
) -> Result<[f32; M], ParametersError> {
    values.try_into().map_err(|_| ParametersError::Length {
        model: p.model.clone(),
        what,
        found: values.len(),
        expected: M,
    })
}

/// A locally learnt model: every rule's θ_i and factor one after another (rule-major), and
/// each rule's update count in `rule_updates`.
impl<const R: usize, const D: usize, const DP: usize> ModelStateIo for [RlsState<f32, D, DP>; R] {
    fn to_parameters(&self, model: &str) -> ModelParameters {
        let mut p = ModelParameters {
            model: model.to_string(),
            algorithm: String::new(),
            theta: Vec::new(),
            factor: Vec::new(),
            updates: 0,
            rule_updates: Vec::new(),
            premise: None,
        };
        for rule in self {
            let one = rule.to_parameters(model);
            p.algorithm = one.algorithm;
            p.theta.extend(one.theta);
            p.factor.extend(one.factor);
            p.updates = p.updates.wrapping_add(one.updates);
            p.rule_updates.push(one.updates);
        }
        p
    }

    fn from_parameters(p: &ModelParameters) -> Result<Self, ParametersError> {
        let layout = || ParametersError::RuleLayout {
            model: p.model.clone(),
            theta: p.theta.len(),
            factor: p.factor.len(),
            rule_counts: p.rule_updates.len(),
            rules: R,
            per_rule: D,
            factor_per_rule: DP,
        };
        if p.theta.len() != R * D || p.factor.len() != R * DP || p.rule_updates.len() != R {
            return Err(layout());
        }
        let mut out = Vec::with_capacity(R);
        for i in 0..R {
            let one = ModelParameters {
                model: p.model.clone(),
                algorithm: p.algorithm.clone(),
                theta: p.theta[i * D..(i + 1) * D].to_vec(),
                factor: p.factor[i * DP..(i + 1) * DP].to_vec(),
                updates: p.rule_updates[i],
                rule_updates: Vec::new(),
                premise: None,
            };
            out.push(RlsState::<f32, D, DP>::from_parameters(&one)?);
        }
        // R states were pushed after the check above: cannot fail, but no panic either.
        out.try_into().map_err(|_| layout())
    }
}

/// Names of the four models in export order.
pub const MODEL_NAMES: [&str; 4] = ["velocity", "q", "r", "p"];

impl<V, Q, R, P> Identifier for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32> + Clone + 'static,
    Q: StateModel<f32> + Clone + 'static,
    R: StateModel<f32> + Clone + 'static,
    P: StateModel<f32> + Clone + 'static,
    V::State: ModelStateIo,
    Q::State: ModelStateIo,
    R::State: ModelStateIo,
    P::State: ModelStateIo,
{
    fn step(&mut self, sample: &HoverSample<f32>) -> Result<StepOutput<f32>, rotorid::Error> {
        HoverIdentifier::step(self, sample)
    }

    fn predict(&self, sample: &HoverSample<f32>) -> Result<HoverState<f32>, rotorid::Error> {
        HoverIdentifier::predict(self, sample)
    }

    fn predict_after(
        &self,
        before: Option<&HoverState<f32>>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error> {
        HoverIdentifier::predict_after(self, before, sample)
    }

    fn resume(&mut self, sample: &HoverSample<f32>) -> Result<HoverState<f32>, rotorid::Error> {
        HoverIdentifier::resume(self, sample)
    }

    fn boxed_clone(&self) -> Box<dyn Identifier> {
        Box::new(self.clone())
    }

    fn compensate(&mut self, gyro_noise: &[f32; 3]) -> Result<Compensation, rotorid::Error> {
        HoverIdentifier::compensate(self, gyro_noise)
    }

    fn observe(
        &self,
        observer: &mut Observer<f32>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error> {
        observer.predict(self, sample)
    }

    fn search_gain(
        &self,
        search: &mut ObserverSearch,
        sample: &HoverSample<f32>,
    ) -> Result<(), rotorid::Error> {
        search.push(self, sample)
    }

    fn parameters(&self) -> Vec<ModelParameters> {
        let s = self.export();
        let with = |mut p: ModelParameters, premise| {
            p.premise = premise;
            p
        };
        vec![
            with(
                s.velocity.to_parameters(MODEL_NAMES[0]),
                PremiseParameters::of(self.velocity_model()),
            ),
            with(
                s.pitch.to_parameters(MODEL_NAMES[1]),
                PremiseParameters::of(self.pitch_model()),
            ),
            with(
                s.yaw.to_parameters(MODEL_NAMES[2]),
                PremiseParameters::of(self.yaw_model()),
            ),
            with(
                s.roll.to_parameters(MODEL_NAMES[3]),
                PremiseParameters::of(self.roll_model()),
            ),
        ]
    }

    fn load(&mut self, parameters: &[ModelParameters]) -> Result<(), ParametersError> {
        let find = |name: &'static str| {
            parameters
                .iter()
                .find(|p| p.model == name)
                .ok_or(ParametersError::MissingModel(name))
        };
        let snapshot = HoverSnapshot {
            velocity: V::State::from_parameters(find(MODEL_NAMES[0])?)?,
            pitch: Q::State::from_parameters(find(MODEL_NAMES[1])?)?,
            yaw: R::State::from_parameters(find(MODEL_NAMES[2])?)?,
            roll: P::State::from_parameters(find(MODEL_NAMES[3])?)?,
        };
        self.import(&snapshot).map_err(ParametersError::Rejected)
    }
}

/// `config` at the sample period `period_us` (µs), with the same ±50 % tolerance as the
/// defaults' 20 ms ± 10 ms.
pub fn at(config: HoverConfig<f32>, period_us: u32) -> HoverConfig<f32> {
    HoverConfig {
        sample_period_us: period_us,
        period_tolerance_us: period_us / 2,
        ..config
    }
}

/// Builds a fresh identifier from the training logs (which only variants that place their
/// premise sets from data read) at a sample period (µs).
pub type BuildFn = fn(&[Vec<HoverSample<f32>>], u32) -> Result<Box<dyn Identifier>, rotorid::Error>;

/// A named identifier configuration to evaluate. Adding a variant is one entry in
/// [`variants`].
#[derive(Clone, Copy)]
pub struct Variant {
    /// Name used in tables, JSON and file names.
    pub name: &'static str,
    /// One-line description for reports.
    pub description: &'static str,
    /// A fresh (untrained) identifier; given the training logs for variants that place their
    /// premise sets from data.
    pub build: BuildFn,
}

impl std::fmt::Debug for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Variant").field("name", &self.name).finish()
    }
}

/// The identifier variants the report compares. The first two are Table 4's columns.
pub fn variants() -> Vec<Variant> {
    vec![
        Variant {
            name: "paper fuzzy",
            description:
                "Eqs. 27-30 with Table 3's sets (27+18+9+9 rules), U-D RLS, λ = 1, α = 1e6, unscaled",
            build: |_, period| {
                Ok(Box::new(PaperFuzzyIdentifier::<f32>::paper_fuzzy(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "paper plain",
            description: "Eqs. 19 and 26 (one rule per model), U-D RLS, λ = 1, α = 1e6, unscaled",
            build: |_, period| {
                Ok(Box::new(PaperPlainIdentifier::<f32>::paper_plain(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "extended fuzzy",
            description: "rates + damping, collective torque, trim (Table 3 sets, 18+9+9 rules); velocity + drag, tail-rotor side force (v_y sets, 3 rules); U-D RLS, helicopter scaling",
            build: |_, period| {
                Ok(Box::new(ExtendedFuzzyIdentifier::<f32>::extended_fuzzy(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "extended plain",
            description: "the extended terms with one rule per model; U-D RLS, helicopter scaling",
            build: |_, period| {
                Ok(Box::new(ExtendedPlainIdentifier::<f32>::extended_plain(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "paper local",
            description: "paper fuzzy's structure and Table 3 sets, each rule its own weighted RLS (local learning)",
            build: |_, period| {
                Ok(Box::new(PaperLocalIdentifier::<f32>::paper_local(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "extended local",
            description: "extended fuzzy's structure and sets, each rule its own weighted RLS (local learning)",
            build: |_, period| {
                Ok(Box::new(ExtendedLocalIdentifier::<f32>::extended_local(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "flight",
            description: "the flight default (FlightIdentifier): extended terms + speed and second-order rate terms, 3 rules per model on forward speed (0, 5, 10 m/s, σ 2.5), local learning, helicopter scaling",
            build: |_, period| {
                Ok(Box::new(FlightIdentifier::<f32>::flight(
                    at(HoverConfig::default(), period),
                    flight_sets(),
                )?))
            },
        },
        Variant {
            name: "flight plain",
            description: "the flight default's terms (incl. speed and second-order rate terms) with one rule per model: what the rules add",
            build: |_, period| {
                Ok(Box::new(FlightPlainIdentifier::<f32>::flight_plain(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "flight extended velocity",
            description: "the flight default with the extended structure's translational model (VelocityStructure::Extended: drag in inertial axes on the sample's own velocity, thrust proportional to the collective): what the flight structure's translational terms add",
            build: |_, period| Ok(Box::new(flight_with_extended_velocity(period)?)),
        },
        Variant {
            name: "flight first-order rates",
            description: "the flight default with the rate models' second-order term held at zero (each rule's η pinned by a zero prior variance): what that term buys in free run and costs at one step",
            build: |_, period| Ok(Box::new(flight_with_first_order_rates(period)?)),
        },
        Variant {
            name: "flight proportional thrust",
            description: "the flight default with the translational model's thrust at zero collective held at zero (each rule's α0 pinned by a zero prior variance): the thrust proportional to the collective, as in Eq. 27; what the affine thrust buys",
            build: |_, period| Ok(Box::new(flight_with_proportional_thrust(period)?)),
        },
        Variant {
            name: "flight yaw on side speed",
            description: "the flight default with its yaw model scheduled on forward and side speed (3 x 3 rules; side sets at -5, 0, 5 m/s, σ 2.5): whether the yaw trim in sideways flight is a matter of scheduling",
            build: |_, period| Ok(Box::new(flight_with_side_speed_yaw(period)?)),
        },
        Variant {
            name: "flight data sets",
            description: "the flight default with its forward-speed sets placed at the training data's quantiles (noise floor 3σ_n)",
            build: |training, period| {
                Ok(Box::new(FlightIdentifier::<f32>::flight(
                    at(HoverConfig::default(), period),
                    forward_speed_sets(training)?,
                )?))
            },
        },
    ]
}

/// [`FlightIdentifier`] with the extended structure's translational model (7 terms; see
/// [`flight_with_extended_velocity`]).
type ExtendedVelocityIdentifier = HoverIdentifier<
    f32,
    LocalVelocityModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
>;

/// [`FlightIdentifier`] whose translational model has the extended structure
/// (`VelocityStructure::Extended`: drag per inertial axis, thrust proportional to the
/// collective) instead of the flight structure (drag along and across the heading, thrust
/// affine in the collective); the same premise, sets, rate models and settings.
fn flight_with_extended_velocity(
    period: u32,
) -> Result<ExtendedVelocityIdentifier, rotorid::Error> {
    let config = at(HoverConfig::default(), period);
    let flight = FlightIdentifier::<f32>::flight(config, flight_sets())?;
    let structure = VelocityStructure::Extended;
    let velocity = LocalVelocityModel::<f32, 3, 7, 28>::with_scaling(
        flight.velocity_model().ts().rules().clone(),
        structure,
        Premise::HeadingVelocity,
        config.rls,
        structure.helicopter_scaling(),
    )?;
    HoverIdentifier::new(
        velocity,
        flight.pitch_model().clone(),
        flight.yaw_model().clone(),
        flight.roll_model().clone(),
        config,
    )
}

/// [`FlightIdentifier`] whose rate models learn without their second-order term `η Δω(k)`
/// (index 6 of [`RateStructure::Flight`]'s terms; see [`pin_to_zero`]). Everything else is the
/// flight default's.
fn flight_with_first_order_rates(period: u32) -> Result<FlightIdentifier<f32>, rotorid::Error> {
    const SECOND_ORDER: usize = 6;
    let mut flight =
        FlightIdentifier::<f32>::flight(at(HoverConfig::default(), period), flight_sets())?;
    let mut snapshot = flight.export();
    for model in [&mut snapshot.pitch, &mut snapshot.yaw, &mut snapshot.roll] {
        pin_to_zero(model, SECOND_ORDER);
    }
    flight.import(&snapshot)?;
    Ok(flight)
}

/// [`FlightIdentifier`] whose translational model learns without the thrust at zero
/// collective `α0` (index 7 of [`VelocityStructure::Flight`]'s terms; see [`pin_to_zero`]): the
/// thrust proportional to the collective, as in Eq. 27. Everything else is the flight
/// default's.
fn flight_with_proportional_thrust(period: u32) -> Result<FlightIdentifier<f32>, rotorid::Error> {
    const AFFINE_THRUST: usize = 7;
    let mut flight =
        FlightIdentifier::<f32>::flight(at(HoverConfig::default(), period), flight_sets())?;
    let mut snapshot = flight.export();
    pin_to_zero(&mut snapshot.velocity, AFFINE_THRUST);
    flight.import(&snapshot)?;
    Ok(flight)
}

/// Sets each untrained rule's prior variance of parameter `term` to zero (the U-D factor's
/// `D_term`; U is still the identity, so nothing else changes). A parameter with zero variance
/// gets zero gain, so it stays exactly 0 and least squares fits the other terms as if it were
/// absent; its covariance with them stays zero, so the gyro-noise compensation leaves it at 0
/// too.
fn pin_to_zero<const D: usize, const DP: usize>(rules: &mut [RlsState<f32, D, DP>], term: usize) {
    // Packed upper triangle, column by column: entry (i, k) at k(k + 1)/2 + i.
    let diagonal = term * (term + 1) / 2 + term;
    for rule in rules {
        if let Some(d) = rule.factor.get_mut(diagonal) {
            *d = 0.0;
        }
    }
}

/// [`FlightIdentifier`] with a 9-rule yaw model (see [`flight_with_side_speed_yaw`]).
type SideSpeedYawIdentifier = HoverIdentifier<
    f32,
    LocalVelocityModel<f32, 3, 8, 36>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 9, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
>;

/// [`FlightIdentifier`] whose yaw model is scheduled on the side speed too: the forward-speed
/// sets times three side-speed sets (left shoulder at −5 m/s, Gaussian at 0, right shoulder at
/// 5 m/s, σ = 2.5 m/s: the forward sets' spacing and spread), 9 rules learnt locally; the
/// other models, the terms and the settings are the flight default's.
fn flight_with_side_speed_yaw(period: u32) -> Result<SideSpeedYawIdentifier, rotorid::Error> {
    let config = at(HoverConfig::default(), period);
    let flight = FlightIdentifier::<f32>::flight(config, flight_sets())?;
    let side = rotorid::hover::table3::three_sets((-5.0, 2.5), (0.0, 2.5), (5.0, 2.5));
    let rules = RuleBase::new([flight_sets(), side, PremiseSets::new()])?;
    let structure = RateStructure::Flight;
    let yaw = LocalRateModel::<f32, 9, 7, 28>::with_scaling(
        RateAxis::Yaw,
        rules,
        structure,
        Premise::HeadingVelocity,
        config.rls,
        structure.helicopter_scaling(RateAxis::Yaw),
    )?;
    HoverIdentifier::new(
        flight.velocity_model().clone(),
        flight.pitch_model().clone(),
        yaw,
        flight.roll_model().clone(),
        config,
    )
}

/// The forward-speed sets of the flight identifier placed from training logs
/// ([`rotorid::premise::quantile_sets`], three sets; noise from the first log's first
/// differences). The core's [`flight_sets`] when there are too few samples.
pub fn forward_speed_sets(
    training: &[Vec<HoverSample<f32>>],
) -> Result<rotorid::rule_base::PremiseSets<f32>, rotorid::Error> {
    let forward = |s: &HoverSample<f32>| {
        let frame = BodyFrame::of(&s.attitude);
        Premise::HeadingVelocity.of(s, &frame)[0]
    };
    let mut values: Vec<f32> = training.iter().flatten().map(forward).collect();
    let first: Vec<f32> = training
        .first()
        .map_or_else(Vec::new, |l| l.iter().map(forward).collect());
    let mut scratch = vec![0.0f32; first.len()];
    match rotorid::premise::noise_std(&first, &mut scratch) {
        Some(noise) if !values.is_empty() => rotorid::premise::quantile_sets(&mut values, 3, noise),
        _ => Ok(flight_sets()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first-order variant's rate models learn every term but η, which stays exactly 0
    /// with zero variance, while the flight default learns an η on the same flight.
    #[test]
    fn first_order_rates_hold_eta_at_zero_and_learn_the_rest() {
        let log = rotorid_sim::flights::identification_flight_for(1, 20.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let mut pinned = flight_with_first_order_rates(20_000).unwrap();
        let mut flight =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        for s in &samples {
            pinned.step(s).unwrap();
            flight.step(s).unwrap();
        }
        let (p, f) = (pinned.export(), flight.export());
        let diagonal = 6 * 7 / 2 + 6;
        for (pm, fm) in [(&p.pitch, &f.pitch), (&p.yaw, &f.yaw), (&p.roll, &f.roll)] {
            // The hover rule fires on this flight: it learns.
            let (hover, flight_hover) = (&pm[0], &fm[0]);
            assert_eq!(hover.theta[6].to_bits(), 0.0f32.to_bits());
            assert_eq!(hover.factor[diagonal].to_bits(), 0.0f32.to_bits());
            assert!(hover.updates > 0);
            assert!(
                hover.theta[..6].iter().all(|&t| t != 0.0),
                "{:?}",
                hover.theta
            );
            assert_ne!(flight_hover.theta[6], 0.0);
            for rule in pm {
                assert_eq!(rule.theta[6].to_bits(), 0.0f32.to_bits());
            }
        }
        // The velocity model is the flight default's, bit for bit.
        assert_eq!(p.velocity, f.velocity);
    }

    #[test]
    fn parameter_export_carries_the_premise_sets_and_reads_back() {
        let id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        let params = Identifier::parameters(&id);
        for p in &params {
            let premise = p.premise.as_ref().expect("three rules per model");
            assert_eq!(premise.kind, "heading-velocity");
            let shapes: Vec<(&str, f32, f32)> = premise.variables[0]
                .iter()
                .map(|s| (s.shape.as_str(), s.centre, s.spread))
                .collect();
            assert_eq!(
                shapes,
                [
                    ("left", 0.0, 2.5),
                    ("gaussian", 5.0, 2.5),
                    ("right", 10.0, 2.5)
                ]
            );
            assert!(premise.variables[1].is_empty() && premise.variables[2].is_empty());
        }
        // The JSON round trip keeps them, and a warm start still loads the states.
        let json = serde_json::to_string(&params).unwrap();
        let back: Vec<ModelParameters> = serde_json::from_str(&json).unwrap();
        assert_eq!(back, params);
        let mut fresh =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        fresh.load(&back).unwrap();
        // A one-rule model writes none.
        let plain = FlightPlainIdentifier::<f32>::flight_plain(HoverConfig::default()).unwrap();
        assert!(Identifier::parameters(&plain)
            .iter()
            .all(|p| p.premise.is_none()));
    }

    #[test]
    fn parameters_that_do_not_fit_are_typed_errors_and_load_nothing() {
        let mut id =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        let before = Identifier::parameters(&id);
        assert_eq!(
            id.load(&[]),
            Err(ParametersError::MissingModel(MODEL_NAMES[0]))
        );
        let plain = FlightPlainIdentifier::<f32>::flight_plain(HoverConfig::default()).unwrap();
        assert!(matches!(
            id.load(&Identifier::parameters(&plain)),
            Err(ParametersError::RuleLayout { rules: 3, .. } | ParametersError::Length { .. })
        ));
        // The velocity model would fit; the q model's algorithm does not: nothing is loaded.
        let mut odd = before.clone();
        odd[1].algorithm = "kalman".to_string();
        assert!(matches!(
            id.load(&odd),
            Err(ParametersError::UnknownAlgorithm { ref algorithm, .. }) if algorithm == "kalman"
        ));
        let mut bad = before.clone();
        bad[0].theta[0] = f32::NAN;
        assert!(matches!(id.load(&bad), Err(ParametersError::Rejected(_))));
        assert_eq!(Identifier::parameters(&id), before);
    }
}
