//! Onboard identification: the two identifiers and the handlers of the identification
//! messages (board-agnostic, like the `link` module).
//!
//! * `Sample` → `Estimate`: one sample stepped through the fuzzy identifier (U-D default or
//!   the paper's covariance form, chosen by `Reset`) and the plain baseline, each timed.
//!   A sample the core rejects leaves both identifiers unchanged (the core's contract) and
//!   the reply says which `rotorid::Error`.
//! * `ParamsRequest` → `Params`…: θ, diag(P) and a summary of each of the four models.
//! * `ExportRequest` → `ExportChunk`…: the identifier's state as a byte stream with CRC,
//!   read straight from the estimators (no copy of the 10.5 KiB state).
//! * `ImportChunk`…: warm start. Plain identifier: staged whole, CRC-checked, then imported
//!   atomically. Fuzzy identifier (10.5 KiB stream): decoded one model at a time into a
//!   staging `RlsState` (at most the velocity model's 6.2 KiB), each model checked and
//!   imported when its last byte arrives, the stream CRC checked at the end. Any failure
//!   (a model the core refuses, a chunk out of order, the CRC, another request arriving
//!   mid-import) resets the fuzzy identifier, so it never runs with a mix of old and new
//!   models (see `docs/protocol.md`).
//! * `SweepStart` → `SweepSample`…, `Ack`: Table 2's excitation generated onboard.

use core::mem::MaybeUninit;
use core::sync::atomic::{AtomicBool, Ordering};

use rotorid::hover::HoverSnapshot;
use rotorid::hover::{HoverModels, StateModel};
use rotorid::sweep::SweepSchedule;
use rotorid::{Error, HoverConfig, HoverState, PaperFuzzyIdentifier, PaperPlainIdentifier};
use rotorid::{RlsState, RlsView};
use rotorid_link::msg::{
    self, DataChunk, IdOutput, Ident, MsgType, NackReason, ParamField, ParamsChunk, Payload,
    RlsForm, SampleMode, SampleMsg, SweepSample, SweepStart,
};
use rotorid_link::{Reader, Writer};

/// Bytes of the plain identifier's snapshot stream (its four models' states).
pub const PLAIN_SNAPSHOT_LEN: usize = stream_len(PlainV::PARAMETERS, PlainV::FACTOR_LEN)
    + stream_len(PlainQ::PARAMETERS, PlainQ::FACTOR_LEN)
    + stream_len(PlainR::PARAMETERS, PlainR::FACTOR_LEN)
    + stream_len(PlainP::PARAMETERS, PlainP::FACTOR_LEN);

/// Why a `Reset` was not carried out.
#[derive(Clone, Copy, Debug, PartialEq, defmt::Format)]
pub enum ResetError {
    /// An identifier failed to build at start-up (not expected: their settings are constants).
    IdentifierMissing,
    /// The core refused the new settings.
    Core(Error),
}

/// Staging area of an import into the plain identifier.
struct ImportStage {
    buf: [u8; PLAIN_SNAPSHOT_LEN],
    received: usize,
    total: u32,
    crc: u32,
}

/// Everything the identification messages act on.
///
/// Lives in a static and is built in place ([`Identification::take`]): a `PaperFuzzyIdentifier<f32>`
/// is 11 KiB, and every by-value move of one during construction would cost that much stack.
/// The identifiers are kept as the `Result`s their constructors returned (always `Ok` after
/// a successful [`Identification::take`]) so that they never have to be moved out.
pub struct Identification {
    fuzzy: Result<PaperFuzzyIdentifier<f32>, Error>,
    plain: Result<PaperPlainIdentifier<f32>, Error>,
    form: RlsForm,
    stage: Option<ImportStage>,
    fuzzy_stage: Option<FuzzyImport>,
}

/// The state types of the two identifiers' models, named through the identifiers' types
/// (their sizes are written nowhere else).
type StateOf<M> = <M as StateModel<f32>>::State;
type FuzzyV = StateOf<<PaperFuzzyIdentifier<f32> as HoverModels>::Velocity>;
type FuzzyQ = StateOf<<PaperFuzzyIdentifier<f32> as HoverModels>::Pitch>;
type FuzzyR = StateOf<<PaperFuzzyIdentifier<f32> as HoverModels>::Yaw>;
type FuzzyP = StateOf<<PaperFuzzyIdentifier<f32> as HoverModels>::Roll>;
type PlainV = StateOf<<PaperPlainIdentifier<f32> as HoverModels>::Velocity>;
type PlainQ = StateOf<<PaperPlainIdentifier<f32> as HoverModels>::Pitch>;
type PlainR = StateOf<<PaperPlainIdentifier<f32> as HoverModels>::Yaw>;
type PlainP = StateOf<<PaperPlainIdentifier<f32> as HoverModels>::Roll>;

