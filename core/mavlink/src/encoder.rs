//! The encoder: rotorid's outputs as MAVLink 2 frames written into a caller's buffer.

use core::fmt::Write as _;

use mavlink_core::MessageData;
use rotorid::convergence::ConvergenceStatus;
use rotorid::Error;

use crate::array_id::{chunk_count, ArrayId, ArrayKind, Model, Sender, ARRAY_LEN};
use crate::dialect::{
    MavAutopilot, MavModeFlag, MavSeverity, MavState, MavType, DEBUG_FLOAT_ARRAY_DATA,
    HEARTBEAT_DATA, NAMED_VALUE_FLOAT_DATA, STATUSTEXT_DATA,
};
use crate::EncodeError;

/// Bytes of a `name` field (NAMED_VALUE_FLOAT, DEBUG_FLOAT_ARRAY).
const NAME_LEN: usize = 10;
/// Bytes of STATUSTEXT's `text`.
const TEXT_LEN: usize = 50;

/// Writes rotorid's telemetry as MAVLink 2 frames (unsigned) from one system and component,
/// numbering them with the link's wrapping sequence byte.
///
/// Every method writes whole frames at the start of `out` and returns their length; a buffer of
/// [`crate::MAX_FRAME_LEN`] bytes fits any single frame. On an error nothing is counted
/// (the sequence number is unchanged) and `out`'s content is unspecified.
#[derive(Clone, Debug)]
pub struct Encoder {
    system_id: u8,
    component_id: u8,
    sequence: u8,
}

impl Encoder {
    /// An encoder for system `system_id` (the vehicle's, `SYSID_THISMAV` / `MAV_SYS_ID`) and
    /// component `component_id` (e.g. 25, `MAV_COMP_ID_USER1`), starting at sequence 0.
    pub const fn new(system_id: u8, component_id: u8) -> Self {
        Self {
            system_id,
            component_id,
            sequence: 0,
        }
    }

    /// Sequence number of the next frame.
    pub fn sequence(&self) -> u8 {
        self.sequence
    }

    /// `HEARTBEAT` (id 0): an onboard component that is not an autopilot
    /// (`MAV_TYPE_ONBOARD_CONTROLLER`, `MAV_AUTOPILOT_INVALID`), `custom_mode` 0, status as given
    /// (`MAV_STATE_ACTIVE` while identifying, `MAV_STATE_CRITICAL` after a fault).
    pub fn heartbeat(&mut self, status: MavState, out: &mut [u8]) -> Result<usize, EncodeError> {
        // Fields in MAVLink wire order: custom_mode, type, autopilot, base_mode, system_status,
        // mavlink_version.
        let mut p = Payload::<{ HEARTBEAT_DATA::ENCODED_LEN }>::new();
        p.put(&0u32.to_le_bytes());
        p.put(&[
            MavType::MAV_TYPE_ONBOARD_CONTROLLER as u8,
            MavAutopilot::MAV_AUTOPILOT_INVALID as u8,
            MavModeFlag::empty().bits(),
            status as u8,
            3,
        ]);
        self.frame::<HEARTBEAT_DATA, _>(p, out)
    }

    /// `DEBUG_FLOAT_ARRAY` (id 350) of one accepted step of `ident` on the sample stamped
    /// `time_us`: the prediction `[v_x v_y v_z q r p]` (m/s, deg/s) for the next sample and the
    /// prior innovation (measured − predicted, same order; NaN when the step had none).
    pub fn step(
        &mut self,
        ident: &Sender,
        time_us: u64,
        prediction: &[f32; 6],
        innovation: Option<&[f32; 6]>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let mut data = [0f32; ARRAY_LEN];
        let nan = [f32::NAN; 6];
        let values = prediction.iter().chain(innovation.unwrap_or(&nan));
        for (d, v) in data.iter_mut().zip(values) {
            *d = *v;
        }
        let mut name = Name::new(ident);
        name.push(b".out");
        self.array(ident, ArrayKind::Step, 0, time_us, name, data, out)
    }

    /// `DEBUG_FLOAT_ARRAY` with chunk `chunk` of `model`'s parameter vector θ (in the core's
    /// order, see docs/protocol.md): floats `58·chunk ..` of `theta`, zeros past its end. There
    /// are [`chunk_count`]`(theta.len())` chunks.
    pub fn theta(
        &mut self,
        ident: &Sender,
        model: Model,
        chunk: u8,
        time_us: u64,
        theta: &[f32],
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let chunks = chunk_count(theta.len());
        if usize::from(chunk) >= chunks || chunks > 256 {
            return Err(EncodeError::ChunkOutOfRange);
        }
        let mut data = [0f32; ARRAY_LEN];
        let start = usize::from(chunk) * ARRAY_LEN;
        for (d, v) in data.iter_mut().zip(theta.iter().skip(start)) {
            *d = *v;
        }
        let mut name = Name::new(ident);
        name.push(b".th");
        name.push(&[model.letter()]);
        name.decimal(u32::from(chunk));
        self.array(
            ident,
            ArrayKind::Theta(model),
            chunk,
            time_us,
            name,
            data,
            out,
        )
    }

