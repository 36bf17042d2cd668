//! The X-Cell 60's heave and yaw derivatives at hover trim, by central differences of the
//! simulator's state derivative (`rotorid_sim::plant::heave_and_yaw_at_hover`, which
//! `host-tests/cli/tests/derivatives.rs` compares with), as one JSON object:
//! `Z_w` (1/s), `Z_col` (m/s² per unit stick), `N_r` (1/s), `N_ped` (rad/s² per unit stick).
//! `scripts/closed-loop.sh` compares the identified derivatives with them. Heave and yaw do
//! not go through the flapping, so the quasi-steady model `rotorid identify` fits holds for
//! them; the roll and pitch rates have no such one-number truth.
//!
//! Run: `cargo run --release -p rotorid-sim --example hover_linearisation`.

use rotorid_sim::plant::{heave_and_yaw_at_hover, FlightConfig};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let d = heave_and_yaw_at_hover(&FlightConfig::default().params)?;
    println!(
        r#"{{"Z_w": {}, "Z_col": {}, "N_r": {}, "N_ped": {}}}"#,
        d.z_w, d.z_col, d.n_r, d.n_ped
    );
    Ok(())
}
