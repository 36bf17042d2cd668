//! The term mask ([`TermMask`]): which rules and terms of the flight default are switched
//! off, and the identifier it leaves ([`masked_flight`], [`SelectedFlight`]).
//!
//! The rules and terms a mask switches off live in the identifier itself (sets that fire one
//! rule, zero prior variances, [`pin_to_zero`]), so its exported state carries them and
//! [`TermMask::of_parameters`] reads them back. The gyro-noise compensation chosen per rate
//! does not: it is not what the identifier learns but which parameters are flown from what
//! it learnt ([`HoverIdentifier::compensate_each`]), so [`SelectedFlight`] keeps it beside
//! the identifier, and the tool asks for it ([`Identifier::compensation`]) wherever it
//! compensates. Which mask a helicopter's data support is the selection's business
//! (`selection.rs`).
//!
//! [`HoverIdentifier::compensate_each`]: rotorid::HoverIdentifier::compensate_each

use rotorid::hover::{
    flight_sets, table3, unscheduled_sets, GyroCompensation, HoverConfig, HoverSample, HoverState,
    Observer, RateStructure, Scheduling, StepOutput, VelocityStructure,
};
use rotorid::rls::{Compensation, RlsState};
use rotorid::snapshot::WriteError;
use rotorid::{DynIdentifier, FlightIdentifier};
use serde::{Deserialize, Serialize};

use super::error::ParametersError;
use super::variants::{at, Identifier, ModelParameters, ObserverSearch};

/// The models in [`TermMask`] order, as named in `params-*.json`.
pub const MODELS: [&str; 4] = ["velocity", "q", "r", "p"];

/// Names of [`VelocityStructure::Flight`]'s terms, in θ order.
pub const VELOCITY_TERMS: [&str; 8] = ["α1", "α2", "d_f", "d_r", "d_u", "σ0", "σ1", "α0"];
/// Names of [`RateStructure::Flight`]'s terms in θ order (for r̂ the first is `𝕀|v|`).
pub const RATE_TERMS: [&str; 7] = ["𝕀", "γ", "δ", "β", "c", "κ", "η"];

/// Which terms of each model are switched off: bit `i` of `off[m]` is term `i` of model
/// `MODELS[m]`; which models have one rule instead of three, and which are scheduled on
/// another speed than the flight default's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TermMask {
    /// Per model, the bits of the terms that are off.
    pub off: [u8; 4],
    /// Per model, whether its rules are off: one rule, not scheduled on the speed
    /// ([`unscheduled_sets`]).
    #[serde(default)]
    pub one_rule: [bool; 4],
    /// Per model, whether its free run and observer fly the parameters compensated for the
    /// gyro noise fully ([`GyroCompensation::Full`]: the second-order term's noise too)
    /// rather than the damping term's alone (only the rate models'; the velocity's is always
    /// false).
    #[serde(default)]
    pub full_compensation: [bool; 4],
    /// Per model, the speed its three rules are scheduled on when it is not the flight
    /// default's (`None`; `flight selected`'s premise candidates).
    #[serde(default)]
    pub schedule: [Option<Schedule>; 4],
}

/// A model's three rules on another speed than the flight default's
/// ([`FlightIdentifier::flight_scheduled`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// The speed.
    pub on: ScheduledOn,
    /// `(centre, spread)` (m/s) of its left shoulder, Gaussian and right shoulder.
    pub sets: [(f32, f32); 3],
}

/// The speeds [`Schedule`] can name (the core's [`Scheduling`] other than the default).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScheduledOn {
    /// The rightward speed in the heading frame (rate models only).
    SideSpeed,
    /// The vertical speed, up.
    VerticalSpeed,
}

impl ScheduledOn {
    /// The core's choice.
    pub fn scheduling(self) -> Scheduling {
        match self {
            Self::SideSpeed => Scheduling::SideSpeed,
            Self::VerticalSpeed => Scheduling::VerticalSpeed,
        }
    }

