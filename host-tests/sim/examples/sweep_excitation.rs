//! The identification flight's known excitation: per sample k of
//! `rotorid_sim::flights::identification_flight`, the swept channel and the sweep's offset
//! from trim (stick units) before the pilot's correction is added, as CSV `k,channel,offset`
//! (channel: lon, lat, ped, col). The same for every seed and every pilot gain (the X-Cell 60's
//! stick scaling is one). `scripts/closed-loop.sh` uses it as the instrument of its
//! instrumental-variable check (the recorded sticks are sweep plus pilot, and the pilot
//! reacts to the noisy states).
//!
//! Run: `cargo run --release -p rotorid-sim --example sweep_excitation > excitation.csv`.

use std::io::Write;

use rotorid::sweep::Channel;
use rotorid_sim::flights::identification_schedule;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let schedule = identification_schedule().map_err(|e| format!("sweeps: {e}"))?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    writeln!(out, "k,channel,offset")?;
    for k in 0..schedule.len() {
        if let Some(e) = schedule.at(k) {
            let name = match e.channel {
                Channel::Longitudinal => "lon",
                Channel::Lateral => "lat",
                Channel::Pedal => "ped",
                Channel::Collective => "col",
            };
            writeln!(out, "{k},{name},{}", e.offset)?;
        }
    }
    out.flush()?;
    Ok(())
}
