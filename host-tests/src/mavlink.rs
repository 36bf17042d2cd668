//! rotorid's MAVLink 2 telemetry of a whole identification run, and what an independent
//! decoder must find in it (the pymavlink test, `tests/mavlink_pymavlink.rs`).
//!
//! [`identification_stream`] runs the onboard pair ([`Mirror`]: the firmware's fuzzy and plain
//! identifiers, host build) over a flight and encodes, with [`rotorid_mavlink::Encoder`], what a
//! vehicle would send: a heartbeat every [`HEARTBEAT_EVERY`] samples, one step array per
//! identifier and sample (or a STATUSTEXT when the core rejected it), convergence values at the
//! end of each window, and θ of every model at the end. Beside the bytes it lists every message
//! with its expected fields straight from the Rust values (floats as f32 bit patterns).

use rotorid::convergence::ConvergenceMonitor;
use rotorid::hover::HoverSample;
use rotorid::telemetry::msg::{IdOutput, SampleMode};
use rotorid::HoverState;
use rotorid_mavlink::{chunk_count, Encoder, Ident, MavState, Model, ARRAY_LEN, MAX_FRAME_LEN};
use serde_json::{json, Value};

use crate::onboard::{messages, Mirror};

/// System id of the stream (a vehicle's default `SYSID_THISMAV`).
pub const SYSTEM_ID: u8 = 1;
/// Component id of the stream (`MAV_COMP_ID_USER1`).
pub const COMPONENT_ID: u8 = 25;
/// A heartbeat before the first sample and after every this many samples.
pub const HEARTBEAT_EVERY: usize = 100;
/// Convergence window (samples), tolerance and settle count of the streamed indicator.
pub const CONVERGENCE: (u32, f32, u16) = (200, 0.1, 3);

/// The encoded stream and, per frame in order, the message the decoder must find.
pub struct Stream {
    /// MAVLink 2 frames back to back.
    pub bytes: Vec<u8>,
    /// One JSON object per frame: `type`, `seq`, `sys`, `comp` and `fields` (name → value;
    /// an f32 as `{"f32": bits}`, an array as a list, text as a string).
    pub expected: Vec<Value>,
}

fn f32s(v: &[f32]) -> Value {
    Value::Array(v.iter().map(|x| json!({ "f32": x.to_bits() })).collect())
}

struct Writer {
    enc: Encoder,
    stream: Stream,
}

impl Writer {
    /// Encodes one frame with `f` and records `fields` as its expectation.
    fn push(
        &mut self,
        kind: &str,
        fields: Value,
        f: impl FnOnce(&mut Encoder, &mut [u8]) -> Result<usize, rotorid_mavlink::EncodeError>,
    ) {
        let seq = self.enc.sequence();
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = f(&mut self.enc, &mut buf).expect("a full-size buffer fits every frame");
        self.stream.bytes.extend_from_slice(&buf[..n]);
        self.stream.expected.push(json!({
            "type": kind, "seq": seq, "sys": SYSTEM_ID, "comp": COMPONENT_ID, "fields": fields,
        }));
    }

    fn heartbeat(&mut self) {
        let fields = json!({ "type": 18, "autopilot": 8, "base_mode": 0, "custom_mode": 0,
                             "system_status": 4, "mavlink_version": 3 });
        self.push("HEARTBEAT", fields, |e, b| {
            e.heartbeat(MavState::MAV_STATE_ACTIVE, b)
        });
    }

    fn output(&mut self, ident: &Ident, time_us: u64, out: &IdOutput) {
        if let Some(err) = &out.error {
            // The documented ASCII spelling of the core's few non-ASCII characters.
            let mut text = format!("{}: {err}", ident.tag());
            for (from, to) in [("µ", "u"), ("θ", "theta"), ("…", "..")] {
                text = text.replace(from, to);
            }
            text.truncate(50);
            let fields = json!({ "severity": 4, "text": text });
            self.push("STATUSTEXT", fields, |e, b| e.rejected(ident, err, b));
            return;
        }
        let mut data = [0f32; ARRAY_LEN];
        data[..6].copy_from_slice(&out.prediction);
        data[6..12].copy_from_slice(&out.innovation.unwrap_or([f32::NAN; 6]));
        let fields = json!({ "time_usec": time_us, "array_id": 0x0100 | u16::from(ident.slot()) << 12,
                             "name": format!("{}.out", ident.tag()), "data": f32s(&data) });
        self.push("DEBUG_FLOAT_ARRAY", fields, |e, b| {
            e.step(ident, time_us, &out.prediction, out.innovation.as_ref(), b)
        });
    }

