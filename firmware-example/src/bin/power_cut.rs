//! The power-cut test's firmware: restores the flight identifier from its persistence record,
//! learns on, and writes a record every `STEPS` samples until record `RECORDS − 1` is written;
//! the flash is a host file that may lose power at a chosen byte (`file_flash`).
//!
//! Command line (semihosting, QEMU's `-append`): `IMAGE BUDGET RECORDS STEPS`, where `BUDGET`
//! is the bytes of flash operations after which power fails (`-`: never). The stream is
//! `step_cost::sample(k)`; record `s` holds the identifier after samples `0 … (s+1)·STEPS − 1`,
//! so a boot that restores record `s` goes on from sample `(s+1)·STEPS` (the import restarts
//! the sample chain: that sample only anchors).
//!
//! Prints (semihosting stdout), one line each: `restored SEQ HASH` or `fresh`; per record
//! written, `wrote SEQ SLOT HASH APPLIED` (APPLIED: flash bytes applied since boot when it was
//! complete); at the end `done HASH`. HASH: FNV-1a (32 bits) of the identifier's snapshot.
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

use core::ffi::CStr;

use cortex_m_rt::entry;
use defmt_semihosting as _;
use firmware_example::file_flash::FileFlash;
use firmware_example::step_cost::sample;
use rotorid::hover::flight_sets;
use rotorid::record::{self, RecordError, Slot, Slots};
use rotorid::snapshot::{Snapshot, WordSink};
use rotorid::{FlightIdentifier, HoverConfig};

/// The C interface's code of the flight identifier (`ROTORID_KIND_FLIGHT`).
const KIND: u32 = 1;
/// Two slots of 2 KiB (two 1 KiB sectors each): a flight record is 1 928 bytes.
const SLOTS: Slots = Slots {
    a: 0,
    b: 2048,
    size: 2048,
};
const CAPACITY: usize = 4096;

/// FNV-1a over the snapshot's bytes.
struct Fnv(u32);

impl WordSink for Fnv {
    fn put_word(&mut self, word: [u8; 4]) {
        for b in word {
            self.0 = (self.0 ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
    }
}

fn hash(id: &FlightIdentifier<f32>) -> u32 {
    let mut h = Fnv(0x811c_9dc5);
    id.put_snapshot(KIND, &mut h);
    h.0
}

fn fail(what: &str) -> ! {
    semihosting::println!("error {}", what);
    board::exit(board::EXIT_INIT)
}

#[entry]
fn main() -> ! {
    let Ok(args) = semihosting::experimental::env::args::<512>() else {
        fail("args")
    };
    let mut words = (&args).skip(1).filter_map(Result::ok);
    let (Some(image), Some(budget), Some(records), Some(steps)) =
        (words.next(), words.next(), words.next(), words.next())
    else {
        fail("usage: power-cut IMAGE BUDGET RECORDS STEPS")
    };
    let budget = match budget {
        "-" => None,
        b => Some(b.parse::<u32>().unwrap_or_else(|_| fail("budget"))),
    };
    let records: u32 = records.parse().unwrap_or_else(|_| fail("records"));
    let steps: u32 = steps.parse().unwrap_or_else(|_| fail("steps"));
    let mut path = [0u8; 256];
    if image.len() >= path.len() {
        fail("image path too long");
    }
    path[..image.len()].copy_from_slice(image.as_bytes());
    let Ok(path) = CStr::from_bytes_until_nul(&path) else {
        fail("image path")
    };
    let Some(mut flash) = FileFlash::open(path, CAPACITY, budget) else {
        fail("image")
    };

    let Ok(mut id) = FlightIdentifier::flight(HoverConfig::default(), flight_sets()) else {
        fail("identifier")
    };
    let mut next = match record::read(&mut flash, &SLOTS, &mut id, KIND) {
        Ok(info) => {
            semihosting::println!("restored {} {:08x}", info.sequence, hash(&id));
            info.sequence.wrapping_add(1)
        }
        Err(RecordError::NoValidRecord) => {
            semihosting::println!("fresh");
            0
        }
        Err(_) => fail("read"),
    };
    let mut k = next * steps;
    while next < records {
        let end = (next + 1) * steps;
        while k < end {
            // A refused sample would break the comparison with the host: report it.
            if id.step(&sample(k)).is_err() {
                fail("step");
            }
            k += 1;
        }
        match record::write(&mut flash, &SLOTS, &id, KIND) {
            Ok(info) if info.sequence == next => {
                let slot = match info.slot {
                    Slot::A => "A",
                    Slot::B => "B",
                };
                semihosting::println!(
                    "wrote {} {} {:08x} {}",
                    info.sequence,
                    slot,
                    hash(&id),
                    flash.applied()
                );
            }
            _ => fail("write"),
        }
        next += 1;
    }
    semihosting::println!("done {:08x}", hash(&id));
    board::exit(0)
}
