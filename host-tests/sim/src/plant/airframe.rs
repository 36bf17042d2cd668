//! The helicopters the simulator flies ([`Airframe`]) and how the pilot and the excitation are
//! scaled to each ([`StickScale`]).
//!
//! Every modelling choice of rotorid was first checked on the X-Cell 60 only; the second
//! airframe, [`Helicopter::flybarless_600`], is physically different (size, head speed,
//! flapping speed and gain, hub stiffness, speed flapping, tail rotor, drag) so that a choice
//! that only fits the X-Cell shows up.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::dynamics::{derivative, State};
use super::error::PlantError;
use super::params::{Helicopter, XCell60};
use super::pilot::PilotGains;
use super::sticks::{Channel, Sticks};
use super::trim::trim_hover;

/// Rotor radius of a 600-class helicopter (m): 600 mm blades in grips ≈ 75 mm from the shaft,
/// a 1.35 m disc.
const FBL600_RADIUS: f64 = 0.675;
/// Head speed (rad/s): 1 900 rpm, a usual governor set-point of flybarless 600-class
/// helicopters (the Froude-scaled X-Cell would turn at 179 rad/s, 1 710 rpm).
const FBL600_HEAD_SPEED: f64 = 1900.0 * core::f64::consts::PI / 30.0;
/// Mass of one main blade (kg): a 600 mm carbon blade weighs 110–130 g.
const FBL600_BLADE_MASS: f64 = 0.12;
/// Cyclic blade pitch at full stick (rad): ±8°, a usual flybarless cyclic throw.
const FBL600_CYCLIC_THROW: f64 = 8.0 * core::f64::consts::PI / 180.0;
/// Hub stiffness relative to the Froude-scaled X-Cell's: flybarless heads fly hard (90 shore)
/// damper rubbers and no see-saw, taken as twice as stiff.
const FBL600_HUB_STIFFENING: f64 = 2.0;
/// Tail rotor radius (m): 95 mm tail blades, against the scaled X-Cell's 0.113 m; flybarless
/// 600s fly larger tails for their faster yaw.
const FBL600_TAIL_RADIUS: f64 = 0.125;
/// Fuselage drag area along x relative to the scaled X-Cell's: a slim canopy instead of the
/// X-Cell's open frame with its fuel tank and engine in the stream.
const FBL600_FORWARD_DRAG: f64 = 0.6;

impl Helicopter {
    /// A flybarless 600-class helicopter (≈ 5.4 kg, 1.35 m rotor at 1 900 rpm), the second
    /// plant.
    ///
    /// No published parameter set of another airframe of this model family was found, so it is
    /// derived: the X-Cell 60 [`Helicopter::froude_scaled`] to a 600-class rotor radius
    /// (s = 0.675 / 0.775 = 0.871: 5.42 kg, inertias ×0.50, lengths ×0.87), then changed where a
    /// flybarless 600 is physically different, each change stated (none chosen from rotorid's
    /// results):
    ///
    /// * **no stabiliser bar**: the flapping speed is the blades' own. `τ_e = 16 / (γ Ω)` with
    ///   the blade Lock number `γ = ρ a c R⁴ / I_b`, `I_b = m_b R² / 3` (m_b = 0.12 kg):
    ///   γ ≈ 3.9 instead of the bar's 0.8, so τ_e ≈ 0.021 s instead of 0.12 s. The swashplate
    ///   pitches the blades directly: `A_lon = B_lat = 1` (steady flapping equals the cyclic,
    ///   instead of the bar mixing's 4.2), with a ±8° cyclic throw (`lon_gain = lat_gain =
    ///   0.14` rad). Nothing washes out the flapping with speed: `K_μ = 1` instead of 0.2.
    /// * **higher head speed**: 1 900 rpm (199 rad/s) instead of the scaled 179 rad/s, so the
    ///   trim `C_T` and collective are lower.
    /// * **stiffer hub**: `K_β` twice the scaled X-Cell's (hard dampers, no teeter).
    /// * **tail rotor**: radius 0.125 m instead of the scaled 0.113 m (same gear ratio).
    /// * **fuselage**: forward drag area 0.6× the scaled X-Cell's (slim canopy).
    ///
    /// Everything else (fins, hub height, blade aerodynamics, stick map of collective and
    /// pedal) is the Froude-scaled X-Cell's.
    pub fn flybarless_600() -> Self {
        let x = XCell60::default();
        let s = FBL600_RADIUS / x.main.radius;
        let mut h = x.froude_scaled(s);
        h.omega = FBL600_HEAD_SPEED;
        let blade_inertia = FBL600_BLADE_MASS * h.main.radius * h.main.radius / 3.0;
        let r2 = h.main.radius * h.main.radius;
        h.gamma_fb = h.rho * h.main.lift_slope * h.main.chord * r2 * r2 / blade_inertia;
        h.a_lon = 1.0;
        h.b_lat = 1.0;
        h.k_mu = 1.0;
        h.sticks.lon_gain = FBL600_CYCLIC_THROW;
        h.sticks.lat_gain = FBL600_CYCLIC_THROW;
        h.k_beta *= FBL600_HUB_STIFFENING;
        h.tail.radius = FBL600_TAIL_RADIUS;
        h.fus_sx *= FBL600_FORWARD_DRAG;
        h
    }
}

