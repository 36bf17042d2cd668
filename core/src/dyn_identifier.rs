//! [`DynIdentifier`]: the calls every identifier kind answers, behind one pointer.
//!
//! The identifiers are distinct types ([`FlightIdentifier`](crate::FlightIdentifier),
//! [`ExtendedPlainIdentifier`](crate::ExtendedPlainIdentifier), …), each with its sizes fixed
//! at compile time. A caller that chooses the kind at run time (the C interface's handle, the
//! command-line tool's list of variants, a firmware that flies one of two models) needs those
//! types behind one pointer: `&mut dyn DynIdentifier`. No allocation is implied: the pointer can
//! be to a `static`, a stack value or a caller's storage.
//!
//! The trait is for `f32` identifiers, the type the snapshot format ([`crate::snapshot`]), the C
//! interface and the link carry. An `f64` identifier is used through its own type.

use crate::error::Error;
use crate::hover::{
    Attitude, AttitudeInput, GyroCompensation, HoverConfig, HoverIdentifier, HoverSample,
    HoverState, StateModel, StepOutput,
};
use crate::rls::Compensation;
use crate::snapshot::{Snapshot, WriteError};

/// An `f32` identifier of any kind, dyn-compatible: [`HoverIdentifier`]'s calls and the
/// snapshot's ([`Snapshot`]), for samples whose attitude comes as `A` (Euler angles by default;
/// [`AnyAttitude`](crate::hover::AnyAttitude) lets the caller choose per sample).
///
/// Implemented for every [`HoverIdentifier`] of `f32` whose models have a snapshot: the kinds of
/// [`crate::snapshot::KindCode`]. Each method is the inherent method or [`Snapshot`] method of
/// the same name, with its errors, and like them a call that fails changes nothing.
pub trait DynIdentifier<A: AttitudeInput<f32> = Attitude<f32>> {
    /// [`HoverIdentifier::step`]: learns from the previous sample to `sample`, predicts the
    /// next state.
    fn step(&mut self, sample: &HoverSample<f32, A>) -> Result<StepOutput<f32>, Error>;

    /// [`HoverIdentifier::predict_after`]: the one-step prediction after `sample`, given the
    /// state of the sample before it; changes nothing.
    fn predict_after(
        &self,
        before: Option<&HoverState<f32>>,
        sample: &HoverSample<f32, A>,
    ) -> Result<HoverState<f32>, Error>;

    /// [`HoverIdentifier::resume`]: starts a new sample chain at `sample` without learning.
    fn resume(&mut self, sample: &HoverSample<f32, A>) -> Result<HoverState<f32>, Error>;

    /// [`HoverIdentifier::compensate`]: the rate models' parameters with the bias of the gyros'
    /// white noise σ `[q r p]` (deg/s) removed.
    fn compensate(&mut self, gyro_noise: &[f32; 3]) -> Result<Compensation, Error> {
        self.compensate_with(gyro_noise, GyroCompensation::Damping)
    }

    /// [`HoverIdentifier::compensate_with`]: [`compensate`](Self::compensate), removing the
    /// noise `how` says on every rate.
    fn compensate_with(
        &mut self,
        gyro_noise: &[f32; 3],
        how: GyroCompensation,
    ) -> Result<Compensation, Error> {
        self.compensate_each(gyro_noise, [how; 3])
    }

    /// [`HoverIdentifier::compensate_each`]: [`compensate`](Self::compensate), removing on
    /// each rate `[q r p]` the noise its entry of `how` says.
    fn compensate_each(
        &mut self,
        gyro_noise: &[f32; 3],
        how: [GyroCompensation; 3],
    ) -> Result<Compensation, Error>;

    /// [`HoverIdentifier::reset`]: forgets everything learnt.
    fn reset(&mut self);

    /// [`HoverIdentifier::config`]: the settings.
    fn config(&self) -> HoverConfig<f32>;

    /// [`Snapshot::SNAPSHOT_SIZE`]: bytes of this identifier's snapshot.
    fn snapshot_size(&self) -> usize;

    /// [`Snapshot::write_snapshot`]: writes the snapshot of kind code `kind` into `out`,
    /// returns its length.
    fn write_snapshot(&self, kind: u32, out: &mut [u8]) -> Result<usize, WriteError>;

    /// [`Snapshot::read_snapshot`]: imports the snapshot `bytes` of kind code `kind`, every
    /// word checked before anything is written.
    fn read_snapshot(&mut self, kind: u32, bytes: &[u8]) -> Result<(), Error>;

    /// [`Snapshot::config_hash`]: the hash of what a snapshot must match to be read back.
    fn config_hash(&self) -> u32;

    /// With the `std` feature: the snapshot of kind code `kind` in a new `Vec`, for host
    /// programs that keep or send it: [`write_snapshot`](Self::write_snapshot) into a buffer
    /// of [`snapshot_size`](Self::snapshot_size) bytes, cut to the length written (which for
    /// the core's identifiers is that size: they cannot fail here).
    #[cfg(feature = "std")]
    fn snapshot_vec(&self, kind: u32) -> Result<std::vec::Vec<u8>, WriteError> {
        let mut out = std::vec![0u8; self.snapshot_size()];
        let n = self.write_snapshot(kind, &mut out)?;
        out.truncate(n);
        Ok(out)
    }
}

