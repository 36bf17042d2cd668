//! Message catalogue: type codes and the payload layouts of the link-level messages.
//!
//! Requests and replies have distinct type codes so every frame is self-describing. Codes
//! `0x01..=0x0F` are the link layer, `0x10..=0x2F` the identification messages, `0x80..=0xFF`
//! are free for vendor experiments. The full table with directions and payload layouts is in
//! `docs/protocol.md`; keep both in sync.
//!
//! Every payload struct has `write(&self, &mut Writer)` and `read(&[u8])`; `read` accepts
//! exactly the layout `write` produces (fixed lengths, no trailing bytes, known enum codes) and
//! never panics.

use super::{LinkStats, PayloadError, Reader, Writer};
use rotorid::error::{ConfigError, Error, Quantity};
use rotorid::hover::{Attitude, Controls, HoverSample};
use rotorid::rls::{Algorithm, RlsState};
use rotorid::sweep::Channel;

/// Message type codes (byte 1 of a raw frame).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MsgType {
    // --- link layer (implemented) ---
    /// FW→host, once at boot: [`Hello`].
    Hello = 0x01,
    /// Host→FW: any payload (≤ 240 B), answered by [`MsgType::Pong`] with the same payload.
    Ping = 0x02,
    /// FW→host: echo of a ping payload.
    Pong = 0x03,
    /// Host→FW: empty; answered by [`MsgType::Stats`].
    StatsRequest = 0x04,
    /// FW→host: [`StatsReport`].
    Stats = 0x05,
    /// Host→FW: [`CostRequest`]; answered by [`MsgType::Cost`].
    CostRequest = 0x06,
    /// FW→host: [`CostReport`].
    Cost = 0x07,
    /// FW→host: [`Ack`] of a command that has no other reply.
    Ack = 0x08,
    /// FW→host: [`Nack`], a request was not understood or not carried out.
    Nack = 0x09,
    /// Host→FW, test hook: one [`FaultKind`] byte; the firmware crashes on purpose.
    FaultInject = 0x0F,

    // --- identification ---
    /// Host→FW: [`SampleMsg`], one measurement sample and what to do with it.
    Sample = 0x10,
    /// FW→host: [`Estimate`], predictions and innovations of both identifiers.
    Estimate = 0x11,
    /// Host→FW: [`ParamsRequest`], ask for a parameter dump.
    ParamsRequest = 0x12,
    /// FW→host: [`ParamsChunk`], one piece of the parameter dump.
    Params = 0x13,
    /// Host→FW: [`ResetMsg`], restart both identifiers; answered by [`MsgType::Ack`].
    Reset = 0x14,
    /// Host→FW: [`ExportRequest`], ask for an export of an identifier's state.
    ExportRequest = 0x15,
    /// FW→host: [`DataChunk`] of exported state.
    ExportChunk = 0x16,
    /// Host→FW: [`DataChunk`] of state to import; each answered by Ack/Nack.
    ImportChunk = 0x17,
    /// Host→FW: [`SweepStart`], run the onboard sweep generator.
    SweepStart = 0x18,
    /// FW→host: [`SweepSample`], one command of the sweep generator.
    SweepSample = 0x19,
    /// Host→FW: empty; answered by [`MsgType::Memory`].
    MemoryRequest = 0x1A,
    /// FW→host: [`MemoryReport`], stack high-water mark and RAM layout.
    Memory = 0x1B,
}

impl MsgType {
    /// Every known type, in code order.
    pub const ALL: [MsgType; 22] = [
        Self::Hello,
        Self::Ping,
        Self::Pong,
        Self::StatsRequest,
        Self::Stats,
        Self::CostRequest,
        Self::Cost,
        Self::Ack,
        Self::Nack,
        Self::FaultInject,
        Self::Sample,
        Self::Estimate,
        Self::ParamsRequest,
        Self::Params,
        Self::Reset,
        Self::ExportRequest,
        Self::ExportChunk,
        Self::ImportChunk,
        Self::SweepStart,
        Self::SweepSample,
        Self::MemoryRequest,
        Self::Memory,
    ];

    /// The type with code `code`, if this build knows it.
    pub fn from_u8(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|t| *t as u8 == code)
    }

    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }
}

/// Boot announcement (`Hello`, 4 B + name): protocol version u8, max payload u16,
/// firmware flags u8, then the firmware name as UTF-8 (rest of the payload).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hello<'a> {
    /// Protocol version the firmware speaks ([`VERSION`](super::VERSION)).
    pub version: u8,
    /// Largest payload the firmware accepts, in bytes.
    pub max_payload: u16,
    /// Bit 0: the [`MsgType::FaultInject`] test hook is enabled.
    pub flags: u8,
    /// Firmware name and version, UTF-8.
    pub name: &'a [u8],
}

impl<'a> Hello<'a> {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.version)?;
        w.put_u16(self.max_payload)?;
        w.put_u8(self.flags)?;
        w.put_bytes(self.name)
    }

    /// Parses the payload.
    pub fn read(payload: &'a [u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        Ok(Self {
            version: r.get_u8()?,
            max_payload: r.get_u16()?,
            flags: r.get_u8()?,
            name: r.rest(),
        })
    }
}

/// Counters of the firmware side (`Stats`, 56 B): its receive [`LinkStats`] (10 × u32 in
/// [`LinkStats::to_array`] order) then four application counters (u32 each).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StatsReport {
    /// What the firmware's frame decoder saw (host→FW direction).
    pub link: LinkStats,
    /// Valid frames with a type the firmware does not handle (answered with Nack).
    pub unknown_type: u32,
    /// Valid frames of a known type whose payload did not parse (answered with Nack).
    pub bad_payload: u32,
    /// UART receive errors (overruns) reported by the driver.
    pub uart_errors: u32,
    /// Frames the firmware sent (FW→host), this reply excluded.
    pub frames_sent: u32,
}

impl StatsReport {
    /// Payload length, in bytes.
    pub const LEN: usize = 4 * (LinkStats::FIELDS + 4);

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        for v in self.link.to_array() {
            w.put_u32(v)?;
        }
        w.put_u32(self.unknown_type)?;
        w.put_u32(self.bad_payload)?;
        w.put_u32(self.uart_errors)?;
        w.put_u32(self.frames_sent)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let mut a = [0u32; LinkStats::FIELDS];
        for v in &mut a {
            *v = r.get_u32()?;
        }
        let s = Self {
            link: LinkStats::from_array(a),
            unknown_type: r.get_u32()?,
            bad_payload: r.get_u32()?,
            uart_errors: r.get_u32()?,
            frames_sent: r.get_u32()?,
        };
        r.finish()?;
        Ok(s)
    }
}

