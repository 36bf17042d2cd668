//! The suite's integration tests, one binary: each file beside this one is a module (a file's
//! tests: `cargo test -p host-tests --release --test integration <file>::`). One binary links
//! the crates once instead of once per file, and its tests share the firmware's build and run
//! side by side (a QEMU test beside a host one) instead of one binary after another.

/// The firmware's step-cost stream and runner (`firmware-example/src/step_cost.rs`), compiled
/// for the host: `firmware_step_cost` compares its bits with the firmware's, `power_cut` feeds
/// its stream. (The tests do not read all of its report's fields.)
#[allow(dead_code)]
#[path = "../../firmware-example/src/step_cost.rs"]
mod step_cost;

mod firmware_ident;
mod firmware_link;
mod firmware_mavlink;
mod firmware_snapshot;
mod firmware_step_cost;
mod fuzz_regressions;
mod golden;
mod link_at_scale;
mod mavlink_pymavlink;
mod no_panic;
mod power_cut;
mod properties;
mod readme_numbers;
mod reference_agreement;
mod regenerate;
mod soak;
mod telemetry;
