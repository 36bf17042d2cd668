//! The record in a NOR flash through `embedded-storage` (erase, then program; read through a
//! 64-byte window): [`read`], [`write`] and the slots' layout [`Slots`].

use embedded_storage::nor_flash::{NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash};

use super::{
    check_header, pick, scan, size, size_of, Header, ReadAt, RecordError, RecordInfo, Slot, Words,
    CHUNK, HEADER_SIZE, MAGIC, VERSION,
};
use crate::error::Error;
use crate::snapshot::{CrcSink, Snapshot, WordSink};

/// One slot of a flash.
struct FlashSlot<'f, F> {
    flash: &'f mut F,
    base: u32,
    len: usize,
}

impl<F: ReadNorFlash> ReadAt for FlashSlot<'_, F> {
    fn len(&self) -> usize {
        self.len
    }
    fn read_at(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), NorFlashErrorKind> {
        let offset = u32::try_from(offset).map_err(|_| NorFlashErrorKind::OutOfBounds)?;
        let at = self
            .base
            .checked_add(offset)
            .ok_or(NorFlashErrorKind::OutOfBounds)?;
        self.flash.read(at, buf).map_err(|e| e.kind())
    }
}

/// Checks the header of the valid record `h` that `slot` holds and imports its snapshot into
/// `id`; returns its sequence number.
fn import_checked<R: ReadAt, I: Snapshot>(
    slot: &mut R,
    h: Header,
    id: &mut I,
    kind: u32,
) -> Result<u32, RecordError> {
    check_header(&h, kind, id.config_hash())?;
    if h.payload != I::SNAPSHOT_SIZE {
        return Err(RecordError::Refused(Error::Incompatible));
    }
    let mut words = Words::new(slot, HEADER_SIZE, HEADER_SIZE + h.payload);
    let imported = id.import_snapshot(kind, &mut words);
    match (imported, words.failed) {
        (_, Some(e)) => Err(RecordError::Storage(e)),
        (Err(e), None) => Err(RecordError::Refused(e)),
        (Ok(()), None) => Ok(h.sequence),
    }
}

/// Streams the record (sequence `sequence`) of `id` into `sink`, its CRC last.
fn put_record<I: Snapshot>(id: &I, kind: u32, sequence: u32, sink: &mut impl WordSink) {
    let mut w = CrcSink::new(sink);
    w.put_word(MAGIC);
    w.put_word(VERSION.to_le_bytes());
    w.put_word(kind.to_le_bytes());
    w.put_word(id.config_hash().to_le_bytes());
    w.put_word(sequence.to_le_bytes());
    // Snapshot sizes are at most a few tens of KiB.
    w.put_word(
        u32::try_from(I::SNAPSHOT_SIZE)
            .unwrap_or(u32::MAX)
            .to_le_bytes(),
    );
    id.put_snapshot(kind, &mut w);
    let crc = w.digest.finalize();
    w.sink.put_word(crc.to_le_bytes());
}

/// The two slots of a flash: byte offsets of A and B, and the bytes of each.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Slots {
    /// Offset of slot A in the flash (bytes).
    pub a: u32,
    /// Offset of slot B in the flash (bytes).
    pub b: u32,
    /// Bytes of each slot: whole erase sectors.
    pub size: u32,
}

impl Slots {
    /// Offset of `slot`.
    pub const fn offset(&self, slot: Slot) -> u32 {
        match slot {
            Slot::A => self.a,
            Slot::B => self.b,
        }
    }

    /// `Layout` unless both slots lie in `capacity` bytes, do not overlap, start and end on
    /// multiples of `align` and hold `needed` bytes, and `io` (read or write size) divides
    /// [`CHUNK`].
    fn check(
        &self,
        capacity: usize,
        align: usize,
        io: usize,
        needed: usize,
    ) -> Result<(), RecordError> {
        let size = self.size as usize;
        let (a, b) = (self.a as usize, self.b as usize);
        let fits = |at: usize| at.checked_add(size).is_some_and(|end| end <= capacity);
        let aligned = |x: usize| align != 0 && x.is_multiple_of(align);
        let ok = needed <= size
            && fits(a)
            && fits(b)
            && (a.saturating_add(size) <= b || b.saturating_add(size) <= a)
            && aligned(a)
            && aligned(b)
            && aligned(size)
            && io != 0
            && CHUNK.is_multiple_of(io);
        if ok {
            Ok(())
        } else {
            Err(RecordError::Layout)
        }
    }

    fn reader<'f, F>(&self, flash: &'f mut F, slot: Slot) -> FlashSlot<'f, F> {
        FlashSlot {
            flash,
            base: self.offset(slot),
            len: self.size as usize,
        }
    }
}

