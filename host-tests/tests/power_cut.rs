//! Power cuts during persistence-record writes, under QEMU: the flight identifier restored
//! after a cut is bit for bit the newest completely written record, never a torn one, and
//! learning on from it gives the same bits as the host learning on from that record.
//!
//! Each trial: a fresh flash image (a host file, all 0xFF); boot 1 of the `power-cut`
//! firmware learns the stream `step_cost::sample` and writes a record every `STEPS` samples,
//! until power fails after a seeded random number of flash bytes (erased plus programmed,
//! uniform over the whole run; a word being programmed keeps its old bytes); boot 2, a real
//! reboot from the same image, restores, learns on to the end and prints the final
//! snapshot's hash. The host replays the same stream with the same core to know every
//! record's bits.
//!
//! `ROTORID_POWER_CUT_TRIALS` (default 50) and `ROTORID_POWER_CUT_SEED` (default 1) set the
//! run; `scripts/power-cut.sh` runs 1 000 trials and writes `docs/power-cut.md` from the
//! summary line this test prints. Needs `qemu-system-arm` (`scripts/setup.sh`).

use crate::step_cost;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use host_tests::firmware_link::{build_firmware, firmware_dir};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorid::hover::flight_sets;
use rotorid::snapshot::{Snapshot, WordSink};
use rotorid::{FlightIdentifier, HoverConfig};

/// `ROTORID_KIND_FLIGHT`, as the firmware writes it.
const KIND: u32 = 1;
/// Records per run and samples between records (the firmware's command line).
const RECORDS: u32 = 4;
const STEPS: u32 = 50;
/// Bytes of the flash image (the firmware's two 2 KiB slots).
const CAPACITY: usize = 4096;
/// The firmware's exit code after a cut (`file_flash::CUT_EXIT`).
const CUT_EXIT: i32 = 3;

struct Fnv(u32);

impl WordSink for Fnv {
    fn put_word(&mut self, word: [u8; 4]) {
        for b in word {
            self.0 = (self.0 ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
    }
}

fn hash(id: &FlightIdentifier<f32>) -> u32 {
    let mut h = Fnv(0x811c_9dc5);
    id.put_snapshot(KIND, &mut h);
    h.0
}

fn fresh() -> FlightIdentifier<f32> {
    FlightIdentifier::flight(HoverConfig::default(), flight_sets()).expect("flight identifier")
}

fn learn(id: &mut FlightIdentifier<f32>, from: u32, to: u32) {
    for k in from..to {
        id.step(&step_cost::sample(k))
            .expect("the stream is accepted");
    }
}

/// The host's replay: the hash of record `s` for every `s`, and the final hash of a run that
/// restores record `s` (index `s`) or starts afresh (index `RECORDS`).
struct Replay {
    record: Vec<u32>,
    finish_from: Vec<u32>,
}

fn replay() -> Replay {
    let mut id = fresh();
    let mut record = Vec::new();
    let mut finish_from = Vec::new();
    for s in 0..RECORDS {
        learn(&mut id, s * STEPS, (s + 1) * STEPS);
        record.push(hash(&id));
        // Restore this record into a fresh identifier (as boot 2 does) and learn on.
        let mut bytes = vec![0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
        id.write_snapshot(KIND, &mut bytes).expect("snapshot");
        let mut on = fresh();
        on.read_snapshot(KIND, &bytes)
            .expect("own snapshot reads back");
        assert_eq!(hash(&on), hash(&id));
        learn(&mut on, (s + 1) * STEPS, RECORDS * STEPS);
        finish_from.push(hash(&on));
    }
    // Never restored: learnt from the start in one run.
    finish_from.push(*record.last().expect("records"));
    Replay {
        record,
        finish_from,
    }
}

/// What one boot printed.
#[derive(Default, Debug)]
struct Boot {
    code: Option<i32>,
    restored: Option<(u32, u32)>,
    fresh: bool,
    /// (sequence, hash, flash bytes applied when complete) of each record written.
    wrote: Vec<(u32, u32, u64)>,
    done: Option<u32>,
}

fn hex(s: &str) -> u32 {
    u32::from_str_radix(s, 16).expect("hex")
}

fn boot(elf: &Path, image: &Path, budget: Option<u64>) -> Boot {
    let budget = budget.map_or("-".to_string(), |b| b.to_string());
    let out = Command::new("qemu-system-arm")
        .args([
            "-cpu",
            "cortex-m4",
            "-machine",
            "mps2-an386",
            "-display",
            "none",
        ])
        .args(["-monitor", "none", "-serial", "null"])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf)
        .arg("-append")
        .arg(format!(
            "{} {budget} {RECORDS} {STEPS}",
            image.to_str().expect("UTF-8 path")
        ))
        .output()
        .expect("qemu-system-arm runs (scripts/setup.sh installs it)");
    let mut b = Boot {
        code: out.status.code(),
        ..Boot::default()
    };
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["restored", s, h] => b.restored = Some((s.parse().expect("seq"), hex(h))),
            ["fresh"] => b.fresh = true,
            ["wrote", s, _slot, h, a] => {
                b.wrote
                    .push((s.parse().expect("seq"), hex(h), a.parse().expect("applied")))
            }
            ["done", h] => b.done = Some(hex(h)),
            _ => panic!("power-cut firmware: unexpected line {line:?}"),
        }
    }
    b
}

fn erased_image(path: &Path) {
    std::fs::write(path, vec![0xFF_u8; CAPACITY]).expect("image written");
}

