//! Onboard identification: the identifier pairs and the handlers of the identification
//! messages (board-agnostic, like the `link` module).
//!
//! Two pairs live side by side; `Reset` chooses which one answers `Sample` ([`IdentPair`]):
//! the paper's (`PaperFuzzyIdentifier` + `PaperPlainIdentifier`, reproduction) and the flight
//! default against its baseline (`FlightIdentifier` with `flight_sets()` +
//! `ExtendedPlainIdentifier`).
//!
//! * `Sample` → `Estimate`: one sample through both identifiers of the active pair, each
//!   timed; what each mode does is [`rotorid_link::SampleChain`] (shared with the host's
//!   mirror). A sample the core rejects leaves the identifier unchanged (the core's contract)
//!   and the reply says which `rotorid::Error`. A `FreeRun` sample while an identifier has
//!   no prediction to continue from is refused (`Nack` `Refused`), nothing changed.
//! * `ParamsRequest` → `Params`…: θ, diag(P) and a summary of each of the four models.
//! * `ExportRequest` → `ExportChunk`…: the identifier's snapshot, the core's one format
//!   (`rotorid::snapshot`, the C interface's export bytes under the same kind code), read
//!   straight from the estimators, for either pair (`snapshot` module).
//! * `ImportChunk`…: warm start, for either pair. The snapshot is staged whole (10 524 B of
//!   static RAM, the largest identifier's), then imported by the core's decoder, which checks
//!   everything before it writes anything: a refused import (chunk out of order, CRC, a
//!   snapshot of another identifier type, a value the core refuses) leaves the identifier
//!   bit for bit unchanged (see `docs/protocol.md`).
//! * Params are implemented for the paper pair; while the flight pair is active they are
//!   refused (`Nack` `Refused`): a locally learnt model has one estimator per rule, which the
//!   `Params` message (one per model) cannot name.
//! * `SweepStart` → `SweepSample`…, `Ack`: Table 2's excitation generated onboard.
//! * `Compensate` → `Ack`: the active pair's rate models compensated for the gyros' noise
//!   (`HoverIdentifier::compensate`), the parameters to free-run with; `CompensateEach`, the
//!   same with a choice per rate (`HoverIdentifier::compensate_each`).

use core::mem::MaybeUninit;
use core::sync::atomic::{AtomicBool, Ordering};

use rotorid::hover::{flight_sets, GyroCompensation, HoverIdentifier, StateModel};
use rotorid::rls::RlsView;
use rotorid::sweep::SweepSchedule;
use rotorid::{
    Error, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig, PaperFuzzyIdentifier,
    PaperPlainIdentifier,
};
use rotorid_link::msg::{
    self, IdOutput, Ident, IdentPair, ImportProgress, MsgType, NackReason, ParamField, ParamsChunk,
    Payload, PremisesMsg, RlsForm, SampleMode, SampleMsg, SweepSample, SweepStart,
};
use rotorid_link::{SampleChain, Writer};

mod snapshot;

pub use snapshot::IMPORT_CAPACITY;

