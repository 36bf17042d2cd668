//! The flight default as the term selection leaves it ([`SelectedFlight`]).
//!
//! The rules and terms the selection switches off live in the identifier itself (sets that
//! fire one rule, zero prior variances), so its exported state carries them. The gyro-noise
//! compensation chosen per rate does not: it is not what the identifier learns but which
//! parameters are flown from what it learnt ([`HoverIdentifier::compensate_each`]), so it
//! is kept beside the identifier, and the tool asks for it ([`Identifier::compensation`])
//! wherever it compensates.
//!
//! [`HoverIdentifier::compensate_each`]: rotorid::HoverIdentifier::compensate_each

use rotorid::hover::{
    GyroCompensation, HoverConfig, HoverSample, HoverState, Observer, StepOutput,
};
use rotorid::rls::Compensation;
use rotorid::snapshot::WriteError;
use rotorid::{DynIdentifier, FlightIdentifier};

use super::error::ParametersError;
use super::selection::{masked_flight, TermMask};
use super::variants::{Identifier, ModelParameters, ObserverSearch};

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
