//! Identification messages: samples in, estimates out, and the requests about the onboard
//! identifiers (reset, parameter dump, export).

use crate::payload::{Field, PayloadError, Reader, Writer};
use rotorid::error::Error;
use rotorid::hover::{table3, Attitude, Controls, GyroCompensation, HoverSample, Scheduling};
use rotorid::rule_base::PremiseSets;

wire_enum! {
    /// What the firmware does with a [`SampleMsg`] (its byte 0).
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum SampleMode {
        /// `step`: learn from the previous sample to this one, then predict the next.
        Learn = 0,
        /// `predict`: one-step prediction with frozen parameters; nothing changes.
        Predict = 1,
        /// `resume`: start a new sample chain here without learning, then predict.
        Resume = 2,
        /// Onboard free run, θ frozen: predict from this sample's attitude and controls with
        /// `v^s` and `ω` replaced by the identifier's own previous prediction (see
        /// [`SampleChain`](crate::SampleChain)). Refused (`Nack`) when an identifier has no
        /// prediction to continue from.
        FreeRun = 3,
    }
}

/// A sample travels as `time_us` u64, then 13 × f32: roll, pitch, yaw (rad), `v^s` x, y, z
/// (m/s), rates q, r, p (deg/s), controls col, ped, lon, lat.
impl Field for HoverSample<f32> {
    const LEN: usize = 8 + 13 * 4;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        let a = &self.attitude;
        w.put_u64(self.time_us)?;
        [a.roll, a.pitch, a.yaw].put(w)?;
        self.velocity.put(w)?;
        self.rates.put(w)?;
        self.controls.to_array().put(w)
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        let time_us = r.get_u64()?;
        let [roll, pitch, yaw] = Field::get(r)?;
        let velocity = Field::get(r)?;
        let rates = Field::get(r)?;
        let [col, ped, lon, lat] = Field::get(r)?;
        Ok(Self {
            time_us,
            attitude: Attitude { roll, pitch, yaw },
            velocity,
            rates,
            controls: Controls { col, ped, lon, lat },
        })
    }
}

fixed_payload! {
    /// `Sample` payload (61 B): mode u8, then the sample: `time_us` u64 and 13 × f32 (roll,
    /// pitch, yaw (rad), `v^s` x, y, z (m/s), rates q, r, p (deg/s), controls col, ped, lon,
    /// lat).
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct SampleMsg for [Sample] {
        /// What to do with the sample.
        pub mode: SampleMode,
        /// The sample, in the core's axes and units.
        pub sample: HoverSample<f32>,
    }
}

/// What one identifier made of a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IdOutput {
    /// `[v_x v_y v_z q r p]` predicted for the next sample (zeros when `error` is set).
    pub prediction: [f32; 6],
    /// Prior innovations of the update (Learn mode after the first sample of a chain).
    pub innovation: Option<[f32; 6]>,
    /// Why the core rejected the sample (its state is then unchanged).
    pub error: Option<Error>,
    /// Stopwatch ticks of the call (SysTick at the core clock in the example firmware).
    pub ticks: u32,
}

impl IdOutput {
    /// A rejected sample.
    pub fn rejected(error: Error, ticks: u32) -> Self {
        Self {
            prediction: [0.0; 6],
            innovation: None,
            error: Some(error),
            ticks,
        }
    }
}

/// An output travels as: error (28 B), flags u8 (bit 0: innovation present), prediction
/// 6 × f32, innovation 6 × f32 (zeros when absent), ticks u32.
impl Field for IdOutput {
    const LEN: usize = super::errors::ERROR_LEN + 1 + 2 * 6 * 4 + 4;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        self.error.put(w)?;
        w.put_u8(u8::from(self.innovation.is_some()))?;
        self.prediction.put(w)?;
        self.innovation.unwrap_or([0.0; 6]).put(w)?;
        w.put_u32(self.ticks)
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        let error = Field::get(r)?;
        let flags = r.get_u8()?;
        if flags > 1 {
            return Err(PayloadError::InvalidValue);
        }
        let prediction = Field::get(r)?;
        let inn: [f32; 6] = Field::get(r)?;
        // Without an innovation its six floats are written as zeros: accept only that.
        if flags == 0 && inn.iter().any(|v| v.to_bits() != 0) {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            prediction,
            innovation: (flags == 1).then_some(inn),
            error,
            ticks: r.get_u32()?,
        })
    }
}

