//! ArduPilot SITL helicopter logs (issue 30): DataFlash logs that ArduPilot itself wrote while
//! its SITL helicopter flew SystemID chirps, doublets and the low-speed envelope
//! (`data/logs/ardupilot-sitl/`, provenance in its README), through the importer and through
//! `rotorid identify`.

use std::path::{Path, PathBuf};
use std::process::Command;

use rotorid_cli::import::{self, LogFormat};
use rotorid_sim::plant::SensorSample;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs/ardupilot-sitl")
}

/// Hover with SystemID chirps at the mixer on each axis, then doublets.
fn hover_log() -> PathBuf {
    dir().join("heli-sid.bin")
}

/// GUIDED velocity steps forward and sideways (docs/ardupilot-sitl.md: the log whose held-out
/// part the flight default predicts better than hold; on `heli-sid.bin` no model is scored).
fn envelope_log() -> PathBuf {
    dir().join("heli-envelope.bin")
}

/// Pearson correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    ab / (aa * bb).sqrt()
}

/// Each control and the body-rate derivative it should drive first: (control, rate) per axis.
fn axis(seg: &[SensorSample], which: usize) -> (Vec<f64>, Vec<f64>) {
    let dt = seg[1].t - seg[0].t;
    let rate = |s: &SensorSample| [s.p, s.q, s.r][which];
    let control = |s: &SensorSample| [s.sticks.lat, s.sticks.lon, s.sticks.ped][which];
    let u = seg[..seg.len() - 1].iter().map(control).collect();
    let dr = seg
        .windows(2)
        .map(|w| (rate(&w[1]) - rate(&w[0])) / dt)
        .collect();
    (u, dr)
}

#[test]
fn the_importer_finds_the_helicopter_controls_in_an_ardupilot_heli_log() {
    let imported = import::import(&hover_log()).expect("ArduPilot's heli log imports");
    assert_eq!(imported.format, LogFormat::DataFlash);
    let rates = imported.native_rates.expect("native rates");
    // LOG_BITMASK ATTITUDE_FAST with LOG_FILE_RATEMAX 50: ANG and RATE (attitude, rates,
    // cyclic, pedal and collective) near 50 Hz, not the 10 Hz of ATT and CTUN; XKF1 at 25 Hz.
    for (name, r) in [
        ("attitude", rates.attitude),
        ("rates", rates.rates),
        ("controls", rates.controls),
    ] {
        let r = r.unwrap_or(0.0);
        assert!((40.0..=55.0).contains(&r), "{name} at {r} Hz");
    }
    let v = rates.velocity.unwrap_or(0.0);
    assert!((20.0..=30.0).contains(&v), "velocity at {v} Hz");
    let seg = imported.longest().expect("a segment");
    assert!(
        seg.len() as f64 / imported.rate_hz > 60.0,
        "{} samples",
        seg.len()
    );
    // Collective within the normalised range and away from its stops in hover; cyclic and
    // pedal excited by the chirps and doublets, within ±1.
    let col: Vec<f64> = seg.iter().map(|s| s.sticks.col).collect();
    let mean_col = col.iter().sum::<f64>() / col.len() as f64;
    assert!(col.iter().all(|c| (0.0..=1.0).contains(c)));
    assert!(
        (0.2..0.9).contains(&mean_col),
        "hover collective {mean_col}"
    );
    for which in 0..3 {
        let (u, _) = axis(seg, which);
        let (lo, hi) = u
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(lo >= -1.0 && hi <= 1.0, "axis {which}: {lo}..{hi}");
        assert!(hi - lo > 0.05, "axis {which} barely moved: {lo}..{hi}");
    }
    // The mapping: each axis's control drives its own rate's derivative more than the other
    // two controls do (the chirps are injected one axis at a time), with positive sign
    // (positive lateral cyclic rolls right, positive longitudinal pitches up, positive
    // pedal yaws right in ArduPilot's convention).
    for which in 0..3 {
        let (own, dr) = axis(seg, which);
        let c_own = correlation(&own, &dr);
        assert!(c_own > 0.2, "axis {which}: correlation {c_own}");
        for other in (0..3).filter(|&o| o != which) {
            let (u, _) = axis(seg, other);
            let c = correlation(&u, &dr);
            assert!(
                c_own > c.abs(),
                "axis {which}: own {c_own}, control {other} {c}"
            );
        }
    }
}

#[test]
fn identify_runs_on_an_ardupilot_heli_envelope_log_and_names_a_model() {
    let out = std::env::temp_dir().join(format!("rotorid-ardupilot-sitl-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_rotorid"))
        .args(["identify", "--no-plots", "--out"])
        .arg(&out)
        .arg(envelope_log())
        .output()
        .expect("runs");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{stderr}");
    let m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("metrics.json")).expect("metrics.json"),
    )
    .expect("json");
    assert_eq!(m["logs"][0]["format"], "DataFlash");
    let model = m["verdict"]["model"]
        .as_str()
        .expect("the verdict names a model");
    let variants: Vec<&str> = m["variants"]
        .as_array()
        .expect("variants")
        .iter()
        .filter_map(|v| v["name"].as_str())
        .collect();
    assert!(variants.contains(&model), "{model} not among {variants:?}");
    assert!(stdout.contains(model), "{stdout}");
    // Every variant was evaluated on all six axes with finite errors.
    for v in m["variants"].as_array().expect("variants") {
        let fr = v["free_run"].as_array().expect("free_run");
        assert_eq!(fr.len(), 6);
        assert!(
            fr.iter().all(|x| x.as_f64().is_some_and(f64::is_finite)),
            "{v}"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}
