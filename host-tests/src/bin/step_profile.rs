//! Where the firmware's instructions go, per step, on the emulated Cortex-M4F.
//!
//! Runs the firmware in QEMU with an execution trace (`-singlestep -d exec,nochain`: one log
//! line per executed instruction, with its address), streams `A` and then `B` samples of the
//! identification flight in two boots, and reports `(count_B − count_A)/(B − A)` per function
//! (`arm-none-eabi-nm`) and per source line (`arm-none-eabi-addr2line`, innermost inlined
//! location). Boot and set-up cancel out; what remains is one sample: both identifiers' steps
//! plus the link's handling of the frames.
//!
//! Usage: `step_profile [--covariance] [--lines=L] [A B]` (default 5 25; `L` source lines,
//! default 25). QEMU writes one log line per
//! instruction (about 100 MB per 10 samples, in the temporary directory, removed afterwards).
//!
//! `step_profile --identifier NAME [A B]` (default 150 250) profiles one identifier alone
//! instead: it traces firmware-example's `step-cost` binary stepping only `NAME` (e.g.
//! `FlightIdentifier`) through its worst-case stream for `A` and then `B` steps, and reports
//! the same tables per step (construction cancels out). About 1 GB of trace per 250 steps of
//! the flight identifier, removed as soon as it is counted.

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use host_tests::firmware_link::{step_cost_elf, step_cost_qemu, BootOptions, LinkError};
use host_tests::onboard::{Onboard, OnboardError};
use rotorid_cli::error_chain::Chain;
use rotorid_link::msg::{RlsForm, SampleMode, SampleMsg};
use rotorid_sim::flights::{identification_flight, to_hover_samples};
use rotorid_sim::plant::PlantError;

/// `firmware-example`'s name for the stream without an identifier (`step_cost::STREAM_ONLY`).
const STREAM_ONLY: &str = "stream";

/// Seed of the identification flight (the one `docs/cost.md` measures).
const ID_SEED: u64 = 1;

/// What one traced run executed.
struct Trace {
    /// Executed instructions per address.
    counts: HashMap<u32, u64>,
    /// Calls: (address of the call site, entered function's start) → count.
    calls: HashMap<(u32, u32), u64>,
    /// The firmware ELF.
    elf: std::path::PathBuf,
}