fixed_payload! {
    /// `Estimate` payload (171 B): the sample's `time_us` u64 and mode u8, then the fuzzy and
    /// the plain identifier's [`IdOutput`] (81 B each) of the [`IdentPair`] the last `Reset`
    /// chose.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct Estimate for [Estimate] {
        /// Time stamp of the sample this answers.
        pub time_us: u64,
        /// The sample's mode.
        pub mode: SampleMode,
        /// The pair's Takagi-Sugeno identifier (paper fuzzy, or the flight default).
        pub fuzzy: IdOutput,
        /// The pair's single-rule baseline (paper plain, or extended plain).
        pub plain: IdOutput,
    }
}

wire_enum! {
    /// Which identifier of the active pair a request (params, export, import) is about:
    /// export and import serve both pairs, params the paper pair only.
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum Ident {
        /// The Takagi-Sugeno identifier (`PaperFuzzyIdentifier<f32>`, or on the flight
        /// pair `FlightIdentifier<f32>`).
        Fuzzy = 0,
        /// The single-rule baseline (`PaperPlainIdentifier<f32>`, or on the flight pair
        /// `ExtendedPlainIdentifier<f32>`).
        Plain = 1,
    }
}

wire_enum! {
    /// RLS form chosen by a `Reset` (its only byte).
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum RlsForm {
        /// `HoverConfig::default()`: Bierman U-D, α = 10⁶, λ = 1.
        UdDefault = 0,
        /// `HoverConfig::paper()`: the paper's covariance form, α = 10⁶, λ = 1.
        PaperCovariance = 1,
    }
}

wire_enum! {
    /// Which pair of identifiers answers `Sample` (the `fuzzy` and `plain` outputs of an
    /// [`Estimate`]), chosen by a `Reset`.
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum IdentPair {
        /// The paper's pair (reproduction): `PaperFuzzyIdentifier<f32>` and
        /// `PaperPlainIdentifier<f32>`.
        Paper = 0,
        /// The flight default and its baseline: `FlightIdentifier<f32>` (built with
        /// `flight_sets()`) and `ExtendedPlainIdentifier<f32>`.
        Flight = 1,
    }
}

fixed_payload! {
    /// `Reset` payload (2 B): the [`RlsForm`] of every identifier from now on, and the
    /// [`IdentPair`] that answers `Sample`. Answered by `Ack` once every identifier is back at
    /// θ = 0, P = αI, without a previous sample or prediction.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct ResetMsg for [Reset] {
        /// RLS form.
        pub form: RlsForm,
        /// The pair that answers `Sample`.
        pub pair: IdentPair,
    }
}

fixed_payload! {
    /// `ParamsRequest` and `ExportRequest` payload (1 B): the [`Ident`].
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct IdentRequest for [ParamsRequest, ExportRequest] {
        /// Which identifier.
        pub ident: Ident,
    }
}

fixed_payload! {
    /// `Compensate` payload (12 B): the white noise σ of each gyro rate `[q r p]` (deg/s,
    /// f32). The active pair's identifiers replace their rate models' parameters by those
    /// compensated for it (`HoverIdentifier::compensate`): the parameters to free-run with.
    /// Answered by `Ack`, or `Nack` (refused, nothing changed) for a σ that is not finite,
    /// negative or above 2000. Learning continues from the compensated parameters; a `Reset`
    /// starts afresh.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct CompensateMsg for [Compensate] {
        /// σ of `[q r p]` (deg/s).
        pub gyro_noise: [f32; 3],
    }
}

wire_enum! {
    /// How one rate model is compensated for its gyro's noise (`CompensateEach`): the core's
    /// [`GyroCompensation`], one byte.
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum RateCompensation {
        /// [`GyroCompensation::Damping`]: the damping term's noise (what `Compensate` does).
        #[default]
        Damping = 0,
        /// [`GyroCompensation::Full`]: the damping and the second-order terms' noise.
        Full = 1,
    }
}

