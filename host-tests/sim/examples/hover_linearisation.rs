//! The X-Cell 60's heave and yaw derivatives at hover trim, by central differences of the
//! simulator's state derivative (the path of `host-tests/cli/tests/derivatives.rs`'s
//! comparison and of `rotorid_sim::plant::steady_response_per_stick`), as one JSON object:
//! `Z_w` (1/s), `Z_col` (m/s² per unit stick), `N_r` (1/s), `N_ped` (rad/s² per unit stick).
//! `scripts/closed-loop.sh` compares the identified derivatives with them. Heave and yaw do
//! not go through the flapping, so the quasi-steady model `rotorid identify` fits holds for
//! them; the roll and pitch rates have no such one-number truth.
//!
//! Run: `cargo run --release -p rotorid-sim --example hover_linearisation`.

use nalgebra::Vector3;
use rotorid_sim::plant::{derivative, trim_hover, Channel, FlightConfig, State, Sticks};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let p = FlightConfig::default().params;
    let trim = trim_hover(&p, 0.0)?;
    // The step of the derivatives test: small against trim, large against rounding.
    let h = 1e-4;
    let accel = |sticks: &Sticks, state: &State| {
        let (d, _) = derivative(&p, state, &p.blade_pitch(sticks), &Vector3::zeros());
        (d.vel_body.z, d.omega.z)
    };
    let stick = |ch: Channel| {
        let (mut up, mut down) = (trim.sticks, trim.sticks);
        up.set(ch, up.get(ch) + h);
        down.set(ch, down.get(ch) - h);
        let (a, b) = (accel(&up, &trim.state), accel(&down, &trim.state));
        ((a.0 - b.0) / (2.0 * h), (a.1 - b.1) / (2.0 * h))
    };
    let state = |perturb: fn(&mut State, f64)| {
        let (mut up, mut down) = (trim.state, trim.state);
        perturb(&mut up, h);
        perturb(&mut down, -h);
        let (a, b) = (accel(&trim.sticks, &up), accel(&trim.sticks, &down));
        ((a.0 - b.0) / (2.0 * h), (a.1 - b.1) / (2.0 * h))
    };
    let (z_col, _) = stick(Channel::Col);
    let (_, n_ped) = stick(Channel::Ped);
    let (z_w, _) = state(|s, d| s.vel_body.z += d);
    let (_, n_r) = state(|s, d| s.omega.z += d);
    println!(r#"{{"Z_w": {z_w}, "Z_col": {z_col}, "N_r": {n_r}, "N_ped": {n_ped}}}"#);
    Ok(())
}
