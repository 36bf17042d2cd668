//! The `rotorid` command-line tool end to end: a short simulated flight through `simulate`
//! and `identify` (the product's variants only), and each kind of malformed log giving a
//! positioned error and a non-zero exit (never a panic). The studies' `report` and
//! `robustness-report` are tested with `rotorid-lab` (host-tests/lab/tests/reports.rs).
//!
//! (Over 700 lines: every test here drives the `rotorid` binary through the same flights and
//! temp-dir helpers, which a split would have to share.)

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The studies' ablations of the flight default (`rotorid_lab::ablations`), which the product
/// must not run.
const ABLATIONS: [&str; 5] = [
    "flight extended velocity",
    "flight first-order rates",
    "flight proportional thrust",
    "flight yaw on side speed",
    "flight data sets",
];

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorid"))
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn run(cmd: &mut Command) -> Output {
    cmd.output().expect("runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn simulate(dir: &Path, kind: &str, seed: &str, duration: &str) -> PathBuf {
    simulate_with(dir, kind, seed, duration, &[])
}

/// [`simulate`] with `extra` options (`--plant …`).
fn simulate_with(dir: &Path, kind: &str, seed: &str, duration: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("{kind}.csv"));
    let o = run(bin()
        .args([
            "simulate",
            "--kind",
            kind,
            "--seed",
            seed,
            "--duration",
            duration,
        ])
        .args(extra)
        .arg("-o")
        .arg(&out));
    assert!(o.status.success(), "{}", text(&o.stderr));
    out
}

/// `rotorid identify --no-plots --window 1` with `extra` options; its metrics.json.
fn identify_metrics(train: &Path, verify: &Path, out: &Path, extra: &[&str]) -> serde_json::Value {
    let o = run(bin()
        .args(["identify", "--no-plots", "--window", "1"])
        .args(extra)
        .arg("--train")
        .arg(train)
        .arg("--verify")
        .arg(verify)
        .arg("--out")
        .arg(out));
    assert!(o.status.success(), "{}", text(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
        .expect("json")
}

/// `rotorid identify … | head -1`: the reader goes after the first line; the tool neither
/// panics (as `println!` on a closed pipe does) nor stops writing its files.
#[test]
fn a_reader_that_stops_early_does_not_crash_the_tool() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let dir = tmpdir("epipe");
    let train = simulate(&dir, "identification", "1", "12");
    let verify = simulate(&dir, "verification", "2", "8");
    let out = dir.join("out");
    let mut child = bin()
        .args([
            "identify",
            "--full",
            "--no-plots",
            "--window",
            "1",
            "--train",
        ])
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut first)
        .expect("a first line");
    // The reader is dropped here: the pipe is closed with most of the text unread.
    let o = child.wait_with_output().expect("exits");
    let stderr = text(&o.stderr);
    assert!(!first.is_empty());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(o.status.success(), "{stderr}");
    assert!(out.join("metrics.json").is_file(), "the files are written");
}

