//! A NOR flash backed by a file on the host (semihosting), that can lose power at a chosen
//! byte: the storage of the power-cut test (`src/bin/power_cut.rs`).
//!
//! It behaves as NOR flash: erase sets whole sectors to 0xFF, a write programs whole words
//! (4 bytes). Power is cut once `budget` bytes of flash operations (erased bytes plus
//! programmed bytes, counted from boot) have been applied: an erase stops after that many
//! bytes (a partly erased sector), a write stops at the last whole word within the budget
//! (a word being programmed when power fails keeps its old bytes; the one after it would
//! have its new ones, which a budget 4 bytes larger gives). The firmware then exits at once
//! ([`CUT_EXIT`]), leaving the image as a real cut would.
//!
//! A real driver (the MCU's flash controller) implements the same two traits; nothing else in
//! the record's path changes.

use core::ffi::CStr;

use embedded_storage::nor_flash::{ErrorType, NorFlash, NorFlashErrorKind, ReadNorFlash};
use semihosting::fs::File;
use semihosting::io::{Read, Seek, SeekFrom, Write};

/// Exit code of a run whose power was cut.
pub const CUT_EXIT: i32 = 3;

/// The file's flash.
pub struct FileFlash {
    file: File,
    capacity: usize,
    /// Bytes of flash operations left before power fails (`None`: never).
    budget: Option<u32>,
    /// Bytes of flash operations applied since boot.
    applied: u32,
}

impl FileFlash {
    /// Opens the image `path` (an existing file of `capacity` bytes, read and written in place).
    pub fn open(path: &CStr, capacity: usize, budget: Option<u32>) -> Option<Self> {
        let file = File::options().read(true).write(true).open(path).ok()?;
        Some(Self {
            file,
            capacity,
            budget,
            applied: 0,
        })
    }

    /// Bytes of flash operations applied since boot.
    pub fn applied(&self) -> u32 {
        self.applied
    }

    /// How many of `len` bytes may be applied before power fails (all of them: `len`).
    fn allowance(&self, len: usize) -> usize {
        match self.budget {
            None => len,
            Some(b) => (b.saturating_sub(self.applied) as usize).min(len),
        }
    }

    fn put(&mut self, offset: u32, bytes: &[u8]) -> Result<(), NorFlashErrorKind> {
        self.file
            .seek(SeekFrom::Start(u64::from(offset)))
            .map_err(|_| NorFlashErrorKind::Other)?;
        self.file
            .write_all(bytes)
            .map_err(|_| NorFlashErrorKind::Other)
    }

    /// Applies `n` bytes of an operation; if power fails within it, exits.
    fn spend(&mut self, n: usize, wanted: usize) {
        self.applied = self.applied.saturating_add(n as u32);
        if n < wanted {
            semihosting::process::exit(CUT_EXIT);
        }
    }

    fn check(&self, offset: u32, len: usize, align: usize) -> Result<(), NorFlashErrorKind> {
        let end = (offset as usize).checked_add(len);
        if end.is_none_or(|e| e > self.capacity) {
            return Err(NorFlashErrorKind::OutOfBounds);
        }
        if !(offset as usize).is_multiple_of(align) || !len.is_multiple_of(align) {
            return Err(NorFlashErrorKind::NotAligned);
        }
        Ok(())
    }
}

impl ErrorType for FileFlash {
    type Error = NorFlashErrorKind;
}

impl ReadNorFlash for FileFlash {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.check(offset, bytes.len(), 1)?;
        self.file
            .seek(SeekFrom::Start(u64::from(offset)))
            .map_err(|_| NorFlashErrorKind::Other)?;
        self.file
            .read_exact(bytes)
            .map_err(|_| NorFlashErrorKind::Other)
    }

    fn capacity(&self) -> usize {
        self.capacity
    }
}

impl NorFlash for FileFlash {
    const WRITE_SIZE: usize = 4;
    const ERASE_SIZE: usize = 1024;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        let len = to.checked_sub(from).ok_or(NorFlashErrorKind::OutOfBounds)? as usize;
        self.check(from, len, Self::ERASE_SIZE)?;
        let n = self.allowance(len);
        let ones = [0xFF_u8; 64];
        let mut done = 0;
        while done < n {
            let k = (n - done).min(ones.len());
            self.put(from + done as u32, ones.get(..k).unwrap_or(&ones))?;
            done += k;
        }
        self.spend(n, len);
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.check(offset, bytes.len(), Self::WRITE_SIZE)?;
        // Whole words only: the word being programmed when power fails keeps its old bytes.
        let n = self.allowance(bytes.len()) / 4 * 4;
        self.put(offset, bytes.get(..n).unwrap_or(bytes))?;
        self.spend(n, bytes.len());
        Ok(())
    }
}