/// Dummy workloads the `CostRequest` can run (byte 0 of its payload).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Workload {
    /// Nothing: measures the stopwatch overhead.
    Empty = 0,
    /// `iterations` rounds of a 32-bit xorshift (integer ALU).
    Xorshift = 1,
    /// `iterations` single-precision multiply-adds (FPU).
    FloatMac = 2,
    /// [`encode_frame`](super::encode_frame) of a 240-byte payload (CRC-32 + COBS),
    /// `iterations` times.
    EncodeFrame = 3,
}

impl Workload {
    /// The workload with code `code`.
    pub fn from_u8(code: u8) -> Option<Self> {
        [
            Self::Empty,
            Self::Xorshift,
            Self::FloatMac,
            Self::EncodeFrame,
        ]
        .into_iter()
        .find(|w| *w as u8 == code)
    }
}

/// `CostRequest` payload (5 B): workload u8, iterations u32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CostRequest {
    /// What to run.
    pub workload: Workload,
    /// How many rounds.
    pub iterations: u32,
}

impl CostRequest {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.workload as u8)?;
        w.put_u32(self.iterations)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let workload = Workload::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let iterations = r.get_u32()?;
        r.finish()?;
        Ok(Self {
            workload,
            iterations,
        })
    }
}

/// `Cost` payload (17 B): workload u8, iterations u32, ticks u64, result u32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CostReport {
    /// The workload that ran.
    pub workload: Workload,
    /// Rounds that ran.
    pub iterations: u32,
    /// Elapsed SysTick ticks (core clock; under QEMU `-icount shift=0` one tick is 40
    /// executed instructions), stopwatch overhead included.
    pub ticks: u64,
    /// Result of the workload (keeps the optimiser from deleting it; deterministic).
    pub result: u32,
}

impl CostReport {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.workload as u8)?;
        w.put_u32(self.iterations)?;
        w.put_u64(self.ticks)?;
        w.put_u32(self.result)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let workload = Workload::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let s = Self {
            workload,
            iterations: r.get_u32()?,
            ticks: r.get_u64()?,
            result: r.get_u32()?,
        };
        r.finish()?;
        Ok(s)
    }
}

/// Why a request was refused (byte 3 of a `Nack`).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NackReason {
    /// The message type is unknown or not implemented by this firmware.
    UnknownType = 1,
    /// The payload does not parse for this message type.
    BadPayload = 2,
    /// The request is valid but cannot be carried out now.
    Busy = 3,
    /// The request is valid but refused (e.g. a disabled test hook).
    Refused = 4,
}

/// `Ack` payload (3 B): sequence number u16 and type u8 of the request acknowledged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ack {
    /// Sequence number of the request.
    pub seq: u16,
    /// Type code of the request.
    pub msg_type: u8,
}

impl Ack {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u16(self.seq)?;
        w.put_u8(self.msg_type)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let s = Self {
            seq: r.get_u16()?,
            msg_type: r.get_u8()?,
        };
        r.finish()?;
        Ok(s)
    }
}

/// `Nack` payload (4 B): the request's sequence number u16 and type u8, then the reason u8
/// (a raw code so that reasons added later still parse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Nack {
    /// Sequence number of the request.
    pub seq: u16,
    /// Type code of the request.
    pub msg_type: u8,
    /// [`NackReason`] code.
    pub reason: u8,
}

impl Nack {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u16(self.seq)?;
        w.put_u8(self.msg_type)?;
        w.put_u8(self.reason)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let s = Self {
            seq: r.get_u16()?,
            msg_type: r.get_u8()?,
            reason: r.get_u8()?,
        };
        r.finish()?;
        Ok(s)
    }
}

/// What the `FaultInject` test hook does (byte 0 of its payload).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FaultKind {
    /// Rust `panic!`.
    Panic = 0,
    /// Undefined instruction: UsageFault escalated to HardFault.
    HardFault = 1,
}

impl FaultKind {
    /// The kind with code `code`.
    pub fn from_u8(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::Panic),
            1 => Some(Self::HardFault),
            _ => None,
        }
    }
}

// ------------------------------------------------------------------------------------------
// Identification messages
// ------------------------------------------------------------------------------------------

/// What the firmware does with a [`SampleMsg`] (its byte 0).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SampleMode {
    /// `step`: learn from the previous sample to this one, then predict the next.
    Learn = 0,
    /// `predict`: one-step prediction with frozen parameters; nothing changes.
    Predict = 1,
    /// `resume`: start a new sample chain here without learning, then predict.
    Resume = 2,
}

impl SampleMode {
    /// The mode with code `code`.
    pub fn from_u8(code: u8) -> Option<Self> {
        [Self::Learn, Self::Predict, Self::Resume]
            .into_iter()
            .find(|m| *m as u8 == code)
    }
}

/// `Sample` payload (61 B): mode u8, `time_us` u64, then 13 × f32: roll, pitch, yaw (rad),
/// `v^s` x, y, z (m/s), rates q, r, p (deg/s), controls col, ped, lon, lat.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SampleMsg {
    /// What to do with the sample.
    pub mode: SampleMode,
    /// The sample, in the core's axes and units.
    pub sample: HoverSample<f32>,
}

impl SampleMsg {
    /// Payload length, in bytes.
    pub const LEN: usize = 1 + 8 + 13 * 4;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        let s = &self.sample;
        w.put_u8(self.mode as u8)?;
        w.put_u64(s.time_us)?;
        for v in [s.attitude.roll, s.attitude.pitch, s.attitude.yaw] {
            w.put_f32(v)?;
        }
        for v in s.velocity.into_iter().chain(s.rates) {
            w.put_f32(v)?;
        }
        for v in s.controls.to_array() {
            w.put_f32(v)?;
        }
        Ok(())
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let mode = SampleMode::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let time_us = r.get_u64()?;
        let mut f = [0f32; 13];
        for v in &mut f {
            *v = r.get_f32()?;
        }
        r.finish()?;
        let [roll, pitch, yaw, vx, vy, vz, q, rr, p, col, ped, lon, lat] = f;
        Ok(Self {
            mode,
            sample: HoverSample {
                time_us,
                attitude: Attitude { roll, pitch, yaw },
                velocity: [vx, vy, vz],
                rates: [q, rr, p],
                controls: Controls { col, ped, lon, lat },
            },
        })
    }
}

