//! The defmt transport for QEMU: the binary defmt stream over semihosting to the host's
//! stdout (`qemu-run.sh` pipes it into `defmt-print`).
//!
//! Written here instead of taking `defmt-semihosting` because that crate panics when the logger
//! is taken reentrantly and its writes go through `write_all`'s error path: both would put
//! panic paths on the flight path, which `scripts/no_panic.py --strict` forbids. Here a
//! reentrant log (only possible from a fault handler, since logging holds a critical section)
//! is dropped, and a failed write loses log bytes, never the program. On hardware use
//! `defmt-rtt` instead (see `main.rs`).

use core::sync::atomic::{AtomicBool, AtomicU8, AtomicUsize, Ordering};

/// Semihosting operations (ARM DUI 0471).
const SYS_OPEN: usize = 0x01;
const SYS_WRITE: usize = 0x05;
/// `SYS_OPEN` mode 4 ("w") on the special name ":tt" is the host's stdout.
const MODE_WRITE: usize = 4;

/// Nesting depth of `acquire`: 1 while a frame is being written, more in a reentrant log.
static DEPTH: AtomicU8 = AtomicU8::new(0);
static TAKEN: AtomicBool = AtomicBool::new(false);
/// The stdout handle plus one (0: not opened yet).
static STDOUT: AtomicUsize = AtomicUsize::new(0);
static mut RESTORE: critical_section::RestoreState = critical_section::RestoreState::invalid();
static mut ENCODER: defmt::Encoder = defmt::Encoder::new();

/// One semihosting call.
///
/// # Safety
/// `arg` points to the parameter block `op` expects.
unsafe fn semihost(op: usize, arg: *const usize) -> isize {
    let result: isize;
    // SAFETY: the caller's contract; `bkpt 0xAB` is the semihosting trap on M-profile cores.
    unsafe {
        core::arch::asm!("bkpt 0xAB", inout("r0") op => result, in("r1") arg, options(nostack));
    }
    result
}

fn stdout() -> Option<usize> {
    match STDOUT.load(Ordering::Relaxed) {
        0 => {
            let name = b":tt\0";
            let block = [name.as_ptr() as usize, MODE_WRITE, name.len() - 1];
            // SAFETY: the block is SYS_OPEN's (name, mode, length of the name).
            let handle = unsafe { semihost(SYS_OPEN, block.as_ptr()) };
            let handle = usize::try_from(handle).ok()?;
            STDOUT.store(handle.wrapping_add(1), Ordering::Relaxed);
            Some(handle)
        }
        h => Some(h.wrapping_sub(1)),
    }
}

fn write_out(bytes: &[u8]) {
    if let Some(handle) = stdout() {
        let block = [handle, bytes.as_ptr() as usize, bytes.len()];
        // SAFETY: the block is SYS_WRITE's (handle, buffer, length). The result (bytes not
        // written) is ignored: a lost log byte must not stop the program.
        let _ = unsafe { semihost(SYS_WRITE, block.as_ptr()) };
    }
}

#[defmt::global_logger]
struct Logger;

// SAFETY: frames are written under a critical section and never interleave (a nested frame
// is dropped whole).
unsafe impl defmt::Logger for Logger {
    fn acquire() {
        // SAFETY: released in `release`, in the same nesting order.
        let restore = unsafe { critical_section::acquire() };
        if TAKEN.swap(true, Ordering::Relaxed) {
            // Reentrant (a fault while logging): drop this frame, keep the outer one intact.
            DEPTH.fetch_add(1, Ordering::Relaxed);
            // SAFETY: the token just acquired, released at once (the outer frame still holds
            // the critical section).
            unsafe { critical_section::release(restore) };
            return;
        }
        DEPTH.store(1, Ordering::Relaxed);
        // SAFETY: only the holder of the logger (TAKEN) touches these statics.
        unsafe {
            RESTORE = restore;
            (*core::ptr::addr_of_mut!(ENCODER)).start_frame(write_out);
        }
    }

    unsafe fn flush() {}

    unsafe fn release() {
        if DEPTH.load(Ordering::Relaxed) > 1 {
            DEPTH.fetch_sub(1, Ordering::Relaxed);
            return;
        }
        // SAFETY: the holder of the logger; the token is the one `acquire` stored.
        unsafe {
            (*core::ptr::addr_of_mut!(ENCODER)).end_frame(write_out);
            DEPTH.store(0, Ordering::Relaxed);
            TAKEN.store(false, Ordering::Relaxed);
            critical_section::release(RESTORE);
        }
    }

    unsafe fn write(bytes: &[u8]) {
        if DEPTH.load(Ordering::Relaxed) == 1 {
            // SAFETY: the holder of the logger.
            unsafe { (*core::ptr::addr_of_mut!(ENCODER)).write(bytes, write_out) };
        }
    }
}
