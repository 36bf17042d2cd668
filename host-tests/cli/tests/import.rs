//! Log import (issue 12 part 3): a real PX4 log (`data/logs/esc_status_log.ulg`, MIT, see
//! `data/logs/README.md`), generated helicopter ULog and DataFlash logs (round trip through
//! the importers and `identify`), and truncated, garbage and incomplete logs giving errors that
//! name the file (never a panic).

use std::path::{Path, PathBuf};
use std::process::Command;

use rotorid_cli::import::{self, synth, ImportError, LogFormat};
use rotorid_sim::flights;
use rotorid_sim::plant::SensorSample;

fn real_log() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs/esc_status_log.ulg")
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// `seconds` of the clean identification flight, on an exact 20 ms grid.
fn heli_flight(seconds: f64) -> Vec<SensorSample> {
    let config = rotorid_sim::plant::FlightConfig {
        seed: 3,
        ..Default::default()
    };
    let mut s = flights::identification_flight_with(&config, seconds).expect("simulates");
    s.iter_mut()
        .enumerate()
        .for_each(|(k, x)| x.t = k as f64 * 0.02);
    s
}

/// The real log's position and controls are logged at about 10 Hz: it is identified at
/// 10 Hz, with a warning that says which channels are slow and which PX4 setting logs faster.
#[test]
fn real_px4_log_is_identified_at_its_own_rate() {
    let imported = import::import(&real_log()).expect("imports");
    assert_eq!(imported.rate_hz, 10.0);
    let rates = imported.native_rates.expect("native rates");
    assert!(
        rates.velocity.is_some_and(|r| (9.0..11.0).contains(&r)),
        "{rates:?}"
    );
    assert!(rates.attitude.is_some_and(|r| r > 20.0), "{rates:?}");
    assert!(
        imported
            .warnings
            .iter()
            .any(|w| w.contains("velocity 9.") && w.contains("SDLOG_PROFILE")),
        "{:?}",
        imported.warnings
    );
    for seg in &imported.segments {
        for w in seg.windows(2) {
            assert!(((w[1].t - w[0].t) - 0.1).abs() < 1.5e-6);
        }
    }
}

#[test]
fn real_px4_log_maps_resamples_and_splits() {
    let options = import::ImportOptions {
        rate_hz: Some(50.0),
        ..Default::default()
    };
    let imported = import::import_with(&real_log(), &options).expect("imports");
    assert_eq!(imported.format, LogFormat::ULog);
    // The log has holes: several segments, reported in a note.
    assert!(imported.segments.len() > 1, "{}", imported.segments.len());
    assert!(imported.notes.iter().any(|n| n.contains("split at gaps")));
    for seg in &imported.segments {
        // On the 50 Hz grid, to the microsecond.
        for w in seg.windows(2) {
            assert!(
                ((w[1].t - w[0].t) - 0.02).abs() < 1.5e-6,
                "{}",
                w[1].t - w[0].t
            );
        }
    }
    let longest = imported.longest().expect("a segment");
    assert!(longest.len() >= 500, "{}", longest.len());
    // Frames and units: the logged FRD rates (rad/s) agree with the attitude's rate of change.
    let k = rotorid_cli::log::rate_unit_ratio(longest).expect("the flight moves enough to judge");
    assert!((0.5..2.0).contains(&k), "ratio {k}");
    // Controls of a multicopter's actuator_controls_0: thrust in [0, 1], torques in [−1, 1].
    assert!(longest.iter().all(|s| (0.0..=1.0).contains(&s.sticks.col)));
}

