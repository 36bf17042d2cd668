//! An independent MAVLink client reads rotorid's telemetry: the stream of a real identification
//! run (simulated flight, onboard identifier pair) is decoded by pymavlink, with a dialect module
//! its own `mavgen` makes from `core/mavlink/dialect/rotorid.xml`, and every field is compared
//! with the Rust values (floats bit for bit) by `tests/mavlink_decode.py`.
//!
//! Needs python3 with pymavlink (`scripts/setup.sh` installs it into `.venv/`; `ROTORID_PYTHON`
//! names another interpreter). Without it the test says so and passes, except under CI (`CI`
//! set), where it fails.

use std::path::{Path, PathBuf};
use std::process::Command;

use host_tests::mavlink::identification_stream;
use host_tests::onboard::simulated_flight;

fn python(root: &Path) -> Option<PathBuf> {
    let candidates = [
        std::env::var_os("ROTORID_PYTHON").map(PathBuf::from),
        Some(root.join(".venv/bin/python3")),
        Some(PathBuf::from("python3")),
    ];
    candidates.into_iter().flatten().find(|p| {
        Command::new(p)
            .args(["-c", "import pymavlink.generator.mavgen"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

#[test]
fn pymavlink_decodes_an_identification_run_bit_for_bit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let Some(py) = python(&root) else {
        assert!(
            std::env::var_os("CI").is_none(),
            "python3 with pymavlink is required under CI (scripts/setup.sh installs it)"
        );
        eprintln!(
            "SKIPPED: no python3 with pymavlink (run scripts/setup.sh or set ROTORID_PYTHON)"
        );
        return;
    };
    let flight = simulated_flight(5, 30.0).expect("flight");
    let stream = identification_stream(&flight);
    let types: Vec<&str> = stream
        .expected
        .iter()
        .filter_map(|e| e["type"].as_str())
        .collect();
    for t in [
        "HEARTBEAT",
        "DEBUG_FLOAT_ARRAY",
        "NAMED_VALUE_FLOAT",
        "STATUSTEXT",
    ] {
        assert!(types.contains(&t), "the run has no {t}");
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mavlink-pymavlink");
    std::fs::create_dir_all(&work).expect("work dir");
    let bin = work.join("stream.bin");
    let json = work.join("expected.json");
    std::fs::write(&bin, &stream.bytes).expect("write stream");
    std::fs::write(&json, serde_json::to_vec(&stream.expected).expect("json")).expect("write");
    let out = Command::new(&py)
        .arg(root.join("host-tests/tests/mavlink_decode.py"))
        .arg(root.join("core/mavlink/dialect/rotorid.xml"))
        .args([&bin, &json, &work])
        .output()
        .expect("python runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "pymavlink check failed:\n{stdout}\n{stderr}"
    );
    eprintln!("{} samples: {}", flight.len(), stdout.trim());
}
