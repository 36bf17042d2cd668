//! The paper's helicopter identifiers (Section 5) as thin layers over [`TsRls`](crate::ts::TsRls).
//!
//! Everything here is in the paper's axes and units (see [`crate::frames`] to convert from
//! NED / forward-right-down with rad/s):
//!
//! | symbol | meaning | unit |
//! |---|---|---|
//! | φ, θ, ψ | roll, pitch, yaw (ZYX Euler angles, as PX4/ArduPilot report them) | rad |
//! | `q = [w x y z]`, `R` | or the attitude as a unit quaternion or rotation matrix, body forward-right-down to north-east-down ([`Quaternion`], [`RotationMatrix`]: no trigonometry in the step) | — |
//! | `v^s = [v_x v_y v_z]` | inertial velocity, x east, y up, z south | m/s |
//! | `ω^b = [q r p]` | pitch, yaw, roll rate (conventional signs: nose up, nose right, right wing down) | deg/s |
//! | `u = [u_col u_ped u_lon u_lat]` | normalised controls; `u_col` stands for thrust and must stay positive near hover | −1…1 |
//!
//! A [`HoverIdentifier`] owns one translational model (Eq. 27, three outputs sharing θ) and
//! three angular models (Eqs. 28–30). Each takes the premise and consequent terms from the
//! sample at step k and learns the increment `y(k+1) − y(k)` (the coefficient of the state
//! itself is fixed at 1).

mod attitude;
mod config;
mod frame;
mod identifier;
mod models;
mod noise;
mod observer;
mod sample;
pub mod table3;
mod variants;

pub use crate::error::SampleField;
pub use attitude::{AnyAttitude, Attitude, AttitudeInput, Quaternion, RotationMatrix};
pub use config::{HoverConfig, RegressorScaling};
pub use identifier::{HoverIdentifier, HoverModels, HoverSnapshot, ModelId, StepOutput};
pub use models::{
    right_axis, rotor_axis, BodyFrame, GyroCompensation, Premise, RateAxis, RateModel,
    RateStructure, StateModel, VelocityModel, VelocityStructure,
};
pub use noise::RateNoise;
pub use observer::{GainSearch, Observer};
pub use sample::{Controls, HoverSample, HoverState, SampleLimits};
pub use variants::{
    flight_sets, unscheduled_sets, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier,
    ExtendedPlainIdentifier, FlightIdentifier, FlightPlainIdentifier, GlobalRateModel,
    GlobalVelocityModel, LocalRateModel, LocalVelocityModel, PaperFuzzyIdentifier,
    PaperLocalIdentifier, PaperPlainIdentifier, Scheduling,
};
