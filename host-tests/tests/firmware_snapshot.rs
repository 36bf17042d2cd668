//! The identifier's saved state over the link, under QEMU: the link's snapshot kinds and sizes
//! are the C interface's, and the flight pair exports and imports over the link bit for bit.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (`scripts/setup.sh`).

use host_tests::onboard::{messages, payload, Onboard};
use rotorid_cli::error_chain::Chain;
use rotorid_link::msg::{Ident, MsgType, NackReason, Payload, RlsForm, SampleMode, SampleMsg};

/// `value` of `#define name value` in the C interface's header.
fn c_define(header: &str, name: &str) -> u64 {
    header
        .lines()
        .find_map(|l| {
            let mut w = l.split_whitespace();
            (w.next() == Some("#define") && w.next() == Some(name))
                .then(|| w.next().and_then(|v| v.parse().ok()))
                .flatten()
        })
        .unwrap_or_else(|| panic!("{name} not in rotorid.h"))
}

/// The link's snapshot kinds and lengths are the C interface's (`core/ffi/include/rotorid.h`),
/// so that a snapshot exported over the link imports through `rotorid_import` and back.
#[test]
fn link_snapshot_kinds_and_sizes_are_the_c_interfaces() {
    use rotorid::snapshot::Snapshot;
    use rotorid::{
        ExtendedPlainIdentifier, FlightIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier,
    };
    use rotorid_link::msg::{snapshot_kind, IdentPair};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/ffi/include/rotorid.h");
    let h = std::fs::read_to_string(&path).expect("rotorid.h");
    for (pair, ident, name, size) in [
        (
            IdentPair::Paper,
            Ident::Fuzzy,
            "PAPER_FUZZY",
            PaperFuzzyIdentifier::<f32>::SNAPSHOT_SIZE,
        ),
        (
            IdentPair::Paper,
            Ident::Plain,
            "PAPER_PLAIN",
            PaperPlainIdentifier::<f32>::SNAPSHOT_SIZE,
        ),
        (
            IdentPair::Flight,
            Ident::Fuzzy,
            "FLIGHT",
            FlightIdentifier::<f32>::SNAPSHOT_SIZE,
        ),
        (
            IdentPair::Flight,
            Ident::Plain,
            "EXTENDED_PLAIN",
            ExtendedPlainIdentifier::<f32>::SNAPSHOT_SIZE,
        ),
    ] {
        assert_eq!(
            u64::from(snapshot_kind(pair, ident)),
            c_define(&h, &format!("ROTORID_KIND_{name}")),
            "{name}"
        );
        assert_eq!(
            size as u64,
            c_define(&h, &format!("ROTORID_{name}_EXPORT_SIZE")),
            "{name}"
        );
    }
}

/// The snapshot `bytes` with the u32 at `at` replaced by `word` and the CRC-32 trailer
/// recomputed: intact for the link and for the core's CRC, wrong only in that field.
fn with_word(bytes: &[u8], at: usize, word: u32) -> Vec<u8> {
    let mut b = bytes.to_vec();
    b[at..at + 4].copy_from_slice(&word.to_le_bytes());
    let n = b.len() - 4;
    let crc = rotorid::snapshot::crc32(&b[..n]);
    b[n..].copy_from_slice(&crc.to_le_bytes());
    b
}

