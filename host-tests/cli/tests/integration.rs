//! The command-line tool's integration tests, one binary: each file beside this one is a
//! module (a file's tests: `cargo test -p rotorid-cli --release --test integration <file>::`).
//! One binary links the tool's library once instead of once per file.

mod ardupilot_sitl;
mod cli;
mod corrupt_logs;
mod derivatives;
mod import;
mod pilot_gain;
mod real_logs;
mod verdict;