/// Bytes of one model in the snapshot stream: algorithm u8, updates u32, θ, factor (f32 each).
const fn stream_len(parameters: usize, factor: usize) -> usize {
    5 + 4 * (parameters + factor)
}

const MODEL_LEN: [usize; 4] = [
    stream_len(FuzzyV::PARAMETERS, FuzzyV::FACTOR_LEN),
    stream_len(FuzzyQ::PARAMETERS, FuzzyQ::FACTOR_LEN),
    stream_len(FuzzyR::PARAMETERS, FuzzyR::FACTOR_LEN),
    stream_len(FuzzyP::PARAMETERS, FuzzyP::FACTOR_LEN),
];
/// Bytes of the fuzzy identifier's snapshot stream.
pub const FUZZY_SNAPSHOT_LEN: usize = MODEL_LEN[0] + MODEL_LEN[1] + MODEL_LEN[2] + MODEL_LEN[3];

/// The model of a fuzzy import being received.
// Sized by the velocity model on purpose: this is the static staging area (no allocator),
// one model at a time.
#[allow(clippy::large_enum_variant)]
enum FuzzyModel {
    V(FuzzyV),
    Q(FuzzyQ),
    R(FuzzyR),
    P(FuzzyP),
}

/// A fuzzy import in progress (one model staged at a time).
struct FuzzyImport {
    model: usize,
    /// Bytes of the current model received.
    pos: usize,
    word: [u8; 4],
    state: FuzzyModel,
    received: usize,
    total: u32,
    crc: u32,
    digest: crc::Digest<'static, u32>,
    /// Whether a model has been written into the live identifier.
    touched: bool,
}

static CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

fn blank<const N: usize, const NP: usize>() -> RlsState<f32, N, NP> {
    RlsState {
        algorithm: rotorid::Algorithm::UdFactor,
        theta: [0.0; N],
        factor: [0.0; NP],
        updates: 0,
    }
}

/// Stores byte `pos` of one model's stream (algorithm u8, updates u32, θ, factor as f32).
/// Not generic: one copy serves all four model sizes.
fn store_state_byte(
    (algorithm, updates, theta, factor): (
        &mut rotorid::Algorithm,
        &mut u32,
        &mut [f32],
        &mut [f32],
    ),
    pos: usize,
    b: u8,
    word: &mut [u8; 4],
) -> bool {
    match pos {
        0 => {
            *algorithm = match rotorid::Algorithm::from_code(b) {
                Some(a) => a,
                None => return false,
            };
        }
        1..=4 => {
            let shift = 8 * (pos - 1);
            *updates = (*updates & !(0xff << shift)) | (u32::from(b) << shift);
        }
        _ => {
            let k = (pos - 5) % 4;
            if let Some(w) = word.get_mut(k) {
                *w = b;
            }
            if k == 3 {
                let v = f32::from_le_bytes(*word);
                let i = (pos - 5) / 4;
                let n = theta.len();
                if let Some(t) = theta.get_mut(i) {
                    *t = v;
                } else if let Some(f) = factor.get_mut(i - n) {
                    *f = v;
                }
            }
        }
    }
    true
}

fn parts<const N: usize, const NP: usize>(
    s: &mut RlsState<f32, N, NP>,
) -> (&mut rotorid::Algorithm, &mut u32, &mut [f32], &mut [f32]) {
    (
        &mut s.algorithm,
        &mut s.updates,
        &mut s.theta,
        &mut s.factor,
    )
}

/// `paper_fuzzy(c)` written straight into `dst` (the call's return slot is `dst`).
#[inline(never)]
fn build_fuzzy(
    dst: &mut MaybeUninit<Result<PaperFuzzyIdentifier<f32>, Error>>,
    c: HoverConfig<f32>,
) {
    dst.write(PaperFuzzyIdentifier::paper_fuzzy(c));
}

