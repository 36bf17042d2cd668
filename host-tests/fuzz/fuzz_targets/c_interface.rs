//! Random call sequences on the C interface (`rotorid-ffi`, issue 33): init of each kind,
//! steps, resumes, predictions, exports, imports of hostile bytes, damage to the storage's
//! header and moves of the storage between calls. No crash, and every refused call changed
//! no byte of the storage and wrote no output (the assertions live in
//! `core/ffi/src/sequences.rs`, compiled here by `host-tests/fuzz/ffi`; the crate's unit tests
//! run it too).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = rotorid_ffi::sequences::run(data);
});
