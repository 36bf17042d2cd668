//! Puts the repository's `memory.x` where cortex-m-rt's `link.x` looks for it.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let memory_x = manifest.join("..").join("memory.x");
    let map = fs::read_to_string(&memory_x)
        .unwrap_or_else(|e| panic!("reading {}: {e}", memory_x.display()));
    // KNOWN BUDGET OVERRUN (docs/cost.md): constructing `PaperFuzzyIdentifier<f32>` with the
    // core's by-value constructors needs a ~22 KiB stack transient on top of the 12 KiB the
    // identifiers occupy, more than the 32 KiB budget. Until the core can build in place, the
    // QEMU build links with 64 KiB of RAM (the board has 4 MiB); the steady-state use is
    // measured by stack painting and reported against the 32 KiB target.
    let map = map.replace(
        "RAM   : ORIGIN = 0x20000000, LENGTH = 32K",
        "RAM   : ORIGIN = 0x20000000, LENGTH = 64K",
    );
    fs::write(out.join("memory.x"), map).unwrap_or_else(|e| panic!("writing memory.x: {e}"));
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");
}
