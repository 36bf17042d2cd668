//! Onboard identification over the telemetry link, checked bit for bit against the host.
//!
//! [`Onboard`] boots `firmware-example` in QEMU ([`FirmwareLink`]), streams samples as
//! `Sample` frames (pipelined, a few frames in flight), and compares every `Estimate` with
//! [`Mirror`], the very same computation in the host build: the active pair
//! ([`IdentPair`]: `PaperFuzzyIdentifier<f32>` + `PaperPlainIdentifier<f32>`, or
//! `FlightIdentifier<f32>` + `ExtendedPlainIdentifier<f32>`), each answering through the same
//! [`SampleChain`] as the firmware. The first differing bit stops the stream
//! with a [`Mismatch`] that says where: sample index, time stamp, identifier, field, both bit
//! patterns.

use std::collections::VecDeque;
use std::fmt;

use rotorid::hover::{flight_sets, GyroCompensation, HoverSample};
use rotorid::{
    DynIdentifier, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig, PaperFuzzyIdentifier,
    PaperPlainIdentifier,
};
use rotorid_link::msg::{
    self, Ack, CompensateEachMsg, CompensateMsg, DataChunk, Estimate, IdOutput, Ident, IdentPair,
    IdentRequest, MemoryReport, MsgType, Nack, NackReason, ParamField, ParamsChunk, Payload,
    PremisesMsg, RateCompensation, ResetMsg, RlsForm, SampleMode, SampleMsg, SweepSample,
    SweepStart,
};
use rotorid_link::{Answer, SampleChain, Writer};

use crate::firmware_link::{BootOptions, FirmwareLink, LinkError, OwnedFrame};
use rotorid_sim::plant::flight::{simulate, verification_excitation, FlightConfig};
use rotorid_sim::plant::PlantError;

/// Frames in flight while streaming (the firmware answers in order).
pub const WINDOW: usize = 8;

/// The first difference between the firmware and the host.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// Index of the sample in the stream.
    pub index: usize,
    /// Its time stamp.
    pub time_us: u64,
    /// What differs (identifier and field).
    pub what: String,
    /// Host value, as bits or text.
    pub host: String,
    /// Firmware value.
    pub firmware: String,
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "sample {} (t = {} µs): {} differs: host {}, firmware {}",
            self.index, self.time_us, self.what, self.host, self.firmware
        )
    }
}