/// `identify` writes each flyable variant's state in the core's one saved-state format
/// (`snapshot-*.ridx`: the C interface's export bytes, the link's): the flight default's reads
/// into the core's `FlightIdentifier` with the parameters of `params-flight.json`, and a warm
/// start from a snapshot is the warm start from the same state's JSON.
#[test]
fn snapshots_hold_the_learnt_state_and_warm_start_as_the_parameters_do() {
    use rotorid::snapshot::{KindCode, Snapshot};
    use rotorid::{flight_sets, FlightIdentifier, HoverConfig};
    use rotorid_cli::experiments::{Identifier, ModelParameters};
    let dir = tmpdir("snapshot");
    let train = simulate(&dir, "identification", "1", "12");
    let verify = simulate(&dir, "verification", "2", "8");
    let first = dir.join("first");
    identify_metrics(&train, &verify, &first, &[]);

    let bytes = std::fs::read(first.join("snapshot-flight.ridx")).expect("a snapshot");
    assert_eq!(bytes.len(), FlightIdentifier::<f32>::SNAPSHOT_SIZE);
    assert_eq!(&bytes[..4], b"RIDX");
    let kind = FlightIdentifier::<f32>::KIND;
    assert_eq!(
        bytes[8..12],
        kind.to_le_bytes(),
        "the C interface's ROTORID_KIND_FLIGHT"
    );
    let mut id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
    Snapshot::read_snapshot(&mut id, kind, &bytes).expect("the core reads it");
    let json: Vec<ModelParameters> = serde_json::from_str(
        &std::fs::read_to_string(first.join("params-flight.json")).expect("params"),
    )
    .expect("json");
    assert_eq!(
        serde_json::to_value(Identifier::parameters(&id)).unwrap(),
        serde_json::to_value(&json).unwrap()
    );
    // The ablations' types run on no flight computer: the product writes no such file, and
    // every variant it writes parameters for has its snapshot.
    for entry in std::fs::read_dir(&first).expect("out dir") {
        let name = entry.expect("entry").file_name().into_string().unwrap();
        if let Some(variant) = name
            .strip_prefix("params-")
            .and_then(|n| n.strip_suffix(".json"))
            .filter(|n| !n.ends_with("-compensated"))
        {
            assert!(
                first.join(format!("snapshot-{variant}.ridx")).is_file(),
                "{variant}"
            );
        }
    }

    // Warm start of the first variant (paper fuzzy) from its JSON and from its snapshot.
    let from_json = identify_metrics(
        &train,
        &verify,
        &dir.join("json"),
        &[
            "--warm-start",
            first.join("params-paper-fuzzy.json").to_str().unwrap(),
        ],
    );
    let from_snapshot = identify_metrics(
        &train,
        &verify,
        &dir.join("ridx"),
        &[
            "--warm-start",
            first.join("snapshot-paper-fuzzy.ridx").to_str().unwrap(),
        ],
    );
    assert_eq!(from_json["variants"][0], from_snapshot["variants"][0]);
    // Another kind's snapshot is refused, naming the file.
    let o = run(bin()
        .args(["identify", "--no-plots", "--window", "1", "--warm-start"])
        .arg(first.join("snapshot-flight.ridx"))
        .arg("--train")
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(dir.join("refused")));
    let stderr = text(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("snapshot-flight.ridx")
            && stderr.contains("not a snapshot the first variant can start from"),
        "{stderr}"
    );
}