    fn theta(&mut self, ident: &Ident, model: Model, time_us: u64, theta: &[f32]) {
        for c in 0..chunk_count(theta.len()) {
            let mut data = [0f32; ARRAY_LEN];
            let part = &theta[(c * ARRAY_LEN).min(theta.len())..];
            let k = part.len().min(ARRAY_LEN);
            data[..k].copy_from_slice(&part[..k]);
            let id = u16::from(ident.slot()) << 12 | (2 + model as u16) << 8 | c as u16;
            let letter = char::from(model.letter());
            let fields = json!({ "time_usec": time_us, "array_id": id,
                                 "name": format!("{}.th{letter}{c}", ident.tag()), "data": f32s(&data) });
            self.push("DEBUG_FLOAT_ARRAY", fields, |e, b| {
                e.theta(ident, model, c as u8, time_us, theta, b)
            });
        }
    }
}

/// The telemetry of learning `flight` (every sample in Learn mode, one sample's velocity made
/// NaN at `flight.len() / 2` so that both identifiers reject one sample for real; the sample
/// after it resumes the chain, as a client must after a gap).
pub fn identification_stream(flight: &[HoverSample<f32>]) -> Stream {
    let mut samples = messages(flight, SampleMode::Learn);
    let bad = samples.len() / 2;
    if let Some(m) = samples.get_mut(bad) {
        m.sample.velocity[1] = f32::NAN;
    }
    if let Some(m) = samples.get_mut(bad + 1) {
        m.mode = SampleMode::Resume;
    }
    let mut mirror =
        Mirror::new(rotorid::telemetry::msg::RlsForm::UdDefault).expect("onboard identifiers");
    let (window, tolerance, settle) = CONVERGENCE;
    let mut monitors = [0, 1].map(|_| {
        ConvergenceMonitor::<f32, 6>::new(window, tolerance, settle).expect("monitor config")
    });
    let idents = [
        Ident::new(0, "ts").expect("tag"),
        Ident::new(1, "pl").expect("tag"),
    ];
    let mut w = Writer {
        enc: Encoder::new(SYSTEM_ID, COMPONENT_ID),
        stream: Stream {
            bytes: Vec::new(),
            expected: Vec::new(),
        },
    };
    let mut previous: Option<HoverSample<f32>> = None;
    for (k, m) in samples.iter().enumerate() {
        if k % HEARTBEAT_EVERY == 0 {
            w.heartbeat();
        }
        let est = mirror.apply(m);
        let time_ms = (m.sample.time_us / 1000) as u32;
        for ((ident, out), monitor) in idents.iter().zip([est.fuzzy, est.plain]).zip(&mut monitors)
        {
            w.output(ident, m.sample.time_us, &out);
            let (Some(prev), Some(inn)) = (&previous, out.innovation) else {
                continue;
            };
            let [a, b, c, q, r, p] = inn;
            let innovation = HoverState {
                velocity: [a, b, c],
                rates: [q, r, p],
            };
            let Ok(Some(status)) = monitor.observe_step(prev, &m.sample, &innovation) else {
                continue;
            };
            for (i, rho) in status.ratio.iter().enumerate() {
                let fields = json!({ "time_boot_ms": time_ms, "name": format!("{}.rho{i}", ident.tag()),
                                     "value": { "f32": rho.to_bits() } });
                w.stream.expected.push(json!({ "type": "NAMED_VALUE_FLOAT", "seq": w.enc.sequence().wrapping_add(i as u8),
                    "sys": SYSTEM_ID, "comp": COMPONENT_ID, "fields": fields }));
            }
            let mask: u32 = (0..6).map(|i| u32::from(status.converged[i]) << i).sum();
            let fields = json!({ "time_boot_ms": time_ms, "name": format!("{}.conv", ident.tag()),
                                 "value": { "f32": (mask as f32).to_bits() } });
            w.stream.expected.push(
                json!({ "type": "NAMED_VALUE_FLOAT", "seq": w.enc.sequence().wrapping_add(6),
                "sys": SYSTEM_ID, "comp": COMPONENT_ID, "fields": fields }),
            );
            let mut buf = [0u8; 7 * MAX_FRAME_LEN];
            let n = w
                .enc
                .convergence(ident, time_ms, &status, &mut buf)
                .expect("buffer fits seven frames");
            w.stream.bytes.extend_from_slice(&buf[..n]);
        }
        if est.fuzzy.error.is_none() {
            previous = Some(m.sample);
        }
    }
    let end = samples.last().map_or(0, |m| m.sample.time_us);
    for (ident, which) in idents.iter().zip([
        rotorid::telemetry::msg::Ident::Fuzzy,
        rotorid::telemetry::msg::Ident::Plain,
    ]) {
        let params = mirror.params(which);
        for (model, p) in Model::ALL.into_iter().zip(&params) {
            w.theta(ident, model, end, &p.theta);
        }
    }
    w.stream
}