    /// As [`TermMask::describe`] names it.
    pub fn name(self) -> &'static str {
        match self {
            Self::SideSpeed => "side speed",
            Self::VerticalSpeed => "vertical speed",
        }
    }

    /// The one that schedules on premise variable `variable` of model `model`'s premise
    /// (`[|v_h| up 0]` for the velocity, `[forward right up]` for the rates).
    fn of_variable(model: usize, variable: usize) -> Option<Self> {
        [Self::SideSpeed, Self::VerticalSpeed]
            .into_iter()
            .find(|on| on.scheduling().variable(model > 0) == Some(variable))
    }
}

impl TermMask {
    /// Whether term `term` of model `model` is off.
    pub fn is_off(&self, model: usize, term: usize) -> bool {
        self.off
            .get(model)
            .is_some_and(|bits| bits >> term & 1 == 1)
    }

    /// This mask with term `term` of model `model` off as well.
    pub(super) fn without(mut self, model: usize, term: usize) -> Self {
        if let Some(bits) = self.off.get_mut(model) {
            *bits |= 1 << term;
        }
        self
    }

    /// This mask with model `model`'s rules off (one rule).
    pub(super) fn with_one_rule(mut self, model: usize) -> Self {
        if let Some(one) = self.one_rule.get_mut(model) {
            *one = true;
        }
        self
    }

    /// This mask with model `model`'s rules on `schedule`'s speed.
    pub(super) fn scheduled(mut self, model: usize, schedule: Schedule) -> Self {
        if let Some(s) = self.schedule.get_mut(model) {
            *s = Some(schedule);
        }
        self
    }

    /// Whether model `model` has one rule.
    pub fn has_one_rule(&self, model: usize) -> bool {
        self.one_rule.get(model).copied().unwrap_or(false)
    }

    /// This mask with model `model`'s gyro noise compensated fully.
    pub(super) fn with_full_compensation(mut self, model: usize) -> Self {
        if let Some(full) = self.full_compensation.get_mut(model) {
            *full = true;
        }
        self
    }

    /// The compensation of each rate `[q r p]` ([`HoverIdentifier::compensate_each`]'s order).
    ///
    /// [`HoverIdentifier::compensate_each`]: rotorid::HoverIdentifier::compensate_each
    pub fn compensation(&self) -> [GyroCompensation; 3] {
        // The rate models are models 1, 2, 3 in [`MODELS`]: q, r, p.
        core::array::from_fn(|axis| match self.full_compensation.get(axis + 1) {
            Some(true) => GyroCompensation::Full,
            _ => GyroCompensation::Damping,
        })
    }

    /// The names of the terms that are off, per model (`"r: 𝕀|v|"`, …), a model with one rule
    /// first as `"p: rules"`.
    pub fn describe(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (m, model) in MODELS.iter().enumerate() {
            if self.has_one_rule(m) {
                out.push(format!("{model}: rules"));
            } else if let Some(Some(s)) = self.schedule.get(m) {
                out.push(format!("{model}: rules on the {}", s.on.name()));
            }
            let names: &[&str] = if m == 0 { &VELOCITY_TERMS } else { &RATE_TERMS };
            for (t, name) in names.iter().enumerate() {
                if self.is_off(m, t) {
                    let name = if m == 2 && t == 0 { "𝕀|v|" } else { name };
                    out.push(format!("{model}: {name}"));
                }
            }
        }
        out
    }