#[test]
fn end_to_end_on_a_short_flight() {
    let dir = tmpdir("e2e");
    // 12 s of the lon sweep (trim pad, then the low-frequency start) and 8 s of verification.
    let train = simulate(&dir, "identification", "1", "12");
    let verify = simulate(&dir, "verification", "2", "8");
    let lines = std::fs::read_to_string(&train)
        .expect("log")
        .lines()
        .count();
    assert_eq!(lines, 1 + 600, "header + 50 Hz x 12 s");

    let out = dir.join("out");
    let o = run(bin()
        .args(["identify", "--full", "--train"])
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(&out)
        .args(["--window", "1"]));
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for state in [
        "v_x (m/s)",
        "v_y (m/s)",
        "v_z (m/s)",
        "q (deg/s)",
        "r (deg/s)",
        "p (deg/s)",
    ] {
        assert!(stdout.contains(state), "{state} missing:\n{stdout}");
    }
    assert!(stdout.contains("fuzzy RLS") && stdout.contains("improvement"));

    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
            .expect("json");
    let variants = metrics["variants"].as_array().expect("variants");
    let names: Vec<&str> = variants.iter().filter_map(|v| v["name"].as_str()).collect();
    let expected: Vec<&str> = rotorid_cli::experiments::variants()
        .iter()
        .map(|v| v.name)
        .collect();
    assert_eq!(names, expected);
    // Table 4's columns.
    assert_eq!(&names[..2], ["paper fuzzy", "paper plain"]);
    // The product runs the models a user may fly and the baselines, never the studies'
    // ablations (`rotorid-lab identify` runs those): not in metrics.json, not in the printed
    // tables, no params file.
    for ablation in ABLATIONS {
        assert!(!names.contains(&ablation), "{ablation} in metrics.json");
        assert!(!stdout.contains(ablation), "{ablation} printed:\n{stdout}");
        let file = format!("params-{}.json", ablation.replace(' ', "-"));
        assert!(!out.join(&file).exists(), "{file} written");
    }
    for candidate in rotorid_cli::verdict::CANDIDATES {
        assert!(names.contains(&candidate), "{candidate} missing");
    }
    // f32 against f64 for the extended structures is part of every report.
    let precision = metrics["precision"].as_array().expect("precision");
    assert_eq!(precision.len(), 2);
    for p in precision {
        let max = p["max_relative"].as_f64().expect("max_relative");
        assert!(max.is_finite() && max >= 0.0, "{max}");
    }
    for v in variants {
        for key in ["hold_one_step", "one_step", "one_step_adapting", "free_run"] {
            let arr = v[key].as_array().expect(key);
            assert_eq!(arr.len(), 6);
            for x in arr {
                let x = x.as_f64().expect("number");
                assert!(x.is_finite() && x > 0.0, "{key}: {x}");
            }
        }
        assert_eq!(v["training"]["samples"], 600);
        assert_eq!(v["training"]["updates"], 599);
        // Every variant's one step through its observer, whose gain per state is one of the
        // search's candidates 0.1 … 1.0, found on the training log.
        let observed = v["one_step_observed"]
            .as_array()
            .expect("one_step_observed");
        assert!(observed
            .iter()
            .all(|x| x.as_f64().is_some_and(|x| x.is_finite() && x > 0.0)));
        let gain: Vec<f64> = v["observer_gain"]
            .as_array()
            .expect("observer_gain")
            .iter()
            .map(|k| k.as_f64().expect("gain"))
            .collect();
        assert_eq!(gain.len(), 6);
        for k in &gain {
            let tenths = k * 10.0;
            assert!(
                (1.0..=10.0).contains(&tenths) && (tenths - tenths.round()).abs() < 1e-5,
                "{gain:?}"
            );
        }
    }
    // Table 4's improvement is computed from the two columns.
    let t = &metrics["table4"];
    let (f, p, i) = (
        t["fuzzy"][3].as_f64().unwrap(),
        t["plain"][3].as_f64().unwrap(),
        t["improvement"][3].as_f64().unwrap(),
    );
    assert!((i - 100.0 * (p - f) / p).abs() < 1e-9);
    for fig in [
        "fig2_velocity.png",
        "fig3_rates.png",
        "fig4_velocity_error.png",
        "fig5_rate_error.png",
        "fig6_free_run.png",
    ] {
        let bytes = std::fs::read(out.join(fig)).expect(fig);
        assert!(bytes.starts_with(b"\x89PNG"), "{fig}");
    }

    // Warm start from the exported parameters: the same training data again changes the
    // fuzzy model's predictions (it starts from θ instead of 0).
    let params = out.join("params-paper-fuzzy.json");
    let exported: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&params).expect("params")).expect("json");
    assert_eq!(exported.as_array().map(Vec::len), Some(4));
    let out2 = dir.join("out2");
    let o = run(bin()
        .args(["identify", "--no-plots", "--train"])
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(&out2)
        .arg("--warm-start")
        .arg(&params));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let m2: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out2.join("metrics.json")).expect("metrics"))
            .expect("json");
    assert_eq!(m2["variants"][0]["training"]["samples"], 600);
    assert_ne!(
        m2["variants"][0]["one_step"],
        metrics["variants"][0]["one_step"]
    );
    assert_eq!(
        m2["variants"][1]["one_step"],
        metrics["variants"][1]["one_step"]
    );

    // The free runs' parameters are compensated for the gyro noise estimated from the
    // training log (`--gyro-noise auto`, the default); `none` free-runs the least-squares
    // parameters, which is what the compensated run reports beside its own. One step is the
    // least-squares parameters' either way.
    let sigma = metrics["gyro_noise_deg_s"].as_array().expect("gyro noise");
    assert_eq!(sigma.len(), 3);
    assert!(
        sigma
            .iter()
            .all(|s| s.as_f64().is_some_and(|s| s > 0.0 && s < 5.0)),
        "{sigma:?}"
    );
    let flight = variants
        .iter()
        .find(|v| v["name"] == "flight")
        .expect("flight");
    let [compensated, refused] =
        [0, 1].map(|i| flight["compensated_rules"][i].as_u64().expect("count"));
    assert_eq!(compensated + refused, 9, "three rate models of three rules");
    assert!(compensated > 0, "{flight}");
    // Without compensation and with the observer's gain 1 on every state
    // (`--observer-gain 1`), every variant's observer predicts from the measured state with
    // the least-squares parameters: its one step is the frozen one step, to the last bit.
    let m_none = identify_metrics(
        &train,
        &verify,
        &dir.join("out-none"),
        &["--gyro-noise", "none", "--observer-gain", "1"],
    );
    assert!(m_none["gyro_noise_deg_s"].is_null());
    for v in m_none["variants"].as_array().expect("variants") {
        assert_eq!(v["observer_gain"], serde_json::json!([1.0f32; 6].to_vec()));
        assert_eq!(v["one_step_observed"], v["one_step"], "{}", v["name"]);
    }
    for bad in ["1.5", "-0.1", "0.5,0.5", "x"] {
        let o = run(bin()
            .args(["identify", &format!("--observer-gain={bad}"), "--train"])
            .arg(&train)
            .arg("--verify")
            .arg(&verify));
        assert!(!o.status.success());
        assert!(
            text(&o.stderr).contains("observer gain"),
            "{}",
            text(&o.stderr)
        );
    }
    // `--gyro-compensation full` removes the second-order term's noise too where the data
    // allow it (its share of the pair's information below ½, a stable rate), and the damping
    // term's alone elsewhere: on this 12 s flight nowhere, so its free run is the default's to
    // the bit. One step is the least-squares parameters' either way. (core's
    // errors_in_variables tests show the pair's compensation; docs/full-compensation.md its
    // effect over ten seed pairs.)
    assert_eq!(metrics["gyro_compensation"], "damping");
    let m_full = identify_metrics(
        &train,
        &verify,
        &dir.join("out-full"),
        &["--gyro-compensation", "full"],
    );
    assert_eq!(m_full["gyro_compensation"], "full");
    let flight_full = &m_full["variants"][names.iter().position(|n| *n == "flight").unwrap()];
    assert_eq!(
        flight_full["compensated_rules"],
        flight["compensated_rules"]
    );
    assert_eq!(flight_full["one_step"], flight["one_step"]);
    assert_eq!(flight_full["free_run"], flight["free_run"]);
    let flight_none = &m_none["variants"][names.iter().position(|n| *n == "flight").unwrap()];
    assert_eq!(flight_none["free_run"], flight["free_run_least_squares"]);
    assert_ne!(flight_none["free_run"], flight["free_run"]);
    assert_eq!(flight_none["one_step"], flight["one_step"]);
    assert!(flight_none.get("free_run_least_squares").is_none());
    // `--free-run-velocity measured`: the rates run free on the measured velocity. The
    // velocities then have no free-run error; one step is unchanged; extended plain's rate
    // models read no speed, so their free runs are the same bits; the flight default's read
    // it, so its r's is not.
    assert_eq!(metrics["free_run_velocity"], "model");
    let out_measured = dir.join("out-measured");
    let m_measured = identify_metrics(
        &train,
        &verify,
        &out_measured,
        &["--free-run-velocity", "measured"],
    );
    assert_eq!(m_measured["free_run_velocity"], "measured");
    let by_name = |m: &serde_json::Value, name: &str| {
        m["variants"]
            .as_array()
            .and_then(|vs| vs.iter().find(|v| v["name"] == name).cloned())
            .expect(name)
    };
    for name in &names {
        let (model, measured) = (by_name(&metrics, name), by_name(&m_measured, name));
        assert_eq!(measured["one_step"], model["one_step"], "{name}");
        for i in 0..3 {
            assert_eq!(measured["free_run"][i], 0.0, "{name}: velocity {i}");
            assert!(model["free_run"][i].as_f64().is_some_and(|e| e > 0.0));
        }
    }
    let (plain, plain_measured) = (
        by_name(&metrics, "extended plain"),
        by_name(&m_measured, "extended plain"),
    );
    for i in 3..6 {
        assert_eq!(
            plain_measured["free_run"][i], plain["free_run"][i],
            "rate {i}"
        );
    }
    assert_ne!(
        by_name(&m_measured, "flight")["free_run"][4],
        flight["free_run"][4]
    );
    // Its verdict scores the three rates, not the velocities' zero errors (which once left
    // no verdict at all), and says so.
    let v = &m_measured["verdict"];
    let axes: Vec<&str> = v["axes"]
        .as_array()
        .expect("a verdict")
        .iter()
        .filter_map(|a| a["axis"].as_str())
        .collect();
    assert_eq!(axes, ["roll rate p", "pitch rate q", "yaw rate r"], "{v}");
    assert!(
        v["caveats"].as_array().unwrap()[0]
            .as_str()
            .unwrap()
            .contains("only the rates are scored"),
        "{v}"
    );
    for bad in ["1,2", "-0.3", "NaN", "loud"] {
        let o = run(bin()
            .args(["identify", &format!("--gyro-noise={bad}"), "--train"])
            .arg(&train)
            .arg("--verify")
            .arg(&verify));
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            text(&o.stderr).contains("--gyro-noise"),
            "{}",
            text(&o.stderr)
        );
    }

    // A wrong-shaped warm start is an error, not a panic.
    let o = run(bin()
        .args(["identify", "--no-plots", "--train"])
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(&out2)
        .arg("--warm-start")
        .arg(out.join("params-paper-plain.json")));
    assert_eq!(o.status.code(), Some(1));
    // The variant, what failed, then why (the error's causes).
    assert!(
        text(&o.stderr).contains("paper fuzzy: warm start: model velocity: "),
        "{}",
        text(&o.stderr)
    );

    let _ = std::fs::remove_dir_all(&dir);
}

