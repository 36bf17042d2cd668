//! The core's integration tests, one binary: each file beside this one is a module (a file's
//! tests: `cargo test -p rotorid --test integration <file>::`). They use the public API only.

/// Helpers the files share: the golden-bits check and a simulated flight log.
mod support {
    pub mod flight_log;
    pub mod golden;
}

mod affine_thrust;
mod attitude;
mod compensation;
mod extended;
mod fuzzy;
mod golden;
mod hover;
mod import_then_step;
mod local;
mod observer;
mod px4_arx_rls;
mod record;
mod recovery;
mod rls;
mod view;