/// `paper_plain(c)` written straight into `dst`.
#[inline(never)]
fn build_plain(
    dst: &mut MaybeUninit<Result<PaperPlainIdentifier<f32>, Error>>,
    c: HoverConfig<f32>,
) {
    dst.write(PaperPlainIdentifier::paper_plain(c));
}

static ENGINE_TAKEN: AtomicBool = AtomicBool::new(false);
static mut ENGINE: MaybeUninit<Identification> = MaybeUninit::uninit();

fn config(form: RlsForm) -> HoverConfig<f32> {
    match form {
        RlsForm::PaperCovariance => HoverConfig::paper(),
        _ => HoverConfig::default(),
    }
}

/// The reply path the handlers need (implemented by the link's `Out`).
pub trait Reply {
    /// Sends a frame whose payload `build` writes.
    fn reply(
        &mut self,
        t: MsgType,
        build: &mut dyn FnMut(&mut Writer<'_>) -> Result<(), rotorid_link::PayloadError>,
    );
    /// Acknowledges request `seq` of type `msg_type`.
    fn ack(&mut self, seq: u16, msg_type: u8);
    /// Refuses request `seq` of type `msg_type`.
    fn nack(&mut self, seq: u16, msg_type: u8, reason: NackReason);
}

/// Prediction and innovation of one call, or the core's error.
type StepResult = Result<([f32; 6], Option<[f32; 6]>), Error>;

fn state6(s: &HoverState<f32>) -> [f32; 6] {
    s.to_array()
}

fn ticks32(t: u64) -> u32 {
    u32::try_from(t).unwrap_or(u32::MAX)
}

impl Identification {
    /// The engine, built in its static home with the default (U-D) form; `None` on a second
    /// call or if the core refuses the configuration.
    pub fn take() -> Option<&'static mut Identification> {
        if ENGINE_TAKEN.swap(true, Ordering::AcqRel) {
            return None;
        }
        // SAFETY: the flag above hands out the one `&'static mut` exactly once.
        let slot: &'static mut MaybeUninit<Identification> =
            unsafe { &mut *core::ptr::addr_of_mut!(ENGINE) };
        let p = slot.as_mut_ptr();
        let c = config(RlsForm::UdDefault);
        // SAFETY: fields of the static are written in place, each exactly once, before the
        // reference to the whole is created.
        unsafe {
            build_fuzzy(&mut *core::ptr::addr_of_mut!((*p).fuzzy).cast(), c);
            build_plain(&mut *core::ptr::addr_of_mut!((*p).plain).cast(), c);
            core::ptr::addr_of_mut!((*p).form).write(RlsForm::UdDefault);
            core::ptr::addr_of_mut!((*p).stage).write(None);
            core::ptr::addr_of_mut!((*p).fuzzy_stage).write(None);
        }
        // SAFETY: every field was initialised above.
        let engine = unsafe { slot.assume_init_mut() };
        (engine.fuzzy.is_ok() && engine.plain.is_ok()).then_some(engine)
    }

    /// `Sample`: runs both identifiers, each under `measure`.
    pub fn sample(
        &mut self,
        m: &SampleMsg,
        measure: &mut dyn FnMut(&mut dyn FnMut()) -> u64,
    ) -> msg::Estimate {
        self.abort_fuzzy_import();
        let s = &m.sample;
        let mut fuzzy = None;
        let mut plain = None;
        let tf = {
            let id = &mut self.fuzzy;
            let out = &mut fuzzy;
            measure(&mut || {
                *out = Some(match id {
                    Err(e) => Err(*e),
                    Ok(id) => match m.mode {
                        SampleMode::Predict => id.predict(s).map(|p| (state6(&p), None)),
                        SampleMode::Resume => id.resume(s).map(|p| (state6(&p), None)),
                        _ => id
                            .step(s)
                            .map(|o| (state6(&o.prediction), o.innovation.as_ref().map(state6))),
                    },
                })
            })
        };
        let tp = {
            let id = &mut self.plain;
            let out = &mut plain;
            measure(&mut || {
                *out = Some(match id {
                    Err(e) => Err(*e),
                    Ok(id) => match m.mode {
                        SampleMode::Predict => id.predict(s).map(|p| (state6(&p), None)),
                        SampleMode::Resume => id.resume(s).map(|p| (state6(&p), None)),
                        _ => id
                            .step(s)
                            .map(|o| (state6(&o.prediction), o.innovation.as_ref().map(state6))),
                    },
                })
            })
        };
        let output = |r: Option<StepResult>, t: u64| match r {
            Some(Ok((prediction, innovation))) => IdOutput {
                prediction,
                innovation,
                error: None,
                ticks: ticks32(t),
            },
            Some(Err(e)) => IdOutput::rejected(e, ticks32(t)),
            // The measured closure always runs; this only keeps the code panic-free.
            None => IdOutput::rejected(Error::Numerical, ticks32(t)),
        };
        msg::Estimate {
            time_us: s.time_us,
            mode: m.mode,
            fuzzy: output(fuzzy, tf),
            plain: output(plain, tp),
        }
    }

