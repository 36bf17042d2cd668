//! Which identifier and which quantity a `DEBUG_FLOAT_ARRAY` carries: its `array_id` and `name`.
//!
//! ```text
//! array_id = slot << 12 | kind << 8 | chunk      (slot 0..=15, kind 1..=5, chunk 0..=255)
//! (a tag has 1 to 3 characters, so `abc.thv255` is the longest name: it fills the 10 bytes)
//! name     = "<tag>.out"            kind 1: prediction and innovation of one step
//!            "<tag>.th<m><chunk>"   kind 2..=5: θ of model m = v, q, r, p, floats 58·chunk..
//! ```
//!
//! `array_id` is the key a client should use; names are for people (plots in a GCS).

use crate::EncodeError;

/// Floats in one `DEBUG_FLOAT_ARRAY` (its `data` extension field).
pub const ARRAY_LEN: usize = 58;

/// Most characters in a [`Sender`]'s tag.
pub const MAX_TAG_LEN: usize = 3;

/// Who sends: one identifier on the vehicle, as a slot (0..=15, the top nibble of `array_id`)
/// and a short ASCII tag that starts every message name (e.g. `ts` for the Takagi-Sugeno
/// identifier).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sender {
    slot: u8,
    tag: [u8; MAX_TAG_LEN],
    tag_len: u8,
}

impl Sender {
    /// An identifier in slot `slot` (≤ 15) tagged `tag` (1 to 3 ASCII letters, digits or `_`).
    pub fn new(slot: u8, tag: &str) -> Result<Self, EncodeError> {
        let ok = |b: &u8| b.is_ascii_alphanumeric() || *b == b'_';
        let bytes = tag.as_bytes();
        if slot > 15 || bytes.is_empty() || bytes.len() > MAX_TAG_LEN || !bytes.iter().all(ok) {
            return Err(EncodeError::InvalidSender);
        }
        let mut t = [0u8; MAX_TAG_LEN];
        for (d, s) in t.iter_mut().zip(bytes) {
            *d = *s;
        }
        Ok(Self {
            slot,
            tag: t,
            tag_len: bytes.len() as u8,
        })
    }

    /// The slot, 0..=15.
    pub fn slot(&self) -> u8 {
        self.slot
    }

    /// The tag.
    pub fn tag(&self) -> &str {
        let t = self.tag.get(..usize::from(self.tag_len)).unwrap_or(&[]);
        // Checked ASCII in `new`.
        core::str::from_utf8(t).unwrap_or("")
    }
}

/// One of the four models of a hover identifier, in the core's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Model {
    /// Velocity model (`v^s` x, y, z).
    Velocity = 0,
    /// Pitch-rate model q̂.
    PitchRate = 1,
    /// Yaw-rate model r̂.
    YawRate = 2,
    /// Roll-rate model p̂.
    RollRate = 3,
}

impl Model {
    /// The four models in order.
    pub const ALL: [Model; 4] = [
        Model::Velocity,
        Model::PitchRate,
        Model::YawRate,
        Model::RollRate,
    ];

    /// Letter in message names.
    pub fn letter(self) -> u8 {
        match self {
            Model::Velocity => b'v',
            Model::PitchRate => b'q',
            Model::YawRate => b'r',
            Model::RollRate => b'p',
        }
    }
}

/// What a `DEBUG_FLOAT_ARRAY` holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArrayKind {
    /// One step: `data[0..6]` the prediction `[v_x v_y v_z q r p]` for the next sample,
    /// `data[6..12]` the prior innovation in the same order (NaN when the step had none).
    Step,
    /// θ of one model, floats `58·chunk ..` of it.
    Theta(Model),
}

impl ArrayKind {
    fn code(self) -> u16 {
        match self {
            ArrayKind::Step => 1,
            ArrayKind::Theta(m) => 2 + m as u16,
        }
    }
}

/// A decoded or to-be-encoded `array_id`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArrayId {
    /// Identifier slot, 0..=15.
    pub slot: u8,
    /// Quantity.
    pub kind: ArrayKind,
    /// Chunk (0 for [`ArrayKind::Step`]).
    pub chunk: u8,
}

impl ArrayId {
    /// The wire value.
    pub fn to_u16(self) -> u16 {
        u16::from(self.slot & 0x0F) << 12 | self.kind.code() << 8 | u16::from(self.chunk)
    }

    /// Parses a wire value; `None` for ids this scheme does not use.
    pub fn from_u16(id: u16) -> Option<Self> {
        let kind = match (id >> 8) & 0x0F {
            1 => ArrayKind::Step,
            k @ 2..=5 => ArrayKind::Theta(*Model::ALL.get(usize::from(k - 2))?),
            _ => return None,
        };
        let chunk = (id & 0xFF) as u8;
        if kind == ArrayKind::Step && chunk != 0 {
            return None;
        }
        Some(Self {
            slot: (id >> 12) as u8,
            kind,
            chunk,
        })
    }
}

/// Chunks needed for `len` floats (at least one, so that an empty θ still announces itself).
pub const fn chunk_count(len: usize) -> usize {
    if len == 0 {
        1
    } else {
        len.div_ceil(ARRAY_LEN)
    }
}