/// The newest valid record in the flash's slots, if any.
pub fn newest_in<F: ReadNorFlash>(
    flash: &mut F,
    slots: &Slots,
) -> Result<Option<RecordInfo>, RecordError> {
    slots.check(flash.capacity(), F::READ_SIZE, F::READ_SIZE, size(0))?;
    newest_flash(flash, slots).map(|n| {
        n.map(|(slot, h)| RecordInfo {
            slot,
            sequence: h.sequence,
        })
    })
}

fn newest_flash<F: ReadNorFlash>(
    flash: &mut F,
    slots: &Slots,
) -> Result<Option<(Slot, Header)>, RecordError> {
    let a = scan(&mut slots.reader(flash, Slot::A)).map_err(RecordError::Storage)?;
    let b = scan(&mut slots.reader(flash, Slot::B)).map_err(RecordError::Storage)?;
    Ok(pick(a, b))
}

/// Imports the newest valid record in the flash's slots into `id` (of kind `kind`, built
/// with the configuration and sets the record was learnt under). On `Err` nothing was
/// imported (if the flash gives the same bytes on every read; a read that fails halfway
/// through the import is `Storage`, and then `id` may hold some models of the record:
/// [`reset`](crate::HoverIdentifier::reset) it).
pub fn read<F: ReadNorFlash, I: Snapshot>(
    flash: &mut F,
    slots: &Slots,
    id: &mut I,
    kind: u32,
) -> Result<RecordInfo, RecordError> {
    slots.check(flash.capacity(), F::READ_SIZE, F::READ_SIZE, size(0))?;
    let (slot, h) = newest_flash(flash, slots)?.ok_or(RecordError::NoValidRecord)?;
    import_checked(&mut slots.reader(flash, slot), h, id, kind)
        .map(|sequence| RecordInfo { slot, sequence })
}

/// Writes the record of `id` (kind code `kind`) into the slot that does not hold the newest
/// valid record, with the sequence number after it: erase, then program front to back.
/// Returns where it went. A cut power leaves the other slot's record intact.
pub fn write<F: NorFlash, I: Snapshot>(
    flash: &mut F,
    slots: &Slots,
    id: &I,
    kind: u32,
) -> Result<RecordInfo, RecordError> {
    slots.check(
        flash.capacity(),
        F::ERASE_SIZE,
        F::WRITE_SIZE,
        size_of::<I>(),
    )?;
    if !CHUNK.is_multiple_of(F::READ_SIZE.max(1)) {
        return Err(RecordError::Layout);
    }
    let target = match newest_flash(flash, slots)? {
        Some((slot, h)) => RecordInfo {
            slot: slot.other(),
            sequence: h.sequence.wrapping_add(1),
        },
        None => RecordInfo {
            slot: Slot::A,
            sequence: 0,
        },
    };
    let base = slots.offset(target.slot);
    let end = base.checked_add(slots.size).ok_or(RecordError::Layout)?;
    flash
        .erase(base, end)
        .map_err(|e| RecordError::Storage(e.kind()))?;
    let mut sink = FlashSink {
        flash,
        at: base,
        chunk: [0xFF; CHUNK],
        fill: 0,
        failed: None,
    };
    put_record(id, kind, target.sequence, &mut sink);
    sink.flush();
    match sink.failed {
        Some(e) => Err(RecordError::Storage(e)),
        None => Ok(target),
    }
}

/// Programs words a chunk at a time (the last chunk padded with erased bytes to the write
/// size).
struct FlashSink<'f, F> {
    flash: &'f mut F,
    at: u32,
    chunk: [u8; CHUNK],
    fill: usize,
    failed: Option<NorFlashErrorKind>,
}

impl<F: NorFlash> FlashSink<'_, F> {
    fn flush(&mut self) {
        if self.fill == 0 || self.failed.is_some() {
            return;
        }
        let ws = F::WRITE_SIZE.max(1);
        let len = self.fill.div_ceil(ws).saturating_mul(ws).min(CHUNK);
        if let Some(buf) = self.chunk.get(..len) {
            if let Err(e) = self.flash.write(self.at, buf) {
                self.failed = Some(e.kind());
            }
        }
        self.at = self.at.saturating_add(len as u32);
        self.chunk = [0xFF; CHUNK];
        self.fill = 0;
    }
}

impl<F: NorFlash> WordSink for FlashSink<'_, F> {
    fn put_word(&mut self, word: [u8; 4]) {
        if let Some(dst) = self.chunk.get_mut(self.fill..self.fill + 4) {
            for (d, s) in dst.iter_mut().zip(word) {
                *d = s;
            }
        }
        self.fill += 4;
        if self.fill >= CHUNK {
            self.flush();
        }
    }
}
