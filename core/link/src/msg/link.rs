//! Link-level messages: boot announcement, link statistics, acknowledgements.
//!
//! `Ping`/`Pong` carry raw bytes and `StatsRequest` is empty, so they have no struct here.

use super::message::{MsgType, Payload};
use crate::payload::{Field, PayloadError, Reader, Writer};
use crate::stats::LinkStats;

/// Boot announcement (`Hello`, 4 B + name): protocol version u8, max payload u16,
/// firmware flags u8, then the firmware name as UTF-8 (rest of the payload).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hello<'a> {
    /// Protocol version the firmware speaks ([`VERSION`](crate::wire::VERSION)).
    pub version: u8,
    /// Largest payload the firmware accepts, in bytes.
    pub max_payload: u16,
    /// Bit 0: the [`MsgType::FaultInject`] test hook is enabled.
    pub flags: u8,
    /// Firmware name and version, UTF-8.
    pub name: &'a [u8],
}

impl<'a> Hello<'a> {
    /// Bytes before the name.
    pub const HEADER: usize = 4;
}

impl<'a> Payload<'a> for Hello<'a> {
    const TYPES: &'static [MsgType] = &[MsgType::Hello];

    fn encoded_len(&self) -> usize {
        Self::HEADER + self.name.len()
    }

    fn put_fields(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.version)?;
        w.put_u16(self.max_payload)?;
        w.put_u8(self.flags)?;
        w.put_bytes(self.name)
    }

    fn get_fields(r: &mut Reader<'a>) -> Result<Self, PayloadError> {
        Ok(Self {
            version: r.get_u8()?,
            max_payload: r.get_u16()?,
            flags: r.get_u8()?,
            name: r.get_bytes(r.remaining())?,
        })
    }
}

/// The decoder's counters travel as [`LinkStats::FIELDS`] u32 in [`LinkStats::to_array`] order.
impl Field for LinkStats {
    const LEN: usize = 4 * LinkStats::FIELDS;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        self.to_array().put(w)
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        Field::get(r).map(LinkStats::from_array)
    }
}

fixed_payload! {
    /// Counters of the firmware side (`Stats`, 56 B): its receive [`LinkStats`] (10 × u32 in
    /// [`LinkStats::to_array`] order) then four application counters (u32 each).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct StatsReport for [Stats] {
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
}

wire_enum! {
    /// Why a request was refused (byte 3 of a `Nack`).
    #[non_exhaustive]
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
}

fixed_payload! {
    /// `Ack` payload (3 B): sequence number u16 and type u8 of the request acknowledged.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct Ack for [Ack] {
        /// Sequence number of the request.
        pub seq: u16,
        /// Type code of the request.
        pub msg_type: u8,
    }
}

fixed_payload! {
    /// `Nack` payload (4 B): the request's sequence number u16 and type u8, then the reason u8
    /// (a raw code so that reasons added later still parse).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct Nack for [Nack] {
        /// Sequence number of the request.
        pub seq: u16,
        /// Type code of the request.
        pub msg_type: u8,
        /// [`NackReason`] code.
        pub reason: u8,
    }
}

#[cfg(test)]
mod tests {
    use super::super::message::testing::{rejects_truncated_and_extended, roundtrip};
    use super::*;

    #[test]
    fn link_messages_roundtrip() {
        let s = StatsReport {
            link: LinkStats::from_array([1, 2, 3, 4, 5, 6, 7, 8, 9, 10]),
            unknown_type: 11,
            bad_payload: 12,
            uart_errors: 13,
            frames_sent: 14,
        };
        let b = roundtrip(&s);
        assert_eq!(b.len(), 56);
        assert_eq!(b[..4], [1, 0, 0, 0]);
        assert_eq!(b[52..], [14, 0, 0, 0]);
        assert_eq!(StatsReport::read(&b), Ok(s));
        rejects_truncated_and_extended::<StatsReport>(&b);

        let n = Nack {
            seq: 0x0203,
            msg_type: 0x77,
            reason: NackReason::UnknownType as u8,
        };
        let b = roundtrip(&n);
        assert_eq!(b, [3, 2, 0x77, 1]);
        assert_eq!(Nack::read(&b), Ok(n));
        rejects_truncated_and_extended::<Nack>(&b);

        let a = Ack {
            seq: 5,
            msg_type: 0x14,
        };
        let b = roundtrip(&a);
        assert_eq!(b, [5, 0, 0x14]);
        assert_eq!(Ack::read(&b), Ok(a));
        rejects_truncated_and_extended::<Ack>(&b);

        let h = Hello {
            version: 1,
            max_payload: 240,
            flags: 1,
            name: b"fw 0.1",
        };
        let b = roundtrip(&h);
        assert_eq!(b[..4], [1, 240, 0, 1]);
        assert_eq!(Hello::read(&b), Ok(h));
        for n in 0..Hello::HEADER {
            assert!(Hello::read(&b[..n]).is_err());
        }
    }
}
