//! The identifier variants the tool compares, behind one object-safe [`Identifier`] trait
//! with parameter export/import as plain data.

use rotorid::hover::{
    GainSearch, GyroCompensation, HoverConfig, HoverIdentifier, HoverSample, HoverSnapshot,
    HoverState, Observer, Premise, StateModel,
};
use rotorid::membership::MembershipFunction;
use rotorid::rls::{Algorithm, RlsState};
use rotorid::snapshot::Snapshot;
use rotorid::DynIdentifier;
use serde::{Deserialize, Serialize};

use super::error::ParametersError;

/// What the experiments need of an identifier: the core's dyn-compatible [`DynIdentifier`]
/// (step, prediction, resume, compensation, snapshots) and, on top of it, what needs `std` or
/// the observer: a boxed copy, parameters as plain data, observer predictions. Implemented for
/// every `HoverIdentifier<f32, …>` whose models hold [`RlsState`]s.
pub trait Identifier: DynIdentifier {
    /// A boxed copy (to verify a still-adapting copy next to the frozen one).
    fn boxed_clone(&self) -> Box<dyn Identifier>;
    /// θ and covariance factor of the four models (velocity, q̂, r̂, p̂), for warm start.
    fn parameters(&self) -> Vec<ModelParameters>;
    /// Warm start from [`parameters`](Self::parameters) output; on `Err` nothing changed.
    fn load(&mut self, parameters: &[ModelParameters]) -> Result<(), ParametersError>;
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
    /// The compensation of each rate `[q r p]` ([`DynIdentifier::compensate_each`]) when the
    /// tool is asked for `how`: `how` on every rate, unless the variant chose otherwise from
    /// its training data ([`SelectedFlight`](super::SelectedFlight)).
    fn compensation(&self, how: GyroCompensation) -> [GyroCompensation; 3] {
        [how; 3]
    }
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
    /// `rotorid_flight_sets_t` takes the speed sets the flight kinds' models share: those of
    /// `premise: "heading-velocity"` and `"horizontal-speed"`).
    /// Absent for a model with one rule.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub premise: Option<PremiseParameters>,
}

/// A model's premise and sets, as written next to its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PremiseParameters {
    /// `velocity` (`[v_x v_y v_z]`, m/s), `rates` (`[q r p]`, deg/s), `heading-velocity`
    /// (`[forward right up]`, m/s) or `horizontal-speed` (`[|v_h| up 0]`, m/s).
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
            Premise::HorizontalSpeed => "horizontal-speed",
            _ => "unknown",
        };
        Some(Self {
            kind: kind.to_string(),
            variables: variables.iter().map(|v| Self::sets_of(v)).collect(),
        })
    }

    /// One premise variable's sets, as written.
    pub fn sets_of(sets: &[MembershipFunction<f32>]) -> Vec<SetParameters> {
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
        sets.iter().map(set).collect()
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
    Self: Snapshot,
{
    fn boxed_clone(&self) -> Box<dyn Identifier> {
        Box::new(self.clone())
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
/// the catalogue (`catalogue.rs`).
#[derive(Clone, Copy)]
pub struct Variant {
    /// Name used in tables, JSON and file names.
    pub name: &'static str,
    /// One-line description for reports.
    pub description: &'static str,
    /// A fresh (untrained) identifier; given the training logs for variants that place their
    /// premise sets from data.
    pub build: BuildFn,
    /// The kind code of its identifier type ([`rotorid::snapshot::KindCode`], the C
    /// interface's `ROTORID_KIND_*`), under which its `snapshot-*.ridx` is written; `None`: a
    /// type no flight computer runs (no snapshot file).
    pub kind: Option<u32>,
}

impl std::fmt::Debug for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Variant").field("name", &self.name).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotorid::hover::flight_sets;
    use rotorid::{FlightIdentifier, FlightPlainIdentifier};

    /// The first-order variant's rate models learn every term but η, which stays exactly 0
    /// with zero variance, while the flight default learns an η on the same flight.
    #[test]
    fn parameter_export_carries_the_premise_sets_and_reads_back() {
        let id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        let params = Identifier::parameters(&id);
        for p in &params {
            let premise = p.premise.as_ref().expect("three rules per model");
            // The translational model on the horizontal speed, the rates on the forward speed.
            let kind = if p.model == "velocity" {
                "horizontal-speed"
            } else {
                "heading-velocity"
            };
            assert_eq!(premise.kind, kind, "{}", p.model);
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
