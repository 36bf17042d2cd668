//! Every identifier, including the local-learning ones and the flight default, and the flight
//! default's one-step observer compute the same bits on the Cortex-M4F (QEMU) as on x86_64,
//! on a stream that fires every rule: the
//! firmware's `step-cost` binary prints a hash of all its predictions per identifier, and the
//! very same module (`firmware-example/src/step_cost.rs`) runs here.

use crate::step_cost;

use std::collections::BTreeMap;
use std::process::Command;

use host_tests::firmware_link::{build_firmware, step_cost_elf, step_cost_qemu};
use step_cost::{StepCost, Timer};

struct NoTimer;

impl Timer for NoTimer {
    fn restart(&mut self) {}
    fn elapsed(&mut self) -> u64 {
        0
    }
}

#[test]
fn every_identifier_is_bit_identical_on_the_cortex_m4f() {
    if Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_err()
    {
        panic!("qemu-system-arm is missing: run scripts/setup.sh");
    }
    let mut host = BTreeMap::new();
    step_cost::run(&mut NoTimer, &mut |c: &StepCost| {
        assert_eq!(c.rejected, 0, "{}", c.name);
        host.insert(c.name.to_string(), format!("{:08x}", c.hash));
    });
    let out = step_cost_qemu()
        .expect("firmware builds")
        .output()
        .expect("qemu runs");
    assert!(out.status.success(), "step-cost exited with {}", out.status);
    let text = String::from_utf8_lossy(&out.stdout);
    let mut target = BTreeMap::new();
    for line in text.lines().skip(2) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if let (Some(name), Some(hash)) = (cells.get(1), cells.get(6)) {
            target.insert(name.to_string(), hash.to_string());
        }
    }
    assert_eq!(host.len(), 9, "{host:?}");
    assert_eq!(host, target, "firmware output:\n{text}");
}

/// `Real::sqrt_ieee` for `f32` is the FPU's `vsqrt.f32` on the Cortex-M4F and `libm`'s
/// `sqrtf` here: the same bits over half a million inputs spread over every exponent (both are
/// correctly rounded, as IEEE 754 requires), and here also std's `f32::sqrt`.
#[test]
fn the_square_root_is_bit_identical_on_the_cortex_m4f() {
    let host = step_cost::sqrt_hash();
    let mut std_hash = 0x811c_9dc5u32;
    let mut n = 0;
    for bits in step_cost::sqrt_inputs() {
        let x = f32::from_bits(bits);
        let (ours, std) = (rotorid::Real::sqrt_ieee(x), x.sqrt());
        assert_eq!(
            ours.to_bits(),
            std.to_bits(),
            "sqrt of {x:e} ({bits:#010x})"
        );
        for b in ours.to_bits().to_le_bytes() {
            std_hash = (std_hash ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
        n += 1;
    }
    assert_eq!(n, step_cost::SQRT_INPUTS);
    assert_eq!(std_hash, host, "std's sqrt hashes otherwise");
    let out = step_cost_qemu()
        .expect("firmware builds")
        .args(["-append", "sqrt"])
        .output()
        .expect("qemu runs");
    assert!(
        out.status.success(),
        "step-cost sqrt exited with {}",
        out.status
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        text.trim(),
        format!("sqrt_ieee: {host:08x}"),
        "firmware output:\n{text}"
    );
}

/// The firmware links libgcc's `f64` soft-float (feature `libgcc-soft-float`, on by default),
/// as docs/cost.md says its figures do: none of `compiler_builtins`' float additions or
/// multiplications is left in the step-cost binary, and the `__aeabi_` entry points are there.
#[test]
fn the_firmware_takes_its_double_precision_soft_float_from_libgcc() {
    build_firmware().expect("firmware builds");
    let out = Command::new("arm-none-eabi-nm")
        .args(["-C", "--defined-only"])
        .arg(step_cost_elf())
        .output()
        .expect("arm-none-eabi-nm runs (scripts/setup.sh installs it)");
    assert!(out.status.success());
    let symbols = String::from_utf8_lossy(&out.stdout);
    let defined = |name: &str| symbols.lines().any(|l| l.ends_with(name));
    assert!(
        defined(" __aeabi_dmul") && defined(" __aeabi_dadd"),
        "{symbols}"
    );
    let from_builtins: Vec<&str> = symbols
        .lines()
        .filter(|l| {
            l.contains("compiler_builtins::float::mul")
                || l.contains("compiler_builtins::float::add")
        })
        .collect();
    assert!(from_builtins.is_empty(), "{from_builtins:?}");
}