    /// The mask a flight identifier's exported parameters carry: a term is off when every
    /// rule's prior variance of it is exactly zero (learning never makes a positive variance
    /// zero); a model has one rule when its sets are [`unscheduled_sets`]. Empty for
    /// parameters that are not the flight structure's.
    pub fn of_parameters(parameters: &[ModelParameters]) -> Self {
        let mut mask = Self::default();
        let unscheduled = super::variants::PremiseParameters::sets_of(&unscheduled_sets::<f32>());
        for (m, p) in parameters.iter().enumerate().take(4) {
            if p.premise.as_ref().and_then(|q| q.variables.first()) == Some(&unscheduled) {
                mask = mask.with_one_rule(m);
            }
            if let Some(schedule) = p.premise.as_ref().and_then(|q| Schedule::of(m, q)) {
                mask = mask.scheduled(m, schedule);
            }
            let d = if m == 0 {
                VELOCITY_TERMS.len()
            } else {
                RATE_TERMS.len()
            };
            let per_rule = d * (d + 1) / 2;
            if p.factor.is_empty() || p.factor.len() % per_rule != 0 {
                continue;
            }
            for t in 0..d {
                let diagonal = t * (t + 1) / 2 + t;
                let off = p
                    .factor
                    .chunks(per_rule)
                    .all(|rule| rule.get(diagonal).is_some_and(|&v| v == 0.0));
                if off {
                    mask = mask.without(m, t);
                }
            }
        }
        mask
    }
}

impl Schedule {
    /// The schedule a model's written premise shows: its three sets on another variable than
    /// the first (`None` for the flight default's, or sets that are not three shoulders and a
    /// Gaussian).
    fn of(model: usize, premise: &super::variants::PremiseParameters) -> Option<Self> {
        let (variable, sets) = premise
            .variables
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_empty())?;
        let on = ScheduledOn::of_variable(model, variable)?;
        let [l, c, r] = sets.as_slice() else {
            return None;
        };
        if [l, c, r].map(|s| s.shape.as_str()) != ["left", "gaussian", "right"] {
            return None;
        }
        Some(Self {
            on,
            sets: [l, c, r].map(|s| (s.centre, s.spread)),
        })
    }
}

/// Sets each untrained rule's prior variance of parameter `term` to zero (the U-D factor's
/// `D_term`; U is still the identity, so nothing else changes). A parameter with zero variance
/// gets zero gain, so it stays exactly 0 and least squares fits the other terms as if it were
/// absent; its covariance with them stays zero, so the gyro-noise compensation leaves it at 0
/// too.
pub fn pin_to_zero<const D: usize, const DP: usize>(
    rules: &mut [RlsState<f32, D, DP>],
    term: usize,
) {
    // Packed upper triangle, column by column: entry (i, k) at k(k + 1)/2 + i.
    let diagonal = term * (term + 1) / 2 + term;
    for rule in rules {
        if let Some(d) = rule.factor.get_mut(diagonal) {
            *d = 0.0;
        }
    }
}

/// A fresh flight default (the core's [`FlightIdentifier::flight`] at `period_us`) with the
/// terms of `mask` pinned at zero.
pub fn masked_flight(
    mask: TermMask,
    period_us: u32,
) -> Result<FlightIdentifier<f32>, rotorid::Error> {
    // A model with one rule is not scheduled at all, whatever its schedule says.
    let schedule = |m: usize| mask.schedule[m].filter(|_| !mask.has_one_rule(m));
    let sets = core::array::from_fn(|m| match schedule(m) {
        Some(Schedule {
            sets: [l, c, r], ..
        }) => {
            let wide = |(c, s): (f32, f32)| (f64::from(c), f64::from(s));
            table3::three_sets(wide(l), wide(c), wide(r))
        }
        None if mask.has_one_rule(m) => unscheduled_sets(),
        None => flight_sets(),
    });
    let on = core::array::from_fn(|m| schedule(m).map_or(Scheduling::Speed, |s| s.on.scheduling()));
    // With the speed four times this is `flight_per_model`, bit for bit (core's tests).
    let mut flight =
        FlightIdentifier::<f32>::flight_scheduled(at(HoverConfig::default(), period_us), sets, on)?;
    if mask.off == [0; 4] {
        return Ok(flight);
    }
    let mut snapshot = flight.export();
    for t in 0..VelocityStructure::Flight.terms() {
        if mask.is_off(0, t) {
            pin_to_zero(&mut snapshot.velocity, t);
        }
    }
    let rates = [&mut snapshot.pitch, &mut snapshot.yaw, &mut snapshot.roll];
    for (m, rules) in rates.into_iter().enumerate() {
        for t in 0..RateStructure::Flight.terms() {
            if mask.is_off(m + 1, t) {
                pin_to_zero(rules, t);
            }
        }
    }
    flight.import(&snapshot)?;
    Ok(flight)
}

