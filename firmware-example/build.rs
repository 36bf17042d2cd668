//! Puts the repository's `memory.x` where cortex-m-rt's `link.x` looks for it, and (feature
//! `libgcc-soft-float`, on by default) links GCC's soft-float routines for `f64`.
use std::{env, fs, path::PathBuf, process::Command};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let memory_x = manifest.join("..").join("memory.x");
    let map = fs::read_to_string(&memory_x)
        .unwrap_or_else(|e| panic!("reading {}: {e}", memory_x.display()));
    fs::write(out.join("memory.x"), map).unwrap_or_else(|e| panic!("writing memory.x: {e}"));
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");
    if env::var_os("CARGO_FEATURE_LIBGCC_SOFT_FLOAT").is_some() {
        link_libgcc();
    }
}

/// The Cortex-M4F has no double-precision FPU, and `libm`'s `sincosf` computes in `f64`, so
/// every body frame costs about 60 soft-float additions and multiplications. Rust's
/// `compiler_builtins` implements them in generic Rust; GCC's `libgcc` in hand-written
/// Thumb-2 assembly, about 2 300 instructions per identifier step fewer (docs/cost.md). Both
/// round every operation correctly (IEEE 754, to nearest, ties to even), so the results are
/// the same bits (`scripts/cost.sh` checks the predictions' hashes of both builds).
///
/// Named as a library of this crate, `libgcc.a` comes before `compiler_builtins` (which rustc
/// always links last) on the linker's command line, so the linker takes its definitions.
fn link_libgcc() {
    println!("cargo:rerun-if-env-changed=ARM_NONE_EABI_GCC");
    let gcc = env::var("ARM_NONE_EABI_GCC").unwrap_or_else(|_| "arm-none-eabi-gcc".into());
    let found = Command::new(&gcc)
        .args([
            "-mthumb",
            "-mcpu=cortex-m4",
            "-mfloat-abi=hard",
            "-mfpu=fpv4-sp-d16",
            "-print-libgcc-file-name",
        ])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    // gcc prints the bare name when it has no such library.
    let Some(dir) = found
        .filter(|p| p.is_file())
        .and_then(|p| p.parent().map(PathBuf::from))
    else {
        panic!(
            "feature `libgcc-soft-float`: `{gcc} -print-libgcc-file-name` found no libgcc.a for \
             the Cortex-M4F (hard float). Install the GNU Arm toolchain (`bash scripts/setup.sh`, \
             Debian package gcc-arm-none-eabi), name another gcc in ARM_NONE_EABI_GCC, or build \
             with --no-default-features to keep compiler_builtins' soft-float (same bits, \
             slower)."
        )
    };
    println!("cargo:rustc-link-search=native={}", dir.display());
    println!("cargo:rustc-link-lib=static=gcc");
}
