//! Independent `f64` reference of the paper's equations and a naive dense RLS: the yardsticks
//! the `rotorid` core is tested ([`reference`]) and benchmarked ([`dense_rls`]) against.
//!
//! Written straight from the paper with plain loops and full matrices, it deliberately shares
//! no code with the core: it depends on `std`, `nalgebra` and `rand` (the benchmark's seeded stream) only, never on `rotorid`, so that
//! an error in the core cannot hide in its own yardstick.
pub mod dense_rls;
pub mod reference;