impl<A, V, Q, R, P> DynIdentifier<A> for HoverIdentifier<f32, V, Q, R, P>
where
    A: AttitudeInput<f32>,
    V: StateModel<f32>,
    Q: StateModel<f32>,
    R: StateModel<f32>,
    P: StateModel<f32>,
    Self: Snapshot,
{
    fn step(&mut self, sample: &HoverSample<f32, A>) -> Result<StepOutput<f32>, Error> {
        HoverIdentifier::step(self, sample)
    }
    fn predict_after(
        &self,
        before: Option<&HoverState<f32>>,
        sample: &HoverSample<f32, A>,
    ) -> Result<HoverState<f32>, Error> {
        HoverIdentifier::predict_after(self, before, sample)
    }
    fn resume(&mut self, sample: &HoverSample<f32, A>) -> Result<HoverState<f32>, Error> {
        HoverIdentifier::resume(self, sample)
    }
    fn compensate_each(
        &mut self,
        gyro_noise: &[f32; 3],
        how: [GyroCompensation; 3],
    ) -> Result<Compensation, Error> {
        HoverIdentifier::compensate_each(self, gyro_noise, how)
    }
    fn reset(&mut self) {
        HoverIdentifier::reset(self)
    }
    fn config(&self) -> HoverConfig<f32> {
        HoverIdentifier::config(self)
    }
    fn snapshot_size(&self) -> usize {
        <Self as Snapshot>::SNAPSHOT_SIZE
    }
    fn write_snapshot(&self, kind: u32, out: &mut [u8]) -> Result<usize, WriteError> {
        Snapshot::write_snapshot(self, kind, out)
    }
    fn read_snapshot(&mut self, kind: u32, bytes: &[u8]) -> Result<(), Error> {
        Snapshot::read_snapshot(self, kind, bytes)
    }
    fn config_hash(&self) -> u32 {
        Snapshot::config_hash(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hover::{AnyAttitude, Controls, Quaternion};
    use crate::snapshot::KindCode;
    use crate::{ExtendedPlainIdentifier, FlightIdentifier};

    fn sample(k: u64) -> HoverSample<f32, AnyAttitude<f32>> {
        let t = k as f32 * 0.02;
        HoverSample {
            time_us: k * 20_000,
            velocity: [libm::sinf(t), 0.1 * libm::cosf(3.0 * t), 0.2],
            rates: [5.0 * libm::sinf(2.0 * t), 2.0, -3.0 * libm::cosf(t)],
            attitude: AnyAttitude::Quaternion(Quaternion {
                w: 1.0,
                x: 0.0,
                y: 0.0,
                z: 0.0,
            }),
            controls: Controls {
                lon: 0.1 * libm::sinf(t),
                lat: 0.05,
                ped: 0.02 * libm::cosf(t),
                col: 0.4,
            },
        }
    }

    /// Behind the pointer, each call gives the bits the concrete type gives, and a snapshot
    /// written through one kind reads back only into that kind.
    #[test]
    fn a_kind_behind_the_pointer_gives_its_own_bits() {
        let mut flight =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), crate::flight_sets()).unwrap();
        let mut plain =
            ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()).unwrap();
        let mut direct = flight.clone();
        let any: [&mut dyn DynIdentifier<AnyAttitude<f32>>; 2] = [&mut flight, &mut plain];
        for k in 0..200 {
            let s = sample(k);
            let through = any[0].step(&s).unwrap();
            let own = direct.step(&s).unwrap();
            assert_eq!(
                through.prediction.to_array().map(f32::to_bits),
                own.prediction.to_array().map(f32::to_bits)
            );
            any[1].step(&s).unwrap();
        }
        let mut bytes = [0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        assert_eq!(any[0].snapshot_size(), bytes.len());
        let kind = FlightIdentifier::<f32>::KIND;
        any[0].write_snapshot(kind, &mut bytes).unwrap();
        let mut own = [0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        Snapshot::write_snapshot(&direct, kind, &mut own).unwrap();
        assert_eq!(bytes, own);
        assert_eq!(any[0].config_hash(), Snapshot::config_hash(&direct));
        assert_eq!(any[1].read_snapshot(kind, &bytes), Err(Error::Incompatible));
        any[0].reset();
        any[0].read_snapshot(kind, &bytes).unwrap();
        let mut again = [0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        any[0].write_snapshot(kind, &mut again).unwrap();
        assert_eq!(again, own);
    }

    /// `snapshot_vec` gives the bytes `write_snapshot` writes, at the snapshot's size.
    #[cfg(feature = "std")]
    #[test]
    fn a_snapshot_vec_is_the_written_snapshot() {
        let mut flight =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), crate::flight_sets()).unwrap();
        for k in 0..50 {
            HoverIdentifier::step(&mut flight, &sample(k)).unwrap();
        }
        let kind = FlightIdentifier::<f32>::KIND;
        let mut own = [0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        Snapshot::write_snapshot(&flight, kind, &mut own).unwrap();
        let any: &dyn DynIdentifier<AnyAttitude<f32>> = &flight;
        assert_eq!(any.snapshot_vec(kind).unwrap(), own);
    }
}
