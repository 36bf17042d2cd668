//! The core reproduces the committed golden bits (this build: with the core's `std` feature,
//! optimised; `scripts/test.sh` checks the same files unoptimised with `core/tests/golden.rs`,
//! with and without `std`).
#[test]
fn golden_bits_are_reproduced() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/tests/data");
    if let Err(e) = host_tests::golden::check(&dir) {
        panic!("{e}");
    }
}