/// A helicopter the simulator can fly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Airframe {
    /// The MIT X-Cell 60 ([`XCell60::default`]); the default.
    #[default]
    XCell60,
    /// A flybarless 600-class helicopter ([`Helicopter::flybarless_600`]).
    Flybarless600,
}

impl Airframe {
    /// Every airframe, the default first.
    pub const ALL: [Airframe; 2] = [Airframe::XCell60, Airframe::Flybarless600];

    /// Its parameters.
    pub fn params(self) -> Helicopter {
        match self {
            Airframe::XCell60 => XCell60::default(),
            Airframe::Flybarless600 => Helicopter::flybarless_600(),
        }
    }

    /// Short name (as on the command line).
    pub fn name(self) -> &'static str {
        match self {
            Airframe::XCell60 => "xcell60",
            Airframe::Flybarless600 => "flybarless600",
        }
    }

    /// Name for documents.
    pub fn title(self) -> &'static str {
        match self {
            Airframe::XCell60 => "X-Cell 60",
            Airframe::Flybarless600 => "flybarless 600",
        }
    }

    /// The pilot's and the excitation's stick scaling for this airframe, relative to the
    /// X-Cell 60 (all ones for the X-Cell itself).
    pub fn stick_scale(self) -> Result<StickScale, PlantError> {
        match self {
            Airframe::XCell60 => Ok(StickScale::default()),
            other => StickScale::between(&XCell60::default(), &other.params()),
        }
    }
}

/// Per-channel factor on every stick deflection the pilot and the excitation make, so that the
/// same flight (pilot gains, sweep and manoeuvre amplitudes, designed on the X-Cell 60) makes
/// the same steady response on another airframe.
///
/// The factor of a channel is `X-Cell's steady response per unit stick / this airframe's`:
/// * cyclic: the steady rate where the flapping equation balances, `q = A_lon δ_lon / τ_e` per
///   unit stick (`p = B_lat δ_lat / τ_e`), the rate command a cyclic stick is;
/// * collective: steady vertical speed `−Z_col / Z_w`; pedal: steady yaw rate `−N_ped / N_r`,
///   from the hover linearisation (central differences of the state derivative at trim).
///
/// A pilot whose gains are scaled so closes its attitude, vertical-speed and heading loops at
/// the same bandwidth on both airframes, and a sweep of scaled amplitude reaches the same rates
/// and speeds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StickScale {
    /// Collective factor (–).
    pub col: f64,
    /// Pedal factor (–).
    pub ped: f64,
    /// Longitudinal cyclic factor (–).
    pub lon: f64,
    /// Lateral cyclic factor (–).
    pub lat: f64,
}

impl Default for StickScale {
    /// No scaling (the X-Cell 60).
    fn default() -> Self {
        Self {
            col: 1.0,
            ped: 1.0,
            lon: 1.0,
            lat: 1.0,
        }
    }
}

/// Central-difference step for the hover linearisation (stick units, m/s, rad/s).
const LINEARISATION_STEP: f64 = 1e-4;

impl StickScale {
    /// The factor of one channel.
    pub fn get(&self, ch: Channel) -> f64 {
        match ch {
            Channel::Col => self.col,
            Channel::Ped => self.ped,
            Channel::Lon => self.lon,
            Channel::Lat => self.lat,
        }
    }

