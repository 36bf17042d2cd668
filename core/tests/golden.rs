//! The core without its `std` feature reproduces the same golden bits as the host build
//! (`cargo test -p rotorid` builds the core alone, without `std`).
use crate::support::golden;

#[test]
fn golden_bits_are_reproduced_without_std() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    if let Err(e) = golden::check(&dir) {
        panic!("{e}");
    }
}
