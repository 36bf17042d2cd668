//! Arbitrary bytes into the DataFlash-framed readers and importers (ArduPilot
//! `import::dataflash::channels`, PX4 `import::sdlog2::channels`) and the format detection: an
//! error or channels, never a panic, a hang or an unbounded allocation; on success every
//! series has finite, increasing time stamps and as many values as times.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_cli::import::{self, dataflash, sdlog2, Channels, Series};

fn check<const N: usize>(s: &Series<N>) {
    assert_eq!(s.t.len(), s.v.len());
    assert!(s.t.iter().all(|t| t.is_finite()));
    assert!(s.t.windows(2).all(|w| w[0] < w[1]));
}

fn check_all(c: &Channels) {
    check(&c.attitude);
    check(&c.velocity_ned);
    check(&c.rates_frd);
    check(&c.controls);
    check(&c.in_air);
}

fuzz_target!(|data: &[u8]| {
    let _ = import::detect(data);
    if let Ok((channels, _notes)) = dataflash::channels("fuzz.bin", data) {
        check_all(&channels);
    }
    if let Ok((channels, _notes)) = sdlog2::channels("fuzz.px4log", data) {
        check_all(&channels);
    }
});