/// Why a `Reset` was not carried out.
#[derive(Clone, Copy, Debug, PartialEq, defmt::Format)]
pub enum ResetError {
    /// An identifier failed to build at start-up (not expected: their settings are constants).
    IdentifierMissing,
    /// The core refused the new settings.
    Core(Error),
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
    flight: Result<FlightIdentifier<f32>, Error>,
    extended_plain: Result<ExtendedPlainIdentifier<f32>, Error>,
    /// The pair answering `Sample`.
    pair: IdentPair,
    /// Prediction chains of the active pair's fuzzy and plain identifier.
    fuzzy_chain: SampleChain,
    plain_chain: SampleChain,
    form: RlsForm,
    /// The import being staged, if any, and its bytes (`snapshot` module).
    import: Option<ImportProgress>,
    import_buf: [u8; IMPORT_CAPACITY],
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

/// `FlightIdentifier::flight(c, flight_sets())` written straight into `dst`.
#[inline(never)]
fn build_flight(dst: &mut MaybeUninit<Result<FlightIdentifier<f32>, Error>>, c: HoverConfig<f32>) {
    dst.write(FlightIdentifier::flight(c, flight_sets()));
}

/// `extended_plain(c)` written straight into `dst`.
#[inline(never)]
fn build_extended_plain(
    dst: &mut MaybeUninit<Result<ExtendedPlainIdentifier<f32>, Error>>,
    c: HoverConfig<f32>,
) {
    dst.write(ExtendedPlainIdentifier::extended_plain(c));
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

/// [`Identification::compensate_each`] of one pair: both identifiers take the same σ, so
/// once the first accepted it the second does too.
fn compensate_both<A, B, C, D, E, F, G, H>(
    fuzzy: &mut Result<HoverIdentifier<f32, A, B, C, D>, Error>,
    plain: &mut Result<HoverIdentifier<f32, E, F, G, H>, Error>,
    gyro_noise: &[f32; 3],
    how: [GyroCompensation; 3],
) -> Result<(), Error>
where
    A: StateModel<f32>,
    B: StateModel<f32>,
    C: StateModel<f32>,
    D: StateModel<f32>,
    E: StateModel<f32>,
    F: StateModel<f32>,
    G: StateModel<f32>,
    H: StateModel<f32>,
{
    let (Ok(f), Ok(p)) = (fuzzy, plain) else {
        return Err(Error::Incompatible);
    };
    f.compensate_each(gyro_noise, how)?;
    p.compensate_each(gyro_noise, how)?;
    Ok(())
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
            build_flight(&mut *core::ptr::addr_of_mut!((*p).flight).cast(), c);
            build_extended_plain(&mut *core::ptr::addr_of_mut!((*p).extended_plain).cast(), c);
            core::ptr::addr_of_mut!((*p).pair).write(IdentPair::Paper);
            core::ptr::addr_of_mut!((*p).fuzzy_chain).write(SampleChain::new());
            core::ptr::addr_of_mut!((*p).plain_chain).write(SampleChain::new());
            core::ptr::addr_of_mut!((*p).form).write(RlsForm::UdDefault);
            core::ptr::addr_of_mut!((*p).import).write(None);
            // Zeroed in place: a `[0; N]` value would be built on the stack first.
            core::ptr::addr_of_mut!((*p).import_buf).write_bytes(0, 1);
        }
        // SAFETY: every field was initialised above.
        let engine = unsafe { slot.assume_init_mut() };
        (engine.fuzzy.is_ok()
            && engine.plain.is_ok()
            && engine.flight.is_ok()
            && engine.extended_plain.is_ok())
        .then_some(engine)
    }

    /// `Sample`: runs both identifiers of the active pair, each under `measure`; `None`
    /// (answer `Nack` `Refused`, nothing changed) for a `FreeRun` while an identifier has no
    /// prediction to continue from.
    pub fn sample(
        &mut self,
        m: &SampleMsg,
        measure: &mut dyn FnMut(&mut dyn FnMut()) -> u64,
    ) -> Option<msg::Estimate> {
        if m.mode == SampleMode::FreeRun
            && !(self.fuzzy_chain.can_free_run() && self.plain_chain.can_free_run())
        {
            return None;
        }
        let (fc, pc) = (&mut self.fuzzy_chain, &mut self.plain_chain);
        let (fuzzy, plain) = match self.pair {
            IdentPair::Flight => (
                answer_timed(&mut self.flight, fc, m, measure),
                answer_timed(&mut self.extended_plain, pc, m, measure),
            ),
            _ => (
                answer_timed(&mut self.fuzzy, fc, m, measure),
                answer_timed(&mut self.plain, pc, m, measure),
            ),
        };
        Some(msg::Estimate {
            time_us: m.sample.time_us,
            mode: m.mode,
            fuzzy,
            plain,
        })
    }

    /// `Reset`: every identifier back to θ = 0, P = αI in `form`, both prediction chains
    /// empty, and `pair` answers `Sample` from now on. A new form is set in place
    /// ([`rotorid::HoverIdentifier::reconfigure`]): nothing is rebuilt or moved, so a Reset
    /// costs no stack beyond the call itself.
    pub fn reset(&mut self, form: RlsForm, pair: IdentPair) -> Result<(), ResetError> {
        self.import = None;
        self.fuzzy_chain = SampleChain::new();
        self.plain_chain = SampleChain::new();
        let (Ok(f), Ok(p), Ok(fl), Ok(xp)) = (
            &mut self.fuzzy,
            &mut self.plain,
            &mut self.flight,
            &mut self.extended_plain,
        ) else {
            return Err(ResetError::IdentifierMissing);
        };
        if form == self.form {
            f.reset();
            p.reset();
            fl.reset();
            xp.reset();
        } else {
            let c = config(form);
            // All validate the same settings: the others cannot fail after the first passed.
            f.reconfigure(c).map_err(ResetError::Core)?;
            p.reconfigure(c).map_err(ResetError::Core)?;
            fl.reconfigure(c).map_err(ResetError::Core)?;
            xp.reconfigure(c).map_err(ResetError::Core)?;
            self.form = form;
        }
        self.pair = pair;
        Ok(())
    }

