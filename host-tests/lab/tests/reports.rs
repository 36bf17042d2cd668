//! `rotorid-lab` end to end on a short simulated flight: its `identify` runs the product's
//! catalogue and then the ablations, the product's variants scoring exactly as in
//! `rotorid identify` (the library's [`rotorid_cli::identify::identify`]); `report` and
//! `robustness-report` write their documents from such runs (moved here from the product's
//! tests with the generators).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rotorid_cli::simulate::{simulate, FlightKind, SimulateArgs};
use rotorid_sim::plant::Airframe;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorid-lab"))
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-lab-{}-{name}", std::process::id()));
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

/// A simulated X-Cell 60 flight (what `rotorid simulate` writes), as a CSV log in `dir`.
fn flight(dir: &Path, kind: FlightKind, seed: u64, duration: f64) -> PathBuf {
    let samples = simulate(&SimulateArgs {
        kind,
        seed,
        duration: Some(duration),
        clean: false,
        noise_scale: 1.0,
        airframe: Airframe::XCell60,
        variation: None,
        cyclic_power: 1.0,
        linear: false,
        no_jitter: false,
    })
    .expect("simulate");
    let path = dir.join(format!("{kind:?}-{seed}.csv"));
    rotorid_cli::log::write_log(&path, &samples).expect("write log");
    path
}

/// `rotorid-lab identify --no-plots --window 1` with `extra` options; its metrics.json.
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

