//! The message type codes ([`MsgType`]) and the [`Payload`] trait every message implements:
//! what the message modules share, below them (see the [catalogue](super)).

use crate::payload::{PayloadError, Reader, Writer};

wire_enum! {
    /// Message type codes (byte 1 of a raw frame).
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum MsgType {
        // --- link layer ---
        /// FW→host, once at boot: [`Hello`](super::link::Hello).
        Hello = 0x01,
        /// Host→FW: any payload (≤ 240 B), answered by [`MsgType::Pong`] with the same payload.
        Ping = 0x02,
        /// FW→host: echo of a ping payload.
        Pong = 0x03,
        /// Host→FW: empty; answered by [`MsgType::Stats`].
        StatsRequest = 0x04,
        /// FW→host: [`StatsReport`](super::link::StatsReport).
        Stats = 0x05,
        /// Host→FW, test hook: [`CostRequest`](super::test_hooks::CostRequest); answered by [`MsgType::Cost`].
        CostRequest = 0x06,
        /// FW→host, test hook: [`CostReport`](super::test_hooks::CostReport).
        Cost = 0x07,
        /// FW→host: [`Ack`](super::link::Ack) of a command that has no other reply.
        Ack = 0x08,
        /// FW→host: [`Nack`](super::link::Nack), a request was not understood or not carried out.
        Nack = 0x09,
        /// Host→FW, test hook: one [`FaultKind`](super::test_hooks::FaultKind) byte; the firmware crashes on purpose.
        FaultInject = 0x0F,

        // --- identification ---
        /// Host→FW: [`SampleMsg`](super::ident::SampleMsg), one measurement sample and what to do with it.
        Sample = 0x10,
        /// FW→host: [`Estimate`](super::ident::Estimate), predictions and innovations of both identifiers.
        Estimate = 0x11,
        /// Host→FW: [`ParamsRequest`](super::ident::ParamsRequest), ask for a parameter dump.
        ParamsRequest = 0x12,
        /// FW→host: [`ParamsChunk`](super::params::ParamsChunk), one piece of the parameter dump.
        Params = 0x13,
        /// Host→FW: [`ResetMsg`](super::ident::ResetMsg), restart both identifiers; answered by [`MsgType::Ack`].
        Reset = 0x14,
        /// Host→FW: [`ExportRequest`](super::ident::ExportRequest), ask for an export of an identifier's state.
        ExportRequest = 0x15,
        /// FW→host: [`DataChunk`](super::snapshot::DataChunk) of exported state.
        ExportChunk = 0x16,
        /// Host→FW: [`DataChunk`](super::snapshot::DataChunk) of state to import; each answered by Ack/Nack.
        ImportChunk = 0x17,
        /// Host→FW: [`SweepStart`](super::sweep::SweepStart), run the onboard sweep generator.
        SweepStart = 0x18,
        /// FW→host: [`SweepSample`](super::sweep::SweepSample), one command of the sweep generator.
        SweepSample = 0x19,
        /// Host→FW, test hook: empty; answered by [`MsgType::Memory`].
        MemoryRequest = 0x1A,
        /// FW→host, test hook: [`MemoryReport`](super::test_hooks::MemoryReport), stack high-water mark and RAM layout.
        Memory = 0x1B,
        /// Host→FW: [`CompensateMsg`](super::ident::CompensateMsg), compensate the active pair's rate models for the
        /// gyros' noise (the parameters to free-run with); answered by [`MsgType::Ack`].
        Compensate = 0x1C,
        /// Host→FW: [`CompensateEachMsg`](super::ident::CompensateEachMsg), `Compensate` with a
        /// choice per rate (damping or full); answered by [`MsgType::Ack`].
        CompensateEach = 0x1D,
        /// Host→FW: [`PremisesMsg`](super::ident::PremisesMsg), the flight default's speed sets
        /// per model and the speed each is on (what `flight selected` chose); answered by
        /// [`MsgType::Ack`].
        Premises = 0x1E,
    }
}

/// A message payload: which frame types carry it, its length, and its field list.
///
/// Implementors write the field list once ([`put_fields`](Payload::put_fields) /
/// [`get_fields`](Payload::get_fields)); the provided [`write`](Payload::write) and
/// [`read`](Payload::read) are what senders and receivers call.
pub trait Payload<'a>: Sized {
    /// The frame types whose payload has this layout (two for the shared layouts, e.g.
    /// [`DataChunk`](super::snapshot::DataChunk) for both export and import chunks).
    const TYPES: &'static [MsgType];

    /// Encoded length of this payload, in bytes.
    fn encoded_len(&self) -> usize;

    /// Appends the fields in wire order (called by [`write`](Payload::write) once there is
    /// room for all of them).
    fn put_fields(&self, w: &mut Writer<'_>) -> Result<(), PayloadError>;

    /// Reads the fields in wire order (called by [`read`](Payload::read)).
    fn get_fields(r: &mut Reader<'a>) -> Result<Self, PayloadError>;

    /// Writes the payload; a writer without room for all of it gets nothing.
    fn write(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        let needed = self.encoded_len();
        let remaining = w.remaining();
        if needed > remaining {
            return Err(PayloadError::Overflow { needed, remaining });
        }
        self.put_fields(w)
    }

    /// Parses a whole payload: exactly the fields, no trailing bytes.
    fn read(payload: &'a [u8]) -> Result<Self, PayloadError> {
        let mut r = Reader::new(payload);
        let value = Self::get_fields(&mut r)?;
        r.finish()?;
        Ok(value)
    }
}

#[cfg(test)]
pub(crate) mod testing {
    //! Checks every payload test shares.
    extern crate alloc;
    use super::Payload;
    use alloc::vec::Vec;
    use core::fmt::Debug;

    /// Writes `p`, checks the length it claims, that it reads back equal, that a writer one
    /// byte short gets nothing, and returns the bytes.
    pub fn roundtrip<'a, P: Payload<'a> + PartialEq + Debug>(p: &P) -> Vec<u8> {
        let mut buf = [0u8; crate::wire::MAX_PAYLOAD];
        let mut w = crate::Writer::new(&mut buf);
        p.write(&mut w).unwrap();
        let bytes = w.written().to_vec();
        assert_eq!(bytes.len(), p.encoded_len());
        let mut short = [0u8; crate::wire::MAX_PAYLOAD];
        let mut w = crate::Writer::new(&mut short[..bytes.len() - 1]);
        assert!(p.write(&mut w).is_err());
        assert!(w.is_empty(), "a failed write wrote something");
        bytes
    }

    /// Every strict prefix and every one-byte extension of `bytes` must fail to parse as `P`.
    pub fn rejects_truncated_and_extended<P>(bytes: &[u8])
    where
        P: for<'a> Payload<'a> + Debug,
    {
        for n in 0..bytes.len() {
            assert!(P::read(&bytes[..n]).is_err(), "prefix of {n} bytes parsed");
        }
        let mut longer = bytes.to_vec();
        longer.push(0);
        assert!(P::read(&longer).is_err(), "trailing byte accepted");
    }
}
