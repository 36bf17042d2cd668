//! Arbitrary text into the CLI's CSV log importer: an error or samples, never a panic; and
//! the warnings on what it accepted never panic either.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(samples) = rotorid_cli::log::parse_log("fuzz.csv", data) {
        let _ = rotorid_cli::log::warnings("fuzz.csv", &samples);
        let _ = rotorid_sim::flights::to_hover_samples(&samples);
    }
});
