//! Board support for QEMU's `mps2-an386` (Cortex-M4F, 25 MHz): CMSDK APB UART, SysTick
//! stopwatch, delay, and the semihosting exit path.
//!
//! This is the only file that knows the board. To run on a real flight computer, replace it
//! with a module that offers the same three things from your HAL: a UART (or USB-CDC) type
//! implementing `embedded_io::{Read, Write, ReadReady}`, a [`crate::link::Platform`] (cycle
//! counter + fault hook; on hardware prefer the DWT cycle counter over SysTick), and an `exit`
//! that resets or parks the MCU instead of calling semihosting.

use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::{syst::SystClkSource, SCB, SYST};
use cortex_m_rt::exception;
use rotorid_link::msg::{FaultKind, MemoryReport};

/// Core clock of the mps2-an386 model, in Hz. SysTick counts this clock.
pub const CORE_HZ: u32 = 25_000_000;
/// Base address of UART0 (the telemetry link).
pub const UART0_BASE: usize = 0x4000_4000;
/// Base address of UART1 (MAVLink 2 telemetry, write-only; QEMU's second `-serial`).
pub const UART1_BASE: usize = 0x4000_5000;
/// Baud rate programmed into the UART, in bit/s (QEMU ignores it; real CMSDK UARTs do not).
pub const BAUD: u32 = 115_200;

/// Exit code after a Rust panic.
pub const EXIT_PANIC: i32 = 101;
/// Exit code after a HardFault.
pub const EXIT_HARDFAULT: i32 = 102;
/// Exit code after an unexpected exception or interrupt.
pub const EXIT_UNEXPECTED_IRQ: i32 = 103;
/// Exit code when start-up fails.
pub const EXIT_INIT: i32 = 104;

/// Ends the QEMU run with `code` as the process exit status (semihosting `SYS_EXIT_EXTENDED`).
/// On hardware this would reset the MCU or park it in a safe state.
pub fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}

// CMSDK APB UART register offsets (bytes) and bits.
const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const INTSTATUS: usize = 0x0C;
const BAUDDIV: usize = 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const STATE_TX_OVERRUN: u32 = 1 << 2;
const STATE_RX_OVERRUN: u32 = 1 << 3;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;
const CTRL_RX_INT_EN: u32 = 1 << 3;
const INT_RX: u32 = 1 << 1;
/// Status checks a read makes before it sleeps until a byte arrives ([`CmsdkUart::read`]):
/// about 40 000 instructions, tens of microseconds of QEMU, longer than the gap between two
/// bytes of a frame and far shorter than the host's work between two frames.
const RX_SPINS: u32 = 4000;

/// Errors of [`CmsdkUart`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum UartError {
    /// A received byte was overwritten before it was read (bytes were lost).
    RxOverrun,
}

impl core::fmt::Display for UartError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::RxOverrun => f.write_str("UART receive overrun"),
        }
    }
}

impl core::error::Error for UartError {}

impl embedded_io::Error for UartError {
    fn kind(&self) -> embedded_io::ErrorKind {
        match self {
            // No closer kind exists; the framing layer recovers from the lost bytes.
            Self::RxOverrun => embedded_io::ErrorKind::Other,
        }
    }
}

/// Polled driver for the ARM CMSDK APB UART (1-byte TX and RX holding registers). A read
/// with nothing to read checks the status [`RX_SPINS`] times, then sleeps until a byte
/// arrives (see [`CmsdkUart::wait_for_rx`]).
pub struct CmsdkUart {
    base: usize,
    /// The receive interrupt's bit in the NVIC's first enable/pending registers, for UART0
    /// and UART1 of `mps2-an386` (interrupts 0 and 2); `None` elsewhere (reads then spin).
    rx_irq_bit: Option<u32>,
}

