//! Identification on the paper's flights (Section 7, Table 4): the identifier variants,
//! training, free run and evaluation.
//!
//! * [`one_step_errors`] and [`format_table4`]: the Table 4 analogue.
//! * [`variants`], [`train`], [`free_run`], [`evaluate`]: every identifier the tool compares,
//!   trained on identification logs and measured on verification logs.
//! * [`Regime`], [`one_step_bias`]: where in the flight a model's trim is wrong.
//! * [`ParametersError`], [`EvaluateError`]: what can fail on the way.

mod catalogue;
mod delay;
mod error;
mod evaluation;
mod mask;
mod regimes;
mod selection;
mod table4;
mod variants;

pub use catalogue::*;
pub use delay::*;
pub use error::*;
pub use evaluation::*;
pub use mask::*;
pub use regimes::*;
pub use selection::*;
pub use table4::*;
pub use variants::*;
