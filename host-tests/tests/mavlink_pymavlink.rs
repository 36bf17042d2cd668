//! An independent MAVLink client reads rotorid's telemetry: the stream of a real identification
//! run (simulated flight, onboard identifier pair, host build) is decoded by pymavlink, with a
//! dialect module its own `mavgen` makes from `core/mavlink/dialect/rotorid.xml`, and every
//! field is compared with the Rust values (floats bit for bit) by `tests/mavlink_decode.py`.
//!
//! Needs python3 with pymavlink (`scripts/setup.sh` installs it into `.venv/`; `ROTORID_PYTHON`
//! names another interpreter). Without it the test says so and passes, except under CI (`CI`
//! set), where it fails.

use std::path::Path;

use host_tests::mavlink::{
    check_with_pymavlink, identification_stream, learn_with_one_rejection, python_with_pymavlink,
    PymavlinkError,
};
use host_tests::onboard::simulated_flight;
use rotorid_cli::error_chain::Chain;

#[test]
fn pymavlink_decodes_an_identification_run_bit_for_bit() {
    let Some(py) = python_with_pymavlink() else {
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
    let stream = identification_stream(&learn_with_one_rejection(&flight), true);
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
    match check_with_pymavlink(&py, &stream.bytes, &stream.expected, &work) {
        Ok(summary) => eprintln!("{} samples: {summary}", flight.len()),
        Err(e) => panic!("pymavlink check failed:\n{}", Chain(&e)),
    }
}

/// Without pymavlink too: what cannot run says what and why, as typed errors.
#[test]
fn a_check_that_cannot_run_says_what_failed() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mavlink-pymavlink-errors");
    std::fs::create_dir_all(&dir).unwrap();
    // A work directory below a regular file cannot be created.
    let file = dir.join("a-file");
    std::fs::write(&file, b"").unwrap();
    let under_file = file.join("work");
    match check_with_pymavlink(Path::new("python3"), &[], &[], &under_file) {
        Err(PymavlinkError::Write { path, .. }) => assert_eq!(path, under_file),
        other => panic!("{other:?}"),
    }
    let missing = dir.join("no-such-python");
    match check_with_pymavlink(&missing, &[], &[], &dir) {
        Err(e @ PymavlinkError::Run { .. }) => {
            assert!(std::error::Error::source(&e).is_some(), "{e:?}");
            assert!(Chain(&e)
                .to_string()
                .starts_with(&format!("{}: cannot run: ", missing.display())));
        }
        other => panic!("{other:?}"),
    }
    // An interpreter that runs and fails: its output is the error.
    match check_with_pymavlink(Path::new("false"), &[], &[], &dir) {
        Err(PymavlinkError::Script { .. }) => {}
        other => panic!("{other:?}"),
    }
}