    /// `Reset`: both identifiers back to θ = 0, P = αI in `form`. A new form is set in place
    /// ([`rotorid::HoverIdentifier::reconfigure`]): nothing is rebuilt or moved, so a Reset
    /// costs no stack beyond the call itself.
    pub fn reset(&mut self, form: RlsForm) -> Result<(), ResetError> {
        self.stage = None;
        self.fuzzy_stage = None;
        let (Ok(f), Ok(p)) = (&mut self.fuzzy, &mut self.plain) else {
            return Err(ResetError::IdentifierMissing);
        };
        if form == self.form {
            f.reset();
            p.reset();
            return Ok(());
        }
        let c = config(form);
        // Both validate the same settings: the second cannot fail after the first passed.
        f.reconfigure(c).map_err(ResetError::Core)?;
        p.reconfigure(c).map_err(ResetError::Core)?;
        self.form = form;
        Ok(())
    }

    /// θ of `ident`'s four models (velocity, q̂, r̂, p̂), for telemetry; `None` if that
    /// identifier failed to build.
    pub fn thetas(&self, ident: Ident) -> Option<[&[f32]; 4]> {
        let views = match ident {
            Ident::Plain => self.plain_views(),
            _ => self.fuzzy_views(),
        }?;
        Some(views.map(|v| v.parameters()))
    }

    fn fuzzy_views(&self) -> Option<[RlsView<'_, f32>; 4]> {
        let f = self.fuzzy.as_ref().ok()?;
        Some([
            f.velocity_model().ts().rls().view(),
            f.pitch_model().ts().rls().view(),
            f.yaw_model().ts().rls().view(),
            f.roll_model().ts().rls().view(),
        ])
    }

    fn plain_views(&self) -> Option<[RlsView<'_, f32>; 4]> {
        let p = self.plain.as_ref().ok()?;
        Some([
            p.velocity_model().ts().rls().view(),
            p.pitch_model().ts().rls().view(),
            p.yaw_model().ts().rls().view(),
            p.roll_model().ts().rls().view(),
        ])
    }

    /// `ParamsRequest`: θ, diag(P) and summary of each model, in order.
    pub fn params(&self, seq: u16, ident: Ident, out: &mut dyn Reply) {
        match (ident, &self.fuzzy, &self.plain) {
            (Ident::Plain, _, Ok(p)) => {
                p.for_each_rls(|m, _, v| send_model_params(out, ident, m.index(), &v));
            }
            (Ident::Fuzzy, Ok(f), _) => {
                f.for_each_rls(|m, _, v| send_model_params(out, ident, m.index(), &v));
            }
            _ => out.nack(seq, MsgType::ParamsRequest.code(), NackReason::Refused),
        }
    }

    /// `ExportRequest`: the snapshot stream in `ExportChunk`s.
    pub fn export(&self, seq: u16, ident: Ident, out: &mut dyn Reply) {
        let views = match ident {
            Ident::Plain => self.plain_views(),
            _ => self.fuzzy_views(),
        };
        let Some(views) = views else {
            out.nack(seq, MsgType::ExportRequest.code(), NackReason::Refused);
            return;
        };
        let total = msg::snapshot_len(&views);
        let crc = msg::snapshot_crc(&views);
        let mut offset = 0usize;
        loop {
            let mut data = [0u8; DataChunk::MAX_DATA];
            let n = msg::snapshot_read(&views, offset, &mut data);
            let chunk = DataChunk {
                ident,
                offset: offset as u32,
                total: total as u32,
                crc,
                data: data.get(..n).unwrap_or_default(),
            };
            out.reply(MsgType::ExportChunk, &mut |w| chunk.write(w));
            offset += n;
            if n == 0 || offset >= total {
                break;
            }
        }
    }