/// Bytes of an encoded [`Error`] (see [`write_error`]).
pub const ERROR_LEN: usize = 28;

/// The `code` (or `detail`) sent for an error, quantity or configuration error that a newer
/// `rotorid` defines and this protocol version cannot name (`rotorid`'s error enums are
/// `#[non_exhaustive]`). A reader refuses it as an invalid payload.
pub const UNKNOWN_CODE: u8 = 255;

fn quantity_code(q: Quantity) -> (u8, u16) {
    match q {
        Quantity::Roll => (1, 0),
        Quantity::Pitch => (2, 0),
        Quantity::Yaw => (3, 0),
        Quantity::Velocity(i) => (4, u16::from(i)),
        Quantity::Rate(i) => (5, u16::from(i)),
        Quantity::Control(i) => (6, u16::from(i)),
        Quantity::Time => (7, 0),
        Quantity::Premise(i) => (8, u16::from(i)),
        Quantity::Regressor(i) => (9, i),
        Quantity::Target(i) => (10, u16::from(i)),
        Quantity::Parameter(i) => (11, i),
        Quantity::Covariance(i) => (12, i),
        Quantity::Config => (13, 0),
        // A quantity of a newer core than this protocol version knows.
        _ => (UNKNOWN_CODE, 0),
    }
}

fn quantity_from(code: u8, index: u16) -> Option<Quantity> {
    let small = u8::try_from(index).ok();
    Some(match code {
        1 => Quantity::Roll,
        2 => Quantity::Pitch,
        3 => Quantity::Yaw,
        4 => Quantity::Velocity(small?),
        5 => Quantity::Rate(small?),
        6 => Quantity::Control(small?),
        7 => Quantity::Time,
        8 => Quantity::Premise(small?),
        9 => Quantity::Regressor(index),
        10 => Quantity::Target(small?),
        11 => Quantity::Parameter(index),
        12 => Quantity::Covariance(index),
        13 => Quantity::Config,
        _ => return None,
    })
}

fn config_code(c: ConfigError) -> (u8, u16, u64) {
    let pair = |a: u8, b: u8| u16::from(a) | (u16::from(b) << 8);
    match c {
        ConfigError::MembershipFunction { variable, set } => (1, pair(variable, set), 0),
        ConfigError::RuleCount { expected, found } => (2, expected, u64::from(found)),
        ConfigError::Dimensions => (3, 0, 0),
        ConfigError::InitialCovariance => (4, 0, 0),
        ConfigError::Forgetting => (5, 0, 0),
        ConfigError::ConsequentTerms { needed, found } => (6, pair(needed, found), 0),
        ConfigError::SamplePeriod => (7, 0, 0),
        ConfigError::Sweep => (8, 0, 0),
        ConfigError::Scale => (9, 0, 0),
        _ => (UNKNOWN_CODE, 0, 0),
    }
}

fn config_from(code: u8, index: u16, a: u64) -> Option<ConfigError> {
    let [lo, hi] = index.to_le_bytes();
    Some(match code {
        1 => ConfigError::MembershipFunction {
            variable: lo,
            set: hi,
        },
        2 => ConfigError::RuleCount {
            expected: index,
            found: u32::try_from(a).ok()?,
        },
        3 => ConfigError::Dimensions,
        4 => ConfigError::InitialCovariance,
        5 => ConfigError::Forgetting,
        6 => ConfigError::ConsequentTerms {
            needed: lo,
            found: hi,
        },
        7 => ConfigError::SamplePeriod,
        8 => ConfigError::Sweep,
        9 => ConfigError::Scale,
        _ => return None,
    })
}

/// Writes `Option<Error>` in [`ERROR_LEN`] bytes, losslessly: `code u8` (0 none, 1 NonFinite,
/// 2 OutOfRange, 3 TimeStep, 4 NonMonotonicTime, 5 Config, 6 Incompatible, 7 Numerical),
/// `detail u8` (the [`Quantity`] or [`ConfigError`] code), `index u16`, then three u64
/// (`TimeStep`: `dt_us, min_us, max_us`; `RuleCount`: `found` in the first; otherwise 0).
pub fn write_error(w: &mut Writer<'_>, e: Option<&Error>) -> Result<(), PayloadError> {
    let (code, detail, index, a, b, c) = match e {
        None => (0, 0, 0, 0, 0, 0),
        Some(Error::NonFinite(q)) => {
            let (d, i) = quantity_code(*q);
            (1, d, i, 0, 0, 0)
        }
        Some(Error::OutOfRange(q)) => {
            let (d, i) = quantity_code(*q);
            (2, d, i, 0, 0, 0)
        }
        Some(Error::TimeStep {
            dt_us,
            min_us,
            max_us,
        }) => (3, 0, 0, *dt_us, *min_us, *max_us),
        Some(Error::NonMonotonicTime) => (4, 0, 0, 0, 0, 0),
        Some(Error::Config(cfg)) => {
            let (d, i, a) = config_code(*cfg);
            (5, d, i, a, 0, 0)
        }
        Some(Error::Incompatible) => (6, 0, 0, 0, 0, 0),
        Some(Error::Numerical) => (7, 0, 0, 0, 0, 0),
        Some(_) => (UNKNOWN_CODE, 0, 0, 0, 0, 0),
    };
    if w.remaining() < ERROR_LEN {
        return Err(PayloadError::Overflow {
            needed: ERROR_LEN,
            remaining: w.remaining(),
        });
    }
    w.put_u8(code)?;
    w.put_u8(detail)?;
    w.put_u16(index)?;
    w.put_u64(a)?;
    w.put_u64(b)?;
    w.put_u64(c)
}