/// Errors of the onboard driver.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OnboardError {
    /// The link failed (QEMU, socket, timeout, protocol).
    #[error(transparent)]
    Link(#[from] LinkError),
    /// The firmware computed something else than the host.
    #[error("bit-for-bit check failed: {0}")]
    Mismatch(Box<Mismatch>),
    /// A reply did not parse or did not fit the request.
    #[error("protocol: {0}")]
    Protocol(String),
    /// The host mirror could not be built.
    #[error("building the host mirror")]
    Core(#[source] rotorid::Error),
}

fn config(form: RlsForm) -> HoverConfig<f32> {
    match form {
        RlsForm::PaperCovariance => HoverConfig::paper(),
        _ => HoverConfig::default(),
    }
}

/// The host build of the firmware's computation.
pub struct Mirror {
    /// The paper's Takagi-Sugeno identifier.
    pub fuzzy: PaperFuzzyIdentifier<f32>,
    /// The paper's single-rule baseline.
    pub plain: PaperPlainIdentifier<f32>,
    /// The flight default.
    pub flight: FlightIdentifier<f32>,
    /// Its baseline.
    pub extended_plain: ExtendedPlainIdentifier<f32>,
    /// The pair answering `Sample`.
    pub pair: IdentPair,
    fuzzy_chain: SampleChain,
    plain_chain: SampleChain,
}

fn to_output(r: Option<Answer>) -> IdOutput {
    match r {
        Some(Ok((prediction, innovation))) => IdOutput {
            prediction,
            innovation,
            error: None,
            ticks: 0,
        },
        Some(Err(e)) => IdOutput::rejected(e, 0),
        // Not reached: `apply` refuses a FreeRun without a start before answering.
        None => IdOutput::rejected(rotorid::Error::Numerical, 0),
    }
}

impl Mirror {
    /// Fresh identifiers in `form`, the paper pair answering (as after the firmware's
    /// start-up or a `Reset` to the paper pair).
    pub fn new(form: RlsForm) -> Result<Self, rotorid::Error> {
        Self::with_pair(form, IdentPair::Paper)
    }

    /// Fresh identifiers in `form`, `pair` answering (as after the firmware's `Reset`).
    pub fn with_pair(form: RlsForm, pair: IdentPair) -> Result<Self, rotorid::Error> {
        let c = config(form);
        Ok(Self {
            fuzzy: PaperFuzzyIdentifier::paper_fuzzy(c)?,
            plain: PaperPlainIdentifier::paper_plain(c)?,
            flight: FlightIdentifier::flight(c, flight_sets())?,
            extended_plain: ExtendedPlainIdentifier::extended_plain(c)?,
            pair,
            fuzzy_chain: SampleChain::new(),
            plain_chain: SampleChain::new(),
        })
    }

    /// What the firmware answers to `m` (ticks 0); `None` where it refuses the sample
    /// (`Nack`: a `FreeRun` while an identifier has no prediction to continue from).
    pub fn apply(&mut self, m: &SampleMsg) -> Option<Estimate> {
        let (fc, pc) = (&mut self.fuzzy_chain, &mut self.plain_chain);
        if m.mode == SampleMode::FreeRun && !(fc.can_free_run() && pc.can_free_run()) {
            return None;
        }
        let (f, p) = match self.pair {
            IdentPair::Flight => (
                fc.answer(&mut self.flight, m),
                pc.answer(&mut self.extended_plain, m),
            ),
            _ => (fc.answer(&mut self.fuzzy, m), pc.answer(&mut self.plain, m)),
        };
        Some(Estimate {
            time_us: m.sample.time_us,
            mode: m.mode,
            fuzzy: to_output(f),
            plain: to_output(p),
        })
    }

    /// What the firmware does on `Compensate` and `CompensateEach`: the active pair's rate
    /// models compensated for the gyros' noise σ `[q r p]` (deg/s), in place, each rate as
    /// `how` says (`Compensate`: damping on every rate).
    pub fn compensate_each(
        &mut self,
        gyro_noise: &[f32; 3],
        how: [GyroCompensation; 3],
    ) -> Result<(), rotorid::Error> {
        match self.pair {
            IdentPair::Flight => {
                self.flight.compensate_each(gyro_noise, how)?;
                self.extended_plain.compensate_each(gyro_noise, how)?;
            }
            _ => {
                self.fuzzy.compensate_each(gyro_noise, how)?;
                self.plain.compensate_each(gyro_noise, how)?;
            }
        }
        Ok(())
    }
}

const STATES: [&str; 6] = ["v_x", "v_y", "v_z", "q", "r", "p"];

fn hex(x: f32) -> String {
    format!("{:08x}", x.to_bits())
}

/// Compares everything but the tick counts, bit for bit; returns the first difference.
pub fn compare(index: usize, host: &Estimate, fw: &Estimate) -> Result<(), Box<Mismatch>> {
    let mm = |what: String, h: String, f: String| {
        Err(Box::new(Mismatch {
            index,
            time_us: host.time_us,
            what,
            host: h,
            firmware: f,
        }))
    };
    if host.time_us != fw.time_us || host.mode != fw.mode {
        return mm(
            "reply order (time stamp, mode)".into(),
            format!("{} {:?}", host.time_us, host.mode),
            format!("{} {:?}", fw.time_us, fw.mode),
        );
    }
    for (name, h, f) in [
        ("fuzzy", &host.fuzzy, &fw.fuzzy),
        ("plain", &host.plain, &fw.plain),
    ] {
        if h.error != f.error {
            return mm(
                format!("{name} error"),
                format!("{:?}", h.error),
                format!("{:?}", f.error),
            );
        }
        for (i, state) in STATES.iter().enumerate() {
            if h.prediction[i].to_bits() != f.prediction[i].to_bits() {
                return mm(
                    format!("{name} prediction {state}"),
                    hex(h.prediction[i]),
                    hex(f.prediction[i]),
                );
            }
        }
        match (h.innovation, f.innovation) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                for (i, state) in STATES.iter().enumerate() {
                    if a[i].to_bits() != b[i].to_bits() {
                        return mm(format!("{name} innovation {state}"), hex(a[i]), hex(b[i]));
                    }
                }
            }
            (a, b) => {
                return mm(
                    format!("{name} innovation presence"),
                    format!("{}", a.is_some()),
                    format!("{}", b.is_some()),
                )
            }
        }
    }
    Ok(())
}

