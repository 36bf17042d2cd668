//! `rotorid simulate --pilot-gain-scale`: the default is today's flight bit for bit, another
//! factor flies another closed loop, and a factor out of range is refused with the range.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-pilot-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// `rotorid simulate --kind identification --seed 3 --duration 100` with `extra` options.
fn fly(dir: &Path, name: &str, extra: &[&str]) -> (Output, PathBuf) {
    let out = dir.join(name);
    let o = Command::new(env!("CARGO_BIN_EXE_rotorid"))
        .args([
            "simulate",
            "--kind",
            "identification",
            "--seed",
            "3",
            "--duration",
            "100",
        ])
        .args(extra)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    (o, out)
}

fn csv(o: &Output, path: &Path) -> Vec<u8> {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(path).expect("log written")
}

#[test]
fn scale_one_is_the_default_flight_and_other_scales_fly_another_loop() {
    let dir = tmpdir("scale");
    let (o, p) = fly(&dir, "default.csv", &[]);
    let default = csv(&o, &p);
    let (o, p) = fly(&dir, "one.csv", &["--pilot-gain-scale", "1"]);
    assert_eq!(
        csv(&o, &p),
        default,
        "--pilot-gain-scale 1 changed the flight"
    );
    let (o, p) = fly(&dir, "half.csv", &["--pilot-gain-scale", "0.5"]);
    let half = csv(&o, &p);
    // Same sweeps and samples, other sticks: the pilot's corrections are half as large.
    let lines = |b: &[u8]| b.iter().filter(|&&c| c == b'\n').count();
    assert_eq!(lines(&half), lines(&default));
    assert_ne!(half, default);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_scale_out_of_range_is_refused_with_the_range() {
    let dir = tmpdir("range");
    for bad in ["0", "0.01", "11", "NaN", "inf"] {
        let (o, p) = fly(&dir, "bad.csv", &["--pilot-gain-scale", bad]);
        assert!(!o.status.success(), "{bad} accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--pilot-gain-scale must be in [0.05, 10]"),
            "{err}"
        );
        assert!(!p.exists(), "{bad}: a log was written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