    /// `Compensate` and `CompensateEach`: both identifiers of the active pair compensate
    /// their rate models for the gyros' white noise σ `[q r p]` (deg/s) in place, each rate
    /// as `how` says (`HoverIdentifier::compensate_each`; `Compensate` is damping on every
    /// rate). The first is checked before the second is changed, so on `Err` (σ refused)
    /// nothing changed.
    pub fn compensate_each(
        &mut self,
        gyro_noise: &[f32; 3],
        how: [GyroCompensation; 3],
    ) -> Result<(), Error> {
        match self.pair {
            IdentPair::Flight => {
                compensate_both(&mut self.flight, &mut self.extended_plain, gyro_noise, how)
            }
            _ => compensate_both(&mut self.fuzzy, &mut self.plain, gyro_noise, how),
        }
    }

    /// `Premises`: the flight pair's `FlightIdentifier` rebuilt on `m`'s sets and speeds
    /// (`FlightIdentifier::flight_scheduled`, θ = 0, P = αI in the current form), kept across
    /// `Reset` until the next `Premises`. When the flight pair answers, its fuzzy prediction
    /// chain restarts and an import in progress is dropped. On `Err` (the core refused the
    /// sets or a speed) nothing changed.
    pub fn premises(&mut self, m: &PremisesMsg) -> Result<(), Error> {
        let built =
            FlightIdentifier::flight_scheduled(config(self.form), m.sets(), m.scheduling())?;
        self.flight = Ok(built);
        if self.pair == IdentPair::Flight {
            self.fuzzy_chain = SampleChain::new();
            self.import = None;
        }
        Ok(())
    }

    /// The pair answering `Sample`.
    pub fn pair(&self) -> IdentPair {
        self.pair
    }

    /// θ of `ident`'s four models (velocity, q̂, r̂, p̂), for telemetry; `None` if that
    /// identifier failed to build.
    pub fn thetas(&self, ident: Ident) -> Option<[&[f32]; 4]> {
        if self.pair != IdentPair::Paper {
            return None;
        }
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
            _ if self.pair != IdentPair::Paper => {
                out.nack(seq, MsgType::ParamsRequest.code(), NackReason::Refused)
            }
            (Ident::Plain, _, Ok(p)) => {
                p.for_each_rls(|m, _, v| send_model_params(out, ident, m.index(), &v));
            }
            (Ident::Fuzzy, Ok(f), _) => {
                f.for_each_rls(|m, _, v| send_model_params(out, ident, m.index(), &v));
            }
            _ => out.nack(seq, MsgType::ParamsRequest.code(), NackReason::Refused),
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

/// `chain.answer(id, m)` under `measure`, as the identifier's [`IdOutput`].
fn answer_timed<Vm, Qm, Rm, Pm>(
    id: &mut Result<HoverIdentifier<f32, Vm, Qm, Rm, Pm>, Error>,
    chain: &mut SampleChain,
    m: &SampleMsg,
    measure: &mut dyn FnMut(&mut dyn FnMut()) -> u64,
) -> IdOutput
where
    Vm: StateModel<f32>,
    Qm: StateModel<f32>,
    Rm: StateModel<f32>,
    Pm: StateModel<f32>,
{
    let mut answer = None;
    let t = ticks32(measure(&mut || {
        answer = Some(match id {
            Err(e) => Err(*e),
            // `None` only for a FreeRun without a start, refused before we get here.
            Ok(id) => chain.answer(id, m).unwrap_or(Err(Error::Numerical)),
        })
    }));
    match answer {
        Some(Ok((prediction, innovation))) => IdOutput {
            prediction,
            innovation,
            error: None,
            ticks: t,
        },
        Some(Err(e)) => IdOutput::rejected(e, t),
        // The measured closure always runs; this only keeps the code panic-free.
        None => IdOutput::rejected(Error::Numerical, t),
    }
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