const HEADER: &str = "time_s,u_col,u_ped,u_lon,u_lat,roll_rad,pitch_rad,yaw_rad,v_north_mps,v_east_mps,v_down_mps,p_radps,q_radps,r_radps";

fn rows(n: usize) -> Vec<String> {
    (0..n)
        .map(|k| {
            format!(
                "{},0.5,0.4,0,0.03,0.08,0,0,0.1,0,0,0.01,0.02,0.03",
                k as f64 * 0.02
            )
        })
        .collect()
}

/// Writes `content` as a log and runs `identify` with it as the verification log (the
/// training log is valid); returns stderr after checking the exit code and that the file is
/// named.
fn malformed(dir: &Path, name: &str, content: &str) -> String {
    let good = dir.join("good.csv");
    std::fs::write(&good, format!("{HEADER}\n{}\n", rows(20).join("\n"))).expect("write");
    let bad = dir.join(format!("{name}.csv"));
    std::fs::write(&bad, content).expect("write");
    let o = run(bin()
        .args(["identify", "--no-plots", "--train"])
        .arg(&good)
        .arg("--verify")
        .arg(&bad)
        .arg("--out")
        .arg(dir.join("out")));
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{name}: {err}");
    assert!(!err.contains("panicked"), "{name}: {err}");
    assert!(err.contains(&format!("{name}.csv")), "{name}: {err}");
    err
}