/// A fresh flight default with the rules and terms of a [`TermMask`] switched off and the
/// mask's compensation per rate: every call is the flight identifier's, and
/// [`Identifier::compensation`] is [`GyroCompensation::Full`] on the rates the mask chose it
/// for.
#[derive(Clone, Debug)]
pub struct SelectedFlight {
    id: FlightIdentifier<f32>,
    compensation: [GyroCompensation; 3],
}

impl SelectedFlight {
    /// The flight default at `period_us` as `mask` says ([`masked_flight`]).
    pub fn new(mask: TermMask, period_us: u32) -> Result<Self, rotorid::Error> {
        Ok(Self {
            id: masked_flight(mask, period_us)?,
            compensation: mask.compensation(),
        })
    }
}

impl DynIdentifier for SelectedFlight {
    fn step(&mut self, sample: &HoverSample<f32>) -> Result<StepOutput<f32>, rotorid::Error> {
        self.id.step(sample)
    }
    fn predict_after(
        &self,
        before: Option<&HoverState<f32>>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error> {
        self.id.predict_after(before, sample)
    }
    fn resume(&mut self, sample: &HoverSample<f32>) -> Result<HoverState<f32>, rotorid::Error> {
        self.id.resume(sample)
    }
    fn compensate_each(
        &mut self,
        gyro_noise: &[f32; 3],
        how: [GyroCompensation; 3],
    ) -> Result<Compensation, rotorid::Error> {
        self.id.compensate_each(gyro_noise, how)
    }
    fn reset(&mut self) {
        self.id.reset()
    }
    fn config(&self) -> HoverConfig<f32> {
        self.id.config()
    }
    fn snapshot_size(&self) -> usize {
        <FlightIdentifier<f32> as DynIdentifier>::snapshot_size(&self.id)
    }
    fn write_snapshot(&self, kind: u32, out: &mut [u8]) -> Result<usize, WriteError> {
        <FlightIdentifier<f32> as DynIdentifier>::write_snapshot(&self.id, kind, out)
    }
    fn read_snapshot(&mut self, kind: u32, bytes: &[u8]) -> Result<(), rotorid::Error> {
        <FlightIdentifier<f32> as DynIdentifier>::read_snapshot(&mut self.id, kind, bytes)
    }
    fn config_hash(&self) -> u32 {
        <FlightIdentifier<f32> as DynIdentifier>::config_hash(&self.id)
    }
}

impl Identifier for SelectedFlight {
    /// Full where either the mask or `how` says so.
    fn compensation(&self, how: GyroCompensation) -> [GyroCompensation; 3] {
        core::array::from_fn(|axis| match self.compensation.get(axis) {
            Some(GyroCompensation::Full) => GyroCompensation::Full,
            _ => how,
        })
    }
    fn boxed_clone(&self) -> Box<dyn Identifier> {
        Box::new(self.clone())
    }
    fn parameters(&self) -> Vec<ModelParameters> {
        self.id.parameters()
    }
    fn load(&mut self, parameters: &[ModelParameters]) -> Result<(), ParametersError> {
        self.id.load(parameters)
    }
    fn observe(
        &self,
        observer: &mut Observer<f32>,
        sample: &HoverSample<f32>,
    ) -> Result<HoverState<f32>, rotorid::Error> {
        self.id.observe(observer, sample)
    }
    fn search_gain(
        &self,
        search: &mut ObserverSearch,
        sample: &HoverSample<f32>,
    ) -> Result<(), rotorid::Error> {
        self.id.search_gain(search, sample)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_name_their_terms_and_read_back_from_parameters() {
        let mask = TermMask::default()
            .without(0, 7)
            .without(2, 0)
            .with_one_rule(2)
            .without(3, 6);
        assert_eq!(
            mask.describe(),
            ["velocity: α0", "r: rules", "r: 𝕀|v|", "p: η"]
        );
        let id = masked_flight(mask, 20_000).unwrap();
        let params = Identifier::parameters(&id);
        assert_eq!(TermMask::of_parameters(&params), mask);
        let full = masked_flight(TermMask::default(), 20_000).unwrap();
        assert_eq!(
            TermMask::of_parameters(&Identifier::parameters(&full)),
            TermMask::default()
        );
    }

    /// A model scheduled on another speed: the exported parameters carry its sets on that
    /// premise variable, the mask reads back from them bit for bit, and it is named; the
    /// identifier is the core's `flight_scheduled`.
    #[test]
    fn schedules_are_carried_by_the_parameters_and_named() {
        use rotorid::hover::StateModel;
        let side = Schedule {
            on: ScheduledOn::SideSpeed,
            sets: [(-1.5, 0.75), (0.0, 0.75), (1.25, 0.625)],
        };
        let vertical = Schedule {
            on: ScheduledOn::VerticalSpeed,
            sets: [(-0.5, 0.25), (0.0, 0.25), (0.5, 0.25)],
        };
        let mask = TermMask::default()
            .scheduled(0, vertical)
            .scheduled(2, side)
            .without(2, 0)
            .scheduled(3, vertical);
        assert_eq!(
            mask.describe(),
            [
                "velocity: rules on the vertical speed",
                "r: rules on the side speed",
                "r: 𝕀|v|",
                "p: rules on the vertical speed"
            ]
        );
        let id = masked_flight(mask, 20_000).unwrap();
        assert_eq!(TermMask::of_parameters(&Identifier::parameters(&id)), mask);
        // The yaw model's sets are on the heading frame's second variable, the velocity's on
        // its second (up), the roll model's on its third (up).
        let (_, yaw) = id.yaw_model().premise_sets();
        assert!(yaw[0].is_empty() && yaw[1].len() == 3 && yaw[2].is_empty());
        let (_, velocity) = id.velocity_model().premise_sets();
        assert!(velocity[0].is_empty() && velocity[1].len() == 3);
        let (_, roll) = id.roll_model().premise_sets();
        assert!(roll[2].len() == 3);
        // The translational model has no side speed: refused, not scheduled elsewhere.
        let sideways = TermMask::default().scheduled(0, side);
        assert!(masked_flight(sideways, 20_000).is_err());
        // A schedule of a model with one rule is moot: the model is its one-rule form.
        let moot = TermMask::default().with_one_rule(1).scheduled(1, side);
        let one = TermMask::default().with_one_rule(1);
        assert!(
            masked_flight(moot, 20_000).unwrap().export()
                == masked_flight(one, 20_000).unwrap().export()
        );
    }

    #[test]
    fn the_masks_full_compensation_is_added_to_what_the_tool_asks() {
        use GyroCompensation::{Damping, Full};
        let mask = TermMask {
            full_compensation: [false, false, true, false],
            ..TermMask::default()
        };
        let selected = SelectedFlight::new(mask, 20_000).unwrap();
        assert_eq!(selected.compensation(Damping), [Damping, Full, Damping]);
        assert_eq!(selected.compensation(Full), [Full; 3]);
        // Any other identifier compensates every rate as asked.
        let flight = masked_flight(TermMask::default(), 20_000).unwrap();
        assert_eq!(flight.compensation(Damping), [Damping; 3]);
    }
}