/// Reads what [`write_error`] wrote. Unknown codes are [`PayloadError::InvalidValue`].
pub fn read_error(r: &mut Reader<'_>) -> Result<Option<Error>, PayloadError> {
    let bytes = r.get_bytes(ERROR_LEN)?;
    let mut r = Reader::new(bytes);
    let (code, detail, index) = (r.get_u8()?, r.get_u8()?, r.get_u16()?);
    let (a, b, c) = (r.get_u64()?, r.get_u64()?, r.get_u64()?);
    let bad = PayloadError::InvalidValue;
    let error = decode_error(code, detail, index, [a, b, c])?;
    // Only the canonical encoding is accepted (unused fields zero), so that every accepted
    // payload writes back to the same bytes: re-encode and compare.
    let mut again = [0u8; ERROR_LEN];
    write_error(&mut Writer::new(&mut again), error.as_ref())?;
    if again.as_slice() != bytes {
        return Err(bad);
    }
    Ok(error)
}

/// The error of a decoded `code, detail, index, [a, b, c]`.
fn decode_error(
    code: u8,
    detail: u8,
    index: u16,
    [a, b, c]: [u64; 3],
) -> Result<Option<Error>, PayloadError> {
    let bad = PayloadError::InvalidValue;
    Ok(Some(match code {
        0 => return Ok(None),
        1 => Error::NonFinite(quantity_from(detail, index).ok_or(bad)?),
        2 => Error::OutOfRange(quantity_from(detail, index).ok_or(bad)?),
        3 => Error::TimeStep {
            dt_us: a,
            min_us: b,
            max_us: c,
        },
        4 => Error::NonMonotonicTime,
        5 => Error::Config(config_from(detail, index, a).ok_or(bad)?),
        6 => Error::Incompatible,
        7 => Error::Numerical,
        _ => return Err(bad),
    }))
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
    /// Payload bytes of one output.
    pub const LEN: usize = ERROR_LEN + 1 + 2 * 6 * 4 + 4;

    /// A rejected sample.
    pub fn rejected(error: Error, ticks: u32) -> Self {
        Self {
            prediction: [0.0; 6],
            innovation: None,
            error: Some(error),
            ticks,
        }
    }

    /// Writes the output: error (28 B), flags u8 (bit 0: innovation present), prediction
    /// 6 × f32, innovation 6 × f32 (zeros when absent), ticks u32.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        write_error(w, self.error.as_ref())?;
        w.put_u8(u8::from(self.innovation.is_some()))?;
        for v in self.prediction {
            w.put_f32(v)?;
        }
        for v in self.innovation.unwrap_or([0.0; 6]) {
            w.put_f32(v)?;
        }
        w.put_u32(self.ticks)
    }

    /// Reads an output.
    pub fn read(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        let error = read_error(r)?;
        let flags = r.get_u8()?;
        if flags > 1 {
            return Err(PayloadError::InvalidValue);
        }
        let mut prediction = [0f32; 6];
        for v in &mut prediction {
            *v = r.get_f32()?;
        }
        let mut inn = [0f32; 6];
        for v in &mut inn {
            *v = r.get_f32()?;
        }
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

/// `Estimate` payload (171 B): the sample's `time_us` u64 and mode u8, then the fuzzy and the
/// plain identifier's [`IdOutput`] (81 B each).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Estimate {
    /// Time stamp of the sample this answers.
    pub time_us: u64,
    /// The sample's mode.
    pub mode: SampleMode,
    /// The Takagi-Sugeno identifier.
    pub fuzzy: IdOutput,
    /// The plain (single-rule) identifier.
    pub plain: IdOutput,
}

impl Estimate {
    /// Payload length, in bytes.
    pub const LEN: usize = 8 + 1 + 2 * IdOutput::LEN;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u64(self.time_us)?;
        w.put_u8(self.mode as u8)?;
        self.fuzzy.write(w)?;
        self.plain.write(w)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let time_us = r.get_u64()?;
        let mode = SampleMode::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let fuzzy = IdOutput::read(&mut r)?;
        let plain = IdOutput::read(&mut r)?;
        r.finish()?;
        Ok(Self {
            time_us,
            mode,
            fuzzy,
            plain,
        })
    }
}

/// Which onboard identifier a request is about.
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Ident {
    /// The Takagi-Sugeno identifier (`PaperFuzzyIdentifier<f32>`).
    Fuzzy = 0,
    /// The single-rule baseline (`PaperPlainIdentifier<f32>`).
    Plain = 1,
}

impl Ident {
    /// The identifier with code `code`.
    pub fn from_u8(code: u8) -> Option<Self> {
        [Self::Fuzzy, Self::Plain]
            .into_iter()
            .find(|i| *i as u8 == code)
    }
}

/// RLS form chosen by a `Reset` (its only byte).
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RlsForm {
    /// `HoverConfig::default()`: Bierman U-D, α = 10⁶, λ = 1.
    UdDefault = 0,
    /// `HoverConfig::paper()`: the paper's covariance form, α = 10⁶, λ = 1.
    PaperCovariance = 1,
}

/// `Reset` payload (1 B): the [`RlsForm`] of both identifiers from now on. Answered by `Ack`
/// once both identifiers are back at θ = 0, P = αI, without a previous sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ResetMsg {
    /// RLS form.
    pub form: RlsForm,
}

impl ResetMsg {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.form as u8)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let form = match r.get_u8()? {
            0 => RlsForm::UdDefault,
            1 => RlsForm::PaperCovariance,
            _ => return Err(PayloadError::InvalidValue),
        };
        r.finish()?;
        Ok(Self { form })
    }
}

/// `ParamsRequest` and `ExportRequest` payload (1 B): the [`Ident`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IdentRequest {
    /// Which identifier.
    pub ident: Ident,
}

/// `ParamsRequest` payload.
pub type ParamsRequest = IdentRequest;
/// `ExportRequest` payload.
pub type ExportRequest = IdentRequest;

impl IdentRequest {
    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.ident as u8)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let ident = Ident::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        r.finish()?;
        Ok(Self { ident })
    }
}

/// Which vector a [`ParamsChunk`] carries.
#[non_exhaustive]
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamField {
    /// θ (f32 bits), N words.
    Theta = 0,
    /// diag(P) (f32 bits), N words.
    CovarianceDiagonal = 1,
    /// [`ParamsChunk::SUMMARY_WORDS`] words: trace(P) (f32 bits), updates, windup guards,
    /// last innovation (f32 bits), algorithm (0 covariance, 1 U-D).
    Summary = 2,
}

