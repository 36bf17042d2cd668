//! Arbitrary text into the CLI's CSV log importer: an error or samples, never a panic; and
//! the warnings on what it accepted never panic either.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(samples) = host_tests::log::parse_log("fuzz.csv", data) {
        let _ = host_tests::log::warnings("fuzz.csv", &samples);
        let _ = host_tests::flights::to_hover_samples(&samples);
    }
});