#[test]
fn generated_heli_logs_round_trip() {
    let flight = heli_flight(20.0);
    let dir = tmpdir("roundtrip");
    for (name, bytes, format) in [
        ("heli.ulg", synth::ulog(&flight, true), LogFormat::ULog),
        (
            "heli.bin",
            synth::dataflash(&flight, true),
            LogFormat::DataFlash,
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("write");
        let imported = import::import(&path).expect(name);
        assert_eq!(imported.format, format);
        assert_eq!(imported.segments.len(), 1, "{name}");
        let seg = &imported.segments[0];
        assert_eq!(seg.len(), flight.len(), "{name}");
        for (a, b) in seg.iter().zip(&flight) {
            // Time stamps after the writers' 1 s boot; values through f32 (and, for ULog, the
            // attitude through a quaternion, for DataFlash through degrees).
            assert!((a.t - 1.0 - b.t).abs() < 1e-9, "{name}: t {} {}", a.t, b.t);
            let close = |x: f64, y: f64, what: &str| {
                assert!(
                    (x - y).abs() <= 2e-5 * y.abs().max(1.0),
                    "{name} t={}: {what} {x} vs {y}",
                    b.t
                );
            };
            close(a.roll, b.roll, "roll");
            close(a.pitch, b.pitch, "pitch");
            close(a.yaw, b.yaw, "yaw");
            close(a.v_north, b.v_north, "v_n");
            close(a.v_east, b.v_east, "v_e");
            close(a.v_down, b.v_down, "v_d");
            close(a.p, b.p, "p");
            close(a.q, b.q, "q");
            close(a.r, b.r, "r");
            close(a.sticks.col, b.sticks.col, "col");
            close(a.sticks.ped, b.sticks.ped, "ped");
            close(a.sticks.lon, b.sticks.lon, "lon");
            close(a.sticks.lat, b.sticks.lat, "lat");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A CSV log at 100 Hz (the 50 Hz flight with a sample halfway between each two: states
/// interpolated, controls held) is put back on the 50 Hz grid, with a note: the states as
/// they were, each control the mean of the two rows logged since the previous grid time
/// (the row halfway, which holds the previous command, and the row at the grid time); the
/// 50 Hz log itself is taken as it is.
#[test]
fn csv_logs_at_another_rate_are_resampled_at_50_hz() {
    // Time stamps on whole microseconds, as a log's are (and the resampling grid is).
    let mut flight = heli_flight(10.0);
    for (k, s) in flight.iter_mut().enumerate() {
        s.t = (k as f64 * 20_000.0) / 1e6;
    }
    let mut fast = Vec::new();
    for w in flight.windows(2) {
        let (a, b) = (w[0], w[1]);
        let mid = |x: f64, y: f64| 0.5 * (x + y);
        fast.push(a);
        fast.push(SensorSample {
            t: mid(a.t, b.t),
            roll: mid(a.roll, b.roll),
            pitch: mid(a.pitch, b.pitch),
            yaw: mid(a.yaw, b.yaw),
            v_north: mid(a.v_north, b.v_north),
            v_east: mid(a.v_east, b.v_east),
            v_down: mid(a.v_down, b.v_down),
            p: mid(a.p, b.p),
            q: mid(a.q, b.q),
            r: mid(a.r, b.r),
            ..a
        });
    }
    fast.extend(flight.last().copied());
    let dir = tmpdir("csv-rate");
    let (slow_path, fast_path) = (dir.join("50hz.csv"), dir.join("100hz.csv"));
    rotorid_cli::log::write_log(&slow_path, &flight).expect("write");
    rotorid_cli::log::write_log(&fast_path, &fast).expect("write");

    let slow = import::import(&slow_path).expect("50 Hz");
    assert!(slow.notes.is_empty(), "{:?}", slow.notes);
    assert_eq!(slow.segments, vec![flight.clone()]);

    let imported = import::import(&fast_path).expect("100 Hz");
    assert_eq!(imported.format, LogFormat::Csv);
    assert!(
        imported
            .notes
            .iter()
            .any(|n| n.contains("100.0 Hz") && n.contains("resampled")),
        "{:?}",
        imported.notes
    );
    assert_eq!(imported.segments.len(), 1);
    let seg = &imported.segments[0];
    assert_eq!(seg.len(), flight.len());
    for (k, (a, b)) in seg.iter().zip(&flight).enumerate() {
        let (x, mut y) = (rotorid_cli::log::values(a), rotorid_cli::log::values(b));
        if k > 0 {
            let before = rotorid_cli::log::values(&flight[k - 1]);
            for i in 1..=4 {
                y[i] = (before[i] + y[i]) / 2.0;
            }
        }
        for (i, (x, y)) in x.iter().zip(y.iter()).enumerate() {
            assert!(
                (x - y).abs() <= 1e-9 * y.abs().max(1.0),
                "t={} column {i}: {x} vs {y}",
                b.t
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gaps_split_generated_logs() {
    let mut flight = heli_flight(6.0);
    // Drop 0.5 s in the middle (a logging dropout).
    flight.drain(100..125);
    let dir = tmpdir("gap");
    let path = dir.join("gap.bin");
    std::fs::write(&path, synth::dataflash(&flight, true)).expect("write");
    let imported = import::import(&path).expect("imports");
    assert_eq!(imported.segments.len(), 2);
    assert_eq!(imported.segments[0].len(), 100);
    assert_eq!(imported.segments[1].len(), flight.len() - 100);
    assert_eq!(import::segments_for_identify(&imported, true).len(), 2);
    assert_eq!(
        import::segments_for_identify(&imported, false)[0].len(),
        175
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A log that never leaves the ground (collective at idle throughout) is refused for what the
/// cuts did, not blamed on gaps in the data; `--from`/`--to` replaces the in-air detector.
#[test]
fn a_log_cut_away_entirely_says_so() {
    let mut flight = heli_flight(6.0);
    flight.iter_mut().for_each(|s| s.sticks.col = 0.0);
    let dir = tmpdir("ground");
    let path = dir.join("ground.bin");
    std::fs::write(&path, synth::dataflash(&flight, true)).expect("write");
    let e = import::import(&path).expect_err("nothing in the air");
    assert!(matches!(e, ImportError::AllCut { .. }), "{e:?}");
    let text = e.to_string();
    assert!(text.contains("nothing left after the cuts"), "{text}");
    assert!(text.contains("collective at idle"), "{text}");
    assert!(!text.contains("gap"), "{text}");
    let options = import::ImportOptions {
        from_s: Some(0.0),
        to_s: Some(1e6),
        ..Default::default()
    };
    let imported = import::import_with(&path, &options).expect("the window replaces the detector");
    assert_eq!(imported.segments.len(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A channel out of its range throughout (here a collective logged 0…1000, as ArduCopter 3.3
/// wrote it, by a firmware the log does not name) is refused for what the cuts did, with a
/// hint at its units, not blamed on gaps in the data or on the ground.
#[test]
fn a_channel_out_of_range_throughout_says_so() {
    let mut flight = heli_flight(6.0);
    flight.iter_mut().for_each(|s| s.sticks.col *= 1000.0);
    let dir = tmpdir("units");
    let path = dir.join("units.bin");
    std::fs::write(&path, synth::dataflash(&flight, true)).expect("write");
    let e = import::import(&path).expect_err("no plausible collective");
    assert!(matches!(e, ImportError::AllCut { .. }), "{e:?}");
    let text = e.to_string();
    assert!(text.contains("collective command"), "{text}");
    assert!(text.contains("other units"), "{text}");
    assert!(
        !text.contains("gap") && !text.contains("left the ground"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A loss of control (the attitude 45° off the autopilot's demand for 0.2 s) is cut with a
/// second on each side and named, in a DataFlash log (`ATT` `DesRoll DesPitch`) and in the
/// real PX4 log whose quadrotor tumbles at the end (`vehicle_attitude_setpoint`).
#[test]
fn a_loss_of_control_is_cut() {
    let flight = heli_flight(12.0);
    let demand = |s: &SensorSample| {
        let off = if (6.0..6.2).contains(&s.t) {
            45f64.to_radians()
        } else {
            0.0
        };
        [s.roll + off, s.pitch]
    };
    let dir = tmpdir("tumble");
    let path = dir.join("tumble.bin");
    std::fs::write(
        &path,
        synth::dataflash_with_demand(&flight, true, Some(&demand)),
    )
    .expect("write");
    let lost_control = |imported: &import::Imported| -> Vec<import::resample::Cut> {
        let lost: Vec<_> = imported
            .cuts
            .iter()
            .filter(|c| c.reason.contains("off the autopilot's demand"))
            .cloned()
            .collect();
        assert_eq!(lost.len(), 1, "{:?}", imported.cuts);
        lost
    };
    let imported = import::import(&path).expect("imports");
    let lost = lost_control(&imported);
    // Log time is the sample time after a 1 s boot.
    assert!((lost[0].from_s - 6.0).abs() < 0.03, "{:?}", lost[0]);
    assert!((lost[0].to_s - 8.2).abs() < 0.03, "{:?}", lost[0]);
    assert_eq!(imported.segments.len(), 2);

    let real = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs/real/ekf_failure.ulg");
    let lost = lost_control(&import::import(&real).expect("imports"));
    assert!((113.0..114.0).contains(&lost[0].from_s), "{:?}", lost[0]);
    let _ = std::fs::remove_dir_all(&dir);
}

fn import_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Result<import::Imported, ImportError> {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    import::import(&path)
}

#[test]
fn incomplete_truncated_and_garbage_logs() {
    let dir = tmpdir("bad");
    let flight = heli_flight(4.0);

    // No helicopter controls: a named error, for both formats.
    for (name, bytes) in [
        ("quad.ulg", synth::ulog(&flight, false)),
        ("quad.bin", synth::dataflash(&flight, false)),
    ] {
        let e = import_bytes(&dir, name, &bytes)
            .expect_err(name)
            .to_string();
        assert!(
            e.contains(name) && e.contains("no helicopter controls"),
            "{e}"
        );
    }
    // The real log has no vehicle_angular_velocity but older fields: still imports (above);
    // a ULog with no topic at all names the attitude.
    let header_only = &synth::ulog(&flight, true)[..16];
    let e = import_bytes(&dir, "header.ulg", header_only)
        .expect_err("no data")
        .to_string();
    assert!(e.contains("header.ulg") && e.contains("no attitude"), "{e}");

    // Truncated mid-record: the data before the cut, with a note.
    let full = synth::ulog(&flight, true);
    let cut = &full[..full.len() * 2 / 3 + 3];
    let imported = import_bytes(&dir, "cut.ulg", cut).expect("prefix imports");
    assert!(
        imported.notes.iter().any(|n| n.contains("truncated")),
        "{:?}",
        imported.notes
    );
    let n = imported.segments[0].len();
    assert!(n > 100 && n < flight.len(), "{n}");
    let full = synth::dataflash(&flight, true);
    let imported =
        import_bytes(&dir, "cut.bin", &full[..full.len() / 2 + 5]).expect("prefix imports");
    // DataFlash too gets its note (issue 34: it had none).
    assert!(
        imported
            .notes
            .iter()
            .any(|n| n.contains("cut.bin: the log is truncated at byte")),
        "{:?}",
        imported.notes
    );
    let n = imported.segments[0].len();
    assert!(n > 50 && n < flight.len(), "{n}");

    // Garbage: after a ULog or DataFlash magic, or none (read as CSV). Errors, no panic.
    let mut noise = Vec::new();
    let mut x: u32 = 12345;
    for _ in 0..20_000 {
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
        noise.push((x >> 16) as u8);
    }
    for (name, prefix) in [
        ("noise.ulg", &b"ULog\x01\x12\x35\x01"[..]),
        ("noise.bin", &[0xA3, 0x95][..]),
        ("noise.dat", &b""[..]),
        ("empty.ulg", &b""[..]),
    ] {
        let bytes = if name == "empty.ulg" {
            Vec::new()
        } else {
            [prefix, &noise].concat()
        };
        let e = import_bytes(&dir, name, &bytes)
            .expect_err(name)
            .to_string();
        assert!(e.contains(name), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_convert_and_identify_on_ulog_and_dataflash() {
    let dir = tmpdir("cli");
    let bin = || Command::new(env!("CARGO_BIN_EXE_rotorid"));
    let train = dir.join("train.ulg");
    std::fs::write(&train, synth::ulog(&heli_flight(30.0), true)).expect("write");
    let mut verify_flight = heli_flight(12.0);
    verify_flight.iter_mut().for_each(|s| s.t += 100.0);
    let verify = dir.join("verify.bin");
    std::fs::write(&verify, synth::dataflash(&verify_flight, true)).expect("write");

    let o = bin()
        .args(["identify", "--no-plots", "--full", "--train"])
        .arg(&train)
        .arg("--verify")
        .arg(&verify)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("runs");
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("Table 4") && out.contains("verify.bin"),
        "{out}"
    );

    // convert: the real log's longest segment, readable by the CSV reader.
    let csv = dir.join("real.csv");
    let o = bin()
        .arg("convert")
        .arg(real_log())
        .arg("-o")
        .arg(&csv)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let samples = rotorid_cli::log::read_log(&csv).expect("valid CSV");
    let longest = import::import(&real_log()).expect("imports");
    assert_eq!(samples.len(), longest.longest().map_or(0, Vec::len));

    // A garbage log through the CLI: exit 1, the file named, no panic.
    let bad = dir.join("bad.ulg");
    std::fs::write(&bad, b"ULog\x01\x12\x35\x01garbage").expect("write");
    let o = bin()
        .arg("convert")
        .arg(&bad)
        .arg("-o")
        .arg(dir.join("x.csv"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("bad.ulg") && !err.contains("panicked"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Corrupted copies of valid logs (bytes overwritten at pseudo-random places, fixed seed):
/// every one gives a result or an error naming the file, never a panic.
#[test]
fn corrupted_logs_never_panic() {
    let dir = tmpdir("corrupt");
    let flight = heli_flight(2.0);
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    for (ext, good) in [
        ("ulg", synth::ulog(&flight, true)),
        ("bin", synth::dataflash(&flight, true)),
    ] {
        for case in 0..150 {
            let mut bytes = good.clone();
            for _ in 0..1 + case % 8 {
                let at = (next() % bytes.len() as u64) as usize;
                bytes[at] = next() as u8;
            }
            if case % 5 == 0 {
                bytes.truncate((next() % bytes.len() as u64) as usize);
            }
            let name = format!("c{case}.{ext}");
            if let Err(e) = import_bytes(&dir, &name, &bytes) {
                assert!(e.to_string().contains(&name), "{e}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
