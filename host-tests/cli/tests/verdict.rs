//! `rotorid identify`'s default output is a decision: the model to fly, per axis against
//! holding the measured state and the linear baseline, what the log could not show, and the
//! derivatives; with no `--verify` a later part of the data is held out; `--verify` equal to a
//! training log is warned about; a warm start that predicts absurdly is refused; `convert
//! --all` writes every segment; `--from`/`--to` select a window.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rotorid_cli::import::synth;
use rotorid_sim::flights;
use rotorid_sim::plant::SensorSample;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorid"))
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-verdict-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn run(cmd: &mut Command) -> Output {
    cmd.output().expect("runs")
}

/// `seconds` of the realistic identification flight (seed 1) as a CSV log.
fn flight_csv(dir: &Path, seconds: f64) -> PathBuf {
    let log = flights::identification_flight_for(1, seconds).expect("simulates");
    let path = dir.join("flight.csv");
    rotorid_cli::log::write_log(&path, &log).expect("write");
    path
}

fn metrics(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
        .expect("json")
}

#[test]
fn the_default_output_is_a_verdict_that_fits_a_screen() {
    let dir = tmpdir("screen");
    let log = flight_csv(&dir, 80.0);
    let out = dir.join("out");
    let o = run(bin()
        .args(["identify", "--no-plots", "--out"])
        .arg(&out)
        .arg(&log));
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{stderr}");
    assert!(
        stdout.lines().count() <= 40,
        "{} lines:\n{stdout}",
        stdout.lines().count()
    );
    assert!(
        stdout.contains("Model to fly") || stdout.contains("No model to fly"),
        "{stdout}"
    );
    // Axes in the autopilot's frame, against hold and the linear baseline.
    for axis in [
        "north velocity",
        "east velocity",
        "down velocity",
        "roll rate p",
        "pitch rate q",
        "yaw rate r",
        "vs hold",
        "vs linear",
        "M_lon",
    ] {
        assert!(stdout.contains(axis), "{axis} missing:\n{stdout}");
    }
    // No variant tables, no Table 4 by default.
    assert!(
        !stdout.contains("Table 4") && !stdout.contains("converged"),
        "{stdout}"
    );
    // The hold-out: said on the console, recorded in metrics.json; verification after training.
    assert!(stderr.contains("held out for verification"), "{stderr}");
    let m = metrics(&out);
    assert!(m["split"].as_str().is_some_and(|s| s.contains("the last")));
    assert_eq!(m["rate_hz"], 50.0);
    let verdict = &m["verdict"];
    assert_eq!(verdict["axes"].as_array().map(Vec::len), Some(6));
    assert!(verdict["model"].is_string());
    // Derivatives with units and corrected standard errors.
    let derivs = m["derivatives"]["regions"][0]["axes"]
        .as_array()
        .expect("fitted axes");
    let all: Vec<&serde_json::Value> = derivs
        .iter()
        .flat_map(|a| a["derivatives"].as_array().into_iter().flatten())
        .collect();
    assert!(!all.is_empty(), "{}", m["derivatives"]);
    assert!(all.iter().all(|d| d["unit"].is_string()));
    // The first 56 s are the longitudinal sweep: its control power is determined.
    assert!(all
        .iter()
        .any(|d| d["symbol"] == "M_lon" && d["se"].is_number() && d["determined"] == true));
    // The training and verification sample counts add up to the log's.
    let n = m["training_samples"].as_u64().unwrap() + m["verification_samples"].as_u64().unwrap();
    assert_eq!(n, 4000);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn verifying_on_a_training_log_is_warned_about() {
    let dir = tmpdir("same");
    let log = flight_csv(&dir, 30.0);
    let copy = dir.join("copy.csv");
    std::fs::copy(&log, &copy).expect("copy");
    let o = run(bin()
        .args(["identify", "--no-plots", "--out"])
        .arg(dir.join("out"))
        .arg(&log)
        .arg("--verify")
        .arg(&copy));
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("is also a training log"),
        "{}",
        text(&o.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_warm_start_that_predicts_absurdly_is_refused() {
    let dir = tmpdir("warm");
    let log = flight_csv(&dir, 30.0);
    let out = dir.join("out");
    let o = run(bin()
        .args(["identify", "--no-plots", "--out"])
        .arg(&out)
        .arg(&log));
    assert!(o.status.success(), "{}", text(&o.stderr));
    // The first variant's parameters, each θ scaled to 1e11.
    let path = out.join("params-paper-fuzzy.json");
    let mut params: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("params")).expect("json");
    fn blow_up(v: &mut serde_json::Value, in_theta: bool) {
        match v {
            serde_json::Value::Number(_) if in_theta => *v = serde_json::json!(1e11),
            serde_json::Value::Array(a) => a.iter_mut().for_each(|x| blow_up(x, in_theta)),
            serde_json::Value::Object(o) => {
                for (k, x) in o.iter_mut() {
                    blow_up(x, in_theta || k == "theta");
                }
            }
            _ => {}
        }
    }
    blow_up(&mut params, false);
    let bad = dir.join("bad.json");
    std::fs::write(&bad, params.to_string()).expect("write");
    let o = run(bin()
        .args(["identify", "--no-plots", "--out"])
        .arg(dir.join("out2"))
        .arg(&log)
        .arg("--warm-start")
        .arg(&bad));
    let stderr = text(&o.stderr);
    assert!(!o.status.success());
    assert!(stderr.contains("warm start refused"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// 20 s of flight with a 0.5 s logging dropout at 8 s, as a DataFlash log.
fn two_segment_log(dir: &Path) -> PathBuf {
    let mut flight: Vec<SensorSample> =
        flights::identification_flight_for(3, 20.0).expect("simulates");
    flight.drain(400..425);
    let path = dir.join("two.bin");
    std::fs::write(&path, synth::dataflash(&flight, true)).expect("write");
    path
}

#[test]
fn convert_all_writes_every_segment_and_from_to_select_a_window() {
    let dir = tmpdir("convert");
    let log = two_segment_log(&dir);
    let out = dir.join("seg.csv");
    let o = run(bin()
        .arg("convert")
        .arg(&log)
        .arg("-o")
        .arg(&out)
        .arg("--all"));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let first = rotorid_cli::log::read_log(&dir.join("seg-1.csv")).expect("segment 1");
    let second = rotorid_cli::log::read_log(&dir.join("seg-2.csv")).expect("segment 2");
    assert_eq!(first.len() + second.len(), 1000 - 25);
    // A window in log time (the writer's clock starts at 1 s): only what lies inside.
    let o = run(bin()
        .arg("convert")
        .arg(&log)
        .arg("-o")
        .arg(dir.join("window.csv"))
        .args(["--from", "12", "--to", "16"]));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let w = rotorid_cli::log::read_log(&dir.join("window.csv")).expect("window");
    assert!(w.first().is_some_and(|s| s.t >= 12.0) && w.last().is_some_and(|s| s.t <= 16.0));
    assert!(w.len() >= 195, "{}", w.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// One DataFlash record stamped far in the future mid-log costs that record, not the rest of
/// its channel, and a note says so.
#[test]
fn a_future_time_stamp_costs_one_record_not_the_rest_of_the_log() {
    let dir = tmpdir("glitch");
    let mut flight: Vec<SensorSample> =
        flights::identification_flight_for(3, 20.0).expect("simulates");
    flight[500].t += 1000.0;
    let path = dir.join("glitch.bin");
    std::fs::write(&path, synth::dataflash(&flight, true)).expect("write");
    let imported = rotorid_cli::import::import(&path).expect("imports");
    let n: usize = imported.segments.iter().map(Vec::len).sum();
    assert!(n >= 990, "{n} of 1000 samples kept");
    assert!(
        imported.notes.iter().any(|n| n.contains("jumps")),
        "{:?}",
        imported.notes
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A real log of a vehicle armed on a bench (ArduSub, nothing moved, no control input) beats
/// hold by chance on drift and noise; the verdict says there is no model to fly, and why.
#[test]
fn a_bench_log_gives_no_model_to_fly() {
    let log = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs/real/ardusub_bench_small.bin");
    let dir = tmpdir("bench");
    let o = run(bin()
        .args(["identify", "--no-plots", "--out"])
        .arg(&dir)
        .arg(&log));
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(stdout.contains("No model to fly"), "{stdout}");
    let m = metrics(&dir);
    assert_eq!(m["verdict"]["fly"], false, "{}", m["verdict"]);
    let why = m["verdict"]["why"].as_str().unwrap();
    assert!(why.contains("no stick moved"), "{why}");
}

/// Issue 34's criterion on the real logs committed under `data/logs/real/` (and the ESC log):
/// wherever the training data are long enough for the term selection (24 s: six blocks of two
/// 2 s windows), it runs, and both the flight default's and `flight selected`'s free runs
/// predict pitch and roll no worse than holding the measured rate on the held-out part, except
/// where [`KNOWN_WORSE`] says one does not, and there the verdict says so. docs/real-logs.md
/// has the table; a log shorter than that keeps every term and is not judged here.
///
/// A known failure is asserted as one: if it starts to pass, this test fails, and the list
/// and docs/real-logs.md are brought up to date.
/// None today: with the controls' delay chosen from each log, the flight default's pitch free
/// run on ArduCopter's 10 Hz log went from 1.07 of hold (no delay) to 0.79 (100 ms).
const KNOWN_WORSE: [(&str, &str, &str); 0] = [];

#[test]
fn on_real_logs_the_flight_models_beat_hold_on_pitch_and_roll() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs");
    let logs = [
        "real/battery_brownout.ulg",
        "real/ekf_failure.ulg",
        "real/gps_interference.ulg",
        "real/sample_px4_events.ulg",
        "esc_status_log.ulg",
        "real/arducopter_spark404_log.bin",
    ];
    let mut judged = 0;
    for name in logs {
        let dir = tmpdir(&name.replace('/', "-"));
        let o = run(bin()
            .args(["identify", "--no-plots", "--out"])
            .arg(&dir)
            .arg(data.join(name)));
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let m = metrics(&dir);
        let training_s = m["training_samples"].as_f64().unwrap() / m["rate_hz"].as_f64().unwrap();
        if training_s < 24.0 {
            continue;
        }
        judged += 1;
        // The controls' delay was chosen on the training data (every candidate scored), and
        // the verdict says when one was applied.
        let delay = &m["control_delay"];
        assert!(
            delay["scores"].as_array().is_some_and(|s| s.len() >= 2),
            "{name}: {delay}"
        );
        if delay["delay_s"].as_f64().unwrap() > 0.0 {
            let caveats = m["verdict"]["caveats"].to_string();
            assert!(
                caveats.contains("act") && caveats.contains("after they are logged"),
                "{name}: {caveats}"
            );
        }
        let off = m["verdict"]["terms_off"].as_array().map_or(0, Vec::len);
        assert!(
            off > 0,
            "{name}: {training_s:.0} s of training, no term switched off"
        );
        for variant in ["flight", "flight selected"] {
            let scores = m["variants"]
                .as_array()
                .unwrap()
                .iter()
                .find(|v| v["name"] == variant)
                .expect(variant);
            for (axis, i, label) in [("q", 3, "pitch rate q"), ("p", 5, "roll rate p")] {
                let (f, h) = (
                    scores["free_run"][i].as_f64().unwrap(),
                    scores["hold_free_run"][i].as_f64().unwrap(),
                );
                if KNOWN_WORSE.contains(&(variant, name, axis)) {
                    assert!(
                        f > h,
                        "{name}: {variant}'s {axis} now beats hold ({f} ≤ {h}): update KNOWN_WORSE"
                    );
                    // The verdict says so: a caveat names the axis.
                    let caveats = m["verdict"]["caveats"].to_string();
                    assert!(
                        caveats.contains("worse than hold on") && caveats.contains(label),
                        "{name}: the verdict does not name {label}: {caveats}"
                    );
                } else {
                    assert!(f <= h, "{name}: {variant}'s {axis} free run {f} > hold {h}");
                }
            }
        }
    }
    assert_eq!(judged, 5, "the logs with 24 s of training or more");
}
