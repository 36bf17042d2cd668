//! Where the firmware's instructions go, per step, on the emulated Cortex-M4F.
//!
//! Runs the firmware in QEMU with an execution trace (`-singlestep -d exec,nochain`: one log
//! line per executed instruction, with its address), streams `A` and then `B` samples of the
//! identification flight in two boots, and reports `(count_B − count_A)/(B − A)` per function
//! (`arm-none-eabi-nm`) and per source line (`arm-none-eabi-addr2line`, innermost inlined
//! location). Boot and set-up cancel out; what remains is one sample: both identifiers' steps
//! plus the link's handling of the frames.
//!
//! Usage: `step_profile [--covariance] [A B]` (default 5 25). QEMU writes one log line per
//! instruction (about 100 MB per 10 samples, in the temporary directory, removed afterwards).

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use host_tests::firmware_link::BootOptions;
use host_tests::onboard::{Onboard, OnboardError};
use rotorid_cli::error_chain::Chain;
use rotorid_link::msg::{RlsForm, SampleMode, SampleMsg};
use rotorid_sim::flights::{identification_flight, to_hover_samples};
use rotorid_sim::plant::PlantError;

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
    #[error("cannot run {tool}")]
    Tool {
        tool: &'static str,
        source: std::io::Error,
    },
}

/// Traces a run of `n` samples.
fn trace(form: RlsForm, n: usize) -> Result<Trace, ProfileError> {
    let dir = std::env::temp_dir().join(format!("rotorid-profile-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| ProfileError::TraceDir {
        path: dir.clone(),
        source,
    })?;
    let log = dir.join("exec.log");
    let opts = BootOptions {
        icount: true,
        extra_args: vec![
            "-singlestep".into(),
            "-d".into(),
            "exec,nochain".into(),
            "-D".into(),
            log.display().to_string(),
        ],
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
    let _ = std::fs::remove_dir_all(&dir);
    Ok(Trace { counts, calls, elf })
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

fn run() -> Result<(), ProfileError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let form = if args.iter().any(|a| a == "--covariance") {
        RlsForm::PaperCovariance
    } else {
        RlsForm::UdDefault
    };
    let nums: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let (a, b) = match nums[..] {
        [a, b] if b > a => (a, b),
        _ => (5, 25),
    };
    let ta = trace(form, a)?;
    let tb = trace(form, b)?;
    let (ca, cb, elf) = (&ta.counts, &tb.counts, &tb.elf);
    let per = (b - a) as f64;
    let mut diff: Vec<(u32, f64)> = cb
        .iter()
        .map(|(&pc, &n)| (pc, (n as f64 - *ca.get(&pc).unwrap_or(&0) as f64) / per))
        .filter(|&(_, d)| d > 0.0)
        .collect();
    diff.sort_by_key(|&(pc, _)| pc);
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
    println!("Instructions per sample ({form:?}, samples {a}..{b}): {total:.0} (both identifiers and the link)\n");
    println!("| function | instructions/sample | share |\n|---|---:|---:|");
    let mut v: Vec<_> = by_func.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for (n, d) in v.iter().take(20) {
        println!("| `{n}` | {d:.0} | {:.1} % |", 100.0 * d / total);
    }
    let mut edges: HashMap<(String, String), f64> = HashMap::new();
    for (&(site, callee), &n) in &tb.calls {
        let d = (n as f64 - *ta.calls.get(&(site, callee)).unwrap_or(&0) as f64) / per;
        if d > 0.0 {
            *edges.entry((name_of(site), name_of(callee))).or_default() += d;
        }
    }
    println!("\n| caller | callee | calls/sample |\n|---|---|---:|");
    let mut v: Vec<_> = edges.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for ((caller, callee), d) in v.iter().take(15) {
        println!("| `{caller}` | `{callee}` | {d:.1} |");
    }
    println!(
        "\n| source line (innermost outside std) | instructions/sample | share |\n|---|---:|---:|"
    );
    let mut v: Vec<_> = by_line.into_iter().collect();
    v.sort_by(|x, y| y.1.total_cmp(&x.1));
    for (n, d) in v.iter().take(25) {
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