/// The flight pair over the link (issue 31): run A learns part of the envelope flight and
/// exports both identifiers; the bytes are the core's snapshot of the host's identifiers
/// after the same stream (the C interface's export). A fresh firmware run B refuses broken
/// and foreign snapshots bit for bit unchanged, imports A's, and from then on predicts
/// exactly what A predicts (learning, one step ahead and free run), bit for bit.
#[test]
fn flight_pair_exports_and_imports_over_the_link_bit_for_bit() {
    use rotorid::snapshot::{Snapshot, MAGIC};
    use rotorid::FlightIdentifier;
    use rotorid_link::msg::{stream_crc, DataChunk, IdentPair, KIND_EXTENDED_PLAIN, KIND_FLIGHT};
    use rotorid_sim::envelope::{envelope_flight, EnvelopeKind};
    use rotorid_sim::flights::to_hover_samples;
    let flight =
        to_hover_samples(&envelope_flight(1, EnvelopeKind::Identification).expect("flight"));
    // After the export: a new chain (Resume), learning, then θ frozen: one step ahead from
    // measured states and a 2 s free run.
    let mut next = vec![SampleMsg {
        mode: SampleMode::Resume,
        sample: flight[400],
    }];
    next.extend(messages(&flight[401..600], SampleMode::Learn));
    next.push(SampleMsg {
        mode: SampleMode::Resume,
        sample: flight[600],
    });
    next.extend(messages(&flight[601..650], SampleMode::Predict));
    next.extend(messages(&flight[650..750], SampleMode::FreeRun));
    let idents = [Ident::Fuzzy, Ident::Plain];

    // Run A.
    let mut a = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    a.reset_pair(RlsForm::UdDefault, IdentPair::Flight)
        .expect("reset");
    a.stream(&messages(&flight[..400], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    let snaps = idents.map(|i| a.export(i).expect("export"));
    for ((i, s), kind) in idents
        .iter()
        .zip(&snaps)
        .zip([KIND_FLIGHT, KIND_EXTENDED_PLAIN])
    {
        assert_eq!(
            s,
            &a.mirror.export(*i),
            "{i:?}: firmware export = host's core snapshot"
        );
        assert_eq!((&s[..4], &s[8..12]), (&MAGIC[..], &kind.to_le_bytes()[..]));
    }
    assert_eq!(snaps[0].len(), FlightIdentifier::<f32>::SNAPSHOT_SIZE);
    let ra = a
        .stream(&next, |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    let a_end = idents.map(|i| a.export(i).expect("export"));
    drop(a); // one QEMU at a time

    // Run B: a fresh firmware that has learnt something else (the flight's first 40 samples).
    let mut b = Onboard::boot(RlsForm::UdDefault, false).expect("boot");
    b.reset_pair(RlsForm::UdDefault, IdentPair::Flight)
        .expect("reset");
    b.stream(&messages(&flight[..40], SampleMode::Learn), |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    let before = idents.map(|i| b.export(i).expect("export"));
    assert_ne!(before, snaps);
    let s = &snaps[0];
    let refused = NackReason::Refused as u8;
    let bad_payload = NackReason::BadPayload as u8;
    let mut core_crc_wrong = s.clone();
    core_crc_wrong[700] ^= 0x10;
    let cases: [(&str, Ident, Vec<u8>, u8); 7] = [
        // Intact for the link, refused by the core's decoder.
        (
            "paper fuzzy kind",
            Ident::Fuzzy,
            with_word(s, 8, 3),
            refused,
        ),
        (
            "format version 1",
            Ident::Fuzzy,
            with_word(s, 4, 1),
            refused,
        ),
        (
            "θ₀ NaN",
            Ident::Fuzzy,
            with_word(s, 20, f32::NAN.to_bits()),
            refused,
        ),
        (
            "unknown RLS form",
            Ident::Fuzzy,
            with_word(s, 12, 7),
            refused,
        ),
        ("snapshot CRC", Ident::Fuzzy, core_crc_wrong, refused),
        // Refused by the link's staging.
        (
            "plain's snapshot as fuzzy",
            Ident::Fuzzy,
            snaps[1].clone(),
            bad_payload,
        ),
        (
            "fuzzy's snapshot as plain",
            Ident::Plain,
            snaps[0].clone(),
            bad_payload,
        ),
    ];
    for (what, ident, bytes, reason) in &cases {
        let crc = stream_crc(bytes);
        assert_eq!(
            b.import(*ident, bytes, crc).expect("import"),
            Err(*reason),
            "{what}"
        );
        if *reason == refused {
            assert!(
                b.mirror.import(*ident, bytes).is_err(),
                "{what}: the host refuses too"
            );
        }
        assert_eq!(
            idents.map(|i| b.export(i).expect("export")),
            before,
            "{what}: changed"
        );
    }
    // A stream CRC that does not match its bytes: refused at the last chunk.
    assert_eq!(
        b.import(Ident::Fuzzy, s, stream_crc(s) ^ 1)
            .expect("import"),
        Err(bad_payload)
    );
    assert_eq!(idents.map(|i| b.export(i).expect("export")), before);
    // An import left halfway (3 of its 9 chunks acknowledged, then other requests): staged
    // only, nothing imported.
    for k in 0..3 {
        let at = k * DataChunk::MAX_DATA;
        let c = DataChunk {
            ident: Ident::Fuzzy,
            offset: at as u32,
            total: s.len() as u32,
            crc: stream_crc(s),
            data: &s[at..at + DataChunk::MAX_DATA],
        };
        b.link
            .send(MsgType::ImportChunk.code(), &payload(|w| c.write(w)))
            .expect("send");
        assert_eq!(b.link.recv().expect("reply").kind(), Some(MsgType::Ack));
    }
    assert_eq!(idents.map(|i| b.export(i).expect("export")), before);
    // The real imports, on both sides, and B continues as A did.
    for (i, s) in idents.iter().zip(&snaps) {
        assert_eq!(
            b.import(*i, s, stream_crc(s)).expect("import"),
            Ok(()),
            "{i:?}"
        );
        b.mirror.import(*i, s).expect("host import");
        assert_eq!(&b.export(*i).expect("export"), s, "{i:?}");
    }
    // The import restarted the prediction chains: no free run from the old model's last
    // prediction (refused on both sides, nothing changed).
    let none = b
        .stream(&messages(&flight[400..401], SampleMode::FreeRun), |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    assert_eq!((none.estimates.len(), none.refused.len()), (0, 1));
    let rb = b
        .stream(&next, |_| {})
        .unwrap_or_else(|e| panic!("{}", Chain(&e)));
    assert!(ra.refused.is_empty() && rb.refused.is_empty());
    assert_eq!(ra.estimates.len(), next.len());
    let bits = |r: &host_tests::onboard::StreamResult| -> Vec<[u32; 24]> {
        r.estimates
            .iter()
            .map(|e| {
                let mut w = [0u32; 24];
                for (k, x) in [e.fuzzy.prediction, e.plain.prediction]
                    .iter()
                    .chain(&[
                        e.fuzzy.innovation.unwrap_or([0.0; 6]),
                        e.plain.innovation.unwrap_or([0.0; 6]),
                    ])
                    .flatten()
                    .enumerate()
                {
                    w[k] = x.to_bits();
                }
                w
            })
            .collect()
    };
    assert_eq!(
        bits(&ra),
        bits(&rb),
        "B's predictions after the import = A's"
    );
    assert!(rb
        .estimates
        .iter()
        .all(|e| e.fuzzy.error.is_none() && e.plain.error.is_none()));
    assert_eq!(idents.map(|i| b.export(i).expect("export")), a_end);
}
