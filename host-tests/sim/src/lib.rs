//! Helicopter simulator: the rigid-body plant with its rotor (the X-Cell 60 and a second,
//! flybarless 600-class airframe: [`plant::Airframe`]), the hover-hold pilot, GPS/INS-like
//! sensors, and the paper's flights flown on it (the Table 2 identification sweeps, the
//! verification flight, the envelope flights) as logs in the paper's axes.
//!
//! It is the ground truth the identifiers are tried on, so it may depend on `rotorid` (for the
//! sweep schedule, frames and sample types) and general-purpose crates only; nothing here knows
//! the command-line tool, the firmware or the tests (arrows point down: tool → simulator → core).
pub mod envelope;
pub mod flights;
pub mod plant;