    /// The scaling that makes `plant` respond per stick as `reference` does.
    pub fn between(reference: &Helicopter, plant: &Helicopter) -> Result<Self, PlantError> {
        let r = steady_response_per_stick(reference)?;
        let p = steady_response_per_stick(plant)?;
        Ok(Self {
            col: r.col / p.col,
            ped: r.ped / p.ped,
            lon: r.lon / p.lon,
            lat: r.lat / p.lat,
        })
    }
}

/// The heave and yaw derivatives of a helicopter at hover trim, by central differences of the
/// simulator's state derivative ([`derivative`]) in body axes (z down). Heave and yaw do not go
/// through the flapping, so a quasi-steady model (`rotorid identify`'s derivatives) must find
/// them; roll and pitch have no such one-number truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeaveYawDerivatives {
    /// `Z_w`: vertical acceleration per vertical speed (1/s).
    pub z_w: f64,
    /// `Z_col`: vertical acceleration per unit collective stick (m/s² per unit stick).
    pub z_col: f64,
    /// `N_r`: yaw acceleration per yaw rate (1/s).
    pub n_r: f64,
    /// `N_ped`: yaw acceleration per unit pedal stick (rad/s² per unit stick).
    pub n_ped: f64,
}

/// [`HeaveYawDerivatives`] of `p` at hover trim.
pub fn heave_and_yaw_at_hover(p: &Helicopter) -> Result<HeaveYawDerivatives, PlantError> {
    let trim = trim_hover(p, 0.0)?;
    let h = LINEARISATION_STEP;
    let accel = |sticks: &Sticks, state: &State| {
        let (d, _) = derivative(p, state, &p.blade_pitch(sticks), &Vector3::zeros());
        (d.vel_body.z, d.omega.z)
    };
    let stick_slope = |ch: Channel| {
        let (mut up, mut down) = (trim.sticks, trim.sticks);
        up.set(ch, up.get(ch) + h);
        down.set(ch, down.get(ch) - h);
        let (a, b) = (accel(&up, &trim.state), accel(&down, &trim.state));
        ((a.0 - b.0) / (2.0 * h), (a.1 - b.1) / (2.0 * h))
    };
    let state_slope = |perturb: fn(&mut State, f64)| {
        let (mut up, mut down) = (trim.state, trim.state);
        perturb(&mut up, h);
        perturb(&mut down, -h);
        let (a, b) = (accel(&trim.sticks, &up), accel(&trim.sticks, &down));
        ((a.0 - b.0) / (2.0 * h), (a.1 - b.1) / (2.0 * h))
    };
    let (z_col, _) = stick_slope(Channel::Col);
    let (_, n_ped) = stick_slope(Channel::Ped);
    let (z_w, _) = state_slope(|s, d| s.vel_body.z += d);
    let (_, n_r) = state_slope(|s, d| s.omega.z += d);
    Ok(HeaveYawDerivatives {
        z_w,
        z_col,
        n_r,
        n_ped,
    })
}

/// Steady response of `p` at hover per unit of each stick: vertical speed (m/s, up), yaw rate,
/// pitch rate, roll rate (rad/s), as a [`StickScale`]-shaped record. See [`StickScale`].
pub fn steady_response_per_stick(p: &Helicopter) -> Result<StickScale, PlantError> {
    let d = heave_and_yaw_at_hover(p)?;
    let tau = p.tau_e();
    Ok(StickScale {
        // Body z is down: a collective that accelerates up (Z_col < 0) climbs.
        col: d.z_col / d.z_w,
        ped: -d.n_ped / d.n_r,
        lon: p.a_lon * p.sticks.lon_gain / tau,
        lat: p.b_lat * p.sticks.lat_gain / tau,
    })
}

impl PilotGains {
    /// These gains with each channel's stick outputs multiplied by its factor (the attitude
    /// references per velocity and their limit are angles and stay).
    pub fn scaled(&self, s: &StickScale) -> Self {
        Self {
            pitch_att: self.pitch_att * s.lon,
            pitch_rate: self.pitch_rate * s.lon,
            roll_att: self.roll_att * s.lat,
            roll_rate: self.roll_rate * s.lat,
            vertical_speed: self.vertical_speed * s.col,
            altitude: self.altitude * s.col,
            yaw_rate: self.yaw_rate * s.ped,
            heading: self.heading * s.ped,
            ..*self
        }
    }
}
