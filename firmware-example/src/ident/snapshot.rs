//! Export and warm start over the link, for both pairs: the core's snapshot
//! ([`rotorid::snapshot`], the C interface's export bytes) in `ExportChunk`s / `ImportChunk`s.
//!
//! Export streams straight from the estimators ([`msg::export_chunks`]). An import is staged
//! whole in [`IMPORT_CAPACITY`] bytes of static RAM, then handed to the core's decoder
//! ([`Snapshot::read_snapshot`]), which checks length, CRC, header (kind) and every value
//! before it writes anything. Staged rather than decoded on the fly because the decoder reads
//! the snapshot three times (CRC, checks, import) and a link cannot rewind; staging costs the
//! largest snapshot, the paper fuzzy identifier's 10 524 B (the flight default's is 1 900 B),
//! in place of the old per-model decoder's 6.2 KiB stage, and buys an import that is all or
//! nothing for every identifier: any refusal leaves the identifier bit for bit unchanged.

use rotorid::snapshot::Snapshot;
use rotorid::{
    ExtendedPlainIdentifier, FlightIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier,
};
use rotorid_link::msg::{
    self, snapshot_kind, DataChunk, Ident, IdentPair, ImportProgress, MsgType, NackReason, Staged,
};
use rotorid_link::SampleChain;

use super::{Identification, Reply};

const fn max(a: usize, b: usize) -> usize {
    if a > b {
        a
    } else {
        b
    }
}

/// Bytes of the import staging buffer: the largest snapshot of the four identifiers.
pub const IMPORT_CAPACITY: usize = max(
    max(
        <PaperFuzzyIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
        <PaperPlainIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
    ),
    max(
        <FlightIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
        <ExtendedPlainIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
    ),
);

/// Why a complete, intact snapshot was not imported.
enum Refusal {
    /// The identifier failed to build at start-up.
    Missing,
    /// The core refused it (kind, version or a value): nothing changed.
    Core(rotorid::Error),
}

/// `bytes` into `id` under `kind`, all or nothing.
fn import_into<I: Snapshot>(
    id: &mut Result<I, rotorid::Error>,
    kind: u32,
    bytes: &[u8],
) -> Result<(), Refusal> {
    let id = id.as_mut().map_err(|_| Refusal::Missing)?;
    id.read_snapshot(kind, bytes).map_err(Refusal::Core)
}

/// [`msg::export_chunks`] of `id`, or `false` if it failed to build.
fn export_from<I: Snapshot>(
    id: &Result<I, rotorid::Error>,
    kind: u32,
    ident: Ident,
    out: &mut dyn Reply,
) -> bool {
    let Ok(id) = id else { return false };
    msg::export_chunks(id, kind, ident, &mut |c| {
        out.reply(MsgType::ExportChunk, &mut |w| msg::Payload::write(c, w))
    });
    true
}

impl Identification {
    /// Bytes of the snapshot of `ident` of the active pair.
    fn snapshot_size(&self, ident: Ident) -> usize {
        match (self.pair(), ident) {
            (IdentPair::Flight, Ident::Fuzzy) => <FlightIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
            (IdentPair::Flight, _) => <ExtendedPlainIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
            (_, Ident::Fuzzy) => <PaperFuzzyIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
            (_, _) => <PaperPlainIdentifier<f32> as Snapshot>::SNAPSHOT_SIZE,
        }
    }

    /// `ExportRequest`: the snapshot of `ident` of the active pair in `ExportChunk`s.
    pub fn export(&self, seq: u16, ident: Ident, out: &mut dyn Reply) {
        let kind = snapshot_kind(self.pair(), ident);
        let sent = match (self.pair(), ident) {
            (IdentPair::Flight, Ident::Fuzzy) => export_from(&self.flight, kind, ident, out),
            (IdentPair::Flight, _) => export_from(&self.extended_plain, kind, ident, out),
            (_, Ident::Fuzzy) => export_from(&self.fuzzy, kind, ident, out),
            (_, _) => export_from(&self.plain, kind, ident, out),
        };
        if !sent {
            out.nack(seq, MsgType::ExportRequest.code(), NackReason::Refused);
        }
    }

    /// `ImportChunk`: stages chunks in order; on the last, the stream CRC is checked and the
    /// snapshot imported into `ident` of the active pair, all or nothing. `Nack` `BadPayload`
    /// for a chunk that does not continue the import (order, length, CRC), `Refused` for a
    /// snapshot the core refuses; either way the import is dropped and nothing changed. An
    /// import restarts the identifier's sample chain and its prediction chain.
    pub fn import_chunk(&mut self, seq: u16, c: &DataChunk<'_>, out: &mut dyn Reply) {
        let code = MsgType::ImportChunk.code();
        if c.offset == 0 {
            let expected = self.snapshot_size(c.ident);
            self.import = match ImportProgress::start(c, expected, IMPORT_CAPACITY) {
                Ok(p) => Some(p),
                Err(e) => {
                    defmt::warn!("import refused: {}", e);
                    self.import = None;
                    out.nack(seq, code, NackReason::BadPayload);
                    return;
                }
            };
        }
        let staged = match self.import.as_mut() {
            Some(p) => p.take(&mut self.import_buf, c),
            None => Err(msg::StageError::OutOfOrder {
                expected: 0,
                got: c.offset,
            }),
        };
        let len = match staged {
            Ok(Staged::More) => {
                out.ack(seq, code);
                return;
            }
            Ok(Staged::Complete { len }) => len,
            Err(e) => {
                defmt::warn!("import chunk refused: {}", e);
                self.import = None;
                out.nack(seq, code, NackReason::BadPayload);
                return;
            }
        };
        self.import = None;
        let bytes = self.import_buf.get(..len).unwrap_or_default();
        let kind = snapshot_kind(self.pair, c.ident);
        let (result, chain) = match (self.pair, c.ident) {
            (IdentPair::Flight, Ident::Fuzzy) => (
                import_into(&mut self.flight, kind, bytes),
                &mut self.fuzzy_chain,
            ),
            (IdentPair::Flight, _) => (
                import_into(&mut self.extended_plain, kind, bytes),
                &mut self.plain_chain,
            ),
            (_, Ident::Fuzzy) => (
                import_into(&mut self.fuzzy, kind, bytes),
                &mut self.fuzzy_chain,
            ),
            (_, _) => (
                import_into(&mut self.plain, kind, bytes),
                &mut self.plain_chain,
            ),
        };
        match result {
            Ok(()) => {
                *chain = SampleChain::new();
                out.ack(seq, code);
            }
            Err(Refusal::Core(e)) => {
                defmt::warn!("import refused by the core: {}", e);
                out.nack(seq, code, NackReason::Refused);
            }
            Err(Refusal::Missing) => out.nack(seq, code, NackReason::Refused),
        }
    }
}
