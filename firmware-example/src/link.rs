//! Board-agnostic link application: bytes in, frames decoded, messages dispatched, replies out.
//!
//! [`Link`] is generic over any `embedded_io::Read + Write` byte stream (UART, USB-CDC, a TCP
//! socket in a host test) and a [`Platform`] for the few things that need the MCU. Nothing a
//! peer sends can stop it: rejected frames are counted by the decoder, valid frames of unknown
//! type or with bad payloads are counted and answered with `Nack`, I/O errors are counted.

use core::hint::black_box;

use embedded_io::{Read, Write};
use rotorid_link::{
    msg::{
        Ack, CompensateEachMsg, CompensateMsg, CostReport, CostRequest, DataChunk, FaultKind,
        Hello, IdentRequest, MemoryReport, MsgType, Nack, NackReason, Payload, PremisesMsg,
        RateCompensation, ResetMsg, SampleMsg, StatsReport, SweepStart, Workload,
    },
    Frame, FrameDecoder, FrameEncoder, PayloadError, Writer, MAX_PAYLOAD, MAX_WIRE_LEN,
};

use firmware_example::ident::{Identification, Reply};

use crate::mavlink_port::MavlinkPort;

/// What the link needs from the MCU besides the byte stream.
pub trait Platform {
    /// Runs `f` and returns its result and the elapsed time in cycle-counter ticks.
    fn measure<R>(&mut self, f: impl FnOnce() -> R) -> (R, u64);
    /// Crashes on purpose (test hook for the panic and fault paths).
    fn inject_fault(&mut self, kind: FaultKind) -> !;
    /// RAM use: stack region, stack high-water mark, static data.
    fn memory(&self) -> MemoryReport;
}

/// Firmware name sent in `Hello`.
const NAME: &[u8] = concat!("rotorid firmware-example ", env!("CARGO_PKG_VERSION")).as_bytes();
/// `Hello` flag bit 0: the `FaultInject` hook is enabled.
const FLAG_FAULT_INJECT: u8 = 1;

/// Counters of the application layer (the decoder counts the framing layer).
#[derive(Clone, Copy, Debug, Default)]
struct AppCounters {
    unknown_type: u32,
    bad_payload: u32,
    uart_errors: u32,
}

/// The link application; every sample's outputs also go to the MAVLink port `mav`.
pub struct Link<U, P, T> {
    io: U,
    platform: P,
    engine: &'static mut Identification,
    mav: MavlinkPort<T>,
    decoder: FrameDecoder,
    tx: FrameEncoder,
    counters: AppCounters,
    /// What one read brings in. Kept here rather than on `poll`'s stack: a UART read often
    /// brings one byte, and zeroing a fresh buffer for each cost about 77 instructions.
    rx: [u8; 64],
}

impl<U: Read + Write, P: Platform, T: Write> Link<U, P, T> {
    /// A link over `io` serving `engine`, with MAVLink telemetry on `mav`.
    pub fn new(
        io: U,
        platform: P,
        engine: &'static mut Identification,
        mav: MavlinkPort<T>,
    ) -> Self {
        Self {
            io,
            platform,
            engine,
            mav,
            decoder: FrameDecoder::new(),
            tx: FrameEncoder::new(),
            counters: AppCounters::default(),
            rx: [0; 64],
        }
    }

    /// Announces itself with `Hello`, then serves requests forever.
    pub fn run(&mut self) -> ! {
        self.send_hello();
        loop {
            self.poll();
        }
    }

    /// Sends the boot announcement.
    pub fn send_hello(&mut self) {
        let hello = Hello {
            version: rotorid_link::VERSION,
            max_payload: MAX_PAYLOAD as u16,
            flags: FLAG_FAULT_INJECT,
            name: NAME,
        };
        let mut out = Out::new(&mut self.io, &mut self.tx, &mut self.counters);
        out.reply(MsgType::Hello, |w| hello.write(w));
    }

    /// Reads what the stream has (blocking for at least one byte) and handles every frame.
    pub fn poll(&mut self) {
        let Self {
            io,
            platform,
            engine,
            mav,
            decoder,
            tx,
            counters,
            rx,
        } = self;
        let n = match io.read(rx) {
            Ok(n) => n,
            Err(e) => {
                defmt::warn!("read error: {}", embedded_io::Error::kind(&e) as u8);
                counters.uart_errors = counters.uart_errors.wrapping_add(1);
                return;
            }
        };
        for &b in rx.get(..n).unwrap_or_default() {
            match decoder.push(b) {
                None => {}
                Some(Err(e)) => defmt::warn!("rejected frame: {}", e),
                Some(Ok(frame)) if frame.msg_type == MsgType::StatsRequest.code() => {
                    let (seq, empty) = (frame.seq, frame.payload.is_empty());
                    // The frame's borrow of the decoder ends here, so its counters (which
                    // already include this request) can be read.
                    let report = StatsReport {
                        link: *decoder.stats(),
                        unknown_type: counters.unknown_type,
                        bad_payload: counters.bad_payload,
                        uart_errors: counters.uart_errors,
                        frames_sent: tx.frames(),
                    };
                    let mut out = Out::new(io, tx, counters);
                    if empty {
                        out.reply(MsgType::Stats, |w| report.write(w));
                    } else {
                        out.nack(seq, MsgType::StatsRequest.code(), NackReason::BadPayload);
                    }
                }
                Some(Ok(frame)) => handle(
                    frame,
                    platform,
                    engine,
                    mav,
                    &mut Out::new(io, tx, counters),
                ),
            }
        }
    }
}