    /// `ImportChunk`: stages chunks in order; the last one is CRC-checked and imported.
    pub fn import_chunk(&mut self, seq: u16, c: &DataChunk<'_>, out: &mut dyn Reply) {
        let code = MsgType::ImportChunk.code();
        if c.ident != Ident::Plain {
            match self.fuzzy_chunk(c) {
                Ok(()) => out.ack(seq, code),
                Err(reason) => {
                    self.abort_fuzzy_import();
                    out.nack(seq, code, reason);
                }
            }
            return;
        }
        self.abort_fuzzy_import();
        if c.offset == 0 {
            if c.total as usize != PLAIN_SNAPSHOT_LEN {
                self.stage = None;
                out.nack(seq, code, NackReason::BadPayload);
                return;
            }
            self.stage = Some(ImportStage {
                buf: [0; PLAIN_SNAPSHOT_LEN],
                received: 0,
                total: c.total,
                crc: c.crc,
            });
        }
        let Some(st) = self.stage.as_mut() else {
            out.nack(seq, code, NackReason::BadPayload);
            return;
        };
        let in_order = c.offset as usize == st.received && c.total == st.total && c.crc == st.crc;
        let end = st.received + c.data.len();
        let dst = st.buf.get_mut(st.received..end);
        match (in_order, dst) {
            (true, Some(dst)) => {
                dst.copy_from_slice(c.data);
                st.received = end;
            }
            _ => {
                self.stage = None;
                out.nack(seq, code, NackReason::BadPayload);
                return;
            }
        }
        if st.received < st.total as usize {
            out.ack(seq, code);
            return;
        }
        let result = if msg::stream_crc(&st.buf) != st.crc {
            Err(NackReason::BadPayload)
        } else {
            parse_plain(&st.buf).ok_or(NackReason::BadPayload)
        };
        self.stage = None;
        let plain = &mut self.plain;
        match result.and_then(|snap| {
            plain
                .as_mut()
                .map_err(|e| *e)
                .and_then(|p| p.import(&snap))
                .map_err(|e| {
                    defmt::warn!("import refused by the core: {}", e);
                    NackReason::Refused
                })
        }) {
            Ok(()) => out.ack(seq, code),
            Err(reason) => out.nack(seq, code, reason),
        }
    }

    /// Drops a fuzzy import in progress; if it had already written a model, the fuzzy
    /// identifier is reset (never a mix of old and new models).
    fn abort_fuzzy_import(&mut self) {
        if let Some(st) = self.fuzzy_stage.take() {
            if st.touched {
                if let Ok(f) = &mut self.fuzzy {
                    f.reset();
                }
            }
        }
    }

    /// One chunk of a fuzzy import. `Ok` = acknowledge (the last chunk: all imported).
    fn fuzzy_chunk(&mut self, c: &DataChunk<'_>) -> Result<(), NackReason> {
        if c.offset == 0 {
            self.abort_fuzzy_import();
            if c.total as usize != FUZZY_SNAPSHOT_LEN {
                return Err(NackReason::BadPayload);
            }
            self.fuzzy_stage = Some(FuzzyImport {
                model: 0,
                pos: 0,
                word: [0; 4],
                state: FuzzyModel::V(blank()),
                received: 0,
                total: c.total,
                crc: c.crc,
                digest: CRC32.digest(),
                touched: false,
            });
        }
        let Some(st) = self.fuzzy_stage.as_mut() else {
            return Err(NackReason::BadPayload);
        };
        let in_order = c.offset as usize == st.received && c.total == st.total && c.crc == st.crc;
        if !in_order || st.received + c.data.len() > st.total as usize {
            return Err(NackReason::BadPayload);
        }
        st.digest.update(c.data);
        st.received += c.data.len();
        let Ok(f) = &mut self.fuzzy else {
            return Err(NackReason::Refused);
        };
        for &b in c.data {
            let target = match &mut st.state {
                FuzzyModel::V(s) => parts(s),
                FuzzyModel::Q(s) => parts(s),
                FuzzyModel::R(s) | FuzzyModel::P(s) => parts(s),
            };
            let ok = store_state_byte(target, st.pos, b, &mut st.word);
            if !ok {
                return Err(NackReason::BadPayload);
            }
            st.pos += 1;
            if st.pos < MODEL_LEN.get(st.model).copied().unwrap_or(0) {
                continue;
            }
            // A whole model: check and import it, then stage the next.
            if !st.touched {
                f.end_chain();
                st.touched = true;
            }
            let r = match &st.state {
                FuzzyModel::V(s) => f.velocity_model_mut().import(s),
                FuzzyModel::Q(s) => f.pitch_model_mut().import(s),
                FuzzyModel::R(s) => f.yaw_model_mut().import(s),
                FuzzyModel::P(s) => f.roll_model_mut().import(s),
            };
            if let Err(e) = r {
                defmt::warn!("import refused by the core: {}", e);
                return Err(NackReason::Refused);
            }
            st.model += 1;
            st.pos = 0;
            match st.model {
                1 => st.state = FuzzyModel::Q(blank()),
                2 => st.state = FuzzyModel::R(blank()),
                3 => st.state = FuzzyModel::P(blank()),
                _ => {}
            }
        }
        if st.received < st.total as usize {
            return Ok(());
        }
        let done = st.model == MODEL_LEN.len();
        let crc_ok = st.digest.clone().finalize() == st.crc;
        if done && crc_ok {
            // Complete: nothing to undo any more.
            self.fuzzy_stage = None;
            Ok(())
        } else {
            Err(NackReason::BadPayload)
        }
    }

