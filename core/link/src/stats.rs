//! Counters of one receiving direction of a link, and its sequence-number bookkeeping.
//!
//! Framing-level: the counters know frame errors, not messages (the catalogue's `Stats`
//! message carries them; see `msg::link`).

/// Counters of one receiving direction of a link. All counters wrap at `u32::MAX`.
///
/// Every delimiter-terminated, non-empty chunk of bytes ends up in exactly one of
/// `frames_ok`, `cobs_errors`, `crc_errors`, `too_short`, `oversized` or `unknown_version`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkStats {
    /// Valid frames delivered.
    pub frames_ok: u32,
    /// Chunks rejected as invalid COBS.
    pub cobs_errors: u32,
    /// Chunks rejected for a CRC mismatch.
    pub crc_errors: u32,
    /// Chunks shorter than header + CRC.
    pub too_short: u32,
    /// Chunks longer than the receive buffer (dropped up to the next delimiter).
    pub oversized: u32,
    /// Intact frames of an unknown protocol version.
    pub unknown_version: u32,
    /// Times the sequence number jumped forward (one or more frames lost in between).
    pub seq_gaps: u32,
    /// Frames lost according to the sequence numbers (sum of the forward jumps).
    pub lost_frames: u32,
    /// Times the sequence number went backwards or repeated (peer restart, duplicate, or a
    /// jump of 32768 or more); not counted as lost frames.
    pub seq_resets: u32,
    /// Bytes received, delimiters included.
    pub bytes: u32,
}

impl LinkStats {
    /// Number of 32-bit counters in [`LinkStats::to_array`].
    pub const FIELDS: usize = 10;

    /// Total of all rejected chunks.
    pub fn rejected(&self) -> u32 {
        self.cobs_errors
            .wrapping_add(self.crc_errors)
            .wrapping_add(self.too_short)
            .wrapping_add(self.oversized)
            .wrapping_add(self.unknown_version)
    }

    /// Counters in wire order (see `docs/protocol.md`).
    pub fn to_array(&self) -> [u32; Self::FIELDS] {
        [
            self.frames_ok,
            self.cobs_errors,
            self.crc_errors,
            self.too_short,
            self.oversized,
            self.unknown_version,
            self.seq_gaps,
            self.lost_frames,
            self.seq_resets,
            self.bytes,
        ]
    }

    /// Inverse of [`LinkStats::to_array`].
    pub fn from_array(a: [u32; Self::FIELDS]) -> Self {
        let [frames_ok, cobs_errors, crc_errors, too_short, oversized, unknown_version, seq_gaps, lost_frames, seq_resets, bytes] =
            a;
        Self {
            frames_ok,
            cobs_errors,
            crc_errors,
            too_short,
            oversized,
            unknown_version,
            seq_gaps,
            lost_frames,
            seq_resets,
            bytes,
        }
    }
}

/// Sequence-number bookkeeping of one receiving direction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SeqTracker {
    expected: Option<u16>,
}

impl SeqTracker {
    /// A tracker that takes the first sequence number it sees as the start.
    pub const fn new() -> Self {
        Self { expected: None }
    }

    /// Records `seq`; updates `seq_gaps`, `lost_frames` and `seq_resets` in `stats`.
    pub fn observe(&mut self, seq: u16, stats: &mut LinkStats) {
        if let Some(expected) = self.expected {
            let jump = seq.wrapping_sub(expected);
            // Forward jumps of less than half the sequence space are losses; anything else is a
            // duplicate, reordering or peer restart, which must not inflate the loss count.
            if jump != 0 && jump < 0x8000 {
                stats.seq_gaps = stats.seq_gaps.wrapping_add(1);
                stats.lost_frames = stats.lost_frames.wrapping_add(u32::from(jump));
            } else if jump != 0 {
                stats.seq_resets = stats.seq_resets.wrapping_add(1);
            }
        }
        self.expected = Some(seq.wrapping_add(1));
    }
}
