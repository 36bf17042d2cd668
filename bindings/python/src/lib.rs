//! `rotorid._rotorid`: the native half of the `rotorid` Python package (PyO3, abi3). The
//! Python half (`python/rotorid/`) turns what these calls return (little-endian bytes and
//! JSON text) into numpy arrays, pandas DataFrames and result objects; keeping the native
//! surface to bytes and strings keeps it free of numpy's C API, and so one abi3 wheel serves
//! every CPython ≥ 3.9.
//!
//! Why a crate of its own, outside the Cargo workspace: it is a product (the wheel), not a
//! test of the core, and PyO3 needs a Python interpreter to build, which `cargo test` of the
//! workspace must not.

mod errors;
mod identifier;

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rotorid_cli::experiments::FreeRunVelocity;
use rotorid_cli::identify::{self as ident, IdentifyArgs};
use rotorid_cli::import::ImportOptions;
use rotorid_cli::simulate::{self as sim, FlightKind, SimulateArgs};
use rotorid_sim::plant::{Airframe, SensorSample, Sticks};

/// Columns of a log block: `rotorid_cli::log::COLUMNS` (time, controls, attitude, NED
/// velocity, FRD rates; SI units, rad and rad/s).
const LOG_COLUMNS: usize = rotorid_cli::log::COLUMNS.len();

fn f64_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values.into_iter().flat_map(f64::to_le_bytes).collect()
}

/// The rate of `--rate`: `None` (auto) or Hz from 1 to 1000 with a whole number of µs period.
fn check_rate(rate: Option<f64>) -> PyResult<Option<f64>> {
    match rate {
        Some(r) if !(r.is_finite() && (1.0..=1000.0).contains(&r) && (1e6 / r).fract() == 0.0) => {
            Err(errors::input(format!(
                "rate {r} Hz is not an identification rate: None (auto), or Hz from 1 to 1000 whose period is a whole number of µs (50, 25, 20, 10, …)"
            )))
        }
        _ => Ok(rate),
    }
}

/// The column names (SI units in the names), in block order.
#[pyfunction]
fn log_columns() -> Vec<&'static str> {
    rotorid_cli::log::COLUMNS.to_vec()
}

/// Reads a log (CSV, PX4 ULog, ArduPilot DataFlash, PX4 sdlog2) as `rotorid identify` does:
/// ground time and implausible stretches cut, resampled at `rate` (Hz; None: auto), only
/// between `from_s` and `to_s` (s, log time) when given. Returns `(block, info)`: block is
/// n × (1 + 14) little-endian f64 (segment number from 1, then `log_columns()`), info a
/// JSON text (format, rate_hz, notes, warnings, cuts).
#[pyfunction]
#[pyo3(signature = (path, rate=None, from_s=None, to_s=None))]
fn read_log<'py>(
    py: Python<'py>,
    path: PathBuf,
    rate: Option<f64>,
    from_s: Option<f64>,
    to_s: Option<f64>,
) -> PyResult<(Bound<'py, PyBytes>, String)> {
    let options = ImportOptions {
        rate_hz: check_rate(rate)?,
        from_s,
        to_s,
    };
    let imported = py
        .detach(|| rotorid_cli::import::import_with(&path, &options))
        .map_err(|e| errors::log(&e))?;
    let mut block = Vec::new();
    for (k, seg) in imported.segments.iter().enumerate() {
        for s in seg {
            block.extend(((k + 1) as f64).to_le_bytes());
            block.extend(f64_bytes(rotorid_cli::log::values(s)));
        }
    }
    let info = serde_json::json!({
        "format": format!("{:?}", imported.format),
        "rate_hz": imported.rate_hz,
        "notes": imported.notes,
        "warnings": imported.warnings,
        "cuts": imported.cuts.iter().map(|c| serde_json::json!({
            "from_s": c.from_s, "to_s": c.to_s, "reason": c.reason,
        })).collect::<Vec<_>>(),
        "segments": imported.segments.len(),
    });
    Ok((PyBytes::new(py, &block), info.to_string()))
}