impl CmsdkUart {
    /// Enables TX and RX at `baud`, and the receive interrupt's line, which only wakes the
    /// core from a sleep (the NVIC takes no interrupt of the UART).
    ///
    /// # Safety
    /// `base` must be the address of a CMSDK APB UART that nothing else uses, and nothing
    /// else may use its receive interrupt.
    pub unsafe fn new(base: usize, core_hz: u32, baud: u32) -> Self {
        let rx_irq_bit = match base {
            UART0_BASE => Some(1 << 0),
            UART1_BASE => Some(1 << 2),
            _ => None,
        };
        let uart = Self { base, rx_irq_bit };
        // The divider must be >= 16 on real hardware.
        uart.write_reg(BAUDDIV, (core_hz / baud.max(1)).max(16));
        uart.write_reg(CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INT_EN);
        // Clear stale overrun flags and interrupt status (write-one-to-clear).
        uart.write_reg(STATE, STATE_TX_OVERRUN | STATE_RX_OVERRUN);
        uart.write_reg(INTSTATUS, 0xF);
        uart
    }

    fn read_reg(&self, off: usize) -> u32 {
        // SAFETY: `new`'s contract: `base` is a CMSDK UART; offsets are its registers.
        unsafe { read_volatile((self.base + off) as *const u32) }
    }

    fn write_reg(&self, off: usize, v: u32) {
        // SAFETY: as in `read_reg`.
        unsafe { write_volatile((self.base + off) as *mut u32, v) }
    }

    /// Reports (once) and clears a receive overrun.
    fn check_overrun(&mut self) -> Result<(), UartError> {
        if self.read_reg(STATE) & STATE_RX_OVERRUN != 0 {
            self.write_reg(STATE, STATE_RX_OVERRUN);
            return Err(UartError::RxOverrun);
        }
        Ok(())
    }

    fn rx_full(&self) -> bool {
        self.read_reg(STATE) & STATE_RX_FULL != 0
    }

    /// Sleeps (`wfi`) until the receive interrupt is pending, or returns at once if a byte is
    /// already there. The interrupt is enabled in the NVIC only while interrupts are masked
    /// (PRIMASK), so it wakes the core without being taken, and it is disabled and cleared
    /// again before they are unmasked. A byte arriving between the check and the `wfi` leaves
    /// the interrupt pending, and the `wfi` returns at once: no wake-up is lost. Why: a
    /// firmware spinning on the status register keeps QEMU, and a host core, busy whenever it
    /// waits for the host; asleep, QEMU idles (docs/workspace.md has the suite's QEMU CPU time
    /// before and after, `scripts/cpu_use.py`). SysTick still wakes the core to count its wraps.
    fn wait_for_rx(&self) {
        let Some(bit) = self.rx_irq_bit else { return };
        let nvic = cortex_m::peripheral::NVIC::PTR;
        cortex_m::interrupt::free(|_| {
            // SAFETY: the NVIC's registers (a fixed address on every Cortex-M); `new`'s
            // contract gives this UART's interrupt to this driver alone.
            unsafe {
                self.write_reg(INTSTATUS, INT_RX);
                (*nvic).icpr[0].write(bit);
                (*nvic).iser[0].write(bit);
            }
            if !self.rx_full() {
                cortex_m::asm::wfi();
            }
            // SAFETY: as above.
            unsafe {
                (*nvic).icer[0].write(bit);
                self.write_reg(INTSTATUS, INT_RX);
                (*nvic).icpr[0].write(bit);
            }
        });
    }
}

impl embedded_io::ErrorType for CmsdkUart {
    type Error = UartError;
}

impl embedded_io::Read for CmsdkUart {
    /// Blocks until at least one byte arrived, then returns what is there without blocking.
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, UartError> {
        if buf.is_empty() {
            return Ok(0);
        }
        // Spins a little first: within a frame the next byte follows at once, and a sleep per
        // byte would pay a wake-up per byte (QEMU hands the UART one byte at a time).
        let mut spins = 0;
        while !self.rx_full() {
            self.check_overrun()?;
            if spins < RX_SPINS {
                spins += 1;
            } else {
                self.wait_for_rx();
            }
        }
        let mut n = 0;
        for slot in buf.iter_mut() {
            if !self.rx_full() {
                break;
            }
            // Only the low 8 bits of DATA are the byte.
            *slot = (self.read_reg(DATA) & 0xFF) as u8;
            n += 1;
        }
        self.check_overrun().map(|()| n)
    }
}

