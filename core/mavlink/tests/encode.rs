//! The encoder's frames decode (with the generated dialect and mavlink-core's CRC) to exactly
//! what was encoded, and rejected calls change nothing.

use mavlink_core::{calculate_crc, MavlinkVersion, Message};
use proptest::prelude::*;
use rotorid::convergence::ConvergenceStatus;
use rotorid_mavlink::dialect::MavMessage;
use rotorid_mavlink::{
    chunk_count, ArrayId, ArrayKind, EncodeError, Encoder, MavState, Model, Sender, ARRAY_LEN,
    MAX_FRAME_LEN,
};

/// Splits a stream into (sequence, system, component, message) and checks framing and CRC.
fn decode(mut bytes: &[u8]) -> Vec<(u8, u8, u8, MavMessage)> {
    let mut out = Vec::new();
    while !bytes.is_empty() {
        assert_eq!(bytes[0], 0xFD, "MAVLink 2 start byte");
        let len = usize::from(bytes[1]);
        assert_eq!(bytes[2], 0, "no incompatibility flags (unsigned)");
        let id = u32::from_le_bytes([bytes[7], bytes[8], bytes[9], 0]);
        let payload = &bytes[10..10 + len];
        let crc = u16::from_le_bytes([bytes[10 + len], bytes[11 + len]]);
        assert_eq!(
            crc,
            calculate_crc(&bytes[1..10 + len], MavMessage::extra_crc(id))
        );
        let msg = MavMessage::parse(MavlinkVersion::V2, id, payload).expect("parses");
        out.push((bytes[4], bytes[5], bytes[6], msg));
        bytes = &bytes[12 + len..];
    }
    out
}

fn name(n: &[u8]) -> String {
    String::from_utf8(n.iter().copied().take_while(|b| *b != 0).collect()).unwrap()
}

fn ts() -> Sender {
    Sender::new(0, "ts").unwrap()
}

proptest! {
    #[test]
    fn step_arrays_carry_every_bit(p in prop::array::uniform6(any::<u32>()),
                                   i in prop::option::of(prop::array::uniform6(any::<u32>())),
                                   time_us in any::<u64>(), slot in 0u8..16) {
        let ident = Sender::new(slot, "pl").unwrap();
        let pred = p.map(f32::from_bits);
        let inn = i.map(|i| i.map(f32::from_bits));
        let mut enc = Encoder::new(7, 25);
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = enc.step(&ident, time_us, &pred, inn.as_ref(), &mut buf).unwrap();
        let msgs = decode(&buf[..n]);
        prop_assert_eq!(msgs.len(), 1);
        let (seq, sys, comp, MavMessage::DEBUG_FLOAT_ARRAY(d)) = &msgs[0] else { panic!("kind") };
        prop_assert_eq!((*seq, *sys, *comp), (0, 7, 25));
        prop_assert_eq!(d.time_usec, time_us);
        prop_assert_eq!(ArrayId::from_u16(d.array_id),
                        Some(ArrayId { slot, kind: ArrayKind::Step, chunk: 0 }));
        prop_assert_eq!(name(&*d.name), "pl.out");
        for k in 0..6 {
            prop_assert_eq!(d.data[k].to_bits(), p[k]);
            let want = i.map_or(f32::NAN.to_bits(), |i| i[k]);
            prop_assert_eq!(d.data[6 + k].to_bits(), want);
        }
        prop_assert!(d.data[12..].iter().all(|v| v.to_bits() == 0));
        prop_assert_eq!(enc.sequence(), 1);
    }

    #[test]
    fn theta_chunks_reassemble(len in 0usize..200, seed in any::<u32>()) {
        let theta: Vec<f32> = (0..len).map(|k| f32::from_bits(seed.wrapping_mul(k as u32 + 1))).collect();
        let mut enc = Encoder::new(1, 1);
        let mut got = Vec::new();
        for c in 0..chunk_count(len) {
            let mut buf = [0u8; MAX_FRAME_LEN];
            let n = enc.theta(&ts(), Model::YawRate, c as u8, 5, &theta, &mut buf).unwrap();
            let msgs = decode(&buf[..n]);
            let MavMessage::DEBUG_FLOAT_ARRAY(d) = &msgs[0].3 else { panic!("kind") };
            prop_assert_eq!(name(&*d.name), format!("ts.thr{c}"));
            prop_assert_eq!(ArrayId::from_u16(d.array_id),
                            Some(ArrayId { slot: 0, kind: ArrayKind::Theta(Model::YawRate), chunk: c as u8 }));
            got.extend(d.data.iter().map(|v| v.to_bits()));
        }
        prop_assert_eq!(got.len(), chunk_count(len) * ARRAY_LEN);
        prop_assert!(got[..len].iter().zip(&theta).all(|(g, t)| *g == t.to_bits()));
        prop_assert!(got[len..].iter().all(|g| *g == 0));
        let before = enc.sequence();
        let past = chunk_count(len) as u8;
        prop_assert_eq!(enc.theta(&ts(), Model::YawRate, past, 5, &theta, &mut [0u8; MAX_FRAME_LEN]),
                        Err(EncodeError::ChunkOutOfRange));
        prop_assert_eq!(enc.sequence(), before);
    }

    #[test]
    fn a_short_buffer_is_refused_and_nothing_counted(cut in 0usize..60) {
        let mut enc = Encoder::new(1, 1);
        let mut full = [0u8; MAX_FRAME_LEN];
        let n = enc.step(&ts(), 1, &[1.5; 6], None, &mut full).unwrap();
        let mut short = vec![0u8; n.saturating_sub(1 + cut)];
        let r = enc.step(&ts(), 1, &[1.5; 6], None, &mut short);
        prop_assert_eq!(r, Err(EncodeError::BufferTooSmall { needed: n, available: short.len() }));
        prop_assert_eq!(enc.sequence(), 1);
        let status = ConvergenceStatus::<f32, 6> {
            ratio: [0.5; 6], change: [0.0; 6], settled: [0; 6], converged: [true; 6], windows: 3,
        };
        let mut conv = vec![0u8; 100 + cut];
        prop_assert!(enc.convergence(&ts(), 9, &status, &mut conv).is_err());
        prop_assert_eq!(enc.sequence(), 1);
    }
}