/// Converts a log block (n × 14 little-endian f64 in `log_columns()` order: NED velocity,
/// FRD rates in rad/s) to the core's samples, as `rotorid identify` does
/// (`rotorid_sim::flights::to_hover_sample`): returns `(times, floats)`, n little-endian u64
/// (µs) and n × 13 little-endian f32 (attitude rad, velocity m/s in paper axes, rates deg/s
/// `[q r p]`, controls).
#[pyfunction]
fn hover_block<'py>(
    py: Python<'py>,
    block: &[u8],
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
    if !block.len().is_multiple_of(8 * LOG_COLUMNS) {
        return Err(errors::input(format!(
            "log block of {} bytes is not whole rows of {LOG_COLUMNS} f64",
            block.len()
        )));
    }
    let mut times = Vec::new();
    let mut floats = Vec::new();
    for r in block.chunks_exact(8 * LOG_COLUMNS) {
        let mut v = [0f64; LOG_COLUMNS];
        for (x, b) in v.iter_mut().zip(r.chunks_exact(8)) {
            let mut b8 = [0u8; 8];
            b8.copy_from_slice(b);
            *x = f64::from_le_bytes(b8);
        }
        let [t, col, ped, lon, lat, roll, pitch, yaw, v_north, v_east, v_down, p, q, rr] = v;
        let h = rotorid_sim::flights::to_hover_sample(&SensorSample {
            t,
            sticks: Sticks { col, ped, lon, lat },
            roll,
            pitch,
            yaw,
            v_north,
            v_east,
            v_down,
            p,
            q,
            r: rr,
        });
        times.extend(h.time_us.to_le_bytes());
        let c = h.controls;
        let a = h.attitude;
        for x in [a.roll, a.pitch, a.yaw]
            .into_iter()
            .chain(h.velocity)
            .chain(h.rates)
            .chain([c.col, c.ped, c.lon, c.lat])
        {
            floats.extend(x.to_le_bytes());
        }
    }
    Ok((PyBytes::new(py, &times), PyBytes::new(py, &floats)))
}

/// Comma-separated finite numbers in `range`, as the command parses them (f32 from the text).
fn numbers(text: &str, what: &str, ok: impl Fn(f32) -> bool) -> PyResult<Vec<f32>> {
    text.split(',')
        .map(|v| match v.trim().parse::<f32>() {
            Ok(x) if ok(x) => Ok(x),
            _ => Err(errors::input(format!(
                "{what}: {:?} is not a valid value",
                v.chars().take(40).collect::<String>()
            ))),
        })
        .collect()
}

/// `--gyro-noise`: auto, none, σ or `Q,R,P` (deg/s).
fn parse_gyro_noise(text: &str) -> PyResult<ident::GyroNoise> {
    match text {
        "auto" => return Ok(ident::GyroNoise::Auto),
        "none" => return Ok(ident::GyroNoise::None),
        _ => {}
    }
    let v = numbers(text, "gyro_noise (deg/s, ≥ 0)", |x| {
        x.is_finite() && x >= 0.0
    })?;
    match v[..] {
        [x] => Ok(ident::GyroNoise::Given([x; 3])),
        [q, r, p] => Ok(ident::GyroNoise::Given([q, r, p])),
        _ => Err(errors::input(
            "gyro_noise: \"auto\", \"none\", one σ or three (q, r, p) expected",
        )),
    }
}

/// `--observer-gain`: auto, K or six values (0 to 1).
fn parse_observer_gain(text: &str) -> PyResult<ident::ObserverGain> {
    if text == "auto" {
        return Ok(ident::ObserverGain::Auto);
    }
    let v = numbers(text, "observer_gain (0 to 1)", |k| (0.0..=1.0).contains(&k))?;
    match v[..] {
        [k] => Ok(ident::ObserverGain::Given([k; 6])),
        [a, b, c, q, r, p] => Ok(ident::ObserverGain::Given([a, b, c, q, r, p])),
        _ => Err(errors::input(
            "observer_gain: \"auto\", one gain or six (v_x, v_y, v_z, q, r, p) expected",
        )),
    }
}