impl embedded_io::ReadReady for CmsdkUart {
    fn read_ready(&mut self) -> Result<bool, UartError> {
        self.check_overrun()?;
        Ok(self.rx_full())
    }
}

impl embedded_io::Write for CmsdkUart {
    /// Blocks until at least one byte is accepted, then queues as many as fit without blocking.
    fn write(&mut self, buf: &[u8]) -> Result<usize, UartError> {
        let mut n = 0;
        for &b in buf {
            if self.read_reg(STATE) & STATE_TX_FULL != 0 {
                if n > 0 {
                    break;
                }
                while self.read_reg(STATE) & STATE_TX_FULL != 0 {}
            }
            self.write_reg(DATA, u32::from(b));
            n += 1;
        }
        Ok(n)
    }

    /// Every byte, in order, blocking while the holding register is full. Overrides
    /// `embedded_io`'s default, which slices the buffer by what `write` returns and panics on
    /// `Ok(0)`: a panic path in every send (`scripts/no_panic.py` finds such paths).
    fn write_all(&mut self, buf: &[u8]) -> Result<(), UartError> {
        for &b in buf {
            while self.read_reg(STATE) & STATE_TX_FULL != 0 {}
            self.write_reg(DATA, u32::from(b));
        }
        Ok(())
    }

    /// Waits until the holding register is free (the last byte may still be on the wire).
    fn flush(&mut self) -> Result<(), UartError> {
        while self.read_reg(STATE) & STATE_TX_FULL != 0 {}
        Ok(())
    }
}

/// SysTick reload: the full 24-bit range.
const RELOAD: u32 = 0x00FF_FFFF;
/// SysTick wraps since the stopwatch was last restarted.
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Stopwatch on SysTick at the core clock, extended to 64 bits by counting wraps.
///
/// Under QEMU `-icount shift=0` one instruction takes 1 ns of virtual time and SysTick ticks at
/// 25 MHz, so one tick is 40 executed instructions and measurements are deterministic.
pub struct Stopwatch {
    syst: SYST,
}

impl Stopwatch {
    /// Takes SysTick: core clock, 24-bit reload, wrap interrupt on.
    pub fn new(mut syst: SYST) -> Self {
        syst.disable_counter();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Self { syst }
    }

    /// Restarts the count at zero. Re-enabling the counter also realigns its prescaler phase
    /// (in QEMU), which is what makes back-to-back measurements repeat exactly.
    pub fn restart(&mut self) {
        cortex_m::interrupt::free(|_| {
            self.syst.disable_counter();
            self.syst.clear_current();
            SCB::clear_pendst();
            WRAPS.store(0, Ordering::Relaxed);
            self.syst.enable_counter();
        });
    }

    /// Ticks since the last restart.
    pub fn elapsed(&self) -> u64 {
        cortex_m::interrupt::free(|_| {
            let mut wraps = WRAPS.load(Ordering::Relaxed);
            let mut cvr = SYST::get_current();
            // A wrap whose interrupt is still pending: re-read after it, count it ourselves.
            if SCB::is_pendst_pending() {
                cvr = SYST::get_current();
                wraps += 1;
            }
            // After a restart CVR reads 0 until the first tick reloads it to RELOAD, so t ticks
            // into a period CVR is (RELOAD + 1 - t) mod (RELOAD + 1).
            let period = u64::from(RELOAD) + 1;
            let in_period = (period - u64::from(cvr.min(RELOAD))) % period;
            u64::from(wraps) * period + in_period
        })
    }
}

impl crate::link::Platform for Stopwatch {
    fn measure<R>(&mut self, f: impl FnOnce() -> R) -> (R, u64) {
        self.restart();
        let r = f();
        let t = self.elapsed();
        (r, t)
    }

