//! The firmware's flight path cannot panic: no function of the firmware ELF (identification,
//! link, MAVLink, logging transport, start-up) reaches a panic, by `scripts/no_panic.py`'s walk
//! of the static call graph. The one panic in the ELF is the fault-injection test hook's
//! deliberate one.

use std::path::Path;
use std::process::Command;

use host_tests::firmware_link::build_firmware;

#[test]
fn firmware_elf_has_no_panic_path() {
    let elf = build_firmware().expect("firmware builds");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/no_panic.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(&elf)
        .arg("--strict")
        .output()
        .expect("python3 runs (scripts/setup.sh installs it)");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "panic paths in the firmware:\n{report}"
    );
    assert!(report.starts_with("0 of our functions"), "{report}");
}
