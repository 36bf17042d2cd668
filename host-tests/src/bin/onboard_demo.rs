//! Onboard demonstration (`scripts/demo.sh`): identification on the emulated Cortex-M4F over
//! the serial telemetry link, checked bit for bit against the host build.
//!
//! Builds `firmware-example`, boots it in QEMU (`mps2-an386`) and, by default, runs the flight
//! default against its baseline (`FlightIdentifier<f32>` vs `ExtendedPlainIdentifier<f32>`)
//! on the envelope flights: learning over the envelope identification flight, then θ frozen
//! over the envelope-verification flight, one step and 2 s free run (the firmware's own
//! `FreeRun` mode), every error computed from the firmware's predictions, every prediction
//! checked bit for bit against the host, and the errors checked against what
//! `rotorid identify` (docs/results.md) computes on the host for the same flights.
//!
//! `--paper`: the paper's pair (reproduction) on the hover flights, the Table 4 analogue.
//! `--cost`: the cost report of `scripts/cost.sh`.

use std::process::ExitCode;
use std::time::Instant;

use host_tests::firmware_link::LinkError;
use host_tests::onboard::{Onboard, OnboardError};
use indicatif::{ProgressBar, ProgressStyle};
use rotorid::hover::HoverSample;
use rotorid::HoverState;
use rotorid_cli::error_chain::Chain;
use rotorid_cli::experiments::{
    evaluate, format_table4, gyro_noise_of, mean_abs_errors, one_step_mean_abs_errors, variants,
    EvaluateError, EvaluationSettings, FreeRunVelocity,
};
use rotorid_link::msg::{Estimate, Ident, IdentPair, RlsForm, SampleMode, SampleMsg};
use rotorid_sim::envelope::{envelope_flight, EnvelopeKind};
use rotorid_sim::flights::{
    identification_flight, to_hover_samples, verification_flight, SAMPLE_RATE_HZ,
};
use rotorid_sim::plant::PlantError;

const ID_SEED: u64 = 1;
const VER_SEED: u64 = 2;
const VER_DURATION_S: f64 = 120.0;
/// Free-run window (s), as in docs/results.md.
const FREE_RUN_S: f64 = 2.0;
const STATES: [&str; 6] = ["v_x", "v_y", "v_z", "q", "r", "p"];