/// θ, diag(P) and the summary of one model, as dumped by `ParamsRequest`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelParams {
    /// θ.
    pub theta: Vec<f32>,
    /// diag(P).
    pub diagonal: Vec<f32>,
    /// trace(P), updates, windup guards, numerical skips, algorithm.
    pub summary: [u32; ParamsChunk::SUMMARY_WORDS],
}

/// Params of the four models (velocity, q̂, r̂, p̂).
pub type Params = [ModelParams; 4];

fn summary<const N: usize, const NP: usize>(r: &rotorid::rls::Rls<f32, N, NP>) -> ModelParams {
    ModelParams {
        theta: r.parameters().to_vec(),
        diagonal: r.covariance_diagonal().to_vec(),
        summary: msg::summary_words(&r.view()),
    }
}

impl Mirror {
    /// `ident` of the active pair.
    fn selected(&self, ident: Ident) -> &dyn DynIdentifier {
        match (self.pair, ident) {
            (IdentPair::Flight, Ident::Fuzzy) => &self.flight,
            (IdentPair::Flight, _) => &self.extended_plain,
            (_, Ident::Fuzzy) => &self.fuzzy,
            (_, _) => &self.plain,
        }
    }

    /// `ident` of the active pair, to change.
    fn selected_mut(&mut self, ident: Ident) -> &mut dyn DynIdentifier {
        match (self.pair, ident) {
            (IdentPair::Flight, Ident::Fuzzy) => &mut self.flight,
            (IdentPair::Flight, _) => &mut self.extended_plain,
            (_, Ident::Fuzzy) => &mut self.fuzzy,
            (_, _) => &mut self.plain,
        }
    }

    /// What `ParamsRequest{ident}` dumps.
    pub fn params(&self, ident: Ident) -> Params {
        match ident {
            Ident::Plain => {
                let p = &self.plain;
                [
                    summary(p.velocity_model().ts().rls()),
                    summary(p.pitch_model().ts().rls()),
                    summary(p.yaw_model().ts().rls()),
                    summary(p.roll_model().ts().rls()),
                ]
            }
            _ => {
                let f = &self.fuzzy;
                [
                    summary(f.velocity_model().ts().rls()),
                    summary(f.pitch_model().ts().rls()),
                    summary(f.yaw_model().ts().rls()),
                    summary(f.roll_model().ts().rls()),
                ]
            }
        }
    }

    /// What `ExportRequest{ident}` streams: the core's snapshot of `ident` of the active
    /// pair under its kind code ([`msg::snapshot_kind`]), the bytes the C interface's
    /// `rotorid_export` writes for the same identifier.
    pub fn export(&self, ident: Ident) -> Vec<u8> {
        let kind = msg::snapshot_kind(self.pair, ident);
        // The buffer is sized from the identifier: a core identifier cannot fail it.
        self.selected(ident).snapshot_vec(kind).unwrap_or_default()
    }

