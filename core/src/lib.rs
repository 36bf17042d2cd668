#![no_std]
#![doc = "rotorid: see README.md"]
pub mod scalar;
pub mod telemetry;
