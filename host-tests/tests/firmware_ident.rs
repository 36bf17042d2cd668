//! Onboard identification in QEMU, checked bit for bit against the host build.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (`scripts/setup.sh`).
//! `ROTORID_LONG=1` adds the full identification + verification flights (CI).

use std::time::Instant;

use host_tests::golden;
use host_tests::onboard::{messages, simulated_flight, Mirror, Onboard, OnboardError};
use rotorid::hover::HoverSample;
use rotorid::sweep::SweepSchedule;
use rotorid::telemetry::msg::{
    Ident, MsgType, NackReason, RlsForm, SampleMode, SampleMsg, SweepStart,
};

fn hex_all(xs: &[f32]) -> String {
    xs.iter()
        .map(|x| format!("{:08x}", x.to_bits()))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The firmware's run over the golden inputs, in the golden file's format.
fn firmware_golden(form: RlsForm) -> (String, String) {
    let mut ob = Onboard::boot(form, false).expect("boot");
    let inp = golden::inputs(golden::STEPS, golden::SEED);
    let res = ob
        .stream(&messages(&inp, SampleMode::Learn), |_| {})
        .expect("stream");
    let mut fuzzy = String::new();
    let mut plain = String::new();
    for (k, e) in res.estimates.iter().enumerate() {
        for (out, o) in [(&mut fuzzy, &e.fuzzy), (&mut plain, &e.plain)] {
            assert_eq!(o.error, None, "golden step {k}");
            *out += &format!(
                "step {k} pred {} inn {}\n",
                hex_all(&o.prediction),
                hex_all(&o.innovation.unwrap_or([0.0; 6]))
            );
        }
    }
    for (out, ident) in [(&mut fuzzy, Ident::Fuzzy), (&mut plain, Ident::Plain)] {
        let params = ob.params(ident).expect("params");
        for (name, m) in ["velocity", "pitch", "yaw", "roll"].iter().zip(&params) {
            *out += &format!("{name} theta {}\n", hex_all(&m.theta));
            *out += &format!("{name} pdiag {}\n", hex_all(&m.diagonal));
        }
    }
    (fuzzy, plain)
}

fn check_file(name: &str, got: &str) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name);
    let want = std::fs::read_to_string(&path).expect("golden file");
    for (i, (w, g)) in want.lines().zip(got.lines()).enumerate() {
        assert_eq!(
            w,
            g,
            "{name}:{}: firmware differs from the golden bits",
            i + 1
        );
    }
    assert_eq!(
        want.lines().count(),
        got.lines().count(),
        "{name}: line count"
    );
}

#[test]
fn firmware_reproduces_golden_vectors() {
    let t0 = Instant::now();
    let (fuzzy, plain) = firmware_golden(RlsForm::UdDefault);
    check_file("golden_fuzzy_f32_ud.txt", &fuzzy);
    check_file("golden_plain_f32_ud.txt", &plain);
    let (fuzzy, _) = firmware_golden(RlsForm::PaperCovariance);
    check_file("golden_fuzzy_f32_paper.txt", &fuzzy);
    eprintln!("firmware golden vectors: {:?}", t0.elapsed());
}

/// Learns over a flight, dumps parameters and exports, all compared with the host.
fn learn_flight_and_compare(ob: &mut Onboard, flight: &[HoverSample<f32>]) {
    ob.stream(&messages(flight, SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    for ident in [Ident::Fuzzy, Ident::Plain] {
        let fw = ob.params(ident).expect("params");
        let host = ob.mirror.params(ident);
        for (m, (a, b)) in fw.iter().zip(&host).enumerate() {
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.theta), bits(&b.theta), "{ident:?} model {m} θ");
            assert_eq!(
                bits(&a.diagonal),
                bits(&b.diagonal),
                "{ident:?} model {m} diag P"
            );
            assert_eq!(a.summary, b.summary, "{ident:?} model {m} summary");
        }
        assert_eq!(ob.export(ident).expect("export"), ob.mirror.export(ident));
    }
}