#[test]
fn power_cuts_never_leave_a_torn_model() {
    let trials: u64 = std::env::var("ROTORID_POWER_CUT_TRIALS")
        .ok()
        .map_or(50, |t| {
            t.parse().expect("ROTORID_POWER_CUT_TRIALS: a number")
        });
    let seed: u64 = std::env::var("ROTORID_POWER_CUT_SEED")
        .ok()
        .map_or(1, |t| t.parse().expect("ROTORID_POWER_CUT_SEED: a number"));
    let t0 = Instant::now();
    build_firmware().expect("firmware builds");
    let elf = firmware_dir().join("target/thumbv7em-none-eabihf/release/power-cut");
    let dir: PathBuf =
        std::env::temp_dir().join(format!("rotorid-power-cut-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let image = dir.join("flash.bin");
    let want = replay();

    // The uninterrupted run: every record's bits equal the host's, and where each ends.
    erased_image(&image);
    let full = boot(&elf, &image, None);
    assert_eq!(full.code, Some(0), "uninterrupted run: {full:?}");
    assert!(full.fresh);
    let ends: Vec<u64> = full.wrote.iter().map(|w| w.2).collect();
    assert_eq!(full.wrote.len(), RECORDS as usize);
    for (s, w) in full.wrote.iter().enumerate() {
        assert_eq!(w.0, s as u32);
        assert_eq!(
            w.1, want.record[s],
            "record {s}: Cortex-M4F and host differ"
        );
    }
    assert_eq!(full.done, Some(want.finish_from[RECORDS as usize]));
    let total = *ends.last().expect("records");

    // The cuts are drawn up front, so that the trials are the same whatever the jobs.
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let cuts: Vec<u64> = (0..trials).map(|_| rng.random_range(0..total)).collect();
    let jobs: usize = std::env::var("ROTORID_POWER_CUT_JOBS")
        .ok()
        .map_or(2, |t| t.parse().expect("ROTORID_POWER_CUT_JOBS: a number"))
        .max(1);
    let outcomes: Vec<Outcome> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..jobs)
            .map(|j| {
                let (elf, dir, cuts, ends, want) = (&elf, &dir, &cuts, &ends, &want);
                scope.spawn(move || {
                    let image = dir.join(format!("flash-{j}.bin"));
                    (j..cuts.len())
                        .step_by(jobs)
                        .map(|t| trial(t, elf, &image, cuts[t], ends, want))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("trial thread"))
            .collect()
    });
    let torn = outcomes.iter().filter(|o| o.torn).count();
    let wrong_continuation = outcomes.iter().filter(|o| o.wrong_continuation).count();
    let max_lost = outcomes.iter().map(|o| o.lost).max().unwrap_or(0);
    let in_erase = outcomes.iter().filter(|o| o.in_erase).count();
    let restored_none = outcomes.iter().filter(|o| o.restored.is_none()).count();
    let _ = std::fs::remove_dir_all(&dir);
    let elapsed = t0.elapsed().as_secs_f64();
    // One line for scripts/power-cut.sh.
    println!(
        "power-cut summary: trials {trials} seed {seed} jobs {jobs} torn {torn} wrong-continuation \
         {wrong_continuation} max-records-lost {max_lost} cuts-in-erase {in_erase} \
         restored-none {restored_none} record-bytes {} flash-bytes-per-run {total} seconds {elapsed:.1}",
        ends[0] - 2048
    );
    assert_eq!(torn, 0, "restores that were not the newest complete record");
    assert_eq!(wrong_continuation, 0, "learning on from a restored record");
    assert!(max_lost <= 1, "at most the record being written is lost");
}

/// What one trial found.
struct Outcome {
    torn: bool,
    wrong_continuation: bool,
    /// Records begun before the cut that boot 2 did not restore.
    lost: u64,
    in_erase: bool,
    restored: Option<u32>,
}

/// One trial: power fails after `cut` flash bytes of boot 1; boot 2 restores and learns on.
fn trial(trial: usize, elf: &Path, image: &Path, cut: u64, ends: &[u64], want: &Replay) -> Outcome {
    erased_image(image);
    let first = boot(elf, image, Some(cut));
    assert_eq!(
        first.code,
        Some(CUT_EXIT),
        "trial {trial} (cut {cut}): {first:?}"
    );
    // The newest record completely written before the cut, and the one being written.
    let complete = ends.iter().rposition(|&e| e <= cut);
    let begun = ends
        .iter()
        .position(|&e| e > cut)
        .expect("the cut is within the run");
    let start = if begun == 0 { 0 } else { ends[begun - 1] };
    assert_eq!(
        first.wrote.len(),
        complete.map_or(0, |s| s + 1),
        "trial {trial}: boot 1 reports the records completed before the cut"
    );
    let second = boot(elf, image, None);
    assert_eq!(
        second.code,
        Some(0),
        "trial {trial} (cut {cut}): {second:?}"
    );
    let restored = second.restored.map(|r| r.0);
    let ok = match (complete, second.restored) {
        (None, None) => second.fresh,
        (Some(s), Some((seq, h))) => seq == s as u32 && h == want.record[s],
        _ => false,
    };
    if !ok {
        eprintln!(
            "trial {trial}: cut at byte {cut}: restored {restored:?}, want record {complete:?}"
        );
    }
    let from = restored.map_or(RECORDS as usize, |s| s as usize);
    let wrong_continuation = second.done != Some(want.finish_from[from]);
    if wrong_continuation {
        eprintln!("trial {trial}: cut at byte {cut}: learning on differs from the host's");
    }
    Outcome {
        torn: !ok,
        wrong_continuation,
        // Records begun (0 ..= the one being cut) less records restored (0 ..= restored).
        lost: (begun as u64 + 1).saturating_sub(restored.map_or(0, |s| u64::from(s) + 1)),
        // Each record write erases its 2 KiB slot first.
        in_erase: cut - start < 2048,
        restored,
    }
}