    /// `NAMED_VALUE_FLOAT`s (id 251) of a convergence indicator over `M` outputs: `<tag>.rho<i>`
    /// the ratio ρ of output `i` (0-based, the monitor's order) for each output, then
    /// `<tag>.conv`, the bit mask of converged outputs (bit `i` for output `i`) as a float.
    /// `M + 1` frames, each under 32 bytes.
    pub fn convergence<const M: usize>(
        &mut self,
        ident: &Sender,
        time_boot_ms: u32,
        status: &ConvergenceStatus<f32, M>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        if M > 24 {
            // The mask would not be exact in an f32.
            return Err(EncodeError::TooManyOutputs);
        }
        let first = self.sequence;
        // All frames or none counted: on an error the sequence goes back to `first`.
        let mut frames = || -> Result<usize, EncodeError> {
            let mut written = 0;
            let mut mask = 0u32;
            for (i, (rho, converged)) in status.ratio.iter().zip(&status.converged).enumerate() {
                let mut name = Name::new(ident);
                name.push(b".rho");
                name.decimal(i as u32);
                let rest = out.get_mut(written..).unwrap_or(&mut []);
                written += self.named(time_boot_ms, name, *rho, rest)?;
                mask |= u32::from(*converged) << i;
            }
            let mut name = Name::new(ident);
            name.push(b".conv");
            let rest = out.get_mut(written..).unwrap_or(&mut []);
            Ok(written + self.named(time_boot_ms, name, mask as f32, rest)?)
        };
        let result = frames();
        if result.is_err() {
            self.sequence = first;
        }
        result
    }

    /// `STATUSTEXT` (id 253), severity `MAV_SEVERITY_WARNING`: `"<tag>: <error>"` for a sample
    /// the core rejected (its state is then unchanged), in ASCII (Greek letters and `µ` spelled
    /// out: `θ` → `theta`, `µs` → `us`; other non-ASCII → `?`), cut to the field's 50 bytes.
    pub fn rejected(
        &mut self,
        ident: &Sender,
        error: &Error,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let mut text = Text::default();
        // Text::write_str never fails: it stops at the end of the field.
        let _ = write!(text, "{}: {}", ident.tag(), error);
        // severity, text, then the extensions id (0: not chunked) and chunk_seq.
        let mut p = Payload::<{ STATUSTEXT_DATA::ENCODED_LEN }>::new();
        p.put(&[MavSeverity::MAV_SEVERITY_WARNING as u8]);
        p.put(&text.bytes);
        p.put(&[0, 0, 0]);
        self.frame::<STATUSTEXT_DATA, _>(p, out)
    }

    #[allow(clippy::too_many_arguments)]
    fn array(
        &mut self,
        ident: &Sender,
        kind: ArrayKind,
        chunk: u8,
        time_us: u64,
        name: Name,
        data: [f32; ARRAY_LEN],
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let id = ArrayId {
            slot: ident.slot(),
            kind,
            chunk,
        };
        // time_usec, array_id, name, then the extension data.
        let mut p = Payload::<{ DEBUG_FLOAT_ARRAY_DATA::ENCODED_LEN }>::new();
        p.put(&time_us.to_le_bytes());
        p.put(&id.to_u16().to_le_bytes());
        p.put(&name.bytes);
        for x in data {
            p.put(&x.to_le_bytes());
        }
        self.frame::<DEBUG_FLOAT_ARRAY_DATA, _>(p, out)
    }

    fn named(
        &mut self,
        time_boot_ms: u32,
        name: Name,
        value: f32,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        // time_boot_ms, value, name.
        let mut p = Payload::<{ NAMED_VALUE_FLOAT_DATA::ENCODED_LEN }>::new();
        p.put(&time_boot_ms.to_le_bytes());
        p.put(&value.to_le_bytes());
        p.put(&name.bytes);
        self.frame::<NAMED_VALUE_FLOAT_DATA, _>(p, out)
    }

