//! Warm start: the import of an exported state into the onboard identifiers, from `ImportChunk`s.
//! The plain identifier's stream is staged whole; the fuzzy identifier's (10.5 KiB) is decoded
//! one model at a time into a staging `RlsState` (see the module docs of [`super`]).

use rotorid::hover::{HoverModels, HoverSnapshot, StateModel};
use rotorid::{PaperFuzzyIdentifier, PaperPlainIdentifier, RlsState};
use rotorid_link::msg::{
    self, state_len, DataChunk, Ident, IdentPair, MsgType, NackReason, StateDecoder, StateParts,
};
use rotorid_link::Reader;

use super::{Identification, Reply};

/// Bytes of the plain identifier's snapshot stream (its four models' states).
pub const PLAIN_SNAPSHOT_LEN: usize = state_len(PlainV::PARAMETERS, PlainV::FACTOR_LEN)
    + state_len(PlainQ::PARAMETERS, PlainQ::FACTOR_LEN)
    + state_len(PlainR::PARAMETERS, PlainR::FACTOR_LEN)
    + state_len(PlainP::PARAMETERS, PlainP::FACTOR_LEN);

/// Staging area of an import into the plain identifier.
pub(super) struct ImportStage {
    buf: [u8; PLAIN_SNAPSHOT_LEN],
    received: usize,
    total: u32,
    crc: u32,
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

const MODEL_LEN: [usize; 4] = [
    state_len(FuzzyV::PARAMETERS, FuzzyV::FACTOR_LEN),
    state_len(FuzzyQ::PARAMETERS, FuzzyQ::FACTOR_LEN),
    state_len(FuzzyR::PARAMETERS, FuzzyR::FACTOR_LEN),
    state_len(FuzzyP::PARAMETERS, FuzzyP::FACTOR_LEN),
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
pub(super) struct FuzzyImport {
    model: usize,
    /// The current model's bytes so far.
    decoder: StateDecoder,
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

impl Identification {
    /// `ImportChunk`: stages chunks in order; the last one is CRC-checked and imported.
    pub fn import_chunk(&mut self, seq: u16, c: &DataChunk<'_>, out: &mut dyn Reply) {
        let code = MsgType::ImportChunk.code();
        if self.pair() != IdentPair::Paper {
            self.abort_fuzzy_import();
            self.stage = None;
            out.nack(seq, code, NackReason::Refused);
            return;
        }
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
    pub(super) fn abort_fuzzy_import(&mut self) {
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
                decoder: StateDecoder::new(),
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
            let parts = match &mut st.state {
                FuzzyModel::V(s) => StateParts::from(s),
                FuzzyModel::Q(s) => StateParts::from(s),
                FuzzyModel::R(s) | FuzzyModel::P(s) => StateParts::from(s),
            };
            if st.decoder.push(parts, b).is_err() {
                return Err(NackReason::BadPayload);
            }
            if st.decoder.position() < MODEL_LEN.get(st.model).copied().unwrap_or(0) {
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
            st.decoder = StateDecoder::new();
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
}
