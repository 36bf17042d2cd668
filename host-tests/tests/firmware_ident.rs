//! Onboard identification in QEMU, checked bit for bit against the host build.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (`scripts/setup.sh`).
//! `ROTORID_LONG=1` adds the full identification + verification flights
//! (`scripts/onboard-flights.sh`).
//! The saved state over the link: `firmware_snapshot.rs`.

use std::time::Instant;

use host_tests::firmware_link::wire_frame;
use host_tests::golden;
use host_tests::onboard::{messages, payload, simulated_flight, Mirror, Onboard, OnboardError};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorid::hover::HoverSample;
use rotorid::sweep::SweepSchedule;
use rotorid_cli::error_chain::Chain;
use rotorid_link::msg::{
    CompensateEachMsg, Ident, MsgType, Nack, NackReason, Payload, RateCompensation, RlsForm,
    SampleMode, SampleMsg, SweepStart,
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
        .join("../core/tests/data")
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
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
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
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
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

/// Garbage, bit flips and truncated frames injected into the live link while the identifiers
/// run: the firmware keeps going, counts every fault, and still matches the host bit for bit on
/// every good frame (each corrupted `Sample` is sent again intact, as a sender retrying would).
#[test]
fn link_faults_during_identification_are_counted_and_survived() {
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let inp = golden::inputs(240, golden::SEED);
    let msgs = messages(&inp, SampleMode::Learn);
    let (mut n_garbage, mut n_flipped, mut n_truncated) = (0u32, 0u32, 0u32);
    for (i, m) in msgs.iter().enumerate() {
        match i % 5 {
            0 => {
                // Random non-zero bytes, then a delimiter: exactly one rejected frame.
                let len = rng.random_range(12..120);
                let mut g: Vec<u8> = (0..len).map(|_| rng.random_range(1..=255)).collect();
                g.push(0);
                ob.link.send_raw(&g).expect("send");
                n_garbage += 1;
            }
            1 | 2 => {
                // This very sample's frame, one bit flipped or cut short: its sequence number
                // is used up (the firmware sees a gap at the next good frame).
                let seq = ob.link.encoder().next_seq();
                let p = payload(|w| m.write(w));
                let mut w = wire_frame(MsgType::Sample.code(), seq, &p).expect("frame");
                ob.link
                    .encoder()
                    .encode(0, &[], &mut [0u8; 64])
                    .expect("seq");
                if i % 5 == 1 {
                    let at = rng.random_range(0..w.len() - 1);
                    w[at] ^= 1 << rng.random_range(0..8);
                    n_flipped += 1;
                } else {
                    w.truncate(rng.random_range(1..w.len() - 1));
                    w.push(0);
                    n_truncated += 1;
                }
                ob.link.send_raw(&w).expect("send");
            }
            _ => {}
        }
        // The good frame: the estimate is compared with the host bit for bit.
        let res = ob
            .stream(std::slice::from_ref(m), |_| {})
            .unwrap_or_else(|e| panic!("sample {i}: {}", Chain(&e)));
        assert_eq!(res.estimates.len(), 1);
        assert_eq!(res.estimates[0].fuzzy.error, None, "sample {i}");
    }
    let s = ob.link.stats().expect("stats");
    let lost = n_flipped + n_truncated;
    assert_eq!(s.link.lost_frames, lost, "{s:?}");
    assert_eq!(s.link.seq_gaps, lost, "{s:?}");
    assert!(s.link.rejected() >= n_garbage + lost, "{s:?}");
    assert_eq!(s.uart_errors, 0);
    // The faults changed nothing: the same state as a clean run over the same samples.
    let mut clean = Mirror::new(RlsForm::UdDefault).unwrap();
    for m in &msgs {
        clean.apply(m);
    }
    for ident in [Ident::Fuzzy, Ident::Plain] {
        assert_eq!(ob.export(ident).unwrap(), clean.export(ident), "{ident:?}");
    }
    eprintln!(
        "{} samples, {n_garbage} garbage, {n_flipped} bit flips, {n_truncated} truncated: {s:?}",
        msgs.len()
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
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
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
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
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
    // (The flight pair's export and import: `flight_pair_exports_and_imports_...` below.)
    let snap = ob.export(Ident::Plain).expect("export");
    let crc = rotorid_link::msg::stream_crc(&snap);
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
    ob.mirror.import(Ident::Plain, &snap).unwrap();
    // Fuzzy identifier (10 524 B, staged whole onboard): a corrupted stream is refused and
    // leaves it unchanged (here: as fresh as the Reset above made it), then the real one
    // imports, and both sides continue from the same state.
    let fsnap = fresh.export(Ident::Fuzzy);
    let fcrc = rotorid_link::msg::stream_crc(&fsnap);
    let fresh_fuzzy = ob.export(Ident::Fuzzy).expect("export");
    let mut bad = fsnap.clone();
    bad[9000] ^= 4;
    assert_eq!(
        ob.import(Ident::Fuzzy, &bad, fcrc).expect("import"),
        Err(NackReason::BadPayload as u8)
    );
    assert_eq!(ob.export(Ident::Fuzzy).unwrap(), fresh_fuzzy);
    assert_eq!(
        ob.import(Ident::Fuzzy, &fsnap, fcrc).expect("import"),
        Ok(())
    );
    assert_eq!(ob.export(Ident::Fuzzy).unwrap(), fsnap);
    ob.mirror.import(Ident::Fuzzy, &fsnap).unwrap();
    ob.stream(&messages(&inp[150..], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));

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
    // The largest import is the peak: the paper fuzzy identifier's 10 524 B snapshot staged
    // in static RAM, then one model's state (its velocity model, 6.2 KiB) on the stack in the
    // core's decoder. Measured here: 27 000 B static + 8 412 B stack = 35 412 B of the 64 KiB
    // (before the import used the core's decoder: 22 768 B static, under 32 KiB in all).
    assert!(m.static_ram + m.stack_peak <= 40 * 1024, "{m:?}");
    let _ = (MsgType::Memory, OnboardError::Protocol(String::new()));
}

/// `scripts/onboard-flights.sh` only (`ROTORID_LONG=1`; docs/onboard-flights.md): the full
/// identification flight (learning) and a 120 s verification flight (frozen θ), bit for bit,
/// then parameters and exported state.
#[test]
fn full_flights_bit_for_bit_when_long() {
    if std::env::var_os("ROTORID_LONG").is_none() {
        eprintln!("skipped: set ROTORID_LONG=1 for the full identification + verification run");
        return;
    }
    use rotorid_sim::flights::{identification_flight, to_hover_samples, verification_flight};
    let t0 = Instant::now();
    let id = to_hover_samples(&identification_flight(1).expect("flight"));
    let ver = to_hover_samples(&verification_flight(2, 120.0).expect("flight"));
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    learn_flight_and_compare(&mut ob, &id);
    let mut msgs = messages(&ver, SampleMode::Predict);
    msgs[0].mode = SampleMode::Resume;
    ob.stream(&msgs, |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    eprintln!(
        "full flights ({} + {} samples) bit for bit in {:?}",
        id.len(),
        ver.len(),
        t0.elapsed()
    );
}

/// The flight pair (`FlightIdentifier` + `ExtendedPlainIdentifier`, chosen by `Reset`) on a
/// piece of the envelope flight: learning, one step with the measured previous state, then
/// the onboard free run, bit for bit; a `FreeRun` without a start and the paper-only
/// requests are refused on both sides.
#[test]
fn flight_pair_learns_predicts_and_free_runs_bit_for_bit() {
    use rotorid_link::msg::IdentPair;
    use rotorid_sim::envelope::{envelope_flight, EnvelopeKind};
    use rotorid_sim::flights::to_hover_samples;
    let flight =
        to_hover_samples(&envelope_flight(1, EnvelopeKind::Identification).expect("flight"));
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    ob.reset_pair(RlsForm::UdDefault, IdentPair::Flight)
        .expect("reset");
    // Nothing to continue from yet: refused by the firmware as by the host, nothing changed.
    let refused = ob
        .stream(&messages(&flight[..1], SampleMode::FreeRun), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((refused.estimates.len(), refused.refused), (0, vec![0]));
    // Learning (the hover part of the flight and the first acceleration).
    let learned = ob
        .stream(&messages(&flight[..400], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(learned.estimates.iter().all(|e| e.fuzzy.error.is_none()));
    // θ frozen: one step from measured states, then a 2 s free-run window.
    let ver = &flight[400..560];
    let mut msgs = messages(&ver[..50], SampleMode::Predict);
    msgs[0].mode = SampleMode::Resume;
    msgs.extend(messages(&ver[50..], SampleMode::FreeRun));
    let res = ob.stream(&msgs, |_| {}).unwrap_or_else(|e| panic!("{e}"));
    assert!(res.refused.is_empty());
    // The free run really ran on the model's own state: its predictions drift from the
    // one-step ones the measured states give.
    let mirror = &ob.mirror.flight;
    let last = &res.estimates[res.estimates.len() - 1];
    let one_step = mirror
        .predict(&ver[ver.len() - 1])
        .expect("predict")
        .to_array();
    assert_ne!(
        last.fuzzy.prediction.map(f32::to_bits),
        one_step.map(f32::to_bits)
    );
    assert!(res
        .estimates
        .iter()
        .all(|e| e.fuzzy.error.is_none() && e.plain.error.is_none()));
    // `Compensate`: a σ the core refuses is refused onboard (nothing changes, the streams
    // below still match); an accepted one changes the flight identifier's free run, onboard
    // as on the host, bit for bit (`stream` compares every reply with the mirror).
    assert!(ob.compensate([f32::NAN, 0.3, 0.3]).is_err());
    ob.compensate([0.3; 3]).expect("compensate");
    let again = ob.stream(&msgs, |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let free = |r: &host_tests::onboard::StreamResult| -> Vec<[u32; 6]> {
        r.estimates[50..]
            .iter()
            .map(|e| e.fuzzy.prediction.map(f32::to_bits))
            .collect()
    };
    assert_ne!(free(&again), free(&res));
    // `CompensateEach`: the per-rate choice reaches the firmware. A refused σ changes
    // nothing; full compensation of q and p (r damping only) gives other parameters than
    // damping alone would (checked on a copy of the host's identifier), and the firmware's
    // replies equal the host's bit for bit (`stream`), so it applied the same choice.
    let full_qp = [
        RateCompensation::Full,
        RateCompensation::Damping,
        RateCompensation::Full,
    ];
    assert!(ob.compensate_each([0.3, -1.0, 0.3], full_qp).is_err());
    // A code that is neither choice is a bad payload (and changes nothing either: the stream
    // below still matches the host's).
    let mut bad = payload(|w| {
        CompensateEachMsg {
            gyro_noise: [0.3; 3],
            how: full_qp,
        }
        .write(w)
    });
    bad[13] = 2;
    let f = ob
        .link
        .request(MsgType::CompensateEach, &bad, MsgType::Nack)
        .expect("nack");
    let nack = Nack::read(&f.payload).expect("nack payload");
    assert_eq!(nack.reason, NackReason::BadPayload as u8);
    let mut damping_only = ob.mirror.flight.clone();
    damping_only.compensate(&[0.3; 3]).expect("compensate");
    ob.compensate_each([0.3; 3], full_qp)
        .expect("compensate each");
    ob.stream(&msgs, |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let predict = |id: &rotorid::FlightIdentifier<f32>| {
        id.predict(&ver[0])
            .expect("predict")
            .to_array()
            .map(f32::to_bits)
    };
    assert_ne!(predict(&ob.mirror.flight), predict(&damping_only));
    // Params are the paper pair's: refused while the flight pair answers (export and import
    // are not: `flight_pair_exports_and_imports_over_the_link_bit_for_bit`).
    assert!(matches!(
        ob.params(Ident::Fuzzy),
        Err(OnboardError::Protocol(_))
    ));
}

/// `Premises` over the link: the flight pair's `FlightIdentifier` rebuilt on other sets and
/// speeds (what `flight selected` flies when it moves a model's rules) learns bit for bit as
/// the host's `FlightIdentifier::flight_scheduled`, keeps them across `Reset`, and learns
/// otherwise than the flight default; premises the core refuses (the velocity model on the
/// side speed) and an unknown speed are refused with nothing changed.
#[test]
fn premises_rebuild_the_flight_pair_bit_for_bit() {
    use rotorid::FlightIdentifier;
    use rotorid_link::msg::{IdentPair, PremisesMsg, Schedule};
    use rotorid_sim::envelope::{envelope_flight, EnvelopeKind};
    use rotorid_sim::flights::to_hover_samples;
    let flight =
        to_hover_samples(&envelope_flight(1, EnvelopeKind::Identification).expect("flight"));
    let mut ob = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    ob.reset_pair(RlsForm::UdDefault, IdentPair::Flight)
        .expect("reset");
    let m = PremisesMsg {
        on: [
            Schedule::VerticalSpeed,
            Schedule::SideSpeed,
            Schedule::Speed,
            Schedule::VerticalSpeed,
        ],
        centre: [
            -1.0, 0.0, 1.0, -2.0, 0.0, 2.0, 0.0, 5.0, 10.0, -1.0, 0.0, 1.0,
        ],
        spread: [0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 2.5, 2.5, 2.5, 0.5, 0.5, 0.5],
    };
    ob.premises(m).expect("premises");
    // Kept across a Reset (the mirror rebuilds them too).
    ob.reset_pair(RlsForm::UdDefault, IdentPair::Flight)
        .expect("reset");
    let learned = ob
        .stream(&messages(&flight[..400], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(learned.estimates.iter().all(|e| e.fuzzy.error.is_none()));
    let scheduled = ob.export(Ident::Fuzzy).expect("export");
    assert_eq!(scheduled, ob.mirror.export(Ident::Fuzzy));
    // The flight default on the same samples learns something else.
    let mut default = Mirror::with_pair(RlsForm::UdDefault, IdentPair::Flight).expect("mirror");
    for s in messages(&flight[..400], SampleMode::Learn) {
        default.apply(&s);
    }
    assert_ne!(scheduled, default.export(Ident::Fuzzy));
    let host = FlightIdentifier::flight_scheduled(
        rotorid::HoverConfig::default(),
        m.sets(),
        m.scheduling(),
    )
    .expect("host build");
    assert_eq!(
        rotorid::snapshot::Snapshot::config_hash(&host),
        rotorid::snapshot::Snapshot::config_hash(&ob.mirror.flight)
    );

    // Refused, nothing changed: the core's refusal, then a speed this build does not know.
    let mut sideways = m;
    sideways.on[0] = Schedule::SideSpeed;
    let refused = payload(|w| sideways.write(w));
    let f = ob
        .link
        .request(MsgType::Premises, &refused, MsgType::Nack)
        .expect("nack");
    assert_eq!(
        Nack::read(&f.payload).expect("nack payload").reason,
        NackReason::Refused as u8
    );
    let mut unknown = payload(|w| m.write(w));
    unknown[2] = 7;
    let f = ob
        .link
        .request(MsgType::Premises, &unknown, MsgType::Nack)
        .expect("nack");
    assert_eq!(
        Nack::read(&f.payload).expect("nack payload").reason,
        NackReason::BadPayload as u8
    );
    assert_eq!(ob.export(Ident::Fuzzy).expect("export"), scheduled);
    let memory = ob.memory().expect("memory");
    assert!(
        memory.static_ram + memory.stack_peak <= 40 * 1024,
        "{memory:?}"
    );
}