impl From<RateCompensation> for GyroCompensation {
    fn from(c: RateCompensation) -> Self {
        match c {
            RateCompensation::Damping => Self::Damping,
            RateCompensation::Full => Self::Full,
        }
    }
}

fixed_payload! {
    /// `CompensateEach` payload (15 B): `Compensate`'s σ `[q r p]` (deg/s, f32), then how each
    /// rate is compensated (`q r p`, one [`RateCompensation`] byte each), as the C interface's
    /// `rotorid_compensate_each` takes them: what `rotorid identify`'s `flight selected` names
    /// per rate (`metrics.json`'s `verdict.full_compensation`). The active pair's identifiers
    /// compensate their rate models so (`HoverIdentifier::compensate_each`). Answered by
    /// `Ack`, or `Nack` (refused, nothing changed) for a σ `Compensate` refuses; an unknown
    /// code is a bad payload.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct CompensateEachMsg for [CompensateEach] {
        /// σ of `[q r p]` (deg/s).
        pub gyro_noise: [f32; 3],
        /// How each of `q r p` is compensated.
        pub how: [RateCompensation; 3],
    }
}

wire_enum! {
    /// The speed a flight model's three rules are on (`Premises`): the core's
    /// [`Scheduling`], one byte, the C interface's `ROTORID_SCHEDULE_*` codes.
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum Schedule {
        /// [`Scheduling::Speed`]: the flight default's (horizontal speed for the velocity
        /// model, forward speed for the rate models).
        #[default]
        Speed = 0,
        /// [`Scheduling::SideSpeed`]: the side speed (rate models only).
        SideSpeed = 1,
        /// [`Scheduling::VerticalSpeed`]: the vertical speed.
        VerticalSpeed = 2,
    }
}

impl From<Schedule> for Scheduling {
    fn from(s: Schedule) -> Self {
        match s {
            Schedule::Speed => Self::Speed,
            Schedule::SideSpeed => Self::SideSpeed,
            Schedule::VerticalSpeed => Self::VerticalSpeed,
        }
    }
}

fixed_payload! {
    /// `Premises` payload (100 B): for each model of the flight default (velocity, q̂, r̂,
    /// p̂) the [`Schedule`] its rules are on, then its three speed sets (left shoulder,
    /// Gaussian, right shoulder; m/s): the centres of the four models (4 × 3 f32), then their
    /// spreads (4 × 3 f32). What `rotorid identify`'s `flight selected` chose, as the C
    /// interface's `rotorid_init_flight_scheduled` takes it (a model with one rule has
    /// `rotorid::hover::unscheduled_sets`). The firmware rebuilds the flight pair's
    /// `FlightIdentifier` so (`FlightIdentifier::flight_scheduled`, θ = 0, P = αI) and keeps
    /// these premises across `Reset` until the next `Premises`; an `ImportChunk` stream then
    /// brings the learnt parameters. Answered by `Ack`, or `Nack` (refused, nothing changed)
    /// for sets or a schedule the core refuses; an unknown code is a bad payload.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct PremisesMsg for [Premises] {
        /// The speed each model's rules are on.
        pub on: [Schedule; 4],
        /// Centres c of each model's three sets, model-major (m/s).
        pub centre: [f32; 12],
        /// Spreads σ of the same sets (m/s, > 0).
        pub spread: [f32; 12],
    }
}

impl PremisesMsg {
    /// Each model's three sets as the core takes them (a left shoulder, a Gaussian and a
    /// right shoulder), unchecked: [`rotorid::FlightIdentifier::flight_scheduled`] checks them.
    pub fn sets(&self) -> [PremiseSets<f32>; 4] {
        let three = |of: &[f32; 12], m: usize| -> [f32; 3] {
            core::array::from_fn(|i| of.get(3 * m + i).copied().unwrap_or(0.0))
        };
        core::array::from_fn(|m| {
            table3::shoulder_sets(three(&self.centre, m), three(&self.spread, m))
        })
    }

