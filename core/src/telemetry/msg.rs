//! Message catalogue: type codes and the payload layouts of the link-level messages.
//!
//! Requests and replies have distinct type codes so every frame is self-describing. Codes
//! `0x01..=0x0F` are the link layer (implemented now), `0x10..=0x2F` are reserved for the
//! identification messages, `0x80..=0xFF` are free for vendor experiments. The full table with
//! directions and payload layouts is in `docs/protocol.md`; keep both in sync.

use super::{LinkStats, PayloadError, Reader, Writer};

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

    // --- identification (reserved, not implemented yet) ---
    /// Host→FW: one measurement sample (inputs, outputs, time stamp).
    Sample = 0x10,
    /// FW→host: predictions and innovations for the last sample.
    Estimate = 0x11,
    /// Host→FW: ask for a parameter dump.
    ParamsRequest = 0x12,
    /// FW→host: parameter dump (chunked: offset + bytes).
    Params = 0x13,
    /// Host→FW: reset the identifier; answered by [`MsgType::Ack`].
    Reset = 0x14,
    /// Host→FW: ask for an export of the identifier state.
    ExportRequest = 0x15,
    /// FW→host: one chunk of exported state (offset + bytes).
    ExportChunk = 0x16,
    /// Host→FW: one chunk of state to import; answered by Ack/Nack.
    ImportChunk = 0x17,
    /// Host→FW: configure and start the sweep (excitation) generator.
    SweepStart = 0x18,
    /// FW→host: one sample of the sweep generator output.
    SweepSample = 0x19,
}

impl MsgType {
    /// Every known type, in code order.
    pub const ALL: [MsgType; 20] = [
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
