//! The smallest useful Rust firmware: the flight default initialised and stepped, attitude as
//! a quaternion, nothing else (no link, no logging). Its flash is what a Rust autopilot pays for
//! the identifier (`scripts/footprint.sh` measures it beside the C equivalent, docs/cost.md).
//! Exits through semihosting (0: every step accepted).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use rotorid::hover::{flight_sets, Controls, HoverSample, Quaternion};
use rotorid::{FlightIdentifier, HoverConfig};

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    semihosting::process::exit(2)
}

#[entry]
fn main() -> ! {
    let Ok(mut id) = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()) else {
        semihosting::process::exit(1)
    };
    let mut ok = true;
    for k in 0..100u32 {
        let t = 0.02 * k as f32;
        let sample = HoverSample {
            time_us: 1_000_000 + 20_000 * u64::from(k),
            attitude: Quaternion::default(),
            velocity: [0.1 * t, 0.0, 0.0],
            rates: [(k % 7) as f32 - 3.0, 0.0, 0.0],
            controls: Controls {
                col: 0.5,
                ..Controls::default()
            },
        };
        ok &= core::hint::black_box(id.step(&sample)).is_ok();
    }
    semihosting::process::exit(if ok { 0 } else { 1 })
}