    /// The core's scheduling of each model.
    pub fn scheduling(&self) -> [Scheduling; 4] {
        self.on.map(Into::into)
    }
}

/// `ParamsRequest` payload.
pub type ParamsRequest = IdentRequest;
/// `ExportRequest` payload.
pub type ExportRequest = IdentRequest;

#[cfg(test)]
mod tests {
    use super::super::message::testing::{rejects_truncated_and_extended, roundtrip};
    use super::super::message::Payload;
    use super::*;
    use rotorid::error::Quantity;
    use rotorid::membership::MembershipFunction;

    fn sample() -> HoverSample<f32> {
        HoverSample {
            time_us: 0x0123_4567_89AB_CDEF,
            attitude: Attitude {
                roll: -0.0,
                pitch: f32::from_bits(0x7FC0_1234),
                yaw: 3.0,
            },
            velocity: [1.0, -2.5, f32::MIN_POSITIVE],
            rates: [f32::INFINITY, 7.0, -8.0],
            controls: Controls {
                col: 0.5,
                ped: -0.1,
                lon: 0.2,
                lat: 0.3,
            },
        }
    }

    /// The 13 floats of a sample, in wire order, as bits.
    fn bits(s: &HoverSample<f32>) -> [u32; 13] {
        let mut out = [0u32; 13];
        let all = [s.attitude.roll, s.attitude.pitch, s.attitude.yaw]
            .into_iter()
            .chain(s.velocity)
            .chain(s.rates)
            .chain(s.controls.to_array());
        for (o, v) in out.iter_mut().zip(all) {
            *o = v.to_bits();
        }
        out
    }

    #[test]
    fn sample_roundtrips_bit_exact_and_rejects_bad_payloads() {
        for &mode in SampleMode::ALL {
            let m = SampleMsg {
                mode,
                sample: sample(),
            };
            let b = roundtrip(&m);
            assert_eq!(b.len(), 61);
            // Wire order: mode, time, then the floats in `bits` order.
            assert_eq!(b[0], mode as u8);
            assert_eq!(b[1..9], 0x0123_4567_89AB_CDEFu64.to_le_bytes());
            let floats: [u32; 13] = core::array::from_fn(|i| {
                u32::from_le_bytes(b[9 + 4 * i..][..4].try_into().unwrap())
            });
            assert_eq!(floats, bits(&m.sample));
            let back = SampleMsg::read(&b).unwrap();
            assert_eq!(back.mode, mode);
            assert_eq!(back.sample.time_us, m.sample.time_us);
            assert_eq!(bits(&back.sample), bits(&m.sample));
            rejects_truncated_and_extended::<SampleMsg>(&b);
        }
        let mut b = roundtrip(&SampleMsg {
            mode: SampleMode::Learn,
            sample: sample(),
        });
        b[0] = 4;
        assert_eq!(SampleMsg::read(&b), Err(PayloadError::InvalidValue));
    }

    #[test]
    fn estimate_roundtrips_and_rejects_bad_payloads() {
        let e = Estimate {
            time_us: 42,
            mode: SampleMode::Learn,
            fuzzy: IdOutput {
                prediction: [1.0, -0.0, 3.0, f32::from_bits(1), 5.0, 6.0],
                innovation: Some([0.5; 6]),
                error: None,
                ticks: 1234,
            },
            plain: IdOutput::rejected(
                Error::NonFinite(Quantity::Sample(rotorid::hover::SampleField::Rate(0))),
                7,
            ),
        };
        let b = roundtrip(&e);
        assert_eq!(b.len(), 171);
        const { assert!(Estimate::LEN <= crate::wire::MAX_PAYLOAD) };
        assert_eq!(Estimate::read(&b), Ok(e));
        rejects_truncated_and_extended::<Estimate>(&b);
        let mut bad = b.clone();
        bad[8] = 9; // mode
        assert!(Estimate::read(&bad).is_err());
        let mut bad = b.clone();
        bad[9 + super::super::errors::ERROR_LEN] = 2; // flags
        assert!(Estimate::read(&bad).is_err());
        // Plain has no innovation: a non-zero float there is refused.
        let mut bad = b;
        bad[9 + IdOutput::LEN + super::super::errors::ERROR_LEN + 1 + 24] = 1;
        assert!(Estimate::read(&bad).is_err());
    }