/// Identifies as `rotorid identify` (the GIL released meanwhile); `gyro_noise` and
/// `observer_gain` in the command's syntax (`auto`, `none`, `0.3`, `0.3,0.4,0.5`). Returns
/// `(metrics_json, parameters_json, text, notes)`: metrics.json's text (byte for byte the
/// command's for the same arguments), every variant's θ (as params-*.json), what the command prints on stdout (the verdict, the derivatives), and
/// its notes and warnings. With `out`, writes metrics.json, params-*.json and (`plots`) the
/// figures there.
#[pyfunction]
#[pyo3(signature = (train, verify=None, holdout=0.3, rate=None, from_s=None, to_s=None, out=None, window=2.0, plots=true, warm_start=None, gyro_noise="auto", free_run_velocity="model", observer_gain="auto", control_delay=None))]
#[allow(clippy::too_many_arguments)]
fn identify(
    py: Python<'_>,
    train: Vec<PathBuf>,
    verify: Option<PathBuf>,
    holdout: f64,
    rate: Option<f64>,
    from_s: Option<f64>,
    to_s: Option<f64>,
    out: Option<PathBuf>,
    window: f64,
    plots: bool,
    warm_start: Option<PathBuf>,
    gyro_noise: &str,
    free_run_velocity: &str,
    observer_gain: &str,
    control_delay: Option<f64>,
) -> PyResult<(String, String, String, Vec<String>)> {
    if !(holdout.is_finite() && holdout > 0.0 && holdout < 1.0) {
        return Err(errors::input(format!(
            "holdout must be a fraction in (0, 1), got {holdout}"
        )));
    }
    if let Some(d) = control_delay.filter(|d| !(0.0..=1.0).contains(d)) {
        return Err(errors::input(format!(
            "control_delay must be seconds from 0 to 1, got {d}"
        )));
    }
    let args = IdentifyArgs {
        verify,
        holdout,
        options: ImportOptions {
            rate_hz: check_rate(rate)?,
            from_s,
            to_s,
        },
        out,
        window,
        no_plots: !plots,
        warm_start,
        gyro_noise: parse_gyro_noise(gyro_noise)?,
        free_run_velocity: match free_run_velocity {
            "model" => FreeRunVelocity::Model,
            "measured" => FreeRunVelocity::Measured,
            other => {
                return Err(errors::input(format!(
                    "free_run_velocity {:?}: expected \"model\" or \"measured\"",
                    other.chars().take(40).collect::<String>()
                )))
            }
        },
        observer_gain: parse_observer_gain(observer_gain)?,
        control_delay_s: control_delay,
        ..IdentifyArgs::new(train)
    };
    let result = py.detach(|| {
        let mut collect = ident::Collect::default();
        let outcome = ident::identify(&args, &mut collect)?;
        // Every variant's trained θ (params-*.json's content), by variant name.
        let params: serde_json::Map<String, serde_json::Value> = outcome
            .metrics
            .variants
            .iter()
            .map(|v| {
                let p = serde_json::to_value(&v.parameters).unwrap_or(serde_json::Value::Null);
                (v.name.clone(), p)
            })
            .collect();
        Ok::<_, ident::IdentifyError>((
            outcome.metrics_json()?,
            serde_json::Value::Object(params).to_string(),
            collect.text,
            collect.notes,
        ))
    });
    result.map_err(|e| errors::identify(&e))
}

/// Flies the simulator as `rotorid simulate` does. Without `out` returns the log block
/// (n × 14 little-endian f64, `log_columns()`); with it, writes the CSV there (the
/// command's bytes) and returns None.
#[pyfunction]
#[pyo3(signature = (kind, seed=1, plant="xcell60", plant_variation=None, duration=None, clean=false, noise_scale=1.0, cyclic_power=1.0, out=None))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    kind: &str,
    seed: u64,
    plant: &str,
    plant_variation: Option<u64>,
    duration: Option<f64>,
    clean: bool,
    noise_scale: f64,
    cyclic_power: f64,
    out: Option<PathBuf>,
) -> PyResult<Option<Bound<'py, PyBytes>>> {
    let kind = match kind {
        "identification" => FlightKind::Identification,
        "verification" => FlightKind::Verification,
        "envelope" => FlightKind::Envelope,
        "envelope-verification" | "envelope_verification" => FlightKind::EnvelopeVerification,
        other => {
            return Err(errors::input(format!(
                "unknown flight kind {:?}; expected identification, verification, envelope or envelope-verification",
                other.chars().take(40).collect::<String>()
            )))
        }
    };
    let airframe = match plant {
        "xcell60" => Airframe::XCell60,
        "flybarless600" => Airframe::Flybarless600,
        other => {
            return Err(errors::input(format!(
                "unknown plant {:?}; expected xcell60 or flybarless600",
                other.chars().take(40).collect::<String>()
            )))
        }
    };
    let args = SimulateArgs {
        duration,
        clean,
        noise_scale,
        airframe,
        variation: plant_variation,
        cyclic_power,
        ..SimulateArgs::new(kind, seed)
    };
    let samples = py
        .detach(|| sim::simulate(&args))
        .map_err(|e| errors::simulate(&e))?;
    match out {
        Some(path) => {
            rotorid_cli::log::write_log(&path, &samples).map_err(|e| errors::csv(&e))?;
            Ok(None)
        }
        None => Ok(Some(PyBytes::new(
            py,
            &f64_bytes(samples.iter().flat_map(rotorid_cli::log::values)),
        ))),
    }
}

#[pymodule]
fn _rotorid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<identifier::Identifier>()?;
    m.add("KINDS", identifier::KIND_NAMES.to_vec())?;
    m.add("FLOATS_PER_SAMPLE", identifier::FLOATS_PER_SAMPLE)?;
    m.add_function(wrap_pyfunction!(log_columns, m)?)?;
    m.add_function(wrap_pyfunction!(read_log, m)?)?;
    m.add_function(wrap_pyfunction!(hover_block, m)?)?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    Ok(())
}
