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
    flight_sets, unscheduled_sets, GyroCompensation, HoverConfig, HoverSample, HoverState,
    Observer, RateStructure, StepOutput, VelocityStructure,
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
/// `MODELS[m]`; and which models have one rule instead of three.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
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
    let sets = core::array::from_fn(|m| {
        if mask.has_one_rule(m) {
            unscheduled_sets()
        } else {
            flight_sets()
        }
    });
    let mut flight =
        FlightIdentifier::<f32>::flight_per_model(at(HoverConfig::default(), period_us), sets)?;
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