#[test]
fn lab_identify_adds_the_ablations_and_reports_are_written_from_its_runs() {
    let dir = tmpdir("reports");
    // 12 s of the lon sweep and 8 s of verification, as the product's end-to-end test.
    let train = flight(&dir, FlightKind::Identification, 1, 12.0);
    let verify = flight(&dir, FlightKind::Verification, 2, 8.0);
    let out = dir.join("out");
    let metrics = identify_metrics(&train, &verify, &out, &[]);

    // The full catalogue: the product's variants in the product's order, then the ablations.
    let names: Vec<&str> = metrics["variants"]
        .as_array()
        .expect("variants")
        .iter()
        .filter_map(|v| v["name"].as_str())
        .collect();
    let product: Vec<&str> = rotorid_cli::experiments::variants()
        .iter()
        .map(|v| v.name)
        .collect();
    let ablations: Vec<&str> = rotorid_lab::ablations::ablations()
        .iter()
        .map(|v| v.name)
        .collect();
    assert!(!ablations.is_empty());
    assert_eq!(names, [product.clone(), ablations.clone()].concat());
    for a in &ablations {
        let file = format!("params-{}.json", a.replace(' ', "-"));
        assert!(out.join(&file).exists(), "{file} missing");
    }

    // The product's identification of the same logs (what `rotorid identify` and the Python
    // package call): no ablation, and each of its variants, the verdict, the derivatives and
    // everything else the same values as in the lab's run (the ablations are evaluated after
    // the product's variants and read none of their results).
    let mut args = rotorid_cli::identify::IdentifyArgs::new(vec![train.clone()]);
    args.verify = Some(verify.clone());
    args.window = 1.0;
    let mut collect = rotorid_cli::identify::Collect::default();
    let outcome = rotorid_cli::identify::identify(&args, &mut collect).expect("product identify");
    let product_metrics: serde_json::Value =
        serde_json::from_str(&outcome.metrics_json().expect("json")).expect("json");
    let product_variants = product_metrics["variants"].as_array().expect("variants");
    assert_eq!(product_variants.len(), product.len());
    for v in product_variants {
        let name = v["name"].as_str().expect("name");
        assert!(!ablations.contains(&name), "{name}");
        let lab = metrics["variants"]
            .as_array()
            .and_then(|vs| vs.iter().find(|l| l["name"] == name))
            .expect(name);
        assert_eq!(lab, v, "{name}");
    }
    for (key, value) in product_metrics.as_object().expect("object") {
        if key != "variants" {
            assert_eq!(&metrics[key], value, "{key}");
        }
    }

    let out_measured = dir.join("out-measured");
    let m_measured = identify_metrics(
        &train,
        &verify,
        &out_measured,
        &["--free-run-velocity", "measured"],
    );
    let by_name = |m: &serde_json::Value, name: &str| {
        m["variants"]
            .as_array()
            .and_then(|vs| vs.iter().find(|v| v["name"] == name).cloned())
            .expect(name)
    };

    // `report` of this run's metrics as both the realistic and the clean run, with `extra`.
    let report = |extra: &[std::ffi::OsString]| {
        run(bin()
            .args(["report", "--realistic"])
            .arg(out.join("metrics.json"))
            .arg("--clean")
            .arg(out.join("metrics.json"))
            .args(extra)
            .arg("-o")
            .arg(dir.join("results.md")))
    };

    // `report` names the file it could not read, then the system's reason.
    let lone = dir.join("lone");
    std::fs::create_dir_all(&lone).expect("dir");
    std::fs::copy(out.join("metrics.json"), lone.join("metrics.json")).expect("copy");
    let o = report(&["--envelope".into(), lone.join("metrics.json").into()]);
    assert_eq!(o.status.code(), Some(1));
    let missing = lone.join("params-flight.json");
    assert!(
        text(&o.stderr).contains(&format!("{}: cannot read: ", missing.display())),
        "{}",
        text(&o.stderr)
    );

    // `--condition GROUP|LABEL|METRICS` adds a row of the flight default's ratios to its
    // group's table; a value without three parts is refused before anything is read.
    let condition = format!("Same pair|once more|{}", out.join("metrics.json").display());
    let o = report(&["--condition".into(), condition.into()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let md = std::fs::read_to_string(dir.join("results.md")).expect("results.md");
    let row = md
        .lines()
        .find(|l| l.starts_with("| once more | "))
        .unwrap_or_else(|| panic!("no condition row in:\n{md}"));
    assert!(md.contains("#### Same pair\n"), "{md}");
    // Eleven cells (label, six states, one step, two drags, q's speed stability), the drags
    // and M_u read from params-flight.json and params-extended-plain.json.
    assert_eq!(row.matches(" | ").count(), 10, "{row}");
    assert!(!row.contains("–"), "{row}");
    let o = report(&["--condition".into(), "two|parts".into()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("expected GROUP|LABEL|METRICS"),
        "{}",
        text(&o.stderr)
    );

    // `robustness-report --run FAMILY|LABEL|HOVER|ENVELOPE`: one row per plant in its family's
    // table, each criterion marked, and the family's count of plants meeting each.
    let m = out.join("metrics.json").display().to_string();
    let robustness = |runs: &[String]| {
        let mut cmd = bin();
        cmd.arg("robustness-report");
        for r in runs {
            cmd.args(["--run", r]);
        }
        run(cmd
            .args(["--how", "by hand", "-o"])
            .arg(dir.join("robustness.md")))
    };
    let o = robustness(&[
        format!("Fam|plant A|{m}|{m}"),
        format!("Fam|plant B|{m}|{m}"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let md = std::fs::read_to_string(dir.join("robustness.md")).expect("robustness.md");
    assert!(md.contains("### Fam\n"), "{md}");
    assert!(md.contains("by hand"), "{md}");
    // The criteria tables come first; the second-order term's section follows them.
    let (criteria, second_order) = md
        .split_once("## The hover one-step miss on q and the second-order term")
        .unwrap_or_else(|| panic!("no second-order section in:\n{md}"));
    assert!(second_order.contains("### Fam: with / without the second-order term"));
    // Between them, the model the verdict chose on each plant: the same on two equal plants.
    let (criteria, choice) = criteria
        .split_once("## The model the verdict chooses")
        .unwrap_or_else(|| panic!("no section on the verdict's choice in:\n{md}"));
    let chosen: Vec<&str> = choice
        .lines()
        .filter(|l| l.starts_with("| plant "))
        .collect();
    assert_eq!(chosen.len(), 3, "{choice}");
    assert_eq!(
        chosen[1].replace("plant A", "plant B"),
        chosen[2],
        "{choice}"
    );
    assert!(
        choice.contains("Of 4 runs (hover and envelope)"),
        "{choice}"
    );
    let pairs: Vec<&str> = second_order
        .lines()
        .filter(|l| l.starts_with("| plant "))
        .collect();
    assert_eq!(pairs.len(), 3, "{second_order}");
    // Each cell pairs the flight default's ratio with the first-order variant's.
    assert_eq!(pairs[1].matches(" / ").count(), 7, "{}", pairs[1]);
    assert!(second_order.contains(
        "Of 2 plants: hover one step from the measured state on q within 3 % with the term: "
    ));
    let rows: Vec<&str> = criteria
        .lines()
        .filter(|l| l.starts_with("| plant "))
        .collect();
    // The header row starts with "| plant |" too.
    assert_eq!(rows.len(), 3, "{md}");
    assert_eq!(rows[1].replace("plant A", "plant B"), rows[2], "{md}");
    assert!(md.contains("Of 2 plants: "), "{md}");
    // Two equal plants: both meet every criterion or neither does.
    let all = if rows[1].contains('❌') { 0 } else { 2 };
    assert!(md.contains(&format!("every criterion: {all}.")), "{md}");
    let o = robustness(&["Fam|plant A|only-hover".into()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("expected FAMILY|LABEL|HOVER|ENVELOPE"),
        "{}",
        text(&o.stderr)
    );
    assert!(
        !md.contains("## The envelope miss on r"),
        "no measured runs given"
    );
    // With a fifth part (the envelope pair's run on the measured velocity): r's ratio as flown
    // and on the measured velocity, per plant.
    let mv = out_measured.join("metrics.json").display().to_string();
    let o = robustness(&[format!("Fam|plant A|{m}|{m}|{mv}")]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let md = std::fs::read_to_string(dir.join("robustness.md")).expect("robustness.md");
    let (_, section) = md
        .split_once("## The envelope miss on r and the velocity model")
        .unwrap_or_else(|| panic!("no measured-velocity section in:\n{md}"));
    let r_ratio = |m: &serde_json::Value| {
        let r = |name| by_name(m, name)["free_run"][4].as_f64().expect("r");
        r("flight") / r("extended plain")
    };
    let row = section
        .lines()
        .find(|l| l.starts_with("| plant A |"))
        .unwrap_or_else(|| panic!("no row in:\n{section}"));
    let cells: Vec<f64> = row
        .split('|')
        .filter_map(|c| c.split_whitespace().next()?.parse().ok())
        .collect();
    let expected = [r_ratio(&metrics), r_ratio(&m_measured)];
    assert_eq!(cells.len(), 2, "{row}");
    for (cell, e) in cells.iter().zip(expected) {
        assert!((cell - e).abs() <= 0.005, "{row}: {expected:?}");
    }
    let o = robustness(&[format!("Fam|plant A|{m}|{m}|{mv}|extra")]);
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}
