//! The committed C header is what cbindgen makes of the sources today.
//!
//! Regenerate it with `ROTORID_BLESS=1 cargo test --manifest-path core/ffi/Cargo.toml --test header`.

use std::path::Path;

#[test]
fn committed_header_is_up_to_date() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config =
        cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let path = crate_dir.join("include/rotorid.h");
    if std::env::var_os("ROTORID_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("header written");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/rotorid.h is stale: regenerate it with \
         ROTORID_BLESS=1 cargo test --manifest-path core/ffi/Cargo.toml --test header"
    );
}