#[test]
fn convergence_names_values_and_mask() {
    let status = ConvergenceStatus::<f32, 6> {
        ratio: [0.25, 0.5, 0.75, 1.0, 1.25, f32::from_bits(0x3f80_0001)],
        change: [0.0; 6],
        settled: [0; 6],
        converged: [true, false, true, false, false, true],
        windows: 4,
    };
    let mut enc = Encoder::new(3, 4);
    let mut buf = [0u8; 7 * 40];
    let n = enc.convergence(&ts(), 1234, &status, &mut buf).unwrap();
    let msgs = decode(&buf[..n]);
    assert_eq!(msgs.len(), 7);
    for (k, (seq, _, _, m)) in msgs.iter().enumerate() {
        let MavMessage::NAMED_VALUE_FLOAT(v) = m else {
            panic!("kind")
        };
        assert_eq!(usize::from(*seq), k);
        assert_eq!(v.time_boot_ms, 1234);
        if k < 6 {
            assert_eq!(name(&*v.name), format!("ts.rho{k}"));
            assert_eq!(v.value.to_bits(), status.ratio[k].to_bits());
        } else {
            assert_eq!(name(&*v.name), "ts.conv");
            assert_eq!(v.value, (1 | 4 | 32) as f32);
        }
    }
}

#[test]
fn rejected_samples_become_ascii_warnings_cut_to_the_field() {
    let mut enc = Encoder::new(1, 1);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let cases = [
        (
            rotorid::Error::TimeStep {
                dt_us: 41_000,
                min_us: 10_000,
                max_us: 30_000,
            },
            "ts: sample interval 41000 us outside the accepted ",
        ),
        (
            rotorid::Error::NonFinite(rotorid::Quantity::Parameter(3)),
            "ts: parameter theta[3] is not finite",
        ),
    ];
    for (err, want) in cases {
        let n = enc.rejected(&ts(), &err, &mut buf).unwrap();
        let MavMessage::STATUSTEXT(s) = &decode(&buf[..n])[0].3 else {
            panic!("kind")
        };
        assert_eq!(s.severity as u8, 4, "MAV_SEVERITY_WARNING");
        assert_eq!(name(&*s.text), want, "{err}");
    }
}

#[test]
fn heartbeat_is_an_onboard_component() {
    let mut enc = Encoder::new(1, 25);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = enc.heartbeat(MavState::MAV_STATE_ACTIVE, &mut buf).unwrap();
    let MavMessage::HEARTBEAT(h) = &decode(&buf[..n])[0].3 else {
        panic!("kind")
    };
    assert_eq!(h.mavtype as u8, 18);
    assert_eq!(h.autopilot as u8, 8);
    assert_eq!(h.system_status as u8, 4);
    assert_eq!(h.mavlink_version, 3);
}

