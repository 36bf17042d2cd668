//! Why a binary log cannot be read at all (as opposed to the remarks of [`super::issues`],
//! which a reader makes and reads on): the reason carried by [`super::ImportError::Malformed`]
//! beside the byte offset.

/// What makes a ULog or DataFlash log unreadable.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Malformation {
    /// The input ends inside the file header.
    #[error("the file ends inside its {expected}-byte header (it has {got} bytes): the log is empty or cut")]
    ShortHeader {
        /// Header length (bytes).
        expected: usize,
        /// Bytes present.
        got: usize,
    },
    /// The first bytes are not the format's magic bytes.
    #[error("the file does not start with the format's magic bytes")]
    BadMagic,
    /// ULog incompatible-flag bits this reader does not know: the spec says not to read on.
    #[error("incompatible flag bits {bits:#04x} in flag byte {byte} that this reader does not know (a newer ULog version?): it cannot read the log safely")]
    UnknownIncompatFlags {
        /// Index of the flag byte (0…7).
        byte: usize,
        /// The unknown bits.
        bits: u8,
    },
    /// No record could be read at all.
    #[error("no valid record after the magic bytes (not a log, or corrupt from the start)")]
    NoRecords,
}

/// A binary log reader's failure: the input could not be read, or is unreadable at `offset`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The system failed to read the input.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// The log is unreadable from `offset` on.
    #[error("at byte {offset}: {reason}")]
    Malformed {
        /// Byte offset of the offending structure.
        offset: u64,
        /// What is wrong.
        reason: Malformation,
    },
}
