//! MAVLink 2 telemetry port (UART1), beside the COBS link on UART0.
//!
//! Always on, write-only: an autopilot's TELEM port, not a second command channel (samples and
//! requests arrive on the COBS link). What it sends (docs/protocol.md, "MAVLink 2"): a
//! `HEARTBEAT` at boot and after every [`HEARTBEAT_EVERY`] samples, for every sample each
//! identifier's step array (or a `STATUSTEXT` when it rejected the sample), and θ of every model
//! after a `ParamsRequest` for that identifier. Heartbeats count samples instead of time
//! because this firmware has no timer interrupt; at 50 samples/s that is every 2 s.

use embedded_io::Write;
use rotorid_link::msg::{Estimate, IdOutput, Ident};
use rotorid_mavlink::{chunk_count, Encoder, MavState, Model, Sender, MAX_FRAME_LEN};

/// A heartbeat after this many samples.
pub const HEARTBEAT_EVERY: u32 = 100;
/// MAVLink system id (a vehicle's default) and component id (`MAV_COMP_ID_USER1`).
pub const SYSTEM_ID: u8 = 1;
/// See [`SYSTEM_ID`].
pub const COMPONENT_ID: u8 = 25;

/// The port: a byte sink, the encoder and what the messages need to know.
pub struct MavlinkPort<W> {
    io: W,
    enc: Encoder,
    idents: [Sender; 2],
    samples: u32,
    last_time_us: u64,
}

impl<W: Write> MavlinkPort<W> {
    /// A port writing to `io`; sends the boot heartbeat. `None` only if the identifier tags
    /// are invalid (a programming error).
    pub fn new(io: W) -> Option<Self> {
        let idents = [Sender::new(0, "ts").ok()?, Sender::new(1, "pl").ok()?];
        let mut port = Self {
            io,
            enc: Encoder::new(SYSTEM_ID, COMPONENT_ID),
            idents,
            samples: 0,
            last_time_us: 0,
        };
        port.send(|e, b| e.heartbeat(MavState::MAV_STATE_ACTIVE, b));
        Some(port)
    }

    /// The outputs of one sample, both identifiers.
    pub fn estimate(&mut self, est: &Estimate) {
        self.last_time_us = est.time_us;
        let [ts, pl] = self.idents;
        for (ident, out) in [(ts, &est.fuzzy), (pl, &est.plain)] {
            self.output(&ident, est.time_us, out);
        }
        self.samples = self.samples.wrapping_add(1);
        if self.samples.is_multiple_of(HEARTBEAT_EVERY) {
            self.send(|e, b| e.heartbeat(MavState::MAV_STATE_ACTIVE, b));
        }
    }

    /// θ of the four models of `which` (after a `ParamsRequest`), stamped with the last sample.
    pub fn thetas(&mut self, which: Ident, thetas: &[&[f32]; 4]) {
        let ident = match which {
            Ident::Plain => self.idents[1],
            _ => self.idents[0],
        };
        let time_us = self.last_time_us;
        for (model, theta) in Model::ALL.into_iter().zip(thetas) {
            for c in 0..chunk_count(theta.len()).min(256) {
                self.send(|e, b| e.theta(&ident, model, c as u8, time_us, theta, b));
            }
        }
    }

    fn output(&mut self, ident: &Sender, time_us: u64, out: &IdOutput) {
        match &out.error {
            Some(err) => self.send(|e, b| e.rejected(ident, err, b)),
            None => self
                .send(|e, b| e.step(ident, time_us, &out.prediction, out.innovation.as_ref(), b)),
        }
    }

    fn send(
        &mut self,
        f: impl FnOnce(&mut Encoder, &mut [u8]) -> Result<usize, rotorid_mavlink::EncodeError>,
    ) {
        let mut buf = [0u8; MAX_FRAME_LEN];
        match f(&mut self.enc, &mut buf) {
            Ok(n) => {
                if let Err(e) = self.io.write_all(buf.get(..n).unwrap_or_default()) {
                    defmt::warn!("MAVLink write: {}", embedded_io::Error::kind(&e) as u8);
                }
            }
            Err(e) => defmt::error!("MAVLink encode: {}", defmt::Display2Format(&e)),
        }
    }
}
