//! Arbitrary bytes into the ULog reader and importer (`import::ulog::channels`): an error or
//! channels, never a panic, a hang or an unbounded allocation; on success every series has
//! finite, increasing time stamps and as many values as times.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_cli::import::ulog;

fuzz_target!(|data: &[u8]| {
    if let Ok((channels, _notes)) = ulog::channels("fuzz.ulg", data) {
        assert!(channels.is_well_formed());
    }
});
