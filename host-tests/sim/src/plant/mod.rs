//! X-Cell 60 plant simulator.
//!
//! A nonlinear six-degree-of-freedom model of a miniature helicopter after Gavrilets, Mettler
//! and Feron (AIAA 2001-4333), as specified in `shared/plant/xcell60.md`:
//!
//! * [`sticks`]: the pilot's commands ([`Sticks`]) on the four control channels ([`Channel`]);
//! * [`error`]: the simulator's errors ([`PlantError`]);
//! * [`airframe`]: the airframes ([`Airframe`]) and the stick scaling between them;
//! * [`params`]: the published parameters ([`Helicopter`], the X-Cell 60 by default, and the second airframe) and the stick map ([`StickMap`]);
//! * [`rotor`]: blade-element thrust with momentum inflow (main and tail rotor);
//! * [`dynamics`]: forces, moments, the state derivative and an RK4 step;
//! * [`trim`]: the hover trim solver ([`trim_hover`]);
//! * [`pilot`]: the hover-hold pilot flying the channels that are not excited;
//! * [`sensors`]: 50 Hz samples with jitter, noise and turbulence options;
//! * [`flight`]: the flight runner [`simulate`] and verification manoeuvres;
//! * [`linear`]: a plant's linearisation about hover ([`LinearHover`]), flown with
//!   [`FlightConfig::linear`];
//! * [`variation`]: other helicopters of the same kind, drawn around an airframe
//!   ([`Helicopter::varied`]).
//!
//! Frames and units: body forward-right-down, inertial north-east-down, SI, angles in rad,
//! rates in rad/s. Conversion to the paper's X-Plane axes is left to the experiment layer
//! (see `shared/paper/NOTES.md`).
//!
//! Everything random comes from a `u64` seed through `rand_chacha::ChaCha8Rng`, with separate
//! streams for jitter, measurement noise and turbulence, so the same seed gives the same
//! samples bit for bit.

pub mod airframe;
pub mod dynamics;
pub mod error;
pub mod flight;
pub mod linear;
pub mod params;
pub mod pilot;
pub mod rotor;
pub mod sensors;
pub mod sticks;
pub mod trim;
pub mod variation;

pub use airframe::{
    heave_and_yaw_at_hover, steady_response_per_stick, Airframe, HeaveYawDerivatives, StickScale,
};
pub use dynamics::{derivative, rk4_step, rk4_with, Aero, BladePitch, State, StateDot};
pub use error::PlantError;
pub use flight::{
    simulate, verification_excitation, verification_excitation_scaled, Excitation, Flight,
    FlightConfig, Limits,
};
pub use linear::LinearHover;
pub use params::{Helicopter, RotorBlades, StickMap, XCell60};
pub use pilot::{HoverPilot, PilotGains};
pub use rotor::{solve_rotor, RotorSolution};
pub use sensors::{NoiseStd, SensorSample, Turbulence};
pub use sticks::{Channel, Sticks};
pub use trim::{trim_hover, HoverTrim};
