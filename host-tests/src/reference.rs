//! Independent f64 reference of the paper equations.