    /// `SweepStart`: streams the requested part of Table 2's schedule, then acknowledges.
    pub fn sweep(&self, seq: u16, s: &SweepStart, out: &mut dyn Reply) {
        let code = MsgType::SweepStart.code();
        let amps = s.amplitudes.map(f64::from);
        let Ok(schedule) = SweepSchedule::table2(amps, u32::from(s.rate_hz)) else {
            out.nack(seq, code, NackReason::BadPayload);
            return;
        };
        let total = schedule.len();
        let end = s.start.saturating_add(s.count);
        for k in s.start..end {
            let Some(e) = schedule.at(k) else { break };
            let m = SweepSample {
                k,
                total,
                channel: e.channel,
                offset: e.offset,
            };
            out.reply(MsgType::SweepSample, &mut |w| m.write(w));
        }
        out.ack(seq, code);
    }
}

type PlainSnapshot = HoverSnapshot<PlainV, PlainQ, PlainR, PlainP>;

fn parse_plain(bytes: &[u8]) -> Option<PlainSnapshot> {
    let mut r = Reader::new(bytes);
    let velocity = msg::read_rls_state(&mut r).ok()?;
    let pitch = msg::read_rls_state(&mut r).ok()?;
    let yaw = msg::read_rls_state(&mut r).ok()?;
    let roll = msg::read_rls_state(&mut r).ok()?;
    r.finish().ok()?;
    Some(HoverSnapshot {
        velocity,
        pitch,
        yaw,
        roll,
    })
}

/// Sends one estimator's θ, diag(P) and summary as `Params` chunks. Size-erased (an
/// [`RlsView`]): one copy serves every model of both identifiers.
fn send_model_params(out: &mut dyn Reply, ident: Ident, model: u8, rls: &RlsView<'_, f32>) {
    let n = rls.len();
    for field in [ParamField::Theta, ParamField::CovarianceDiagonal] {
        let value = |i: usize| match field {
            ParamField::Theta => rls.parameters().get(i).copied(),
            _ => rls.covariance_diagonal_entry(i),
        };
        for start in (0..n).step_by(ParamsChunk::MAX_WORDS) {
            let end = n.min(start + ParamsChunk::MAX_WORDS);
            let mut words = [0u8; 4 * ParamsChunk::MAX_WORDS];
            for (dst, i) in words.chunks_exact_mut(4).zip(start..end) {
                let v = value(i).unwrap_or(0.0);
                dst.copy_from_slice(&v.to_bits().to_le_bytes());
            }
            let c = ParamsChunk {
                ident,
                model,
                field,
                index: start as u16,
                total: n as u16,
                words: words.get(..4 * (end - start)).unwrap_or_default(),
            };
            out.reply(MsgType::Params, &mut |w| c.write(w));
        }
    }
    let summary = msg::summary_words(rls);
    let mut words = [0u8; 4 * ParamsChunk::SUMMARY_WORDS];
    for (dst, v) in words.chunks_exact_mut(4).zip(summary) {
        dst.copy_from_slice(&v.to_le_bytes());
    }
    let c = ParamsChunk {
        ident,
        model,
        field: ParamField::Summary,
        index: 0,
        total: ParamsChunk::SUMMARY_WORDS as u16,
        words: &words,
    };
    out.reply(MsgType::Params, &mut |w| c.write(w));
}
