//! rotorid's MAVLink 2 telemetry of a whole identification run, and what an independent
//! decoder must find in it (the pymavlink tests, `tests/mavlink_pymavlink.rs` on the host
//! build and `tests/firmware_mavlink.rs` on the firmware's UART1 under QEMU).
//!
//! [`identification_stream`] runs the onboard pair ([`Mirror`]: the firmware's fuzzy and plain
//! identifiers, host build) over samples and encodes, with [`rotorid_mavlink::Encoder`], what the
//! example firmware sends (`firmware-example/src/mavlink_port.rs`): a heartbeat at the start and
//! after every [`HEARTBEAT_EVERY`] samples, one step array per identifier and sample (or a
//! STATUSTEXT when the core rejected it), optionally convergence values at the end of each
//! window (host only), and θ of every model at the end (the firmware's answer to a
//! `ParamsRequest` for the fuzzy, then the plain identifier). Beside the bytes it lists every
//! message with its expected fields straight from the Rust values (floats as f32 bit
//! patterns); [`check_with_pymavlink`] has pymavlink decode bytes and compare.

use std::path::{Path, PathBuf};
use std::process::Command;

use rotorid::convergence::ConvergenceMonitor;
use rotorid::hover::HoverSample;
use rotorid::HoverState;
use rotorid_link::msg::{IdOutput, SampleMode, SampleMsg};
use rotorid_mavlink::{chunk_count, Encoder, MavState, Model, Sender, ARRAY_LEN, MAX_FRAME_LEN};
use serde_json::{json, Value};

use crate::onboard::{messages, Mirror};

/// System id of the stream (a vehicle's default `SYSID_THISMAV`).
pub const SYSTEM_ID: u8 = 1;
/// Component id of the stream (`MAV_COMP_ID_USER1`).
pub const COMPONENT_ID: u8 = 25;
/// A heartbeat before the first sample and after every this many samples (the firmware's
/// `mavlink_port::HEARTBEAT_EVERY`).
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

    fn output(&mut self, ident: &Sender, time_us: u64, out: &IdOutput) {
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

    fn theta(&mut self, ident: &Sender, model: Model, time_us: u64, theta: &[f32]) {
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

/// Learning `flight`: every sample in Learn mode, one sample's velocity made NaN at
/// `flight.len() / 2` so that both identifiers reject one sample for real, and the sample after
/// it resuming the chain, as a client must after a gap.
pub fn learn_with_one_rejection(flight: &[HoverSample<f32>]) -> Vec<SampleMsg> {
    let mut samples = messages(flight, SampleMode::Learn);
    let bad = samples.len() / 2;
    if let Some(m) = samples.get_mut(bad) {
        m.sample.velocity[1] = f32::NAN;
    }
    if let Some(m) = samples.get_mut(bad + 1) {
        m.mode = SampleMode::Resume;
    }
    samples
}

/// The telemetry of `samples` (see the module docs); convergence messages only if
/// `convergence` (the example firmware runs no convergence monitor).
pub fn identification_stream(samples: &[SampleMsg], convergence: bool) -> Stream {
    let mut mirror =
        Mirror::new(rotorid_link::msg::RlsForm::UdDefault).expect("onboard identifiers");
    let (window, tolerance, settle) = CONVERGENCE;
    let mut monitors = [0, 1].map(|_| {
        ConvergenceMonitor::<f32, 6>::new(window, tolerance, settle).expect("monitor config")
    });
    let idents = [
        Sender::new(0, "ts").expect("tag"),
        Sender::new(1, "pl").expect("tag"),
    ];
    let mut w = Writer {
        enc: Encoder::new(SYSTEM_ID, COMPONENT_ID),
        stream: Stream {
            bytes: Vec::new(),
            expected: Vec::new(),
        },
    };
    let mut previous: Option<HoverSample<f32>> = None;
    w.heartbeat();
    for (k, m) in samples.iter().enumerate() {
        // A refused sample (FreeRun without a start) sends no telemetry onboard either.
        let Some(est) = mirror.apply(m) else {
            continue;
        };
        let time_ms = (m.sample.time_us / 1000) as u32;
        for ((ident, out), monitor) in idents.iter().zip([est.fuzzy, est.plain]).zip(&mut monitors)
        {
            w.output(ident, m.sample.time_us, &out);
            let (true, Some(prev), Some(inn)) = (convergence, &previous, out.innovation) else {
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
        if (k + 1) % HEARTBEAT_EVERY == 0 {
            w.heartbeat();
        }
    }
    let end = samples.last().map_or(0, |m| m.sample.time_us);
    for (ident, which) in idents.iter().zip([
        rotorid_link::msg::Ident::Fuzzy,
        rotorid_link::msg::Ident::Plain,
    ]) {
        let params = mirror.params(which);
        for (model, p) in Model::ALL.into_iter().zip(&params) {
            w.theta(ident, model, end, &p.theta);
        }
    }
    w.stream
}

/// A python3 with pymavlink: `ROTORID_PYTHON`, else `.venv/` at the repository root (where
/// `scripts/setup.sh` installs it), else `python3` on the path.
pub fn python_with_pymavlink() -> Option<PathBuf> {
    let root = repo_root();
    let candidates = [
        std::env::var_os("ROTORID_PYTHON").map(PathBuf::from),
        Some(root.join(".venv/bin/python3")),
        Some(PathBuf::from("python3")),
    ];
    candidates.into_iter().flatten().find(|p| {
        Command::new(p)
            .args(["-c", "import pymavlink.generator.mavgen"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Why [`check_with_pymavlink`] could not confirm the stream.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PymavlinkError {
    /// The work directory or a file in it could not be written.
    #[error("{}: cannot write", path.display())]
    Write {
        /// The directory or file.
        path: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The expected frames could not be written as JSON.
    #[error("cannot encode the expected frames as JSON")]
    Json(#[from] serde_json::Error),
    /// The interpreter could not be started.
    #[error("{}: cannot run", python.display())]
    Run {
        /// The interpreter.
        python: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The script failed: a frame differs, or pymavlink could not decode the stream.
    #[error("{output}")]
    Script {
        /// The script's standard output and error.
        output: String,
    },
}

/// Has `python` decode `bytes` with pymavlink (`tests/mavlink_decode.py`, module generated by
/// mavgen from `core/mavlink/dialect/rotorid.xml`) and compare every frame with `expected`,
/// working in `work`. Returns the script's summary line, or its output on a mismatch.
pub fn check_with_pymavlink(
    python: &Path,
    bytes: &[u8],
    expected: &[Value],
    work: &Path,
) -> Result<String, PymavlinkError> {
    let root = repo_root();
    let write = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PymavlinkError::Write { path, source }
    };
    std::fs::create_dir_all(work).map_err(write(work))?;
    let bin = work.join("stream.bin");
    let json = work.join("expected.json");
    std::fs::write(&bin, bytes).map_err(write(&bin))?;
    std::fs::write(&json, serde_json::to_vec(expected)?).map_err(write(&json))?;
    let out = Command::new(python)
        .arg(root.join("host-tests/tests/mavlink_decode.py"))
        .arg(root.join("core/mavlink/dialect/rotorid.xml"))
        .args([&bin, &json])
        .arg(work)
        .output()
        .map_err(|source| PymavlinkError::Run {
            python: python.to_path_buf(),
            source,
        })?;
    let stdout = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if out.status.success() {
        Ok(stdout.lines().last().unwrap_or_default().to_string())
    } else {
        Err(PymavlinkError::Script {
            output: format!("{stdout}\n{}", String::from_utf8_lossy(&out.stderr)),
        })
    }
}
