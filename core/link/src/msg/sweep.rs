//! The onboard sweep generator: start it, receive its commands.

use crate::payload::{Field, PayloadError, Reader, Writer};
use rotorid::sweep::Channel;

/// A channel travels as one byte, its index in `[u_col u_ped u_lon u_lat]`.
impl Field for Channel {
    const LEN: usize = 1;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        let code = u8::try_from(self.index()).map_err(|_| PayloadError::InvalidValue)?;
        w.put_u8(code)
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        match r.get_u8()? {
            0 => Ok(Channel::Collective),
            1 => Ok(Channel::Pedal),
            2 => Ok(Channel::Longitudinal),
            3 => Ok(Channel::Lateral),
            _ => Err(PayloadError::InvalidValue),
        }
    }
}

fixed_payload! {
    /// `SweepStart` payload (26 B): amplitudes 4 × f32 `[col, ped, lon, lat]` (stick units),
    /// `rate_hz` u16, `start` u32, `count` u32. The firmware builds
    /// `SweepSchedule::table2(amplitudes, rate_hz)` and streams `count` [`SweepSample`]s from
    /// index `start` (fewer at the end of the schedule), then an `Ack`.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct SweepStart for [SweepStart] {
        /// Per-channel amplitudes `[col, ped, lon, lat]` (stick units).
        pub amplitudes: [f32; 4],
        /// Sample rate (Hz).
        pub rate_hz: u16,
        /// First sample index.
        pub start: u32,
        /// Samples to stream.
        pub count: u32,
    }
}

fixed_payload! {
    /// `SweepSample` payload (17 B): index k u32, schedule length u32, channel u8 (0 col,
    /// 1 ped, 2 lon, 3 lat), offset from trim f64 (stick units).
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct SweepSample for [SweepSample] {
        /// Sample index.
        pub k: u32,
        /// Samples in the whole schedule.
        pub total: u32,
        /// The channel being swept.
        pub channel: Channel,
        /// Offset from trim on it.
        pub offset: f64,
    }
}

#[cfg(test)]
mod tests {
    use super::super::message::testing::{rejects_truncated_and_extended, roundtrip};
    use super::super::message::Payload;
    use super::*;

    #[test]
    fn sweep_messages_roundtrip() {
        let s = SweepStart {
            amplitudes: [0.05, 0.1, 0.2, 0.2],
            rate_hz: 50,
            start: 10,
            count: 500,
        };
        let b = roundtrip(&s);
        assert_eq!(b.len(), 26);
        assert_eq!(b[..4], 0.05f32.to_le_bytes());
        assert_eq!(b[16..18], [50, 0]);
        assert_eq!(SweepStart::read(&b), Ok(s));
        rejects_truncated_and_extended::<SweepStart>(&b);
        for (code, channel) in [
            Channel::Collective,
            Channel::Pedal,
            Channel::Longitudinal,
            Channel::Lateral,
        ]
        .into_iter()
        .enumerate()
        {
            let s = SweepSample {
                k: 3,
                total: 9,
                channel,
                offset: -0.125,
            };
            let b = roundtrip(&s);
            assert_eq!(b.len(), 17);
            assert_eq!(usize::from(b[8]), code);
            assert_eq!(SweepSample::read(&b), Ok(s));
            rejects_truncated_and_extended::<SweepSample>(&b);
        }
        assert!(SweepSample::read(&[0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0]).is_err());
    }
}