    /// Writes one unsigned MAVLink 2 frame of message `D` around `payload`: STX, length,
    /// incompatibility and compatibility flags (0), sequence, system, component, the 3-byte
    /// message id, the payload without its trailing zero bytes (at least one byte, as MAVLink
    /// 2 truncates), and the CRC-16/MCRF4XX of everything after STX plus `D`'s CRC_EXTRA.
    ///
    /// Written here rather than with `mavlink-core`'s serializer, whose bounds checks and
    /// asserts would put panic paths on the firmware's flight path (`scripts/no_panic.py`);
    /// `tests/encode.rs` checks these bytes against that serializer's.
    fn frame<D: MessageData, const N: usize>(
        &mut self,
        payload: Payload<N>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        const { assert!(N >= 1 && N <= 255) };
        let body = payload.bytes;
        let len = body.iter().rposition(|&b| b != 0).map_or(1, |i| i + 1);
        let needed = HEADER_LEN + len + 2;
        if out.len() < needed {
            return Err(EncodeError::BufferTooSmall {
                needed,
                available: out.len(),
            });
        }
        let [id0, id1, id2, _] = D::ID.to_le_bytes();
        let header = [
            MAVLINK_V2_STX,
            len as u8,
            0,
            0,
            self.sequence,
            self.system_id,
            self.component_id,
            id0,
            id1,
            id2,
        ];
        let body = body.get(..len).unwrap_or(&[]);
        let mut crc = X25.digest();
        crc.update(header.get(1..).unwrap_or(&[]));
        crc.update(body);
        crc.update(&[D::EXTRA_CRC]);
        let crc = crc.finalize().to_le_bytes();
        let frame = header.iter().chain(body).chain(&crc);
        for (dst, src) in out.iter_mut().zip(frame) {
            *dst = *src;
        }
        self.sequence = self.sequence.wrapping_add(1);
        Ok(needed)
    }
}

/// MAVLink 2's start byte.
const MAVLINK_V2_STX: u8 = 0xFD;
/// STX and the nine header bytes of an unsigned MAVLink 2 frame.
const HEADER_LEN: usize = 10;
/// MAVLink's checksum: CRC-16/MCRF4XX ("X.25" in the MAVLink docs).
const X25: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_MCRF4XX);

/// A message's payload being filled in wire order (bytes past the end are dropped; every
/// payload here is written with exactly its message's length).
struct Payload<const N: usize> {
    bytes: [u8; N],
    len: usize,
}

impl<const N: usize> Payload<N> {
    fn new() -> Self {
        Self {
            bytes: [0; N],
            len: 0,
        }
    }

    fn put(&mut self, src: &[u8]) {
        for &b in src {
            if let Some(d) = self.bytes.get_mut(self.len) {
                *d = b;
                self.len += 1;
            }
        }
    }
}

/// A `char[10]` name being built; [`Sender`]'s tag limit makes every name this crate builds fit.
struct Name {
    bytes: [u8; NAME_LEN],
    len: usize,
}

impl Name {
    fn new(ident: &Sender) -> Self {
        let mut n = Self {
            bytes: [0; NAME_LEN],
            len: 0,
        };
        n.push(ident.tag().as_bytes());
        n
    }

    fn push(&mut self, s: &[u8]) {
        for &b in s {
            if let Some(d) = self.bytes.get_mut(self.len) {
                *d = b;
                self.len += 1;
            }
        }
    }

    fn decimal(&mut self, v: u32) {
        let mut digits = [0u8; 10];
        let mut n = v;
        let mut k = digits.len();
        loop {
            k -= 1;
            if let Some(d) = digits.get_mut(k) {
                *d = b'0' + (n % 10) as u8;
            }
            n /= 10;
            if n == 0 || k == 0 {
                break;
            }
        }
        self.push(digits.get(k..).unwrap_or(&[]));
    }
}

/// STATUSTEXT's text in ASCII: the core's messages use a few Greek letters and `µ`, which are
/// spelled out (pymavlink and MAVProxy decode the field as ASCII); anything else non-ASCII
/// becomes `?`. Cut at the field's 50 bytes.
struct Text {
    bytes: [u8; TEXT_LEN],
    len: usize,
}

impl Default for Text {
    fn default() -> Self {
        Self {
            bytes: [0; TEXT_LEN],
            len: 0,
        }
    }
}

/// ASCII spelling of a character of the core's error messages.
fn ascii(c: char) -> &'static str {
    match c {
        'µ' | 'μ' => "u",
        'α' => "alpha",
        'λ' => "lambda",
        'θ' => "theta",
        'φ' => "phi",
        'ψ' => "psi",
        'ξ' => "xi",
        '…' => "..",
        _ => "?",
    }
}

impl core::fmt::Write for Text {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for c in s.chars() {
            let mut one = [0u8; 4];
            let part = if c.is_ascii() {
                &*c.encode_utf8(&mut one)
            } else {
                ascii(c)
            };
            for &b in part.as_bytes() {
                if let Some(d) = self.bytes.get_mut(self.len) {
                    *d = b;
                    self.len += 1;
                }
            }
        }
        Ok(())
    }
}