/// Why the demo (or `--cost`) stopped; `main` prints it with its causes.
#[derive(Debug, thiserror::Error)]
enum DemoError {
    #[error("simulation")]
    Simulation(#[from] PlantError),
    #[error("building firmware-example: cannot run cargo")]
    Cargo(#[source] std::io::Error),
    #[error("building firmware-example failed (see cargo's output above)")]
    Build,
    #[error(transparent)]
    Onboard(#[from] OnboardError),
    #[error(transparent)]
    Link(#[from] LinkError),
    /// A streamed estimate differs from the host's (or the stream broke off).
    #[error("bit-for-bit: FAIL")]
    Verdict(#[source] OnboardError),
    #[error("{what}: the firmware refused {count} samples")]
    Refused { what: String, count: usize },
    #[error("{0:?} parameter dump differs from the host")]
    Params(Ident),
    #[error("{0:?} exported state differs from the host")]
    Export(Ident),
    #[error("no variant {0} in rotorid identify")]
    NoVariant(&'static str),
    #[error("the host evaluation (rotorid identify's)")]
    Evaluate(#[from] EvaluateError),
    #[error("the onboard errors differ from `rotorid identify`'s on the host")]
    HostDisagrees,
}

fn bar(len: usize, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(len as u64);
    pb.set_style(
        ProgressStyle::with_template(
            "{msg:<28} [{bar:40}] {pos}/{len} samples ({per_sec}, {elapsed})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb.set_message(what.to_string());
    // Without a terminal (CI, a pipe) the bar is hidden: say what runs instead.
    if pb.is_hidden() {
        println!("  {what}: {len} samples...");
    }
    pb
}

/// Builds the firmware with cargo's own progress on the terminal (the first build takes
/// about a minute); the boot then finds it built.
fn build_firmware() -> Result<(), DemoError> {
    println!(
        "building firmware-example (release, thumbv7em-none-eabihf; cargo's progress follows)..."
    );
    let built =
        std::process::Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
            .args(["build", "--release"])
            .current_dir(host_tests::firmware_link::firmware_dir())
            .env_remove("CARGO_TARGET_DIR")
            .env_remove("RUSTFLAGS")
            .env_remove("CARGO_ENCODED_RUSTFLAGS")
            .env_remove("CARGO_BUILD_TARGET")
            .env_remove("CARGO_MANIFEST_DIR")
            .status()
            .map_err(DemoError::Cargo)?;
    if built.success() {
        Ok(())
    } else {
        Err(DemoError::Build)
    }
}

/// Builds and boots the firmware, `pair` answering.
fn boot(pair: IdentPair, samples: usize) -> Result<Onboard, DemoError> {
    build_firmware()?;
    println!("booting QEMU (mps2-an386) and connecting to the firmware's UART...");
    let mut ob = Onboard::boot(RlsForm::UdDefault, false)?;
    ob.reset_pair(RlsForm::UdDefault, pair)?;
    println!("  firmware says: {}", ob.link.hello().name);
    println!(
        "  streaming {samples} samples to it over the serial link, one frame each way per sample"
    );
    Ok(ob)
}

/// Streams `msgs` under a progress bar; any difference from the host is a FAIL.
fn stream(ob: &mut Onboard, msgs: &[SampleMsg], what: &str) -> Result<Vec<Estimate>, DemoError> {
    let pb = bar(msgs.len(), what);
    let r = ob.stream(msgs, |n| pb.set_position(n as u64));
    pb.finish();
    let r = r.map_err(DemoError::Verdict)?;
    if r.refused.is_empty() {
        Ok(r.estimates)
    } else {
        Err(DemoError::Refused {
            what: what.to_string(),
            count: r.refused.len(),
        })
    }
}

fn learn_messages(samples: &[HoverSample<f32>]) -> Vec<SampleMsg> {
    samples
        .iter()
        .map(|&sample| SampleMsg {
            mode: SampleMode::Learn,
            sample,
        })
        .collect()
}

/// θ frozen: the first sample starts the chain, every sample is predicted from the measured
/// state, the previous one's being the state before it.
fn one_step_messages(samples: &[HoverSample<f32>]) -> Vec<SampleMsg> {
    samples
        .iter()
        .take(samples.len().saturating_sub(1))
        .enumerate()
        .map(|(k, &sample)| SampleMsg {
            mode: if k == 0 {
                SampleMode::Resume
            } else {
                SampleMode::Predict
            },
            sample,
        })
        .collect()
}

/// The onboard free run in windows of `window` steps, as `rotorid_cli`'s `free_run`: each
/// window starts from the measured state (`Resume` on the sample before it, whose prediction
/// is not scored, then `Predict`: the state before the window is the measured one), then
/// `FreeRun` to its end. Returns the messages and, per message, the sample index its
/// prediction is scored against and the window it belongs to (`None` for the `Resume`s).
fn free_run_messages(
    samples: &[HoverSample<f32>],
    window: usize,
) -> (Vec<SampleMsg>, Vec<Option<(usize, usize)>>) {
    let (mut msgs, mut scored) = (Vec::new(), Vec::new());
    let mut push = |mode, k: usize, score| {
        msgs.push(SampleMsg {
            mode,
            sample: samples[k],
        });
        scored.push(score);
    };
    let (mut start, mut w) = (0, 0);
    while start + 1 < samples.len() {
        let end = (start + window).min(samples.len() - 1);
        if start == 0 {
            push(SampleMode::Resume, 0, Some((1, w)));
        } else {
            push(SampleMode::Resume, start - 1, None);
            push(SampleMode::Predict, start, Some((start + 1, w)));
        }
        for j in start + 1..end {
            push(SampleMode::FreeRun, j, Some((j + 1, w)));
        }
        start = end;
        w += 1;
    }
    (msgs, scored)
}

fn state(a: &[f32; 6]) -> HoverState<f32> {
    HoverState {
        velocity: [a[0], a[1], a[2]],
        rates: [a[3], a[4], a[5]],
    }
}

/// Errors of one identifier's onboard outputs.
struct Errors {
    one_step: [f64; 6],
    free_run: [f64; 6],
    /// Free-run windows cut short by a rejected prediction (the rest of such a window is not
    /// scored, as in `rotorid_cli`).
    diverged: usize,
}

fn errors(
    ver: &[HoverSample<f32>],
    one_step: &[Estimate],
    free_run: &[Estimate],
    scored: &[Option<(usize, usize)>],
    out: fn(&Estimate) -> &rotorid_link::msg::IdOutput,
) -> Errors {
    let actual: Vec<HoverState<f32>> = ver.iter().map(HoverSample::state).collect();
    let preds: Vec<Option<HoverState<f32>>> = one_step
        .iter()
        .map(|e| out(e).error.is_none().then(|| state(&out(e).prediction)))
        .collect();
    let one = one_step_mean_abs_errors(&preds, &actual);
    let mut pairs = Vec::new();
    let mut cut: Option<usize> = None;
    let mut diverged = 0;
    for (e, s) in free_run.iter().zip(scored) {
        let Some((k, w)) = *s else { continue };
        if cut == Some(w) {
            continue;
        }
        let o = out(e);
        if o.error.is_some() {
            cut = Some(w);
            diverged += 1;
            continue;
        }
        pairs.push((state(&o.prediction), actual[k]));
    }
    Errors {
        one_step: one,
        free_run: mean_abs_errors(pairs.iter().map(|(p, a)| (p, a))),
        diverged,
    }
}

/// The flight default vs extended plain onboard on the envelope flights.
fn run() -> Result<(), DemoError> {
    let t0 = Instant::now();
    println!("rotorid onboard demo: the flight default identifying on an emulated Cortex-M4F (QEMU mps2-an386)");
    println!("  onboard: FlightIdentifier<f32> (3 rules on forward speed, local learning) vs ExtendedPlainIdentifier<f32> (the baseline)");
    println!(
        "simulating the envelope flights (X-Cell 60 plant; the flights of docs/results.md)..."
    );
    let sim = |seed, kind| envelope_flight(seed, kind).map(|log| to_hover_samples(&log));
    let id = sim(ID_SEED, EnvelopeKind::Identification)?;
    let ver = sim(VER_SEED, EnvelopeKind::Verification)?;
    let window = (FREE_RUN_S * f64::from(SAMPLE_RATE_HZ)).round() as usize;
    let learn = learn_messages(&id);
    let one = one_step_messages(&ver);
    let (free, scored) = free_run_messages(&ver, window);
    println!(
        "  identification: `rotorid simulate --kind envelope --seed {ID_SEED}`, {:.0} s ({} samples), learnt onboard",
        id.len() as f64 / 50.0,
        id.len()
    );
    println!(
        "  verification: `--kind envelope-verification --seed {VER_SEED}`, {:.0} s ({} samples), θ frozen: one step, then free run in {FREE_RUN_S} s windows",
        ver.len() as f64 / 50.0,
        ver.len()
    );
    let mut ob = boot(IdentPair::Flight, learn.len() + one.len() + free.len())?;
    let learned = stream(&mut ob, &learn, "identification (learning)")?;
    let one_est = stream(&mut ob, &one, "verification, one step")?;
    // The free run uses the parameters compensated for the gyros' noise, estimated from the
    // identification flight as `rotorid identify --gyro-noise auto` does.
    let gyro_noise = gyro_noise_of(std::slice::from_ref(&id));
    if let Some(sigma) = gyro_noise {
        println!(
            "  compensating onboard for the gyro noise σ̂ = {:.3}, {:.3}, {:.3} deg/s (q, r, p; from the identification flight)",
            sigma[0], sigma[1], sigma[2]
        );
        ob.compensate(sigma)?;
    }
    let free_est = stream(&mut ob, &free, "verification, free run")?;
    let stats = ob.link.stats()?;
    let rejected = learned
        .iter()
        .filter(|e| e.fuzzy.error.is_some() || e.plain.error.is_some())
        .count();

    let flight = errors(&ver, &one_est, &free_est, &scored, |e| &e.fuzzy);
    let plain = errors(&ver, &one_est, &free_est, &scored, |e| &e.plain);

    // The same flights through `rotorid identify`'s evaluation on the host: docs/results.md's
    // envelope rows for `flight` and `extended plain`.
    println!("checking against `rotorid identify` on the host (docs/results.md's definitions)...");
    let mut host = Vec::new();
    for name in ["flight", "extended plain"] {
        let v = variants()
            .into_iter()
            .find(|v| v.name == name)
            .ok_or(DemoError::NoVariant(name))?;
        let settings = EvaluationSettings {
            window_s: FREE_RUN_S,
            gyro_noise,
            gyro_compensation: rotorid::hover::GyroCompensation::Damping,
            velocity: FreeRunVelocity::Model,
            observer_gain: None,
            rate_hz: f64::from(rotorid_sim::flights::SAMPLE_RATE_HZ),
        };
        host.push(evaluate(
            &v,
            std::slice::from_ref(&id),
            &ver,
            settings,
            None,
            &mut || {},
        )?);
    }
    let same =
        |a: &[f64; 6], b: &[f64; 6]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    let agree = same(&flight.one_step, &host[0].one_step)
        && same(&flight.free_run, &host[0].free_run)
        && same(&plain.one_step, &host[1].one_step)
        && same(&plain.free_run, &host[1].free_run);

    println!();
    println!("Envelope verification flight, θ frozen, computed onboard (mean |error|; m/s, deg/s; ratio < 1: flight better; 1-step: from the measured state, the firmware's own predictions; through an observer: docs/results.md):");
    println!(
        "{:<6} {:>10} {:>10} {:>7}   {:>10} {:>10} {:>7}",
        "state", "1-step fl", "1-step xp", "ratio", "2 s fl", "2 s xp", "ratio"
    );
    let ratio = |a: f64, b: f64| a / b;
    for (i, name) in STATES.iter().enumerate() {
        println!(
            "{:<6} {:>10.4} {:>10.4} {:>7.2}   {:>10.4} {:>10.4} {:>7.2}",
            name,
            flight.one_step[i],
            plain.one_step[i],
            ratio(flight.one_step[i], plain.one_step[i]),
            flight.free_run[i],
            plain.free_run[i],
            ratio(flight.free_run[i], plain.free_run[i]),
        );
    }
    println!("(fl = FlightIdentifier, xp = ExtendedPlainIdentifier; free run: {} windows, {} + {} cut short by a rejected prediction)", scored.iter().flatten().map(|s| s.1).max().map_or(0, |w| w + 1), flight.diverged, plain.diverged);
    let list = |f: &dyn Fn(usize) -> bool| -> String {
        let v: Vec<&str> = (0..6).filter(|&i| f(i)).map(|i| STATES[i]).collect();
        if v.is_empty() {
            "none".into()
        } else {
            v.join(", ")
        }
    };
    let fr = |i: usize| ratio(flight.free_run[i], plain.free_run[i]);
    let os = |i: usize| ratio(flight.one_step[i], plain.one_step[i]);
    println!(
        "Free run: flight better on {}; by at least 30 % (ratio ≤ 0.7) on {}; not better on {}.",
        list(&|i| fr(i) < 1.0),
        list(&|i| fr(i) <= 0.7),
        list(&|i| fr(i) >= 1.0)
    );
    println!(
        "One step from the measured state: flight better on {}; not better on {}.",
        list(&|i| os(i) < 1.0),
        list(&|i| os(i) >= 1.0)
    );
    // Issue 11's envelope criterion, said plainly whichever way it comes out.
    let rates_ok = (3..6).all(|i| fr(i) <= 0.7);
    let velocities_ok = (0..3).filter(|&i| fr(i) <= 0.7).count() >= 2;
    println!(
        "Target (free run ≤ 0.7 × extended plain on q, r, p and on at least two velocities): {}.",
        if rates_ok && velocities_ok {
            "met".to_string()
        } else {
            format!("not met (above 0.7: {})", list(&|i| fr(i) > 0.7))
        }
    );
    println!(
        "Same numbers as `rotorid identify` on the host (docs/results.md, envelope rows `flight` and `extended plain`): {}",
        if agree { "yes, bit for bit" } else { "NO" }
    );
    let n = learned.len() + one_est.len() + free_est.len();
    println!();
    println!(
        "bit-for-bit: PASS — all {n} onboard estimates (predictions and innovations of both \
         identifiers, learning, one step and free run) are identical to the host build ({}).",
        std::env::consts::ARCH
    );
    print_link(&stats, rejected, t0);
    if agree {
        Ok(())
    } else {
        Err(DemoError::HostDisagrees)
    }
}

/// `--paper`: the paper's pair on the hover flights (reproduction of Table 4).
fn paper() -> Result<(), DemoError> {
    let t0 = Instant::now();
    println!("rotorid onboard demo (--paper): the paper's identifiers on an emulated Cortex-M4F (QEMU mps2-an386)");
    println!("simulating the identification and verification flights (X-Cell 60 plant)...");
    let id_log = identification_flight(ID_SEED)?;
    let ver_log = verification_flight(VER_SEED, VER_DURATION_S)?;
    let id = to_hover_samples(&id_log);
    let ver = to_hover_samples(&ver_log);
    println!(
        "  identification flight {:.0} s ({} samples), verification flight {:.0} s ({} samples)",
        id.len() as f64 / 50.0,
        id.len(),
        ver.len() as f64 / 50.0,
        ver.len()
    );
    let mut ob = boot(IdentPair::Paper, id.len() + ver.len())?;
    let learned = stream(&mut ob, &learn_messages(&id), "identification (learning)")?;
    let rejected = learned.iter().filter(|e| e.fuzzy.error.is_some()).count();

    // Verification: θ frozen; the first sample starts the chain, every sample is predicted.
    let verify = one_step_messages(&ver);
    let verified = stream(&mut ob, &verify, "verification (frozen θ)")?;
    // Final parameters and exported state, compared with the host too.
    for ident in [Ident::Fuzzy, Ident::Plain] {
        let fw = ob.params(ident)?;
        let host = ob.mirror.params(ident);
        if fw != host {
            return Err(DemoError::Params(ident));
        }
        let fw = ob.export(ident)?;
        if fw != ob.mirror.export(ident) {
            return Err(DemoError::Export(ident));
        }
    }
    let stats = ob.link.stats()?;

    let preds = |f: fn(&Estimate) -> &[f32; 6]| -> Vec<HoverState<f32>> {
        verified.iter().map(|e| state(f(e))).collect()
    };
    let fuzzy = rotorid_cli::experiments::one_step_errors(&ver, &preds(|e| &e.fuzzy.prediction));
    let plain = rotorid_cli::experiments::one_step_errors(&ver, &preds(|e| &e.plain.prediction));
    println!();
    println!(
        "Table 4 analogue, computed onboard (mean |one-step error| over the verification flight, θ frozen):"
    );
    print!("{}", format_table4(&fuzzy, &plain));
    let n = learned.len() + verified.len();
    println!();
    println!(
        "bit-for-bit: PASS — all {n} onboard estimates (predictions and innovations of both \
         identifiers), the final θ/diag(P)/trace of all 8 models and the exported states are \
         identical to the host build ({}).",
        std::env::consts::ARCH
    );
    print_link(&stats, rejected, t0);
    Ok(())
}

/// The link's counters and the run time.
fn print_link(stats: &rotorid_link::msg::StatsReport, rejected: usize, t0: Instant) {
    println!(
        "link: {} frames received by the firmware, {} rejected, {} lost; {} samples rejected by the core",
        stats.link.frames_ok,
        stats.link.rejected(),
        stats.link.lost_frames,
        rejected
    );
    println!("done in {:.1?}", t0.elapsed());
}

/// `--cost`: the committed cost report (`scripts/cost.sh` → `docs/cost.md`), on stdout.
fn cost() -> Result<(), DemoError> {
    use rotorid_link::msg::Workload;
    let id = to_hover_samples(&identification_flight(ID_SEED)?);
    let steps = 2000usize;
    let msgs = learn_messages(&id[..steps]);
    let mut rows = Vec::new();
    let mut mem: Option<rotorid_link::msg::MemoryReport> = None;
    let mut calib = Vec::new();
    let mut startup = None;
    // The paper pair in both forms, then the flight pair (the demo's) in the default form.
    for (names, form, pair) in [
        (["fuzzy", "plain"], RlsForm::UdDefault, IdentPair::Paper),
        (
            ["fuzzy", "plain"],
            RlsForm::PaperCovariance,
            IdentPair::Paper,
        ),
        (
            ["flight", "extended plain"],
            RlsForm::UdDefault,
            IdentPair::Flight,
        ),
    ] {
        let name = match form {
            RlsForm::PaperCovariance => "paper covariance form",
            _ => "U-D (f32 default)",
        };
        let mut ob = Onboard::boot(form, true)?;
        ob.reset_pair(form, pair)?;
        if calib.is_empty() {
            for n in [1000u32, 2000] {
                let c = ob.link.cost(Workload::Xorshift, n)?;
                calib.push((n, c.ticks));
            }
        }
        let r = ob.stream(&msgs, |_| {})?;
        // Skip the first step (no update, only a prediction).
        let stat = |f: fn(&Estimate) -> u32| {
            let t: Vec<u64> = r.estimates[1..]
                .iter()
                .map(|e| u64::from(f(e)) * 40)
                .collect();
            let mean = t.iter().sum::<u64>() as f64 / t.len() as f64;
            (mean, t.iter().copied().max().unwrap_or(0))
        };
        if startup.is_none() {
            // "stack used by start-up (identifier construction): N B", decoded by defmt-print.
            let log = ob.link.log();
            startup = log.lines().find_map(|l| {
                let rest = l
                    .split("stack used by start-up (identifier construction): ")
                    .nth(1)?;
                rest.split_whitespace().next()?.parse::<u32>().ok()
            });
        }
        rows.push((format!("{}, {name}", names[0]), stat(|e| e.fuzzy.ticks)));
        rows.push((format!("{}, {name}", names[1]), stat(|e| e.plain.ticks)));
        // Static RAM is the same in every boot; the stack peak is the largest of them.
        let m = ob.memory()?;
        mem = Some(match mem {
            Some(old) if old.stack_peak > m.stack_peak => old,
            _ => m,
        });
    }
    println!(
        "| identifier, RLS form | mean instructions/step | max instructions/step | ≤ 60 000 |"
    );
    println!("|---|---:|---:|:-:|");
    for (name, (mean, max)) in &rows {
        let ok = if *max <= 60_000 { "yes" } else { "**no**" };
        println!("| {name} | {mean:.0} | {max} | {ok} |");
    }
    println!();
    println!("Steps measured: {} per run (samples 2..={steps} of the identification flight, seed {ID_SEED}); `flight` is `FlightIdentifier<f32>` (`flight_sets()`), the demo's pair with `extended plain`.", steps - 1);
    for (n, t) in &calib {
        println!("Calibration: xorshift32 x{n} = {t} ticks.");
    }
    if let Some(m) = mem {
        println!();
        println!(
            "Memory (MemoryRequest after each run, the largest stack peak): static RAM {} B, stack peak {} B (link + identification service), static + peak = {} B of the {} B budget.",
            m.static_ram,
            m.stack_peak,
            m.static_ram + m.stack_peak,
            m.ram_size
        );
        match startup {
            Some(s) => println!(
                "Start-up (the four identifiers built in place in their static; firmware log): stack {s} B, static + start-up = {} B of the {} B budget.",
                m.static_ram + s,
                m.ram_size
            ),
            None => println!(
                "Start-up stack: not decoded (install `defmt-print` to read it from the firmware log)."
            ),
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let r = if std::env::args().any(|a| a == "--cost") {
        cost()
    } else if std::env::args().any(|a| a == "--paper") {
        paper()
    } else {
        run()
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{}", Chain(&e));
            ExitCode::FAILURE
        }
    }
}