#[test]
fn sixty_seconds_of_flight_bit_for_bit() {
    let t0 = Instant::now();
    let flight = simulated_flight(11, 64.0).expect("flight");
    assert!(flight.len() >= 3000, "{} samples", flight.len());
    let t_sim = t0.elapsed();
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    learn_flight_and_compare(&mut ob, &flight);
    // Frozen-θ prediction (the verification half of Table 4) on the same flight.
    let res = ob
        .stream(&messages(&flight[..500], SampleMode::Predict), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(res.estimates.iter().all(|e| e.fuzzy.innovation.is_none()));
    let s = ob.link.stats().expect("stats");
    assert_eq!(s.link.rejected(), 0);
    assert_eq!(s.link.lost_frames, 0);
    eprintln!(
        "{} samples ({:.0} s of flight) bit for bit: simulate {t_sim:?}, total {:?}",
        flight.len(),
        flight.len() as f64 / 50.0,
        t0.elapsed()
    );
}

#[test]
fn rejected_sample_leaves_onboard_state_unchanged() {
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    let inp = golden::inputs(200, golden::SEED);
    ob.stream(&messages(&inp[..100], SampleMode::Learn), |_| {})
        .expect("stream");
    let before = (
        ob.export(Ident::Fuzzy).unwrap(),
        ob.export(Ident::Plain).unwrap(),
    );
    let mut bad = Vec::new();
    // Non-finite rate, out-of-range attitude, time going backwards, a 1 s gap.
    let mut s = inp[100];
    s.rates[1] = f32::NAN;
    bad.push(s);
    let mut s = inp[100];
    s.attitude.roll = 100.0;
    bad.push(s);
    let mut s = inp[100];
    s.time_us = inp[98].time_us;
    bad.push(s);
    let mut s = inp[100];
    s.time_us += 1_000_000;
    bad.push(s);
    let res = ob
        .stream(&messages(&bad, SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    let errors: Vec<_> = res.estimates.iter().map(|e| e.fuzzy.error).collect();
    assert!(errors.iter().all(|e| e.is_some()), "{errors:?}");
    assert!(
        matches!(errors[0], Some(rotorid::Error::NonFinite(_))),
        "{errors:?}"
    );
    assert!(
        matches!(errors[1], Some(rotorid::Error::OutOfRange(_))),
        "{errors:?}"
    );
    assert_eq!(errors[2], Some(rotorid::Error::NonMonotonicTime));
    assert!(
        matches!(errors[3], Some(rotorid::Error::TimeStep { .. })),
        "{errors:?}"
    );
    let after = (
        ob.export(Ident::Fuzzy).unwrap(),
        ob.export(Ident::Plain).unwrap(),
    );
    assert!(
        before == after,
        "a rejected sample changed the onboard state"
    );
    // And the chain continues exactly as if nothing happened.
    ob.stream(&messages(&inp[100..], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    let mut clean = Mirror::new(RlsForm::UdDefault).unwrap();
    for s in &inp {
        clean.apply(&SampleMsg {
            mode: SampleMode::Learn,
            sample: *s,
        });
    }
    assert_eq!(ob.export(Ident::Fuzzy).unwrap(), clean.export(Ident::Fuzzy));
}

#[test]
fn warm_start_sweep_memory() {
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    let inp = golden::inputs(300, golden::SEED);
    ob.stream(&messages(&inp[..150], SampleMode::Learn), |_| {})
        .expect("stream");
    // Plain identifier: export, reset, import back (warm start), continue bit for bit.
    let snap = ob.export(Ident::Plain).expect("export");
    let crc = rotorid::telemetry::msg::stream_crc(&snap);
    // A corrupted stream (bad CRC) is refused and changes nothing.
    let mut bad = snap.clone();
    bad[10] ^= 1;
    assert_eq!(
        ob.import(Ident::Plain, &bad, crc).expect("import"),
        Err(NackReason::BadPayload as u8)
    );
    assert_eq!(ob.export(Ident::Plain).unwrap(), snap);
    ob.reset(RlsForm::UdDefault).expect("reset");
    assert_ne!(ob.export(Ident::Plain).unwrap(), snap);
    assert_eq!(ob.import(Ident::Plain, &snap, crc).expect("import"), Ok(()));
    assert_eq!(ob.export(Ident::Plain).unwrap(), snap);
    // The host mirror does the same warm start through the core's API.
    let mut fresh = Mirror::new(RlsForm::UdDefault).unwrap();
    for s in &inp[..150] {
        fresh.apply(&SampleMsg {
            mode: SampleMode::Learn,
            sample: *s,
        });
    }
    ob.mirror.plain.import(&fresh.plain.export()).unwrap();
    // The fuzzy identifier refuses (RAM budget), politely.
    let fsnap = ob.export(Ident::Fuzzy).expect("export");
    assert_eq!(
        ob.import(
            Ident::Fuzzy,
            &fsnap,
            rotorid::telemetry::msg::stream_crc(&fsnap)
        )
        .expect("import"),
        Err(NackReason::Refused as u8)
    );
    ob.stream(&messages(&inp[150..], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));

    // Onboard sweep generator = host schedule, bit for bit.
    let amps = [0.05f32, 0.1, 0.2, 0.2];
    let host = SweepSchedule::table2(amps.map(f64::from), 50).unwrap();
    for (start, count) in [(0u32, 400u32), (host.len() - 100, 1000)] {
        let got = ob
            .sweep(&SweepStart {
                amplitudes: amps,
                rate_hz: 50,
                start,
                count,
            })
            .expect("sweep");
        assert_eq!(got.len() as u32, count.min(host.len() - start));
        for s in got {
            let e = host.at(s.k).expect("in range");
            assert_eq!(
                (s.channel, s.offset.to_bits()),
                (e.channel, e.offset.to_bits())
            );
            assert_eq!(s.total, host.len());
        }
    }
    let m = ob.memory().expect("memory");
    eprintln!("memory: {m:?}");
    assert!(m.stack_peak > 0 && m.stack_peak < m.stack_size, "{m:?}");
    assert!(m.static_ram + m.stack_peak <= 32 * 1024, "{m:?}");
    let _ = (MsgType::Memory, OnboardError::Protocol(String::new()));
}

/// CI only (`ROTORID_LONG=1`): the full identification flight (learning) and a 120 s
/// verification flight (frozen θ), bit for bit, then parameters and exported state.
#[test]
fn full_flights_bit_for_bit_when_long() {
    if std::env::var_os("ROTORID_LONG").is_none() {
        eprintln!("skipped: set ROTORID_LONG=1 for the full identification + verification run");
        return;
    }
    use host_tests::experiments::{identification_flight, to_hover_samples, verification_flight};
    let t0 = Instant::now();
    let id = to_hover_samples(&identification_flight(1).expect("flight"));
    let ver = to_hover_samples(&verification_flight(2, 120.0).expect("flight"));
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    learn_flight_and_compare(&mut ob, &id);
    let mut msgs = messages(&ver, SampleMode::Predict);
    msgs[0].mode = SampleMode::Resume;
    ob.stream(&msgs, |_| {}).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "full flights ({} + {} samples) bit for bit in {:?}",
        id.len(),
        ver.len(),
        t0.elapsed()
    );
}
