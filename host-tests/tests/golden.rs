//! The core reproduces the committed golden bits (this build: with the core's `std` feature;
//! `scripts/test.sh` runs it in debug and release).
#[test]
fn golden_bits_are_reproduced() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/tests/data");
    if let Err(e) = host_tests::golden::check(&dir) {
        panic!("{e}");
    }
}