    #[test]
    fn premises_roundtrip_and_give_the_cores_sets() {
        let m = PremisesMsg {
            on: [
                Schedule::VerticalSpeed,
                Schedule::SideSpeed,
                Schedule::Speed,
                Schedule::VerticalSpeed,
            ],
            centre: core::array::from_fn(|k| k as f32 - 0.5),
            spread: core::array::from_fn(|k| 1.0 + k as f32),
        };
        let b = roundtrip(&m);
        assert_eq!(b.len(), PremisesMsg::LEN);
        assert_eq!(PremisesMsg::LEN, 100);
        assert_eq!(PremisesMsg::read(&b), Ok(m));
        rejects_truncated_and_extended::<PremisesMsg>(&b);
        // A schedule code this build does not know is a bad payload.
        let mut bad = b.clone();
        bad[3] = 3;
        assert_eq!(PremisesMsg::read(&bad), Err(PayloadError::InvalidValue));
        let sets = m.sets();
        assert_eq!(
            sets[2][1],
            MembershipFunction::Gaussian {
                centre: 6.5,
                spread: 8.0
            }
        );
        assert!(matches!(
            sets[3][2],
            MembershipFunction::RightShoulder { .. }
        ));
        assert_eq!(
            m.scheduling(),
            [
                Scheduling::VerticalSpeed,
                Scheduling::SideSpeed,
                Scheduling::Speed,
                Scheduling::VerticalSpeed
            ]
        );
    }

    #[test]
    fn small_requests_roundtrip() {
        for &form in RlsForm::ALL {
            for &pair in IdentPair::ALL {
                let m = ResetMsg { form, pair };
                let b = roundtrip(&m);
                assert_eq!(b, [form as u8, pair as u8]);
                assert_eq!(ResetMsg::read(&b), Ok(m));
                rejects_truncated_and_extended::<ResetMsg>(&b);
            }
        }
        assert!(ResetMsg::read(&[2, 0]).is_err());
        assert!(ResetMsg::read(&[0, 2]).is_err());
        for &ident in Ident::ALL {
            let m = IdentRequest { ident };
            let b = roundtrip(&m);
            assert_eq!(b, [ident as u8]);
            assert_eq!(IdentRequest::read(&b), Ok(m));
            rejects_truncated_and_extended::<IdentRequest>(&b);
        }
        assert!(IdentRequest::read(&[2]).is_err());
        let m = CompensateMsg {
            gyro_noise: [0.3, 0.25, 1.5],
        };
        let b = roundtrip(&m);
        assert_eq!(b.len(), CompensateMsg::LEN);
        assert_eq!(CompensateMsg::read(&b), Ok(m));
        rejects_truncated_and_extended::<CompensateMsg>(&b);
        let m = CompensateEachMsg {
            gyro_noise: [0.3, 0.25, 1.5],
            how: [
                RateCompensation::Full,
                RateCompensation::Damping,
                RateCompensation::Full,
            ],
        };
        let b = roundtrip(&m);
        assert_eq!(b.len(), CompensateEachMsg::LEN);
        assert_eq!(&b[12..], &[1, 0, 1]);
        assert_eq!(CompensateEachMsg::read(&b), Ok(m));
        rejects_truncated_and_extended::<CompensateEachMsg>(&b);
        // Every code but the two known ones, in every rate's byte, is a bad payload.
        for at in 12..15 {
            for code in 2..=u8::MAX {
                let mut bad = b.clone();
                bad[at] = code;
                assert_eq!(
                    CompensateEachMsg::read(&bad),
                    Err(PayloadError::InvalidValue)
                );
            }
        }
        assert_eq!(RateCompensation::ALL.len(), 2);
        assert_eq!(
            GyroCompensation::from(RateCompensation::Damping),
            GyroCompensation::Damping
        );
        assert_eq!(
            GyroCompensation::from(RateCompensation::Full),
            GyroCompensation::Full
        );
    }
}