/// Reply path: encoder, stream and counters borrowed together.
struct Out<'a, U> {
    io: &'a mut U,
    tx: &'a mut FrameEncoder,
    counters: &'a mut AppCounters,
}

impl<'a, U: Write> Out<'a, U> {
    fn new(io: &'a mut U, tx: &'a mut FrameEncoder, counters: &'a mut AppCounters) -> Self {
        Self { io, tx, counters }
    }

    /// Builds a payload with `build` and sends it as one frame of type `t`.
    fn reply(
        &mut self,
        t: MsgType,
        build: impl FnOnce(&mut Writer<'_>) -> Result<(), PayloadError>,
    ) {
        let mut payload = [0u8; MAX_PAYLOAD];
        let mut w = Writer::new(&mut payload);
        match build(&mut w) {
            Ok(()) => self.send(t, w.written()),
            // Only a programming error (a reply larger than a frame) gets here.
            Err(e) => defmt::error!("cannot build {}: {}", t, e),
        }
    }

    fn nack(&mut self, seq: u16, msg_type: u8, reason: NackReason) {
        if reason == NackReason::UnknownType {
            self.counters.unknown_type = self.counters.unknown_type.wrapping_add(1);
        } else if reason == NackReason::BadPayload {
            self.counters.bad_payload = self.counters.bad_payload.wrapping_add(1);
        }
        let nack = Nack {
            seq,
            msg_type,
            reason: reason as u8,
        };
        self.reply(MsgType::Nack, |w| nack.write(w));
    }

    fn send(&mut self, t: MsgType, payload: &[u8]) {
        let mut wire = [0u8; MAX_WIRE_LEN];
        match self.tx.encode(t.code(), payload, &mut wire) {
            Ok(bytes) => {
                if let Err(e) = self.io.write_all(bytes) {
                    defmt::warn!("write error: {}", embedded_io::Error::kind(&e) as u8);
                    self.counters.uart_errors = self.counters.uart_errors.wrapping_add(1);
                }
            }
            Err(e) => defmt::error!("cannot encode {}: {}", t, e),
        }
    }
}

impl<U: Write> Reply for Out<'_, U> {
    fn reply(
        &mut self,
        t: MsgType,
        build: &mut dyn FnMut(&mut Writer<'_>) -> Result<(), PayloadError>,
    ) {
        Out::reply(self, t, build)
    }

    fn ack(&mut self, seq: u16, msg_type: u8) {
        let ack = Ack { seq, msg_type };
        Out::reply(self, MsgType::Ack, |w| ack.write(w));
    }

    fn nack(&mut self, seq: u16, msg_type: u8, reason: NackReason) {
        Out::nack(self, seq, msg_type, reason)
    }
}

/// Dispatches one valid frame (other than `StatsRequest`).
fn handle<U: Write, P: Platform, T: Write>(
    frame: Frame<'_>,
    platform: &mut P,
    engine: &mut Identification,
    mav: &mut MavlinkPort<T>,
    out: &mut Out<'_, U>,
) {
    let (seq, code) = (frame.seq, frame.msg_type);
    match MsgType::from_u8(frame.msg_type) {
        Some(MsgType::Sample) => match SampleMsg::read(frame.payload) {
            Ok(m) => match engine.sample(&m, &mut |f| platform.measure(f).1) {
                Some(est) => {
                    // MAVLink first: once the client has the Estimate, the telemetry is out too.
                    mav.estimate(&est);
                    out.reply(MsgType::Estimate, |w| est.write(w));
                }
                None => out.nack(seq, code, NackReason::Refused),
            },
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::Reset) => match ResetMsg::read(frame.payload) {
            Ok(m) => match engine.reset(m.form, m.pair) {
                Ok(()) => Reply::ack(out, seq, code),
                Err(e) => {
                    defmt::error!("reset failed: {}", e);
                    out.nack(seq, code, NackReason::Refused)
                }
            },
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        // `Compensate` is `CompensateEach` with damping on every rate.
        Some(t @ (MsgType::Compensate | MsgType::CompensateEach)) => {
            let request = if t == MsgType::Compensate {
                CompensateMsg::read(frame.payload)
                    .map(|m| (m.gyro_noise, [RateCompensation::Damping; 3]))
            } else {
                CompensateEachMsg::read(frame.payload).map(|m| (m.gyro_noise, m.how))
            };
            match request {
                Ok((sigma, how)) => match engine.compensate_each(&sigma, how.map(Into::into)) {
                    Ok(()) => Reply::ack(out, seq, code),
                    Err(e) => {
                        defmt::warn!("compensate refused: {}", e);
                        out.nack(seq, code, NackReason::Refused)
                    }
                },
                Err(_) => out.nack(seq, code, NackReason::BadPayload),
            }
        }
        Some(MsgType::Premises) => match PremisesMsg::read(frame.payload) {
            Ok(m) => match engine.premises(&m) {
                Ok(()) => Reply::ack(out, seq, code),
                Err(e) => {
                    defmt::warn!("premises refused: {}", e);
                    out.nack(seq, code, NackReason::Refused)
                }
            },
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::ParamsRequest) => match IdentRequest::read(frame.payload) {
            Ok(r) => {
                if let Some(thetas) = engine.thetas(r.ident) {
                    mav.thetas(r.ident, &thetas);
                }
                engine.params(seq, r.ident, out)
            }
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::ExportRequest) => match IdentRequest::read(frame.payload) {
            Ok(r) => engine.export(seq, r.ident, out),
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::ImportChunk) => match DataChunk::read(frame.payload) {
            Ok(c) => engine.import_chunk(seq, &c, out),
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::SweepStart) => match SweepStart::read(frame.payload) {
            Ok(s) => engine.sweep(seq, &s, out),
            Err(_) => out.nack(seq, code, NackReason::BadPayload),
        },
        Some(MsgType::MemoryRequest) if frame.payload.is_empty() => {
            let m = platform.memory();
            out.reply(MsgType::Memory, |w| m.write(w));
        }
        Some(MsgType::MemoryRequest) => out.nack(seq, code, NackReason::BadPayload),
        Some(MsgType::Ping) => out.send(MsgType::Pong, frame.payload),
        Some(MsgType::CostRequest) => match CostRequest::read(frame.payload) {
            Ok(req) => {
                let report = run_cost(platform, req);
                defmt::info!("cost {}", report);
                out.reply(MsgType::Cost, |w| report.write(w));
            }
            Err(_) => out.nack(frame.seq, frame.msg_type, NackReason::BadPayload),
        },
        Some(MsgType::FaultInject) => match frame.payload {
            [code] => match FaultKind::from_u8(*code) {
                Some(kind) => platform.inject_fault(kind),
                None => out.nack(frame.seq, frame.msg_type, NackReason::BadPayload),
            },
            _ => out.nack(frame.seq, frame.msg_type, NackReason::BadPayload),
        },
        // Replies sent to the firmware, and types this build does not know.
        _ => {
            defmt::warn!("unhandled message type {=u8:#04x}", frame.msg_type);
            out.nack(frame.seq, frame.msg_type, NackReason::UnknownType);
        }
    }
}

/// Runs a dummy workload under the platform's stopwatch.
fn run_cost<P: Platform>(platform: &mut P, req: CostRequest) -> CostReport {
    let n = req.iterations;
    let (result, ticks) = match req.workload {
        Workload::Xorshift => platform.measure(|| {
            let mut x = black_box(0x2545_F491u32);
            for _ in 0..black_box(n) {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
            }
            black_box(x)
        }),
        Workload::FloatMac => platform.measure(|| {
            let (a, b) = (black_box(0.999_f32), black_box(0.5_f32));
            let mut acc = black_box(1.0_f32);
            for _ in 0..black_box(n) {
                acc = acc * a + b;
            }
            black_box(acc).to_bits()
        }),
        Workload::EncodeFrame => {
            let mut payload = [0u8; MAX_PAYLOAD];
            for (i, p) in payload.iter_mut().enumerate() {
                *p = (i % 251) as u8;
            }
            let mut wire = [0u8; MAX_WIRE_LEN];
            platform.measure(|| {
                let mut sum = 0u32;
                for i in 0..black_box(n) {
                    let len = rotorid_link::encode_frame(0x80, i as u16, &payload, &mut wire)
                        .unwrap_or_default();
                    sum = sum.wrapping_add(len as u32);
                }
                black_box(sum)
            })
        }
        // `Empty` and workloads added later: the stopwatch overhead alone.
        _ => platform.measure(|| black_box(0u32)),
    };
    CostReport {
        workload: req.workload,
        iterations: n,
        ticks,
        result,
    }
}