#[test]
fn idents_and_array_ids() {
    assert!(Sender::new(15, "abc").is_ok());
    for (slot, tag) in [(16, "ts"), (0, ""), (0, "abcd"), (0, "t s"), (0, "é")] {
        assert_eq!(
            Sender::new(slot, tag),
            Err(EncodeError::InvalidSender),
            "{slot} {tag:?}"
        );
    }
    for id in 0..=u16::MAX {
        if let Some(a) = ArrayId::from_u16(id) {
            assert_eq!(a.to_u16(), id);
        }
    }
    assert_eq!(
        ArrayId::from_u16(0x0100).map(|a| a.kind),
        Some(ArrayKind::Step)
    );
    assert_eq!(ArrayId::from_u16(0x0101), None, "a step has no chunks");
    assert_eq!(ArrayId::from_u16(0x0600), None);
}

/// The sizes docs/protocol.md quotes for its bandwidth figures.
#[test]
fn documented_frame_sizes() {
    let mut enc = Encoder::new(1, 25);
    let mut buf = [0u8; MAX_FRAME_LEN];
    assert_eq!(enc.heartbeat(MavState::MAV_STATE_ACTIVE, &mut buf), Ok(21));
    let inn = [0.5f32; 6];
    assert_eq!(enc.step(&ts(), 1, &[1.0; 6], Some(&inn), &mut buf), Ok(80));
    assert_eq!(enc.step(&ts(), 1, &[1.0; 6], None, &mut buf), Ok(80));
    let theta = [1.0f32; ARRAY_LEN];
    assert_eq!(
        enc.theta(&ts(), Model::Velocity, 0, 1, &theta, &mut buf),
        Ok(264)
    );
    let status = ConvergenceStatus::<f32, 6> {
        ratio: [0.5; 6],
        change: [0.0; 6],
        settled: [0; 6],
        converged: [false; 6],
        windows: 1,
    };
    let mut frames = [0u8; 7 * MAX_FRAME_LEN];
    assert_eq!(enc.convergence(&ts(), 1, &status, &mut frames), Ok(7 * 27));
}

/// The same frame from mavlink-core's own serializer (the well-kept reference the encoder's
/// hand-written framing must match byte for byte).
fn reference_frame(seq: u8, sys: u8, comp: u8, msg: &MavMessage) -> Vec<u8> {
    let header = mavlink_core::MavHeader {
        system_id: u32::from(sys),
        component_id: comp,
        sequence: seq,
    };
    let mut raw = mavlink_core::MAVLinkV2MessageRaw::new();
    raw.serialize_message(header, msg);
    raw.raw_bytes().to_vec()
}

proptest! {
    #[test]
    fn frames_are_mavlink_cores_bytes(p in prop::array::uniform6(any::<u32>()),
                                      i in prop::option::of(prop::array::uniform6(any::<u32>())),
                                      time_us in any::<u64>(), sys in any::<u8>(),
                                      comp in any::<u8>(), skip in 0u8..255) {
        let ident = Sender::new(3, "fl").unwrap();
        let mut enc = Encoder::new(sys, comp);
        let mut buf = [0u8; MAX_FRAME_LEN];
        // Any sequence number, wrapping included.
        for _ in 0..skip {
            enc.heartbeat(MavState::MAV_STATE_ACTIVE, &mut buf).unwrap();
        }
        let frames = [
            enc.step(&ident, time_us, &p.map(f32::from_bits),
                     i.map(|i| i.map(f32::from_bits)).as_ref(), &mut buf).map(|n| buf[..n].to_vec()),
            enc.heartbeat(MavState::MAV_STATE_CRITICAL, &mut buf).map(|n| buf[..n].to_vec()),
            enc.rejected(&ident, &rotorid::Error::NonMonotonicTime, &mut buf).map(|n| buf[..n].to_vec()),
            enc.convergence(&ident, time_us as u32,
                            &ConvergenceStatus { ratio: [f32::from_bits(p[0])], change: [0.0], settled: [0],
                                                converged: [true], windows: 1 },
                            &mut buf).map(|n| buf[..n].to_vec()),
        ];
        for f in frames {
            let bytes = f.unwrap();
            let mut rest = &bytes[..];
            while !rest.is_empty() {
                let len = 12 + usize::from(rest[1]);
                let (seq, s, c, msg) = decode(&rest[..len]).remove(0);
                prop_assert_eq!(&rest[..len], &reference_frame(seq, s, c, &msg)[..]);
                rest = &rest[len..];
            }
        }
    }
}
