//! Prints the cost of every identifier's step on a stream that fires every rule, as a
//! markdown table on the semihosting console, then exits (run by `scripts/cost.sh` under
//! `qemu-system-arm -icount shift=0`, where one SysTick tick is 40 instructions).
//!
//! Command line (semihosting, QEMU's `-append`): none for the whole table, or
//! `IDENTIFIER STEPS` to step only that identifier (`step_profile --identifier` traces it), or
//! `sqrt` for the hash of the square roots of `step_cost::sqrt_hash` (a host test compares it).
#![no_std]
#![no_main]

#[allow(dead_code)]
#[path = "../board.rs"]
mod board;
#[allow(dead_code)]
#[path = "../link.rs"]
mod link;
#[allow(dead_code)]
#[path = "../mavlink_port.rs"]
mod mavlink_port;

use cortex_m_rt::entry;
use defmt_semihosting as _;
use firmware_example::step_cost::{self, Selection, StepCost, Timer};

struct SysTickTimer(board::Stopwatch);

impl Timer for SysTickTimer {
    fn restart(&mut self) {
        self.0.restart();
    }
    fn elapsed(&mut self) -> u64 {
        self.0.elapsed()
    }
}

#[entry]
fn main() -> ! {
    let Some(cp) = cortex_m::Peripherals::take() else {
        board::exit(board::EXIT_INIT)
    };
    let mut timer = SysTickTimer(board::Stopwatch::new(cp.SYST));
    // Program name, then the optional `IDENTIFIER STEPS`.
    let Ok(args) = semihosting::experimental::env::args::<256>() else {
        board::exit(board::EXIT_INIT)
    };
    let mut words = (&args).skip(1).filter_map(Result::ok);
    let selection = match (words.next(), words.next().map(str::parse)) {
        (None, _) => Selection::ALL,
        (Some("sqrt"), None) => {
            semihosting::println!("sqrt_ieee: {:08x}", step_cost::sqrt_hash());
            board::exit(0)
        }
        (Some(name), Some(Ok(steps))) => Selection {
            only: Some(name),
            steps,
        },
        _ => {
            semihosting::println!("usage: step-cost [IDENTIFIER STEPS | sqrt]");
            board::exit(board::EXIT_INIT)
        }
    };
    semihosting::println!(
        "| identifier | mean instructions/step | worst instructions/step | steps | rejected | predictions (FNV-1a of the bits) |"
    );
    semihosting::println!("|---|---:|---:|---:|---:|---|");
    step_cost::run_selected(selection, &mut timer, &mut |c: &StepCost| {
        semihosting::println!(
            "| {} | {} | {} | {} | {} | {:08x} |",
            c.name,
            c.mean_ticks * 40,
            c.max_ticks * 40,
            c.steps,
            c.rejected,
            c.hash
        );
    });
    board::exit(0)
}