    /// What a complete `ImportChunk` stream of `bytes` does to `ident` of the active pair:
    /// the core imports the snapshot (all or nothing) and, if it did, the identifier's
    /// prediction chain restarts.
    pub fn import(&mut self, ident: Ident, bytes: &[u8]) -> Result<(), rotorid::Error> {
        let kind = msg::snapshot_kind(self.pair, ident);
        let r = self.selected_mut(ident).read_snapshot(kind, bytes);
        if r.is_ok() {
            match ident {
                Ident::Fuzzy => self.fuzzy_chain = SampleChain::new(),
                _ => self.plain_chain = SampleChain::new(),
            }
        }
        r
    }
}

/// Encodes a payload.
pub fn payload(
    f: impl FnOnce(&mut Writer<'_>) -> Result<(), rotorid_link::PayloadError>,
) -> Vec<u8> {
    let mut buf = [0u8; rotorid_link::MAX_PAYLOAD];
    let mut w = Writer::new(&mut buf);
    // Only a message larger than a frame fails, which none of ours is.
    let _ = f(&mut w);
    w.written().to_vec()
}

/// Firmware in QEMU + host mirror.
pub struct Onboard {
    /// The link.
    pub link: FirmwareLink,
    /// The host's copy of the computation.
    pub mirror: Mirror,
    /// Samples streamed since the last reset.
    pub streamed: usize,
    /// The flight default's premises the last `Premises` set (the firmware keeps them across
    /// `Reset`); `None`: `flight_sets()` on the flight default's speed.
    premises: Option<PremisesMsg>,
    /// The RLS form of the last `Reset`.
    form: RlsForm,
}

/// What streaming returned.
#[derive(Clone, Debug, Default)]
pub struct StreamResult {
    /// The firmware's estimates, in order (all bit-identical to the host's), one per
    /// sample not in `refused`.
    pub estimates: Vec<Estimate>,
    /// Stream indices of the samples the firmware refused (`Nack` `Refused`) as the host did.
    pub refused: Vec<usize>,
}

impl Onboard {
    /// Boots the firmware (plain QEMU, or `-icount shift=0`) with identifiers in `form`.
    pub fn boot(form: RlsForm, icount: bool) -> Result<Self, OnboardError> {
        let opts = if icount {
            BootOptions::icount()
        } else {
            BootOptions::default()
        };
        Self::boot_with(form, &opts)
    }

    /// [`boot`](Self::boot) with any QEMU options (e.g. an execution trace).
    pub fn boot_with(form: RlsForm, opts: &BootOptions) -> Result<Self, OnboardError> {
        let link = FirmwareLink::boot_with(opts)?;
        let mut me = Self {
            link,
            mirror: Mirror::new(RlsForm::UdDefault).map_err(OnboardError::Core)?,
            streamed: 0,
            premises: None,
            form: RlsForm::UdDefault,
        };
        me.reset(form)?;
        Ok(me)
    }

    /// Resets both sides to `form`, the paper pair answering.
    pub fn reset(&mut self, form: RlsForm) -> Result<(), OnboardError> {
        self.reset_pair(form, IdentPair::Paper)
    }

    /// Resets both sides to `form`, `pair` answering `Sample`.
    pub fn reset_pair(&mut self, form: RlsForm, pair: IdentPair) -> Result<(), OnboardError> {
        let p = payload(|w| ResetMsg { form, pair }.write(w));
        let f = self.link.request(MsgType::Reset, &p, MsgType::Ack)?;
        expect_ack(&f, MsgType::Reset)?;
        self.mirror = Mirror::with_pair(form, pair).map_err(OnboardError::Core)?;
        self.form = form;
        if let Some(m) = self.premises {
            self.mirror.flight = scheduled_flight(form, &m)?;
        }
        self.streamed = 0;
        Ok(())
    }

    /// `Premises` on both sides: the flight pair's `FlightIdentifier` rebuilt on `m`'s sets
    /// and speeds (θ = 0, P = αI; kept across `Reset`). On the firmware's `Nack` (the core
    /// refused them) an error, and the mirror is as it was.
    pub fn premises(&mut self, m: PremisesMsg) -> Result<(), OnboardError> {
        let p = payload(|w| m.write(w));
        let f = self.link.request(MsgType::Premises, &p, MsgType::Ack)?;
        expect_ack(&f, MsgType::Premises)?;
        self.mirror.flight = scheduled_flight(self.form, &m)?;
        if self.mirror.pair == IdentPair::Flight {
            self.mirror.fuzzy_chain = SampleChain::new();
        }
        self.premises = Some(m);
        Ok(())
    }

    /// `Compensate` on both sides: the active pair's rate models compensated for the gyros'
    /// noise σ `[q r p]` (deg/s), the parameters to free-run with.
    pub fn compensate(&mut self, gyro_noise: [f32; 3]) -> Result<(), OnboardError> {
        let p = payload(|w| CompensateMsg { gyro_noise }.write(w));
        let how = [RateCompensation::Damping; 3];
        self.compensate_as(MsgType::Compensate, &p, gyro_noise, how)
    }

    /// `CompensateEach` on both sides: [`compensate`](Self::compensate) with a choice per rate
    /// `[q r p]`.
    pub fn compensate_each(
        &mut self,
        gyro_noise: [f32; 3],
        how: [RateCompensation; 3],
    ) -> Result<(), OnboardError> {
        let p = payload(|w| CompensateEachMsg { gyro_noise, how }.write(w));
        self.compensate_as(MsgType::CompensateEach, &p, gyro_noise, how)
    }

    /// Sends the compensation request `p` of type `t`, and on its `Ack` compensates the
    /// mirror as the firmware did.
    fn compensate_as(
        &mut self,
        t: MsgType,
        p: &[u8],
        gyro_noise: [f32; 3],
        how: [RateCompensation; 3],
    ) -> Result<(), OnboardError> {
        let f = self.link.request(t, p, MsgType::Ack)?;
        expect_ack(&f, t)?;
        self.mirror
            .compensate_each(&gyro_noise, how.map(Into::into))
            .map_err(OnboardError::Core)
    }

    /// Streams `samples` (each with its mode), compares each reply with the host, calls
    /// `progress(done)` now and then. Stops at the first differing bit.
    pub fn stream(
        &mut self,
        samples: &[SampleMsg],
        mut progress: impl FnMut(usize),
    ) -> Result<StreamResult, OnboardError> {
        let mut in_flight: VecDeque<(usize, Option<Estimate>)> = VecDeque::new();
        let mut out = StreamResult {
            estimates: Vec::with_capacity(samples.len()),
            refused: Vec::new(),
        };
        let mut next = 0;
        while next < samples.len() || !in_flight.is_empty() {
            while next < samples.len() && in_flight.len() < WINDOW {
                let m = &samples[next];
                let host = self.mirror.apply(m);
                self.link
                    .send(MsgType::Sample.code(), &payload(|w| m.write(w)))?;
                in_flight.push_back((self.streamed + next, host));
                next += 1;
            }
            let f = self.link.recv()?;
            let Some((index, host)) = in_flight.pop_front() else {
                return Err(OnboardError::Protocol("unsolicited reply".into()));
            };
            match (f.kind(), host) {
                (Some(MsgType::Estimate), Some(host)) => {
                    let est = Estimate::read(&f.payload)
                        .map_err(|e| OnboardError::Protocol(format!("Estimate payload: {e}")))?;
                    compare(index, &host, &est).map_err(OnboardError::Mismatch)?;
                    out.estimates.push(est);
                }
                // A sample the host refuses too: the firmware must say `Refused`.
                (Some(MsgType::Nack), None) => match Nack::read(&f.payload) {
                    Ok(n) if n.reason == NackReason::Refused.code() => out.refused.push(index),
                    r => {
                        return Err(OnboardError::Protocol(format!(
                            "bad Nack for Sample: {r:?}"
                        )))
                    }
                },
                (kind, host) => {
                    return Err(OnboardError::Mismatch(Box::new(Mismatch {
                        index,
                        time_us: samples
                            .get(index - self.streamed)
                            .map_or(0, |m| m.sample.time_us),
                        what: "reply kind".into(),
                        host: if host.is_some() { "Estimate" } else { "Nack" }.into(),
                        firmware: format!("{kind:?} {:02x?}", f.payload),
                    })))
                }
            }
            let done = out.estimates.len() + out.refused.len();
            if done.is_multiple_of(64) {
                progress(done);
            }
        }
        progress(out.estimates.len() + out.refused.len());
        self.streamed += samples.len();
        Ok(out)
    }

    /// The firmware's parameter dump of `ident`.
    pub fn params(&mut self, ident: Ident) -> Result<Params, OnboardError> {
        self.link.send(
            MsgType::ParamsRequest.code(),
            &payload(|w| IdentRequest { ident }.write(w)),
        )?;
        let mut params: Params = Default::default();
        loop {
            let f = self.link.recv()?;
            if f.kind() != Some(MsgType::Params) {
                return Err(OnboardError::Protocol(format!(
                    "expected Params, got {:?}",
                    f.kind()
                )));
            }
            let c = ParamsChunk::read(&f.payload)
                .map_err(|e| OnboardError::Protocol(format!("Params payload: {e}")))?;
            let m = &mut params[usize::from(c.model)];
            let words: Vec<u32> = c.iter().collect();
            match c.field {
                ParamField::Theta => {
                    m.theta.resize(usize::from(c.total), 0.0);
                    for (i, w) in words.iter().enumerate() {
                        m.theta[usize::from(c.index) + i] = f32::from_bits(*w);
                    }
                }
                ParamField::CovarianceDiagonal => {
                    m.diagonal.resize(usize::from(c.total), 0.0);
                    for (i, w) in words.iter().enumerate() {
                        m.diagonal[usize::from(c.index) + i] = f32::from_bits(*w);
                    }
                }
                _ => {
                    for (i, w) in words.iter().enumerate().take(ParamsChunk::SUMMARY_WORDS) {
                        m.summary[i] = *w;
                    }
                    if c.model == 3 {
                        return Ok(params);
                    }
                }
            }
        }
    }

    /// The firmware's export stream of `ident` (CRC and length checked).
    pub fn export(&mut self, ident: Ident) -> Result<Vec<u8>, OnboardError> {
        self.link.send(
            MsgType::ExportRequest.code(),
            &payload(|w| IdentRequest { ident }.write(w)),
        )?;
        let mut bytes = Vec::new();
        loop {
            let f = self.link.recv()?;
            let c = match f.kind() {
                Some(MsgType::ExportChunk) => DataChunk::read(&f.payload)
                    .map_err(|e| OnboardError::Protocol(format!("ExportChunk: {e}")))?,
                k => {
                    return Err(OnboardError::Protocol(format!(
                        "expected ExportChunk, got {k:?}"
                    )))
                }
            };
            if c.offset as usize != bytes.len() {
                return Err(OnboardError::Protocol(format!(
                    "ExportChunk offset {} after {} bytes",
                    c.offset,
                    bytes.len()
                )));
            }
            bytes.extend_from_slice(c.data);
            if bytes.len() >= c.total as usize {
                if msg::stream_crc(&bytes) != c.crc {
                    return Err(OnboardError::Protocol("export CRC mismatch".into()));
                }
                return Ok(bytes);
            }
        }
    }

    /// Sends an import stream in `ImportChunk`s; returns the firmware's answer to each chunk
    /// (`Ok(())` for Ack, `Err(reason)` for Nack). Stops at the first Nack.
    pub fn import(
        &mut self,
        ident: Ident,
        bytes: &[u8],
        crc: u32,
    ) -> Result<Result<(), u8>, OnboardError> {
        let total = bytes.len() as u32;
        let mut offset = 0usize;
        loop {
            let end = (offset + DataChunk::MAX_DATA).min(bytes.len());
            let c = DataChunk {
                ident,
                offset: offset as u32,
                total,
                crc,
                data: &bytes[offset..end],
            };
            self.link
                .send(MsgType::ImportChunk.code(), &payload(|w| c.write(w)))?;
            let f = self.link.recv()?;
            match f.kind() {
                Some(MsgType::Ack) => {}
                Some(MsgType::Nack) => {
                    let n = Nack::read(&f.payload)
                        .map_err(|e| OnboardError::Protocol(format!("Nack: {e}")))?;
                    return Ok(Err(n.reason));
                }
                k => return Err(OnboardError::Protocol(format!("import answered by {k:?}"))),
            }
            offset = end;
            if offset >= bytes.len() {
                return Ok(Ok(()));
            }
        }
    }

    /// Runs the onboard sweep generator; returns its samples.
    pub fn sweep(&mut self, req: &SweepStart) -> Result<Vec<SweepSample>, OnboardError> {
        self.link
            .send(MsgType::SweepStart.code(), &payload(|w| req.write(w)))?;
        let mut out = Vec::new();
        loop {
            let f = self.link.recv()?;
            match f.kind() {
                Some(MsgType::SweepSample) => out.push(
                    SweepSample::read(&f.payload)
                        .map_err(|e| OnboardError::Protocol(format!("SweepSample: {e}")))?,
                ),
                Some(MsgType::Ack) => {
                    expect_ack(&f, MsgType::SweepStart)?;
                    return Ok(out);
                }
                k => return Err(OnboardError::Protocol(format!("sweep answered by {k:?}"))),
            }
        }
    }

    /// Stack high-water mark and RAM layout.
    pub fn memory(&mut self) -> Result<MemoryReport, OnboardError> {
        let f = self
            .link
            .request(MsgType::MemoryRequest, &[], MsgType::Memory)?;
        MemoryReport::read(&f.payload).map_err(|e| OnboardError::Protocol(format!("Memory: {e}")))
    }
}

/// The firmware's `FlightIdentifier` after `Premises` `m` in `form`.
fn scheduled_flight(form: RlsForm, m: &PremisesMsg) -> Result<FlightIdentifier<f32>, OnboardError> {
    FlightIdentifier::flight_scheduled(config(form), m.sets(), m.scheduling())
        .map_err(OnboardError::Core)
}

fn expect_ack(f: &OwnedFrame, t: MsgType) -> Result<(), OnboardError> {
    match Ack::read(&f.payload) {
        Ok(a) if a.msg_type == t.code() => Ok(()),
        r => Err(OnboardError::Protocol(format!("bad Ack for {t:?}: {r:?}"))),
    }
}

/// Wraps samples as `Sample` messages of one mode.
pub fn messages(samples: &[HoverSample<f32>], mode: SampleMode) -> Vec<SampleMsg> {
    samples
        .iter()
        .map(|&sample| SampleMsg { mode, sample })
        .collect()
}

/// A simulated flight of `duration_s` (realistic sensors, turbulence, the verification
/// manoeuvres: doublets and 3-2-1-1s on all channels), as core samples.
pub fn simulated_flight(seed: u64, duration_s: f64) -> Result<Vec<HoverSample<f32>>, PlantError> {
    let cfg = FlightConfig::realistic(seed, duration_s);
    let mut exc = verification_excitation(seed, duration_s);
    let log = simulate(&cfg, &mut exc)?;
    Ok(rotorid_sim::flights::to_hover_samples(&log))
}