fn with_row(k: usize, row: &str) -> String {
    let mut r = rows(10);
    r[k] = row.to_string();
    format!("{HEADER}\n{}\n", r.join("\n"))
}

#[test]
fn malformed_logs_give_positioned_errors() {
    let dir = tmpdir("bad");

    let e = malformed(&dir, "empty", "");
    assert!(e.contains("empty file"), "{e}");

    let header = HEADER.replace(",q_radps", "");
    let body: Vec<String> = rows(5)
        .iter()
        .map(|r| r.replacen(",0.02,0.03", ",0.03", 1))
        .collect();
    let e = malformed(&dir, "missing", &format!("{header}\n{}\n", body.join("\n")));
    assert!(
        e.contains("line 1") && e.contains("missing column `q_radps`"),
        "{e}"
    );

    let e = malformed(
        &dir,
        "text",
        &with_row(4, "0.08,0.5,0.4,abc,0.03,0.08,0,0,0.1,0,0,0.01,0.02,0.03"),
    );
    assert!(
        e.contains("line 6, column 4 (`u_lon`): not a number: `abc`"),
        "{e}"
    );

    let e = malformed(
        &dir,
        "nan",
        &with_row(2, "0.04,0.5,0.4,0,0.03,0.08,0,0,NaN,0,0,0.01,0.02,0.03"),
    );
    assert!(
        e.contains("line 4, column 9 (`v_north_mps`): not finite"),
        "{e}"
    );

    let e = malformed(
        &dir,
        "backwards",
        &with_row(5, "0.06,0.5,0.4,0,0.03,0.08,0,0,0.1,0,0,0.01,0.02,0.03"),
    );
    assert!(
        e.contains("line 7, column 1 (`time_s`)") && e.contains("does not increase"),
        "{e}"
    );

    let e = malformed(
        &dir,
        "gap",
        &with_row(9, "0.5,0.5,0.4,0,0.03,0.08,0,0,0.1,0,0,0.01,0.02,0.03"),
    );
    assert!(
        e.contains("line 11, column 1 (`time_s`)") && e.contains("gap"),
        "{e}"
    );

    let e = malformed(&dir, "short", &with_row(3, "0.06,0.5,0.4"));
    assert!(e.contains("line 5") && e.contains("column"), "{e}");

    // A rate column in deg/s: by its header, or by its values.
    let e = malformed(
        &dir,
        "degheader",
        &format!(
            "{}\n{}\n",
            HEADER.replace("r_radps", "r_degps"),
            rows(5).join("\n")
        ),
    );
    assert!(
        e.contains("column 14 (`r_degps`)") && e.contains("`r_radps`"),
        "{e}"
    );
    let e = malformed(
        &dir,
        "degvalues",
        &with_row(1, "0.02,0.5,0.4,0,0.03,0.08,0,0,0.1,0,0,0.01,0.02,120"),
    );
    assert!(
        e.contains("line 3, column 14 (`r_radps`)") && e.contains("degrees"),
        "{e}"
    );

    let e = malformed(&dir, "headeronly", &format!("{HEADER}\n"));
    assert!(e.contains("no samples"), "{e}");

    let o = run(bin()
        .args(["identify", "--verify", "x.csv", "--train"])
        .arg(dir.join("nonexistent.csv")));
    assert_eq!(o.status.code(), Some(1));
    // The file, what failed, then the system's reason (the error's source, printed by main).
    let e = text(&o.stderr);
    assert!(e.contains("nonexistent.csv: cannot read: "), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

mod found_as_a_new_user {
    use rotorid_cli::log::{parse_log, rate_unit_ratio, warnings, write_log_to};
    use rotorid_sim::flights::identification_flight_for;

    fn csv(samples: &[rotorid_sim::plant::SensorSample]) -> String {
        let mut v = Vec::new();
        write_log_to(&mut v, samples).unwrap();
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn gentle_rates_in_deg_per_s_are_caught_from_the_attitude() {
        let flight = identification_flight_for(1, 60.0).unwrap();
        let ratio = rate_unit_ratio(&flight).unwrap();
        assert!((0.5..2.0).contains(&ratio), "rad/s: {ratio}");
        assert!(warnings("f.csv", &flight)
            .iter()
            .all(|w| !w.contains("deg/s")));
        // The same flight with rates in deg/s, all still under the 34.9 rad/s range check.
        let mut deg = flight.clone();
        for s in &mut deg {
            s.p = s.p.to_degrees();
            s.q = s.q.to_degrees();
            s.r = s.r.to_degrees();
        }
        // The gentle start of the flight: every rate under 34.9 deg/s, which the range check
        // (34.9 rad/s) cannot tell from rad/s.
        let gentle = deg
            .iter()
            .position(|s| s.p.abs().max(s.q.abs()).max(s.r.abs()) >= 34.9)
            .unwrap_or(deg.len());
        assert!(gentle >= 500, "{gentle}");
        let deg = &deg[..gentle];
        let parsed = parse_log("deg.csv", csv(deg).as_bytes()).unwrap();
        let w = warnings("deg.csv", &parsed);
        assert!(w.iter().any(|w| w.contains("deg/s")), "{w:?}");
    }

    #[test]
    fn extra_fields_and_decimal_commas_are_refused_with_a_hint() {
        let flight = identification_flight_for(1, 0.1).unwrap();
        let text = csv(&flight);
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        lines[2].push_str(",7");
        let e = parse_log("x.csv", lines.join("\n").as_bytes()).unwrap_err();
        assert!(
            e.to_string().contains("has 15 fields, the header has 14"),
            "{e}"
        );
        // A decimal comma: "0.5" written "0,5" splits one field into two.
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        lines[3] = lines[3].replacen('.', ",", 1);
        let e = parse_log("y.csv", lines.join("\n").as_bytes()).unwrap_err();
        assert!(e.to_string().contains("decimal commas"), "{e}");
    }

    #[test]
    fn a_two_row_log_is_flagged_as_too_short() {
        let flight = identification_flight_for(1, 0.04).unwrap();
        assert_eq!(flight.len(), 2);
        assert!(warnings("short.csv", &flight)
            .iter()
            .any(|w| w.contains("only 2 samples")));
    }

    #[test]
    fn quoted_decimal_commas_and_semicolon_exports_get_the_same_advice() {
        let flight = identification_flight_for(1, 0.1).unwrap();
        let text = csv(&flight);
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        // A spreadsheet's quoted field keeps "0,5" in one field.
        let fields: Vec<&str> = lines[2].split(',').collect();
        let quoted = format!("\"{}\"", fields[1].replacen('.', ",", 1));
        lines[2] = [fields[0], &quoted]
            .into_iter()
            .chain(fields[2..].iter().copied())
            .collect::<Vec<_>>()
            .join(",");
        let e = parse_log("q.csv", lines.join("\n").as_bytes()).unwrap_err();
        assert!(
            e.to_string().contains("line 3, column 2 (`u_col`)")
                && e.to_string().contains("decimal comma"),
            "{e}"
        );
        // A `;`-separated export: the header is one field.
        let semi = text.replace(',', ";");
        let e = parse_log("s.csv", semi.as_bytes()).unwrap_err();
        assert!(
            e.to_string().contains("line 1") && e.to_string().contains("';'"),
            "{e}"
        );
    }

    #[test]
    fn gentle_angles_in_degrees_are_caught_from_the_rates() {
        // A gentle roll oscillation (±0.03 rad at 0.5 Hz): in degrees (±1.7) it still passes
        // the radian range check (|φ| ≤ 3.2).
        let mut flight = identification_flight_for(1, 4.0).unwrap();
        let w = std::f64::consts::PI;
        for s in &mut flight {
            (s.roll, s.pitch, s.yaw) = (0.03 * (w * s.t).sin(), 0.0, 0.0);
            (s.p, s.q, s.r) = (0.03 * w * (w * s.t).cos(), 0.0, 0.0);
        }
        assert!(warnings("a.csv", &flight)
            .iter()
            .all(|w| !w.contains("in degrees")));
        let deg: Vec<_> = flight
            .iter()
            .map(|s| rotorid_sim::plant::SensorSample {
                roll: s.roll.to_degrees(),
                ..*s
            })
            .collect();
        assert!(deg.iter().all(|s| s.roll.abs() < 3.2));
        let w = warnings("a.csv", &deg);
        assert!(
            w.iter()
                .any(|w| w.contains("roll_rad, pitch_rad, yaw_rad in degrees")),
            "{w:?}"
        );
    }
}

#[test]
fn identification_duration_beyond_the_sweeps_is_an_error_not_a_silent_clamp() {
    let dir = std::env::temp_dir().join(format!("rotorid-cli-clamp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rotorid"))
        .args([
            "simulate",
            "--kind",
            "identification",
            "--duration",
            "999",
            "-o",
        ])
        .arg(dir.join("x.csv"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("lasts") && err.contains("999"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--plant` picks the airframe for every kind: the flybarless 600 starts at its own trim, and
/// `--plant xcell60` is the default, bit for bit.
/// The collective of a log's first sample (its second column).
fn first_col(log: &str) -> f64 {
    let row = log.lines().nth(1).expect("a sample");
    row.split(',')
        .nth(1)
        .expect("u_col")
        .parse()
        .expect("number")
}

#[test]
fn plant_option_flies_the_chosen_airframe() {
    let dir = tmpdir("plant");
    let fly = |plant: Option<&str>, kind: &str, name: &str| {
        let out = dir.join(name);
        let mut cmd = bin();
        cmd.args(["simulate", "--kind", kind, "--seed", "3"]);
        if kind.starts_with("identification") || kind == "verification" {
            cmd.args(["--duration", "2"]);
        }
        if let Some(p) = plant {
            cmd.args(["--plant", p]);
        }
        let o = run(cmd.arg("-o").arg(&out));
        assert!(o.status.success(), "{}", text(&o.stderr));
        std::fs::read_to_string(&out).expect("log")
    };
    let fbl =
        rotorid_sim::plant::trim_hover(&rotorid_sim::plant::Helicopter::flybarless_600(), 0.0)
            .expect("trims");
    for kind in ["identification", "verification", "envelope-verification"] {
        let default = fly(None, kind, &format!("{kind}-default.csv"));
        let xcell = fly(Some("xcell60"), kind, &format!("{kind}-xcell.csv"));
        assert_eq!(default, xcell, "{kind}");
        let second = fly(Some("flybarless600"), kind, &format!("{kind}-fbl.csv"));
        assert_eq!(first_col(&second), fbl.sticks.col, "{kind}");
        assert!(
            (first_col(&default) - fbl.sticks.col).abs() > 0.05,
            "{kind}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--noise-scale K` multiplies the measurement noise and nothing else: with the same seed the
/// flight is the same, the noise draws are the same, so each logged value's departure from the
/// noise-free (K = 0, turbulence kept) log is K times the default's; K = 1 is the default, bit
/// for bit; a negative or non-finite K is refused.
#[test]
fn noise_scale_multiplies_the_measurement_noise_only() {
    let dir = tmpdir("noise-scale");
    let fly = |scale: Option<&str>, name: &str| -> (String, Vec<Vec<f64>>) {
        let out = dir.join(name);
        let mut cmd = bin();
        cmd.args(["simulate", "--kind", "verification", "--seed", "3"]);
        cmd.args(["--duration", "2"]);
        if let Some(k) = scale {
            cmd.args(["--noise-scale", k]);
        }
        let o = run(cmd.arg("-o").arg(&out));
        assert!(o.status.success(), "{}", text(&o.stderr));
        let log = std::fs::read_to_string(&out).expect("log");
        let values = log
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
            .collect();
        (log, values)
    };
    let (one_log, one) = fly(Some("1"), "one.csv");
    let (default_log, _) = fly(None, "default.csv");
    assert_eq!(one_log, default_log, "--noise-scale 1 is the default");
    let (_, zero) = fly(Some("0"), "zero.csv");
    let (_, three) = fly(Some("3"), "three.csv");
    let mut moved = 0;
    for ((z, o), t) in zero.iter().zip(&one).zip(&three) {
        // Columns 5.. are the states (the controls, 1..=4, are what the pilot commanded).
        for c in 5..z.len() {
            let (d1, d3) = (o[c] - z[c], t[c] - z[c]);
            assert!((d3 - 3.0 * d1).abs() <= 1e-12, "column {c}: {d1} vs {d3}");
            moved += usize::from(d1 != 0.0);
        }
    }
    assert!(moved > 100, "the noise changed the logged states");
    for bad in ["-1", "NaN", "inf"] {
        let o = run(bin()
            .args([
                "simulate",
                "--kind",
                "verification",
                "--noise-scale",
                bad,
                "-o",
            ])
            .arg(dir.join("bad.csv")));
        assert!(!o.status.success(), "{bad}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--plant-variation SEED` flies another helicopter of the plant's kind
/// (`Helicopter::varied`): the same seed gives the same log, another seed or no variation
/// another one, and the log starts at the varied plant's own hover trim.
#[test]
fn plant_variation_flies_another_helicopter_reproducibly() {
    use rotorid_sim::plant::{trim_hover, Helicopter};
    let dir = tmpdir("variation");
    let fly = |plant: &str, variation: Option<&str>, name: &str| {
        let out = dir.join(name);
        let mut cmd = bin();
        cmd.args(["simulate", "--kind", "verification", "--seed", "3"]);
        cmd.args(["--duration", "2", "--plant", plant]);
        if let Some(v) = variation {
            cmd.args(["--plant-variation", v]);
        }
        let o = run(cmd.arg("-o").arg(&out));
        assert!(o.status.success(), "{}", text(&o.stderr));
        std::fs::read_to_string(&out).expect("log")
    };
    for (plant, params) in [
        ("xcell60", Helicopter::default()),
        ("flybarless600", Helicopter::flybarless_600()),
    ] {
        let five = fly(plant, Some("5"), &format!("{plant}-5.csv"));
        assert_eq!(five, fly(plant, Some("5"), &format!("{plant}-5b.csv")));
        assert_ne!(five, fly(plant, Some("6"), &format!("{plant}-6.csv")));
        assert_ne!(five, fly(plant, None, &format!("{plant}.csv")));
        let trim = trim_hover(&params.varied(5), 0.0).expect("variation 5 hovers");
        assert_eq!(first_col(&five), trim.sticks.col, "{plant}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The premise candidates (on by default): on the flybarless helicopter's hover identification
/// flight (seed 2, a pair of docs/ab-premises.md) `flight selected` moves its translational
/// model to the vertical speed, which the verdict names and `params-flight-selected.json`
/// carries (the sets on the premise's second variable, `[|v_h| up 0]`); with
/// `--no-premise-candidates` every model stays on the flight default's speed, and the other
/// variants are the same bits either way.
#[test]
fn premise_candidates_move_a_models_rules_to_another_speed() {
    let dir = tmpdir("premise-candidates");
    let plant = ["--plant", "flybarless600"];
    let train = simulate_with(&dir, "identification", "2", "255", &plant);
    let verify = simulate_with(&dir, "verification", "102", "20", &plant);
    let with = identify_metrics(&train, &verify, &dir.join("with"), &[]);
    let without = identify_metrics(
        &train,
        &verify,
        &dir.join("without"),
        &["--no-premise-candidates"],
    );
    let moved = |m: &serde_json::Value| {
        m["verdict"]["terms_off"]
            .as_array()
            .expect("terms_off")
            .iter()
            .filter_map(|t| t.as_str())
            .filter(|t| t.contains(": rules on the "))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert!(
        moved(&with).contains(&"velocity: rules on the vertical speed".to_string()),
        "{:?}",
        moved(&with)
    );
    assert!(moved(&without).is_empty());
    let params: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("with").join("params-flight-selected.json")).unwrap(),
    )
    .unwrap();
    let velocity = &params[0];
    assert_eq!(velocity["model"], "velocity");
    let variables = velocity["premise"]["variables"]
        .as_array()
        .expect("premise");
    assert!(variables[0].as_array().unwrap().is_empty());
    assert_eq!(variables[1].as_array().unwrap().len(), 3);
    let names: Vec<_> = with["variants"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["name"].as_str().unwrap().to_string())
        .collect();
    for (i, name) in names.iter().enumerate() {
        if name != "flight selected" {
            assert_eq!(with["variants"][i], without["variants"][i], "{name}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