/// `Params` payload (7 B + 4 B per word): ident u8, model u8 (0 velocity, 1 q̂, 2 r̂, 3 p̂),
/// field u8 ([`ParamField`]), index u16 of the first word, total u16 (words in the field),
/// then up to [`ParamsChunk::MAX_WORDS`] u32 words. A dump is, for each model in order, θ,
/// diag(P) and the summary, each in as many chunks as needed; it ends with model 3's summary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParamsChunk<'a> {
    /// Which identifier.
    pub ident: Ident,
    /// Model index: 0 velocity, 1 q̂, 2 r̂, 3 p̂.
    pub model: u8,
    /// What the words are.
    pub field: ParamField,
    /// Index of the first word within the field.
    pub index: u16,
    /// Words in the whole field.
    pub total: u16,
    /// The words, little-endian u32 each (length a multiple of 4).
    pub words: &'a [u8],
}

impl<'a> ParamsChunk<'a> {
    /// Header bytes.
    pub const HEADER: usize = 7;
    /// Most words in one chunk.
    pub const MAX_WORDS: usize = (super::MAX_PAYLOAD - Self::HEADER) / 4;
    /// Words of a [`ParamField::Summary`].
    pub const SUMMARY_WORDS: usize = 5;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        if !self.words.len().is_multiple_of(4) || self.words.len() / 4 > Self::MAX_WORDS {
            return Err(PayloadError::InvalidValue);
        }
        w.put_u8(self.ident as u8)?;
        w.put_u8(self.model)?;
        w.put_u8(self.field as u8)?;
        w.put_u16(self.index)?;
        w.put_u16(self.total)?;
        w.put_bytes(self.words)
    }

    /// Parses the payload.
    pub fn read(payload: &'a [u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let ident = Ident::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let model = r.get_u8()?;
        let field = match r.get_u8()? {
            0 => ParamField::Theta,
            1 => ParamField::CovarianceDiagonal,
            2 => ParamField::Summary,
            _ => return Err(PayloadError::InvalidValue),
        };
        let index = r.get_u16()?;
        let total = r.get_u16()?;
        let words = r.rest();
        let n = words.len() / 4;
        if model > 3
            || !words.len().is_multiple_of(4)
            || n > Self::MAX_WORDS
            || usize::from(index) + n > usize::from(total)
        {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            ident,
            model,
            field,
            index,
            total,
            words,
        })
    }

    /// The words as u32.
    pub fn iter(&self) -> impl Iterator<Item = u32> + 'a {
        self.words
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4])))
    }
}

/// `ExportChunk` / `ImportChunk` payload (13 B + data): ident u8, offset u32 (of the first data
/// byte in the snapshot stream), total u32 (stream length), crc u32 (CRC-32/ISO-HDLC of the
/// whole stream, the same in every chunk), then up to [`DataChunk::MAX_DATA`] bytes. Chunks
/// travel in order; the receiver checks offsets, length and CRC before it uses the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DataChunk<'a> {
    /// Which identifier.
    pub ident: Ident,
    /// Offset of `data` in the stream.
    pub offset: u32,
    /// Stream length, in bytes.
    pub total: u32,
    /// CRC-32 of the whole stream.
    pub crc: u32,
    /// The bytes.
    pub data: &'a [u8],
}

impl<'a> DataChunk<'a> {
    /// Header bytes.
    pub const HEADER: usize = 13;
    /// Most data bytes in one chunk.
    pub const MAX_DATA: usize = super::MAX_PAYLOAD - Self::HEADER;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.ident as u8)?;
        w.put_u32(self.offset)?;
        w.put_u32(self.total)?;
        w.put_u32(self.crc)?;
        if self.data.len() > Self::MAX_DATA {
            return Err(PayloadError::InvalidValue);
        }
        w.put_bytes(self.data)
    }

    /// Parses the payload.
    pub fn read(payload: &'a [u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let ident = Ident::from_u8(r.get_u8()?).ok_or(PayloadError::InvalidValue)?;
        let offset = r.get_u32()?;
        let total = r.get_u32()?;
        let crc = r.get_u32()?;
        let data = r.rest();
        let end = u64::from(offset) + data.len() as u64;
        if data.len() > Self::MAX_DATA || end > u64::from(total) {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            ident,
            offset,
            total,
            crc,
            data,
        })
    }
}

/// CRC-32/ISO-HDLC of a byte stream (the frame CRC), for [`DataChunk::crc`].
pub fn stream_crc(bytes: &[u8]) -> u32 {
    super::CRC.checksum(bytes)
}

/// One model's learnt state as the export stream sees it (borrowed from an `Rls`).
#[derive(Clone, Copy, Debug)]
pub struct ModelView<'a> {
    /// Covariance form.
    pub algorithm: Algorithm,
    /// Updates made.
    pub updates: u32,
    /// θ.
    pub theta: &'a [f32],
    /// Packed P or U-D factor.
    pub factor: &'a [f32],
}

impl ModelView<'_> {
    /// Bytes of this model in the stream: algorithm u8, updates u32, θ, factor (f32 each).
    pub fn len(&self) -> usize {
        5 + 4 * (self.theta.len() + self.factor.len())
    }

    /// Never true (the header is always there).
    pub fn is_empty(&self) -> bool {
        false
    }

    fn byte(&self, i: usize) -> u8 {
        let word = |xs: &[f32], j: usize| {
            xs.get(j / 4)
                .and_then(|v| v.to_bits().to_le_bytes().get(j % 4).copied())
                .unwrap_or(0)
        };
        match i {
            0 => algorithm_code(self.algorithm),
            1..=4 => self.updates.to_le_bytes().get(i - 1).copied().unwrap_or(0),
            _ => {
                let j = i - 5;
                let t = 4 * self.theta.len();
                if j < t {
                    word(self.theta, j)
                } else {
                    word(self.factor, j - t)
                }
            }
        }
    }
}

fn algorithm_code(a: Algorithm) -> u8 {
    match a {
        Algorithm::Covariance => 0,
        Algorithm::UdFactor => 1,
    }
}

