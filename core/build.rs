//! Picks the shape of the RLS update's code by the optimisation level rotorid is built at
//! (`OPT_LEVEL`, which Cargo gives build scripts from the profile, overrides included).
//!
//! At `opt-level = "s"` or `"z"` (the C interface's release profile: flash first) the build
//! asks for small code (`cfg(rotorid_small_code)`): the update over every parameter of an
//! estimator is one out-of-line copy for every size N. At any other level each size gets its
//! own, with Bierman's column loop written out for N ≤ 8 (about twice as fast on the
//! Cortex-M4F, about 1.8 KB larger for the flight identifier). Both shapes compute the same
//! bits (`rls::tests` compares the kernels; `scripts/footprint.sh` compares the C library
//! built at "s" and at 2).

fn main() {
    println!("cargo::rustc-check-cfg=cfg(rotorid_small_code)");
    if matches!(std::env::var("OPT_LEVEL").as_deref(), Ok("s" | "z")) {
        println!("cargo::rustc-cfg=rotorid_small_code");
    }
}
