//! # rotorid firmware example
//!
//! The rotorid telemetry link on a Cortex-M4F, runnable in QEMU (`mps2-an386`):
//! `cargo run --release` in this folder boots it, decodes its defmt log and serves the link on
//! TCP `127.0.0.1:4444` (see `qemu-run.sh`); the host side lives in
//! `host-tests/src/firmware_link.rs`, the protocol in `docs/protocol.md`.
//!
//! Layout:
//! * [`board`]: everything specific to the mps2-an386 model (UART, SysTick, exit path, fault
//!   handlers). Replace it for another board.
//! * [`link`]: the board-agnostic application, generic over `embedded_io::{Read, Write}`.
//! * [`mavlink_port`]: MAVLink 2 telemetry on UART1 beside the link (docs/protocol.md,
//!   "MAVLink 2"); on a vehicle, wire it to the telemetry radio's UART.
//! * [`semihosting_log`]: the defmt transport for QEMU.
//! * `firmware_example::ident` (the library, `src/lib.rs`): the onboard identifiers (fuzzy +
//!   plain) and the identification messages.
//!
//! ## Running it on a real flight computer
//!
//! 1. **Board module**: write a `board` for your MCU with its HAL: a UART/USB-CDC type that
//!    implements `embedded_io::{Read, Write, ReadReady}` (most HALs already do, or wrap
//!    `embedded-hal-nb`), a [`link::Platform`] whose `measure` uses the DWT cycle counter
//!    (`cortex_m::peripheral::DWT::cycle_count`, 1 tick = 1 core cycle) and whose
//!    `inject_fault` you may disable, and an `exit` that resets the MCU
//!    (`cortex_m::peripheral::SCB::sys_reset`) instead of semihosting, which would halt a
//!    chip without a debugger attached.
//! 2. **memory.x** (repository root): set FLASH/RAM origins of your chip; keep the 64/32 KiB
//!    budget lengths if you want the linker to keep enforcing them.
//! 3. **defmt transport**: replace [`semihosting_log`] by `defmt-rtt` (`use defmt_rtt as _;`)
//!    and read the log with `probe-rs run --chip <CHIP>` instead of QEMU + `defmt-print`.
//!    Semihosting is slow and stops a target that has no debugger.
//! 4. **.cargo/config.toml**: `runner = "probe-rs run --chip <CHIP>"`.
//! 5. **f64 soft-float**: `build.rs` links GCC's `libgcc` for it (feature `libgcc-soft-float`,
//!    default; about 2 300 instructions per identifier step fewer than `compiler_builtins`,
//!    the same bits). It needs `arm-none-eabi-gcc`; without it build with
//!    `--no-default-features`.
//!
//! The numerics need nothing: the core is bit-for-bit identical on every IEEE-754 f32 target
//! (no fast-math, no fused multiply-add contraction in Rust).
#![no_std]
#![no_main]

mod board;
mod link;
mod mavlink_port;
// The defmt transport for QEMU (panic-free); on hardware drop it and `use defmt_rtt as _;`.
mod semihosting_log;

use cortex_m_rt::entry;
use embedded_hal::delay::DelayNs;

#[entry]
fn main() -> ! {
    // First, before anything deep runs: fill the free stack with a pattern (high-water mark).
    board::paint_stack();
    let Some(cp) = cortex_m::Peripherals::take() else {
        board::exit(board::EXIT_INIT)
    };
    let Some(engine) = firmware_example::ident::Identification::take() else {
        defmt::error!("identifier construction failed");
        board::exit(board::EXIT_INIT)
    };
    let boot = board::memory_report();
    defmt::info!(
        "stack used by start-up (identifier construction): {=u32} B",
        boot.stack_peak
    );
    // Paint again: `MemoryRequest` then reports the high-water mark of the link + identification
    // service alone (start-up's construction transient is logged above and in docs/cost.md).
    board::paint_stack();
    // SAFETY: UART0 is used by nothing else in this program.
    let uart = unsafe { board::CmsdkUart::new(board::UART0_BASE, board::CORE_HZ, board::BAUD) };
    // SAFETY: UART1 is used by nothing else in this program.
    let uart1 = unsafe { board::CmsdkUart::new(board::UART1_BASE, board::CORE_HZ, board::BAUD) };
    let Some(mav) = mavlink_port::MavlinkPort::new(uart1) else {
        board::exit(board::EXIT_INIT)
    };
    let stopwatch = board::Stopwatch::new(cp.SYST);
    // Give the UART one character time to settle after enabling (matters on hardware only).
    board::Delay::new(board::CORE_HZ).delay_us(100);
    defmt::info!(
        "rotorid firmware-example: protocol v{=u8}, UART0 @ {=usize:#x}",
        rotorid_link::VERSION,
        board::UART0_BASE
    );
    link::Link::new(uart, stopwatch, engine, mav).run()
}
