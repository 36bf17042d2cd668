//! Arbitrary bytes into the DataFlash-framed readers and importers (ArduPilot
//! `import::dataflash::channels`, PX4 `import::sdlog2::channels`) and the format detection: an
//! error or channels, never a panic, a hang or an unbounded allocation; on success every
//! series has finite, increasing time stamps and as many values as times.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_cli::import::{self, dataflash, sdlog2};

fuzz_target!(|data: &[u8]| {
    let _ = import::detect(data);
    if let Ok((channels, _notes)) = dataflash::channels("fuzz.bin", data) {
        assert!(channels.is_well_formed());
    }
    if let Ok((channels, _notes)) = sdlog2::channels("fuzz.px4log", data) {
        assert!(channels.is_well_formed());
    }
});
