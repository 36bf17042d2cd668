//! Onboard demonstration (`scripts/demo.sh`): identification on the emulated Cortex-M4F over
//! the serial telemetry link, checked bit for bit against the host build.
//!
//! Builds `firmware-example`, boots it in QEMU (`mps2-an386`), streams the simulated
//! identification flight (Table 2 sweeps, learning) and the verification flight (frozen θ,
//! one-step prediction), and prints the Table 4 analogue computed from the firmware's
//! predictions together with the bit-for-bit verdict.

use std::process::ExitCode;
use std::time::Instant;

use host_tests::firmware_link::LinkError;
use host_tests::onboard::{Onboard, OnboardError};
use indicatif::{ProgressBar, ProgressStyle};
use rotorid::HoverState;
use rotorid_cli::error_chain::Chain;
use rotorid_cli::experiments::format_table4;
use rotorid_link::msg::{Estimate, Ident, RlsForm, SampleMode, SampleMsg};
use rotorid_sim::flights::{identification_flight, to_hover_samples, verification_flight};
use rotorid_sim::plant::PlantError;

const ID_SEED: u64 = 1;
const VER_SEED: u64 = 2;
const VER_DURATION_S: f64 = 120.0;

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

fn state(a: &[f32; 6]) -> HoverState<f32> {
    HoverState {
        velocity: [a[0], a[1], a[2]],
        rates: [a[3], a[4], a[5]],
    }
}

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
    #[error("{0:?} parameter dump differs from the host")]
    Params(Ident),
    #[error("{0:?} exported state differs from the host")]
    Export(Ident),
}

fn run() -> Result<(), DemoError> {
    let t0 = Instant::now();
    println!("rotorid onboard demo: identification on an emulated Cortex-M4F (QEMU mps2-an386)");
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
    // Build first with cargo's own progress on the terminal (the first build takes about a
    // minute); the boot below then finds the firmware built.
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
    if !built.success() {
        return Err(DemoError::Build);
    }
    println!("booting QEMU (mps2-an386) and connecting to the firmware's UART...");
    let mut ob = Onboard::boot(RlsForm::UdDefault, false)?;
    println!("  firmware says: {}", ob.link.hello().name);
    println!(
        "  streaming {} samples to it over the serial link, one frame each way per sample",
        id.len() + ver.len()
    );

    let learn: Vec<SampleMsg> = id
        .iter()
        .map(|&sample| SampleMsg {
            mode: SampleMode::Learn,
            sample,
        })
        .collect();
    let pb = bar(learn.len(), "identification (learning)");
    let r = ob.stream(&learn, |n| pb.set_position(n as u64));
    pb.finish();
    let learned = r.map_err(DemoError::Verdict)?;
    let rejected = learned
        .estimates
        .iter()
        .filter(|e| e.fuzzy.error.is_some())
        .count();

    // Verification: θ frozen; the first sample starts the chain, every sample is predicted.
    let verify: Vec<SampleMsg> = ver
        .iter()
        .enumerate()
        .map(|(k, &sample)| SampleMsg {
            mode: if k == 0 {
                SampleMode::Resume
            } else {
                SampleMode::Predict
            },
            sample,
        })
        .collect();
    let pb = bar(verify.len(), "verification (frozen θ)");
    let r = ob.stream(&verify, |n| pb.set_position(n as u64));
    pb.finish();
    let verified = r.map_err(DemoError::Verdict)?;

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
        verified.estimates.iter().map(|e| state(f(e))).collect()
    };
    let fuzzy = rotorid_cli::experiments::one_step_errors(&ver, &preds(|e| &e.fuzzy.prediction));
    let plain = rotorid_cli::experiments::one_step_errors(&ver, &preds(|e| &e.plain.prediction));
    println!();
    println!(
        "Table 4 analogue, computed onboard (mean |one-step error| over the verification flight, θ frozen):"
    );
    print!("{}", format_table4(&fuzzy, &plain));
    let n = learned.estimates.len() + verified.estimates.len();
    println!();
    println!(
        "bit-for-bit: PASS — all {n} onboard estimates (predictions and innovations of both \
         identifiers), the final θ/diag(P)/trace of all 8 models and the exported states are \
         identical to the host build ({}).",
        std::env::consts::ARCH
    );
    println!(
        "link: {} frames received by the firmware, {} rejected, {} lost; {} samples rejected by the core",
        stats.link.frames_ok,
        stats.link.rejected(),
        stats.link.lost_frames,
        rejected
    );
    println!("done in {:.1?}", t0.elapsed());
    Ok(())
}

/// `--cost`: the committed cost report (`scripts/cost.sh` → `docs/cost.md`), on stdout.
fn cost() -> Result<(), DemoError> {
    use rotorid_link::msg::Workload;
    let id = to_hover_samples(&identification_flight(ID_SEED)?);
    let steps = 2000usize;
    let msgs: Vec<SampleMsg> = id[..steps]
        .iter()
        .map(|&sample| SampleMsg {
            mode: SampleMode::Learn,
            sample,
        })
        .collect();
    let mut rows = Vec::new();
    let mut mem = None;
    let mut calib = Vec::new();
    let mut startup = None;
    for (name, form) in [
        ("U-D (f32 default)", RlsForm::UdDefault),
        ("paper covariance form", RlsForm::PaperCovariance),
    ] {
        let mut ob = Onboard::boot(form, true)?;
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
        rows.push((format!("fuzzy, {name}"), stat(|e| e.fuzzy.ticks)));
        rows.push((format!("plain, {name}"), stat(|e| e.plain.ticks)));
        mem = Some(ob.memory()?);
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
    println!("Steps measured: {} per form (samples 2..={steps} of the identification flight, seed {ID_SEED}).", steps - 1);
    for (n, t) in &calib {
        println!("Calibration: xorshift32 x{n} = {t} ticks.");
    }
    if let Some(m) = mem {
        println!();
        println!(
            "Memory (MemoryRequest after the runs): static RAM {} B, stack peak {} B (link + identification service), static + peak = {} B of the {} B budget.",
            m.static_ram,
            m.stack_peak,
            m.static_ram + m.stack_peak,
            m.ram_size
        );
        match startup {
            Some(s) => println!(
                "Start-up (both identifiers built in place in their static; firmware log): stack {s} B, static + start-up = {} B of the {} B budget.",
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
