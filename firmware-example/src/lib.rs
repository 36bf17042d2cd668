//! The firmware example's board-agnostic library: onboard identification and its cost probe,
//! shared by the two binaries (`src/main.rs`, the firmware; `src/bin/step_cost.rs`, the
//! worst-case cost table of `docs/cost.md`).
//!
//! * [`ident`]: the two onboard identifiers and the handlers of the identification messages.
//! * [`file_flash`]: a NOR flash in a host file that can lose power mid-write (power-cut test).
//! * [`step_cost`]: every identifier stepped through a stream that fires every rule, timed.
//!
//! It may depend on `rotorid` and `rotorid-link`; the board (`board.rs`) and the serial links
//! (`link.rs`, `mavlink_port.rs`) live in the firmware binary.

#![no_std]

pub mod file_flash;
pub mod ident;
pub mod step_cost;