/// Why the profile could not be made; `main` prints it with its causes.
#[derive(Debug, thiserror::Error)]
enum ProfileError {
    #[error("simulation")]
    Simulation(#[from] PlantError),
    #[error(transparent)]
    Onboard(#[from] OnboardError),
    #[error("{}: cannot create the trace directory", path.display())]
    TraceDir {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: cannot read QEMU's trace", path.display())]
    Trace {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Build(#[from] LinkError),
    #[error("step-cost {identifier} {steps}: QEMU exited with {status}")]
    StepCost {
        identifier: String,
        steps: usize,
        status: std::process::ExitStatus,
    },
    #[error("cannot run {tool}")]
    Tool {
        tool: &'static str,
        source: std::io::Error,
    },
}

/// What a traced run executes.
#[derive(Copy, Clone, Debug)]
enum Workload<'a> {
    /// The link firmware, streaming the identification flight to both identifiers.
    Link(RlsForm),
    /// The `step-cost` binary, stepping one identifier through its worst-case stream.
    StepCost(&'a str),
}

/// Traces a run of `n` samples (or steps).
fn trace(workload: Workload<'_>, n: usize) -> Result<Trace, ProfileError> {
    let dir = std::env::temp_dir().join(format!("rotorid-profile-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| ProfileError::TraceDir {
        path: dir.clone(),
        source,
    })?;
    // The trace is large: removed on every way out of here.
    let dir = RemoveOnDrop(dir);
    let log = dir.0.join("exec.log");
    let trace_args: Vec<String> = vec![
        "-singlestep".into(),
        "-d".into(),
        "exec,nochain".into(),
        "-D".into(),
        log.display().to_string(),
    ];
    let elf = match workload {
        Workload::Link(form) => run_link(form, n, trace_args)?,
        Workload::StepCost(identifier) => run_step_cost(identifier, n, &trace_args)?,
    };
    let funcs = functions(&elf)?;
    let starts: std::collections::HashSet<u32> = funcs.iter().map(|f| f.0).collect();
    let read_error = |source| ProfileError::Trace {
        path: log.clone(),
        source,
    };
    let file = std::fs::File::open(&log).map_err(read_error)?;
    let mut counts = HashMap::new();
    let mut calls = HashMap::new();
    let mut prev = 0u32;
    for line in BufReader::with_capacity(1 << 20, file).lines() {
        let line = line.map_err(read_error)?;
        // "Trace 0: 0x… [cs_base/pc/flags/cflags] symbol"
        let Some(pc) = line
            .split_once('[')
            .and_then(|(_, r)| r.split('/').nth(1))
            .and_then(|h| u32::from_str_radix(h, 16).ok())
        else {
            continue;
        };
        *counts.entry(pc).or_insert(0u64) += 1;
        if starts.contains(&pc) {
            *calls.entry((prev, pc)).or_insert(0u64) += 1;
        }
        prev = pc;
    }
    Ok(Trace { counts, calls, elf })
}

/// A directory removed with everything in it when dropped.
struct RemoveOnDrop(PathBuf);

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Streams `n` samples of the identification flight to the link firmware (QEMU with
/// `qemu_args`); returns the firmware's ELF.
fn run_link(form: RlsForm, n: usize, qemu_args: Vec<String>) -> Result<PathBuf, ProfileError> {
    let opts = BootOptions {
        icount: true,
        extra_args: qemu_args,
    };
    let flight = identification_flight(ID_SEED)?;
    let msgs: Vec<SampleMsg> = to_hover_samples(&flight)[..n]
        .iter()
        .map(|&sample| SampleMsg {
            mode: SampleMode::Learn,
            sample,
        })
        .collect();
    let elf = {
        let mut ob = Onboard::boot_with(form, &opts)?;
        ob.stream(&msgs, |_| {})?;
        // Dropping the link kills QEMU; at most its last log buffer (a few dozen of
        // millions of lines) is lost.
        ob.link.elf().to_path_buf()
    };
    Ok(elf)
}

/// Runs the `step-cost` binary for `steps` steps of `identifier` alone (QEMU with
/// `qemu_args`); returns its ELF.
fn run_step_cost(
    identifier: &str,
    steps: usize,
    qemu_args: &[String],
) -> Result<PathBuf, ProfileError> {
    let tool = "qemu-system-arm";
    let status = step_cost_qemu()?
        .arg("-append")
        .arg(format!("{identifier} {steps}"))
        .args(qemu_args)
        .stdout(Stdio::null())
        .status()
        .map_err(|source| ProfileError::Tool { tool, source })?;
    if !status.success() {
        return Err(ProfileError::StepCost {
            identifier: identifier.to_string(),
            steps,
            status,
        });
    }
    Ok(step_cost_elf())
}

/// Function symbols of the ELF: (start, end, demangled name), sorted.
fn functions(elf: &Path) -> Result<Vec<(u32, u32, String)>, ProfileError> {
    let out = Command::new("arm-none-eabi-nm")
        .args(["-C", "-S", "--defined-only"])
        .arg(elf)
        .output()
        .map_err(|source| ProfileError::Tool {
            tool: "arm-none-eabi-nm",
            source,
        })?;
    let mut f = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let mut it = line.splitn(4, ' ');
        let (Some(a), Some(s), Some(t), Some(name)) = (it.next(), it.next(), it.next(), it.next())
        else {
            continue;
        };
        if !matches!(t, "t" | "T") {
            continue;
        }
        let (Ok(a), Ok(s)) = (u32::from_str_radix(a, 16), u32::from_str_radix(s, 16)) else {
            continue;
        };
        // Thumb functions have bit 0 set in the symbol table.
        let a = a & !1;
        f.push((a, a + s, name.to_string()));
    }
    f.sort();
    Ok(f)
}

/// Source location of each address (`crate/file:line`): the innermost inlined frame outside
/// the Rust standard library (iterator adapters and the like say little), via addr2line.
fn lines(elf: &Path, pcs: &[u32]) -> Result<HashMap<u32, String>, ProfileError> {
    let tool = "arm-none-eabi-addr2line";
    let mut child = Command::new(tool)
        .arg("-e")
        .arg(elf)
        .args(["-a", "-i"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|source| ProfileError::Tool { tool, source })?;
    let mut stdin = child.stdin.take().ok_or_else(|| ProfileError::Tool {
        tool,
        source: std::io::Error::new(std::io::ErrorKind::BrokenPipe, "no stdin pipe"),
    })?;
    let input: String = pcs.iter().map(|pc| format!("{pc:#x}\n")).collect();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child
        .wait_with_output()
        .map_err(|source| ProfileError::Tool { tool, source })?;
    let _ = writer.join();
    let text = String::from_utf8_lossy(&out.stdout);
    let mut map: HashMap<u32, String> = HashMap::new();
    let mut current = None;
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("0x") {
            current = u32::from_str_radix(h, 16).ok();
            continue;
        }
        let Some(a) = current else { continue };
        let loc = line.split(" (").next().unwrap_or(line);
        let std_lib = loc.starts_with("/rustc/") || loc.contains("/library/");
        let entry = map.entry(a).or_insert_with(|| String::from("?"));
        if entry != "?" && !entry.starts_with("std ") {
            continue; // an earlier (more inner) frame outside std was found
        }
        *entry = if std_lib {
            if entry == "?" {
                format!("std {}", short(loc))
            } else {
                entry.clone()
            }
        } else {
            short(loc)
        };
    }
    Ok(map)
}

/// `…/<crate>/src/<file>:<line>` → `<crate>/<file>:<line>`.
fn short(loc: &str) -> String {
    match loc.rfind("/src/") {
        Some(i) => {
            let head = &loc[..i];
            let krate = head.rsplit('/').next().unwrap_or(head);
            format!("{krate}/{}", &loc[i + 5..])
        }
        None => loc.to_string(),
    }
}

/// Executed instructions and calls per sample (or step): `(run of b − run of a)/(b − a)`,
/// per address and per (call site, callee); and the ELF.
#[allow(clippy::type_complexity)]
fn per_step(
    workload: Workload<'_>,
    a: usize,
    b: usize,
) -> Result<(HashMap<u32, f64>, HashMap<(u32, u32), f64>, PathBuf), ProfileError> {
    let ta = trace(workload, a)?;
    let tb = trace(workload, b)?;
    let per = (b - a) as f64;
    Ok((
        difference(&tb.counts, &ta.counts, per),
        difference(&tb.calls, &ta.calls, per),
        tb.elf,
    ))
}

/// `(later − earlier)/per`, key by key.
fn difference<K: Copy + Eq + std::hash::Hash>(
    later: &HashMap<K, u64>,
    earlier: &HashMap<K, u64>,
    per: f64,
) -> HashMap<K, f64> {
    later
        .iter()
        .map(|(&k, &n)| (k, (n as f64 - *earlier.get(&k).unwrap_or(&0) as f64) / per))
        .collect()
}

fn run() -> Result<(), ProfileError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let identifier = args
        .iter()
        .position(|a| a == "--identifier")
        .and_then(|i| args.get(i + 1));
    let workload = match identifier {
        Some(name) => Workload::StepCost(name),
        None if args.iter().any(|a| a == "--covariance") => {
            Workload::Link(RlsForm::PaperCovariance)
        }
        None => Workload::Link(RlsForm::UdDefault),
    };
    let nums: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let source_lines = args
        .iter()
        .find_map(|a| a.strip_prefix("--lines="))
        .and_then(|n| n.parse().ok())
        .unwrap_or(25);
    let (a, b) = match (&nums[..], workload) {
        (&[a, b], _) if b > a => (a, b),
        (_, Workload::StepCost(_)) => (150, 250),
        (_, Workload::Link(_)) => (5, 25),
    };
    let (mut counts, mut calls, elf) = per_step(workload, a, b)?;
    if let Workload::StepCost(_) = workload {
        // Take away the stream's generation (libm's sinf/cosf in f64 soft-float), which the
        // identifier's loop also runs outside its timed step: same addresses in both.
        let (stream, stream_calls, _) = per_step(Workload::StepCost(STREAM_ONLY), a, b)?;
        for (pc, d) in stream {
            *counts.entry(pc).or_default() -= d;
        }
        for (edge, d) in stream_calls {
            *calls.entry(edge).or_default() -= d;
        }
    }
    // What is left of the harness after the subtraction is its loop around the step (a few
    // dozen instructions); residues of ±0 below one instruction per hundred steps are noise.
    let mut diff: Vec<(u32, f64)> = counts.into_iter().filter(|&(_, d)| d > 0.01).collect();
    diff.sort_by_key(|&(pc, _)| pc);
    let elf = &elf;
    let total: f64 = diff.iter().map(|&(_, d)| d).sum();
    let funcs = functions(elf)?;
    let name_of = |pc: u32| -> String {
        let i = funcs.partition_point(|f| f.0 <= pc);
        match i.checked_sub(1).and_then(|i| funcs.get(i)) {
            Some((s, e, n)) if pc >= *s && pc < *e => n.clone(),
            _ => format!("?{pc:#x}"),
        }
    };
    let mut by_func: HashMap<String, f64> = HashMap::new();
    for &(pc, d) in &diff {
        *by_func.entry(name_of(pc)).or_default() += d;
    }
    let pcs: Vec<u32> = diff.iter().map(|&(pc, _)| pc).collect();
    let locs = lines(elf, &pcs)?;
    let mut by_line: HashMap<String, f64> = HashMap::new();
    for &(pc, d) in &diff {
        let l = locs.get(&pc).cloned().unwrap_or_else(|| "?".into());
        *by_line.entry(l).or_default() += d;
    }
    let per_what = match workload {
        Workload::Link(form) => {
            println!("Instructions per sample ({form:?}, samples {a}..{b}): {total:.0} (both identifiers and the link)\n");
            "sample"
        }
        Workload::StepCost(name) => {
            println!("Instructions per step of `{name}` (step-cost stream, steps {a}..{b}): {total:.0} (the step and the harness's hash of its prediction)\n");
            "step"
        }
    };
    println!("| function | instructions/{per_what} | share |\n|---|---:|---:|");
    let mut v: Vec<_> = by_func.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for (n, d) in v.iter().take(20) {
        println!("| `{n}` | {d:.0} | {:.1} % |", 100.0 * d / total);
    }
    let mut edges: HashMap<(String, String), f64> = HashMap::new();
    for (&(site, callee), &d) in &calls {
        if d > 0.01 {
            *edges.entry((name_of(site), name_of(callee))).or_default() += d;
        }
    }
    println!("\n| caller | callee | calls/{per_what} |\n|---|---|---:|");
    let mut v: Vec<_> = edges.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for ((caller, callee), d) in v.iter().take(15) {
        println!("| `{caller}` | `{callee}` | {d:.1} |");
    }
    println!(
        "\n| source line (innermost outside std) | instructions/{per_what} | share |\n|---|---:|---:|"
    );
    let mut v: Vec<_> = by_line.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for (n, d) in v.iter().take(source_lines) {
        println!("| `{n}` | {d:.0} | {:.1} % |", 100.0 * d / total);
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("step_profile: {}", Chain(&e));
            ExitCode::FAILURE
        }
    }
}
