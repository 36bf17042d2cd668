//! End-to-end tests of firmware-example in QEMU over the telemetry link.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target; decodes the firmware log
//! with `defmt-print` when installed (only for error messages).

use std::time::{Duration, Instant};

use host_tests::firmware_link::{wire_frame, FirmwareLink};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorid_link::msg::{MsgType, Nack, NackReason, Payload, Workload};
use rotorid_link::{FrameDecoder, MAX_PAYLOAD};

/// Bitwise CRC-32/ISO-HDLC, independent of the `crc` crate, to forge unknown-version frames.
fn crc32(data: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in data {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Plain COBS encoder (no delimiter), independent of the `cobs` crate.
fn cobs_encode(raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0u8];
    let mut code_at = 0;
    for &b in raw {
        if b == 0 || out.len() - code_at == 0xFF {
            out[code_at] = (out.len() - code_at) as u8;
            code_at = out.len();
            out.push(0);
            if b == 0 {
                continue;
            }
        }
        out.push(b);
    }
    out[code_at] = (out.len() - code_at) as u8;
    out
}

fn payload(rng: &mut ChaCha8Rng, len: usize) -> Vec<u8> {
    // Plenty of zeros so COBS is exercised.
    (0..len)
        .map(|_| {
            if rng.random_bool(0.2) {
                0
            } else {
                rng.random()
            }
        })
        .collect()
}

#[test]
fn hello_and_200_pings() {
    let t0 = Instant::now();
    let mut link = FirmwareLink::boot().expect("boot");
    assert_eq!(link.hello().version, rotorid_link::VERSION);
    assert_eq!(usize::from(link.hello().max_payload), MAX_PAYLOAD);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for i in 0..200usize {
        let len = match i {
            0 => 0,
            1 => MAX_PAYLOAD,
            _ => (i * 37) % (MAX_PAYLOAD + 1),
        };
        let p = payload(&mut rng, len);
        let echo = link.ping(&p).expect("ping");
        assert_eq!(echo, p, "ping {i} (len {len})");
    }
    let s = link.stats().expect("stats");
    assert_eq!(s.link.frames_ok, 201);
    assert_eq!(s.link.rejected(), 0);
    assert_eq!(s.link.lost_frames, 0);
    assert_eq!(s.frames_sent, 201, "hello + 200 pongs");
    let rx = link.rx_stats();
    assert_eq!((rx.frames_ok, rx.rejected(), rx.lost_frames), (202, 0, 0));
    eprintln!("boot + 200 pings: {:?}", t0.elapsed());
}

#[test]
fn garbage_between_good_frames_is_counted_and_survived() {
    let mut link = FirmwareLink::boot().expect("boot");
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    // The oracle sees exactly the bytes the firmware sees.
    let mut oracle = FrameDecoder::<{ rotorid_link::MAX_ENCODED_LEN }>::new();
    let sent = |link: &mut FirmwareLink, oracle: &mut FrameDecoder, bytes: &[u8]| {
        for &b in bytes {
            let _ = oracle.push(b);
        }
        link.send_raw(bytes).expect("send");
    };
    let (mut n_good, mut n_lost, mut n_oversized, mut n_short, mut n_version) = (0, 0, 0, 0, 0);
    let (mut n_unknown_type, mut n_bad_payload, mut replies) = (0u32, 0u32, 1u32);
    for round in 0..120 {
        match round % 6 {
            0 => {
                // Random garbage, terminated so the next good frame starts clean.
                let len = rng.random_range(1..100);
                let mut g: Vec<u8> = (0..len).map(|_| rng.random()).collect();
                g.push(0);
                sent(&mut link, &mut oracle, &g);
            }
            1 => {
                // A real frame with one bit flipped (its sequence number is lost).
                let seq = link.encoder().next_seq();
                let mut w = wire_frame(MsgType::Ping.code(), seq, &payload(&mut rng, 30)).unwrap();
                let i = rng.random_range(0..w.len() - 1);
                w[i] ^= 1 << rng.random_range(0..8);
                link.encoder().encode(0, &[], &mut [0u8; 64]).unwrap();
                sent(&mut link, &mut oracle, &w);
                n_lost += 1;
            }
            2 => {
                // A real frame cut short, then a delimiter.
                let seq = link.encoder().next_seq();
                let w = wire_frame(MsgType::Ping.code(), seq, &payload(&mut rng, 50)).unwrap();
                let cut = rng.random_range(1..w.len() - 1);
                let mut t = w[..cut].to_vec();
                t.push(0);
                link.encoder().encode(0, &[], &mut [0u8; 64]).unwrap();
                sent(&mut link, &mut oracle, &t);
                n_lost += 1;
            }
            3 => {
                // Oversized burst without delimiter, and a valid-COBS chunk that is too short.
                let mut o: Vec<u8> = (0..300).map(|_| rng.random_range(1..=255)).collect();
                o.push(0);
                o.extend_from_slice(&[4, 1, 2, 3, 0]);
                sent(&mut link, &mut oracle, &o);
                n_oversized += 1;
                n_short += 1;
            }
            4 => {
                // Intact frame of the next protocol version (seq 0, not ours: does not count
                // as loss).
                let mut raw = vec![rotorid_link::VERSION + 1, MsgType::Ping.code(), 0, 0, 9, 9];
                raw.extend_from_slice(&crc32(&raw).to_le_bytes());
                let mut enc = cobs_encode(&raw);
                enc.push(0);
                sent(&mut link, &mut oracle, &enc);
                n_version += 1;
            }
            _ => {
                // Valid frames the firmware must refuse politely.
                let t = if round % 12 == 5 {
                    0x77
                } else {
                    MsgType::CostRequest.code()
                };
                let seq = link.encoder().next_seq();
                let w = wire_frame(t, seq, &[1, 2]).unwrap();
                link.encoder().encode(0, &[], &mut [0u8; 64]).unwrap();
                sent(&mut link, &mut oracle, &w);
                let f = link.recv().expect("nack");
                assert_eq!(f.kind(), Some(MsgType::Nack));
                let nack = Nack::read(&f.payload).unwrap();
                assert_eq!((nack.seq, nack.msg_type), (seq, t));
                if t == 0x77 {
                    assert_eq!(nack.reason, NackReason::UnknownType as u8);
                    n_unknown_type += 1;
                } else {
                    assert_eq!(nack.reason, NackReason::BadPayload as u8);
                    n_bad_payload += 1;
                }
                n_good += 1;
                replies += 1;
            }
        }
        // Every good frame after the junk is answered.
        let len = rng.random_range(0..=MAX_PAYLOAD);
        let p = payload(&mut rng, len);
        let seq = link.encoder().next_seq();
        let w = wire_frame(MsgType::Ping.code(), seq, &p).unwrap();
        link.encoder().encode(0, &[], &mut [0u8; 64]).unwrap();
        sent(&mut link, &mut oracle, &w);
        let f = link.recv().expect("pong after injection");
        assert_eq!(
            (f.kind(), &f.payload),
            (Some(MsgType::Pong), &p),
            "round {round}"
        );
        n_good += 1;
        replies += 1;
    }
    let seq = link.encoder().next_seq();
    let w = wire_frame(MsgType::StatsRequest.code(), seq, &[]).unwrap();
    link.encoder().encode(0, &[], &mut [0u8; 64]).unwrap();
    sent(&mut link, &mut oracle, &w);
    let f = link.recv().expect("stats");
    let s = rotorid_link::msg::StatsReport::read(&f.payload).expect("stats payload");
    n_good += 1;

    // Exactly what an identical decoder counted on the host...
    assert_eq!(s.link, *oracle.stats());
    // ...and what was injected.
    assert_eq!(s.link.frames_ok, n_good);
    assert_eq!(s.link.lost_frames, n_lost);
    assert_eq!(s.link.seq_gaps, n_lost);
    assert_eq!(s.link.seq_resets, 0);
    assert_eq!(s.link.oversized, n_oversized);
    assert_eq!(s.link.unknown_version, n_version);
    assert!(s.link.too_short >= n_short);
    assert!(s.link.cobs_errors + s.link.crc_errors >= 40, "{s:?}");
    assert_eq!(s.unknown_type, n_unknown_type);
    assert_eq!(s.bad_payload, n_bad_payload);
    assert_eq!(s.uart_errors, 0);
    assert_eq!(s.frames_sent, replies);
    let rx = link.rx_stats();
    assert_eq!((rx.rejected(), rx.lost_frames), (0, 0));
    eprintln!("firmware stats after injection: {s:?}");
}

fn fault_exits(kind: u8, code: i32, needle: &str) {
    let mut link = FirmwareLink::boot().expect("boot");
    link.send(MsgType::FaultInject.code(), &[kind])
        .expect("send");
    let status = link
        .wait_exit(Duration::from_secs(20))
        .expect("QEMU must exit, not hang");
    assert_eq!(status.code(), Some(code), "log:\n{}", link.log());
    let log = link.log();
    if !log.contains("bytes of binary defmt log") {
        assert!(log.contains(needle), "log:\n{log}");
    }
}

#[test]
fn hard_fault_exits_qemu_with_failure_code() {
    fault_exits(1, 102, "HardFault");
}

#[test]
fn panic_exits_qemu_with_failure_code() {
    fault_exits(0, 101, "deliberate panic");
}

#[test]
fn cost_is_deterministic_under_icount() {
    let t0 = Instant::now();
    let cases = [
        (Workload::Empty, 0),
        (Workload::Xorshift, 1000),
        (Workload::Xorshift, 2000),
        (Workload::FloatMac, 1000),
        (Workload::EncodeFrame, 10),
    ];
    let run = || {
        let mut link = FirmwareLink::boot_icount().expect("boot");
        // Some unrelated traffic first so the two runs reach the measurement differently.
        for i in 0..5 {
            link.ping(&[i; 17]).expect("ping");
        }
        let mut out = Vec::new();
        for &(w, n) in &cases {
            let a = link.cost(w, n).expect("cost");
            let b = link.cost(w, n).expect("cost");
            assert_eq!(a, b, "same run, {w:?} x{n}");
            out.push(a);
        }
        out
    };
    let first = run();
    let second = run();
    assert_eq!(first, second, "run to run");
    let ticks: Vec<u64> = first.iter().map(|c| c.ticks).collect();
    // More work costs more, and twice the xorshift rounds cost about twice the rounds' share.
    assert!(
        ticks[1] > ticks[0] && ticks[3] > ticks[0] && ticks[4] > ticks[0],
        "{first:?}"
    );
    let per_1000 = ticks[2] - ticks[1];
    assert!(
        per_1000 > 0 && per_1000.abs_diff(ticks[1] - ticks[0]) <= 2,
        "{ticks:?}"
    );
    eprintln!(
        "icount cost ticks (1 tick = 40 instructions): {first:?} in {:?}",
        t0.elapsed()
    );
}