/// Length of the snapshot stream of `models`.
pub fn snapshot_len(models: &[ModelView<'_>]) -> usize {
    models.iter().map(ModelView::len).sum()
}

/// Copies the snapshot stream of `models` (each model's bytes, in order) from `offset` into
/// `out`; returns the bytes written (fewer than `out.len()` at the end of the stream).
pub fn snapshot_read(models: &[ModelView<'_>], offset: usize, out: &mut [u8]) -> usize {
    let mut start = 0usize;
    let mut n = 0usize;
    for m in models {
        let len = m.len();
        while n < out.len() && offset + n < start + len {
            let pos = offset + n;
            if pos >= start {
                if let Some(o) = out.get_mut(n) {
                    *o = m.byte(pos - start);
                }
                n += 1;
            } else {
                break;
            }
        }
        start += len;
    }
    n
}

/// CRC-32 of the snapshot stream of `models` (computed piecewise, without a stream buffer).
pub fn snapshot_crc(models: &[ModelView<'_>]) -> u32 {
    let mut digest = super::CRC.digest();
    let mut buf = [0u8; 64];
    let mut offset = 0;
    loop {
        let n = snapshot_read(models, offset, &mut buf);
        if n == 0 {
            break;
        }
        digest.update(buf.get(..n).unwrap_or_default());
        offset += n;
    }
    digest.finalize()
}

/// Reads one model's state (as written by the snapshot stream) into an [`RlsState`].
pub fn read_rls_state<const N: usize, const NP: usize>(
    r: &mut Reader<'_>,
) -> Result<RlsState<f32, N, NP>, PayloadError> {
    let algorithm = match r.get_u8()? {
        0 => Algorithm::Covariance,
        1 => Algorithm::UdFactor,
        _ => return Err(PayloadError::InvalidValue),
    };
    let updates = r.get_u32()?;
    let mut theta = [0f32; N];
    for v in &mut theta {
        *v = r.get_f32()?;
    }
    let mut factor = [0f32; NP];
    for v in &mut factor {
        *v = r.get_f32()?;
    }
    Ok(RlsState {
        algorithm,
        theta,
        factor,
        updates,
    })
}

/// `SweepStart` payload (26 B): amplitudes 4 × f32 `[col, ped, lon, lat]` (stick units),
/// `rate_hz` u16, `start` u32, `count` u32. The firmware builds
/// `SweepSchedule::table2(amplitudes, rate_hz)` and streams `count` [`SweepSample`]s from index
/// `start` (fewer at the end of the schedule), then an `Ack`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SweepStart {
    /// Per-channel amplitudes `[col, ped, lon, lat]` (stick units).
    pub amplitudes: [f32; 4],
    /// Sample rate (Hz).
    pub rate_hz: u16,
    /// First sample index.
    pub start: u32,
    /// Samples to stream.
    pub count: u32,
}

impl SweepStart {
    /// Payload length, in bytes.
    pub const LEN: usize = 16 + 2 + 4 + 4;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        for a in self.amplitudes {
            w.put_f32(a)?;
        }
        w.put_u16(self.rate_hz)?;
        w.put_u32(self.start)?;
        w.put_u32(self.count)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let mut amplitudes = [0f32; 4];
        for a in &mut amplitudes {
            *a = r.get_f32()?;
        }
        let s = Self {
            amplitudes,
            rate_hz: r.get_u16()?,
            start: r.get_u32()?,
            count: r.get_u32()?,
        };
        r.finish()?;
        Ok(s)
    }
}

/// `SweepSample` payload (17 B): index k u32, schedule length u32, channel u8 (0 col, 1 ped,
/// 2 lon, 3 lat), offset from trim f64 (stick units).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SweepSample {
    /// Sample index.
    pub k: u32,
    /// Samples in the whole schedule.
    pub total: u32,
    /// The channel being swept.
    pub channel: Channel,
    /// Offset from trim on it.
    pub offset: f64,
}

impl SweepSample {
    /// Payload length, in bytes.
    pub const LEN: usize = 4 + 4 + 1 + 8;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u32(self.k)?;
        w.put_u32(self.total)?;
        w.put_u8(self.channel.index() as u8)?;
        w.put_f64(self.offset)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let k = r.get_u32()?;
        let total = r.get_u32()?;
        let channel = match r.get_u8()? {
            0 => Channel::Collective,
            1 => Channel::Pedal,
            2 => Channel::Longitudinal,
            3 => Channel::Lateral,
            _ => return Err(PayloadError::InvalidValue),
        };
        let offset = r.get_f64()?;
        r.finish()?;
        Ok(Self {
            k,
            total,
            channel,
            offset,
        })
    }
}

/// `Memory` payload (16 B): RAM the firmware uses, in bytes — stack region size, stack peak
/// (high-water mark of the painted stack), static data (`.data` + `.bss` + `.uninit`), and
/// the RAM region size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MemoryReport {
    /// Bytes between the end of static data and the initial stack pointer.
    pub stack_size: u32,
    /// Deepest stack use since boot (bytes below the initial stack pointer).
    pub stack_peak: u32,
    /// Static RAM, in bytes.
    pub static_ram: u32,
    /// RAM region, in bytes.
    pub ram_size: u32,
}

impl MemoryReport {
    /// Payload length, in bytes.
    pub const LEN: usize = 16;