    fn memory(&self) -> MemoryReport {
        memory_report()
    }

    fn inject_fault(&mut self, kind: FaultKind) -> ! {
        match kind {
            FaultKind::HardFault => {
                defmt::warn!("fault injection: executing UDF");
                // UsageFault is disabled, so the undefined instruction escalates to HardFault.
                cortex_m::asm::udf()
            }
            _ => {
                defmt::error!("fault injection: deliberate panic");
                panic!("fault injection: deliberate panic")
            }
        }
    }
}

/// Busy-wait delay on the core clock (`embedded_hal::delay::DelayNs`).
pub struct Delay {
    core_hz: u32,
}

impl Delay {
    /// A delay for a core running at `core_hz`.
    pub const fn new(core_hz: u32) -> Self {
        Self { core_hz }
    }
}

impl embedded_hal::delay::DelayNs for Delay {
    fn delay_ns(&mut self, ns: u32) {
        let cycles = u64::from(ns) * u64::from(self.core_hz) / 1_000_000_000;
        cortex_m::asm::delay(u32::try_from(cycles).unwrap_or(u32::MAX).max(1));
    }
}

#[exception]
unsafe fn HardFault(ef: &cortex_m_rt::ExceptionFrame) -> ! {
    defmt::error!(
        "HardFault: pc={=u32:#010x} lr={=u32:#010x} xpsr={=u32:#010x}",
        ef.pc(),
        ef.lr(),
        ef.xpsr()
    );
    exit(EXIT_HARDFAULT)
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    defmt::error!("unexpected exception or interrupt {=i16}", irqn);
    exit(EXIT_UNEXPECTED_IRQ)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    // Only the location: formatting the message would link core::fmt (≈ 3 KiB of flash).
    match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    }
    exit(EXIT_PANIC)
}

// ---- stack painting -----------------------------------------------------------------------

/// Word the free stack is filled with at boot.
const STACK_PAINT: u32 = 0x5AC3_A55A;
/// Bytes below the current stack pointer left unpainted (the painting function's own frame).
const PAINT_MARGIN: usize = 64;

extern "C" {
    // Provided by cortex-m-rt's link.x: initial SP (top of RAM), lowest stack address (end of
    // static RAM) and start of RAM data.
    static _stack_start: u32;
    static _stack_end: u32;
    static __sdata: u32;
}

fn stack_bounds() -> (usize, usize, usize) {
    // Only the addresses of the linker symbols are taken, never their contents.
    (
        core::ptr::addr_of!(__sdata) as usize,
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    )
}

/// Fills the unused stack (from the end of static RAM up to just below the current stack
/// pointer) with [`STACK_PAINT`]. Call first thing in `main`.
#[inline(never)]
pub fn paint_stack() {
    let (_, bottom, _) = stack_bounds();
    let sp = cortex_m::register::msp::read() as usize;
    let top = sp.saturating_sub(PAINT_MARGIN) & !3;
    let mut p = bottom;
    while p < top {
        // SAFETY: [bottom, top) is free stack below the live frames: nothing else uses it.
        unsafe { write_volatile(p as *mut u32, STACK_PAINT) };
        p += 4;
    }
}

/// Stack size, deepest use since boot (lowest overwritten word of the paint), static RAM.
pub fn memory_report() -> MemoryReport {
    let (data, bottom, top) = stack_bounds();
    let mut p = bottom;
    // SAFETY: reads words of the stack region, all initialised (painted or used).
    while p < top && unsafe { read_volatile(p as *const u32) } == STACK_PAINT {
        p += 4;
    }
    let u = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
    MemoryReport {
        stack_size: u(top - bottom),
        stack_peak: u(top - p),
        static_ram: u(bottom - data),
        ram_size: RAM_SIZE,
    }
}

/// The RAM budget of `memory.x`, in bytes (the QEMU build links with more, see build.rs).
pub const RAM_SIZE: u32 = 64 * 1024;
