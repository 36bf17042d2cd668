//! The firmware's MAVLink port (UART1, QEMU's second `-serial`, captured to a file) sends,
//! byte for byte, what the host build encodes for the same samples, and pymavlink decodes it
//! to the host's values (floats bit for bit). Skips like `mavlink_pymavlink` without pymavlink
//! (the byte comparison still runs).

use std::path::Path;

use host_tests::firmware_link::BootOptions;
use host_tests::mavlink::{
    check_with_pymavlink, identification_stream, learn_with_one_rejection, python_with_pymavlink,
};
use host_tests::onboard::{simulated_flight, Onboard};
use rotorid_cli::error_chain::Chain;
use rotorid_link::msg::{Ident, RlsForm};

#[test]
fn firmware_uart1_is_the_host_stream_and_pymavlink_reads_it() {
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("firmware-mavlink");
    std::fs::create_dir_all(&work).expect("work dir");
    let capture = work.join("uart1.bin");
    let _ = std::fs::remove_file(&capture);
    let opts = BootOptions {
        extra_args: vec!["-serial".into(), format!("file:{}", capture.display())],
        ..BootOptions::default()
    };
    let flight = simulated_flight(5, 30.0).expect("flight");
    let samples = learn_with_one_rejection(&flight);
    let mut ob =
        Onboard::boot_with(RlsForm::UdDefault, &opts).unwrap_or_else(|e| panic!("{}", Chain(&e)));
    ob.stream(&samples, |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    for ident in [Ident::Fuzzy, Ident::Plain] {
        ob.params(ident).unwrap_or_else(|e| panic!("{}", Chain(&e)));
    }
    let mem = ob.memory().unwrap_or_else(|e| panic!("{}", Chain(&e)));
    // The θ arrays precede the Params replies on the wire, so the capture is complete.
    drop(ob);
    eprintln!(
        "stack high-water mark of the link + identification + MAVLink service: {} of {} B",
        mem.stack_peak, mem.stack_size
    );
    let fw = std::fs::read(&capture).expect("UART1 capture");
    let host = identification_stream(&samples, false);
    assert_eq!(
        fw.len(),
        host.bytes.len(),
        "firmware and host stream lengths"
    );
    if let Some(k) = (0..fw.len()).find(|&k| fw[k] != host.bytes[k]) {
        panic!("firmware and host streams differ first at byte {k}");
    }
    eprintln!(
        "{} samples: firmware UART1 = host stream, {} bytes, {} messages",
        samples.len(),
        fw.len(),
        host.expected.len()
    );
    let Some(py) = python_with_pymavlink() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "pymavlink is required under CI"
        );
        eprintln!("SKIPPED pymavlink part: no python3 with pymavlink (scripts/setup.sh)");
        return;
    };
    match check_with_pymavlink(&py, &fw, &host.expected, &work) {
        Ok(summary) => eprintln!("firmware stream: {summary}"),
        Err(e) => panic!(
            "pymavlink check of the firmware stream failed:\n{}",
            Chain(&e)
        ),
    }
}