    /// Writes the payload.
    pub fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u32(self.stack_size)?;
        w.put_u32(self.stack_peak)?;
        w.put_u32(self.static_ram)?;
        w.put_u32(self.ram_size)
    }

    /// Parses the payload.
    pub fn read(payload: &[u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let s = Self {
            stack_size: r.get_u32()?,
            stack_peak: r.get_u32()?,
            static_ram: r.get_u32()?,
            ram_size: r.get_u32()?,
        };
        r.finish()?;
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    extern crate alloc;
    use super::*;
    use alloc::vec;
    use alloc::vec::Vec;

    #[test]
    fn codes_are_unique_and_roundtrip() {
        for (i, t) in MsgType::ALL.iter().enumerate() {
            assert_eq!(MsgType::from_u8(t.code()), Some(*t));
            for u in &MsgType::ALL[..i] {
                assert_ne!(t.code(), u.code());
            }
        }
        assert_eq!(MsgType::from_u8(0), None);
        assert_eq!(MsgType::from_u8(0xFF), None);
    }

    #[test]
    fn payload_roundtrips() {
        let mut buf = [0u8; 64];
        let s = StatsReport {
            link: LinkStats::from_array([1, 2, 3, 4, 5, 6, 7, 8, 9, 10]),
            unknown_type: 11,
            bad_payload: 12,
            uart_errors: 13,
            frames_sent: 14,
        };
        let mut w = Writer::new(&mut buf);
        s.write(&mut w).unwrap();
        assert_eq!(w.len(), StatsReport::LEN);
        assert_eq!(StatsReport::read(w.written()), Ok(s));

        let c = CostReport {
            workload: Workload::FloatMac,
            iterations: 1000,
            ticks: 1 << 40,
            result: 7,
        };
        let mut w = Writer::new(&mut buf);
        c.write(&mut w).unwrap();
        assert_eq!(CostReport::read(w.written()), Ok(c));
        assert!(CostRequest::read(&[9, 0, 0, 0, 0]).is_err());
        assert!(CostRequest::read(&[1, 0, 0, 0]).is_err());
        assert!(CostRequest::read(&[1, 0, 0, 0, 0, 0]).is_err());
        assert_eq!(
            CostRequest::read(&[2, 1, 0, 0, 0]),
            Ok(CostRequest {
                workload: Workload::FloatMac,
                iterations: 1
            })
        );
        let n = Nack {
            seq: 3,
            msg_type: 0x77,
            reason: NackReason::UnknownType as u8,
        };
        let mut w = Writer::new(&mut buf);
        n.write(&mut w).unwrap();
        assert_eq!(Nack::read(w.written()), Ok(n));
        let h = Hello {
            version: 1,
            max_payload: 240,
            flags: 1,
            name: b"fw 0.1",
        };
        let mut w = Writer::new(&mut buf);
        h.write(&mut w).unwrap();
        assert_eq!(Hello::read(w.written()), Ok(h));
    }

    fn roundtrip_len<F: Fn(&mut Writer<'_>) -> Result<(), PayloadError>>(write: F) -> Vec<u8> {
        let mut buf = [0u8; 240];
        let mut w = Writer::new(&mut buf);
        write(&mut w).unwrap();
        w.written().to_vec()
    }

    /// Every strict prefix and every one-byte extension of `bytes` must fail to parse.
    fn rejects_truncated_and_extended<T: core::fmt::Debug>(
        bytes: &[u8],
        read: impl Fn(&[u8]) -> Result<T, PayloadError>,
    ) {
        for n in 0..bytes.len() {
            assert!(read(&bytes[..n]).is_err(), "prefix of {n} bytes parsed");
        }
        let mut longer = bytes.to_vec();
        longer.push(0);
        assert!(read(&longer).is_err(), "trailing byte accepted");
    }

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
        for mode in [SampleMode::Learn, SampleMode::Predict, SampleMode::Resume] {
            let m = SampleMsg {
                mode,
                sample: sample(),
            };
            let b = roundtrip_len(|w| m.write(w));
            assert_eq!(b.len(), SampleMsg::LEN);
            let back = SampleMsg::read(&b).unwrap();
            assert_eq!(back.mode, mode);
            assert_eq!(back.sample.time_us, m.sample.time_us);
            assert_eq!(bits(&back.sample), bits(&m.sample));
            rejects_truncated_and_extended(&b, SampleMsg::read);
        }
        let mut b = roundtrip_len(|w| {
            SampleMsg {
                mode: SampleMode::Learn,
                sample: sample(),
            }
            .write(w)
        });
        b[0] = 3;
        assert_eq!(SampleMsg::read(&b), Err(PayloadError::InvalidValue));
    }

    fn all_errors() -> Vec<Option<Error>> {
        let qs = [
            Quantity::Roll,
            Quantity::Pitch,
            Quantity::Yaw,
            Quantity::Velocity(2),
            Quantity::Rate(1),
            Quantity::Control(3),
            Quantity::Time,
            Quantity::Premise(2),
            Quantity::Regressor(1484),
            Quantity::Target(2),
            Quantity::Parameter(53),
            Quantity::Covariance(1484),
            Quantity::Config,
        ];
        let cs = [
            ConfigError::MembershipFunction {
                variable: 2,
                set: 1,
            },
            ConfigError::RuleCount {
                expected: 27,
                found: 70_000,
            },
            ConfigError::Dimensions,
            ConfigError::InitialCovariance,
            ConfigError::Forgetting,
            ConfigError::ConsequentTerms {
                needed: 3,
                found: 2,
            },
            ConfigError::SamplePeriod,
            ConfigError::Sweep,
            ConfigError::Scale,
        ];
        let mut v = vec![
            None,
            Some(Error::TimeStep {
                dt_us: u64::MAX,
                min_us: 10_000,
                max_us: 30_000,
            }),
            Some(Error::NonMonotonicTime),
            Some(Error::Incompatible),
            Some(Error::Numerical),
        ];
        for q in qs {
            v.push(Some(Error::NonFinite(q)));
            v.push(Some(Error::OutOfRange(q)));
        }
        for c in cs {
            v.push(Some(Error::Config(c)));
        }
        v
    }

    #[test]
    fn every_error_roundtrips() {
        for e in all_errors() {
            let b = roundtrip_len(|w| write_error(w, e.as_ref()));
            assert_eq!(b.len(), ERROR_LEN);
            assert_eq!(read_error(&mut Reader::new(&b)), Ok(e));
            for n in 0..ERROR_LEN {
                assert!(read_error(&mut Reader::new(&b[..n])).is_err());
            }
        }
        let mut b = [0u8; ERROR_LEN];
        b[0] = 8;
        assert_eq!(
            read_error(&mut Reader::new(&b)),
            Err(PayloadError::InvalidValue)
        );
        b[0] = 1;
        b[1] = 14;
        assert!(read_error(&mut Reader::new(&b)).is_err());
        b[1] = 4;
        b[2] = 0;
        b[3] = 1; // Velocity(256) does not fit a u8
        assert!(read_error(&mut Reader::new(&b)).is_err());
        // A writer without room writes nothing.
        let mut small = [0u8; 10];
        let mut w = Writer::new(&mut small);
        assert!(write_error(&mut w, Some(&Error::Numerical)).is_err());
        assert!(w.is_empty());
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
            plain: IdOutput::rejected(Error::NonFinite(Quantity::Rate(0)), 7),
        };
        let b = roundtrip_len(|w| e.write(w));
        assert_eq!(b.len(), Estimate::LEN);
        const { assert!(Estimate::LEN <= crate::MAX_PAYLOAD) };
        assert_eq!(Estimate::read(&b), Ok(e));
        rejects_truncated_and_extended(&b, Estimate::read);
        let mut bad = b.clone();
        bad[8] = 9; // mode
        assert!(Estimate::read(&bad).is_err());
        let mut bad = b;
        bad[9 + ERROR_LEN] = 2; // flags
        assert!(Estimate::read(&bad).is_err());
    }

    #[test]
    fn small_requests_roundtrip() {
        for form in [RlsForm::UdDefault, RlsForm::PaperCovariance] {
            let m = ResetMsg { form };
            let b = roundtrip_len(|w| m.write(w));
            assert_eq!(ResetMsg::read(&b), Ok(m));
            rejects_truncated_and_extended(&b, ResetMsg::read);
        }
        assert!(ResetMsg::read(&[2]).is_err());
        for ident in [Ident::Fuzzy, Ident::Plain] {
            let m = IdentRequest { ident };
            let b = roundtrip_len(|w| m.write(w));
            assert_eq!(IdentRequest::read(&b), Ok(m));
            rejects_truncated_and_extended(&b, IdentRequest::read);
        }
        assert!(IdentRequest::read(&[2]).is_err());
        let m = MemoryReport {
            stack_size: 1,
            stack_peak: 2,
            static_ram: 3,
            ram_size: 4,
        };
        let b = roundtrip_len(|w| m.write(w));
        assert_eq!(b.len(), MemoryReport::LEN);
        assert_eq!(MemoryReport::read(&b), Ok(m));
        rejects_truncated_and_extended(&b, MemoryReport::read);
        let s = SweepStart {
            amplitudes: [0.05, 0.1, 0.2, 0.2],
            rate_hz: 50,
            start: 10,
            count: 500,
        };
        let b = roundtrip_len(|w| s.write(w));
        assert_eq!(b.len(), SweepStart::LEN);
        assert_eq!(SweepStart::read(&b), Ok(s));
        rejects_truncated_and_extended(&b, SweepStart::read);
        for channel in [
            Channel::Collective,
            Channel::Pedal,
            Channel::Longitudinal,
            Channel::Lateral,
        ] {
            let s = SweepSample {
                k: 3,
                total: 9,
                channel,
                offset: -0.125,
            };
            let b = roundtrip_len(|w| s.write(w));
            assert_eq!(b.len(), SweepSample::LEN);
            assert_eq!(SweepSample::read(&b), Ok(s));
            rejects_truncated_and_extended(&b, SweepSample::read);
        }
        assert!(SweepSample::read(&[0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0]).is_err());
    }

    #[test]
    fn chunks_roundtrip_and_check_bounds() {
        let words: Vec<u8> = (0..8u8).collect();
        let c = ParamsChunk {
            ident: Ident::Fuzzy,
            model: 3,
            field: ParamField::Summary,
            index: 0,
            total: 2,
            words: &words,
        };
        let b = roundtrip_len(|w| c.write(w));
        assert_eq!(ParamsChunk::read(&b), Ok(c));
        assert_eq!(c.iter().collect::<Vec<_>>(), [0x0302_0100, 0x0706_0504]);
        for n in 0..ParamsChunk::HEADER {
            assert!(ParamsChunk::read(&b[..n]).is_err());
        }
        assert!(
            ParamsChunk::read(&b[..b.len() - 1]).is_err(),
            "partial word"
        );
        let mut bad = b.clone();
        bad[1] = 4; // model
        assert!(ParamsChunk::read(&bad).is_err());
        let mut bad = b.clone();
        bad[5] = 1; // total 1 < index + words
        assert!(ParamsChunk::read(&bad).is_err());
        let too_many = [0u8; 4 * (ParamsChunk::MAX_WORDS + 1)];
        let mut buf = [0u8; 300];
        let big = ParamsChunk {
            words: &too_many,
            total: 1000,
            ..c
        };
        assert!(big.write(&mut Writer::new(&mut buf)).is_err());

        let data = [9u8; DataChunk::MAX_DATA];
        let d = DataChunk {
            ident: Ident::Plain,
            offset: 7,
            total: 7 + DataChunk::MAX_DATA as u32,
            crc: 0xDEAD_BEEF,
            data: &data,
        };
        let b = roundtrip_len(|w| d.write(w));
        assert_eq!(b.len(), crate::MAX_PAYLOAD);
        assert_eq!(DataChunk::read(&b), Ok(d));
        for n in 0..DataChunk::HEADER {
            assert!(DataChunk::read(&b[..n]).is_err());
        }
        let mut bad = b;
        bad[5] = 0; // total < offset + len
        assert!(DataChunk::read(&bad).is_err());
    }

    #[test]
    fn snapshot_stream_reads_back_exactly() {
        let theta = [1.0f32, -2.0];
        let factor = [3.0f32, 0.5, 4.0];
        let views = [
            ModelView {
                algorithm: Algorithm::UdFactor,
                updates: 77,
                theta: &theta,
                factor: &factor,
            },
            ModelView {
                algorithm: Algorithm::Covariance,
                updates: 1,
                theta: &factor[..2],
                factor: &theta[..1],
            },
        ];
        let len = snapshot_len(&views);
        assert_eq!(len, 25 + 17);
        // Read in odd-sized pieces; must equal one big read.
        let mut whole = vec![0u8; len + 5];
        assert_eq!(snapshot_read(&views, 0, &mut whole), len);
        whole.truncate(len);
        let mut pieces = Vec::new();
        let mut off = 0;
        loop {
            let mut buf = [0u8; 7];
            let n = snapshot_read(&views, off, &mut buf);
            if n == 0 {
                break;
            }
            pieces.extend_from_slice(&buf[..n]);
            off += n;
        }
        assert_eq!(pieces, whole);
        assert_eq!(snapshot_crc(&views), stream_crc(&whole));
        let mut r = Reader::new(&whole);
        let a = read_rls_state::<2, 3>(&mut r).unwrap();
        assert_eq!(
            (a.algorithm, a.updates, a.theta, a.factor),
            (Algorithm::UdFactor, 77, theta, factor)
        );
        let b = read_rls_state::<2, 1>(&mut r).unwrap();
        assert_eq!((b.algorithm, b.updates), (Algorithm::Covariance, 1));
        assert_eq!(r.finish(), Ok(()));
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&whole[..20])).is_err());
        let mut bad = whole.clone();
        bad[0] = 2;
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&bad)).is_err());
    }
}
