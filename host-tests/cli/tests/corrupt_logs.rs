//! Corrupt, truncated and foreign inputs to the ULog, DataFlash and sdlog2 readers (issue 34,
//! part 5): the inputs that panicked the former parser crates, and each header field of each
//! format at its edge values. Every one gives an error naming the file and the byte offset,
//! or a result with a note giving the offset; never a panic.

use std::path::{Path, PathBuf};

use rotorid_cli::import::{self, dataflash, sdlog2, synth, ulog, ImportError, LogFormat, NotALog};
use rotorid_sim::plant::SensorSample;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorid-corrupt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// `seconds` of the identification flight on an exact 20 ms grid.
fn flight(seconds: f64) -> Vec<SensorSample> {
    let config = rotorid_sim::plant::FlightConfig {
        seed: 5,
        ..Default::default()
    };
    let mut s =
        rotorid_sim::flights::identification_flight_with(&config, seconds).expect("simulates");
    s.iter_mut()
        .enumerate()
        .for_each(|(k, x)| x.t = k as f64 * 0.02);
    s
}

fn import_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Result<import::Imported, ImportError> {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    import::import(&path)
}

/// The input is reported at `offset`: an error naming the file and the offset, or a result
/// with a note naming them.
fn assert_reported(dir: &Path, name: &str, bytes: &[u8], offset: usize) {
    let at = format!("byte {offset}");
    match import_bytes(dir, name, bytes) {
        Ok(imported) => assert!(
            imported
                .notes
                .iter()
                .any(|n| n.contains(name) && n.contains(&at)),
            "{name}: no note at {at}: {:?}",
            imported.notes
        ),
        Err(e) => {
            let e = e.to_string();
            assert!(e.contains(name) && e.contains(&at), "{name}: {e}");
        }
    }
}

fn ulog_msg(kind: u8, payload: &[u8]) -> Vec<u8> {
    let mut m = (payload.len() as u16).to_le_bytes().to_vec();
    m.push(kind);
    m.extend_from_slice(payload);
    m
}

/// Offset of the first message after the synthetic ULog's header and flag bits.
const ULOG_DEFS: usize = 16 + 3 + 40;

/// The synthetic ULog with `extra` inserted after its flag bits (reported at [`ULOG_DEFS`]).
fn ulog_with(extra: &[u8]) -> Vec<u8> {
    let mut log = synth::ulog(&flight(2.0), true);
    log.splice(ULOG_DEFS..ULOG_DEFS, extra.iter().copied());
    log
}

#[test]
fn ulog_parameter_messages_that_panicked_px4_ulog() {
    let dir = tmpdir("ulog-param");
    // An empty 'P' message, and one whose key length (200) exceeds its size.
    for (name, msg) in [
        ("empty_p.ulg", ulog_msg(b'P', &[])),
        ("long_key_p.ulg", ulog_msg(b'P', b"\xc8int32_t x")),
    ] {
        assert_reported(&dir, name, &ulog_with(&msg), ULOG_DEFS);
        // And the flight is still read whole.
        let imported = import_bytes(&dir, name, &ulog_with(&msg)).expect(name);
        assert_eq!(imported.segments[0].len(), flight(2.0).len(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ulog_message_sizes_at_their_edges_for_every_type() {
    let dir = tmpdir("ulog-sizes");
    for kind in *b"BFIMPQARDLCSO" {
        // Size 0, and size 1 with a key length past the end where the type has a key.
        for payload in [&[][..], &[0xFF][..]] {
            let name = format!("size{}_{}.ulg", payload.len(), char::from(kind));
            assert_reported(&dir, &name, &ulog_with(&ulog_msg(kind, payload)), ULOG_DEFS);
        }
    }
    // Unknown types: skipped by their size, with a note.
    for kind in [0x00u8, 0xFF, b'Z'] {
        let name = format!("type{kind:02x}.ulg");
        let log = ulog_with(&ulog_msg(kind, &[1, 2, 3, 4]));
        assert_reported(&dir, &name, &log, ULOG_DEFS);
    }
    // Size u16::MAX at the end: a cut record.
    let mut log = synth::ulog(&flight(2.0), true);
    let at = log.len();
    log.extend_from_slice(&[0xFF, 0xFF, b'D', 0, 0]);
    assert_reported(&dir, "max_size.ulg", &log, at);
    // Header lengths 7…15 (the magic, then cut): an error at the cut.
    let full = synth::ulog(&flight(1.0), true);
    for n in [7, 8, 15] {
        let name = format!("header{n}.ulg");
        assert_reported(&dir, &name, &full[..n], n);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ulog_formats_subscriptions_and_flags_that_cannot_be_read() {
    let dir = tmpdir("ulog-formats");
    for (k, format) in [
        &b"no colon"[..],
        b":float x;",
        b"a:float[99999999] x;",
        b"a:float[] x;",
        b"a:float;",
        b"a:\xff\xfe float x;",
    ]
    .iter()
    .enumerate()
    {
        let name = format!("format{k}.ulg");
        assert_reported(&dir, &name, &ulog_with(&ulog_msg(b'F', format)), ULOG_DEFS);
    }
    // A topic of an unknown nested type, and one whose name is no format: their
    // subscriptions are reported.
    let mut extra = ulog_msg(b'F', b"odd:uint64_t timestamp;mystery m;");
    let sub_at = ULOG_DEFS + extra.len();
    extra.extend(ulog_msg(b'A', b"\x00\x20\x00odd"));
    assert_reported(&dir, "nested.ulg", &ulog_with(&extra), sub_at);
    let extra = ulog_msg(
        b'A',
        b"\x00\x21\x00no_such_topic_name_runs_past_the_formats",
    );
    assert_reported(&dir, "undefined.ulg", &ulog_with(&extra), ULOG_DEFS);
    // Incompatible flag bits this reader does not know: an error at the flag message.
    let mut log = synth::ulog(&flight(1.0), true);
    log[16 + 3 + 8] = 0x02;
    let e = import_bytes(&dir, "flags.ulg", &log)
        .expect_err("unknown incompatible flags")
        .to_string();
    assert!(e.contains("flags.ulg") && e.contains("byte 16"), "{e}");
    // Data of no subscription, and of the wrong length, at the end of the log.
    for (name, data) in [
        (
            "no_sub.ulg",
            &b"\x63\x00\x01\x02\x03\x04\x05\x06\x07\x08"[..],
        ),
        ("wrong_len.ulg", &b"\x00\x00\x01\x02"[..]),
    ] {
        let mut log = synth::ulog(&flight(2.0), true);
        let at = log.len();
        log.extend(ulog_msg(b'D', data));
        assert_reported(&dir, name, &log, at);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A DataFlash `FMT` record (89 bytes).
fn fmt(kind: u8, len: u8, name: &[u8], format: &[u8], labels: &[u8]) -> Vec<u8> {
    let mut r = vec![0xA3, 0x95, 0x80, kind, len];
    for (text, n) in [(name, 4), (format, 16), (labels, 64)] {
        let mut b = text.to_vec();
        b.resize(n, 0);
        r.extend_from_slice(&b);
    }
    r
}

/// The synthetic DataFlash log's formats (4 × 89 bytes) end here.
const DF_DEFS: usize = 4 * 89;
/// Length of one sample's records in the synthetic DataFlash log (ATT, XKF1, RATE, CTUN).
const DF_SAMPLE: usize = 23 + 24 + 35 + 15;

fn dataflash_with(extra: &[u8]) -> Vec<u8> {
    let mut log = synth::dataflash(&flight(2.0), true);
    log.splice(DF_DEFS..DF_DEFS, extra.iter().copied());
    log
}

#[test]
fn dataflash_fmt_lengths_below_3_and_the_92_byte_file() {
    let dir = tmpdir("df-fmt");
    // The 92-byte file: an FMT of length 0, and a record of its type.
    let mut small = fmt(1, 0, b"BAD", b"B", b"x");
    small.extend_from_slice(&[0xA3, 0x95, 1]);
    assert_eq!(small.len(), 92);
    assert_reported(&dir, "92.bin", &small, 0);
    let mut reader = dataflash::reader::Reader::new(small.as_slice());
    assert!(reader.next_record().expect("reads").is_none());
    assert_eq!(reader.issues().items()[0].offset, 0);
    // Lengths 0, 1 and 2 for an unused type (a note), and for ATT (then no attitude: the
    // error says why).
    for len in 0..3u8 {
        let name = format!("len{len}.bin");
        let log = dataflash_with(&fmt(0x90, len, b"UNU", b"Q", b"TimeUS"));
        assert_reported(&dir, &name, &log, DF_DEFS);
        let name = format!("att_len{len}.bin");
        let log = dataflash_with(&fmt(0x81, len, b"ATT", b"Qfff", b"TimeUS,Roll,Pitch,Yaw"));
        assert_reported(&dir, &name, &log, DF_DEFS);
        let e = import_bytes(&dir, &name, &log).expect_err("no attitude");
        assert!(e.to_string().contains("no attitude"), "{e}");
    }
    // Length 255 (the most a byte holds) is a valid, if wasteful, format.
    let mut log = dataflash_with(&fmt(0x90, 255, b"BIG", b"Qf", b"TimeUS,V"));
    let mut big = vec![0xA3, 0x95, 0x90];
    big.resize(255, 7);
    log.extend(big);
    let imported = import_bytes(&dir, "len255.bin", &log).expect("reads");
    assert!(imported.notes.is_empty(), "{:?}", imported.notes);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dataflash_type_ids_format_strings_and_names_at_their_edges() {
    let dir = tmpdir("df-fields");
    let cases: [(&str, Vec<u8>); 7] = [
        // Format characters DataFlash does not define.
        ("char_x.bin", fmt(0x90, 20, b"UNK", b"Qx", b"TimeUS,X")),
        ("char_ff.bin", fmt(0x90, 20, b"UNK", b"\xff", b"X")),
        // A format longer than the length.
        (
            "too_long.bin",
            fmt(0x90, 3 + 8, b"LONG", b"QQQ", b"TimeUS,A,B"),
        ),
        // A name that is not text, with no NUL before the format.
        (
            "name.bin",
            [
                fmt(0x90, 5, b"\xff\xfe\xfd\xfc", b"Z", b"x"),
                vec![0xA3, 0x95, 0x90, 1, 2],
            ]
            .concat(),
        ),
        // A record of a type with no FMT.
        ("undefined.bin", vec![0xA3, 0x95, 0x99, 0, 0, 0]),
        // Fewer labels than format characters.
        ("labels.bin", fmt(0x90, 3 + 8 + 4, b"LAB", b"Qf", b"TimeUS")),
        // ATT redefined with another format.
        (
            "redefined.bin",
            fmt(0x81, 3 + 8 + 12, b"ATT", b"Qfff", b"TimeUS,R,P,Y"),
        ),
    ];
    for (name, extra) in cases {
        if name == "name.bin" {
            // Readable (its format is fine): the name is only for matching.
            let log = dataflash_with(&extra);
            let imported = import_bytes(&dir, name, &log).expect(name);
            assert_eq!(imported.segments[0].len(), flight(2.0).len());
            assert!(imported.notes.iter().all(|n| n.contains(name)));
        } else {
            assert_reported(&dir, name, &dataflash_with(&extra), DF_DEFS);
        }
    }
    // Type ids 0 and 255 are ordinary types; an FMT for type 128 (FMT itself) is ignored.
    for kind in [0u8, 255, 128] {
        let mut log = dataflash_with(&fmt(kind, 3 + 8 + 4, b"EDGE", b"Qf", b"TimeUS,V"));
        if kind != 128 {
            log.extend([&[0xA3, 0x95, kind][..], &[0; 12]].concat());
        }
        let name = format!("type{kind}.bin");
        let imported = import_bytes(&dir, &name, &log).expect(&name);
        assert!(imported.notes.is_empty(), "{name}: {:?}", imported.notes);
    }
    // Cut in the middle of a record, and inside a record's 3-byte header: a note at the
    // record's start.
    let full = synth::dataflash(&flight(2.0), true);
    let record = DF_DEFS + 40 * DF_SAMPLE + 23; // the 41st sample's XKF1
    for cut in [record + 1, record + 2, record + 10] {
        let name = format!("cut{cut}.bin");
        assert_reported(&dir, &name, &full[..cut], record);
        let imported = import_bytes(&dir, &name, &full[..cut]).expect(&name);
        assert!(
            imported.notes.iter().any(|n| n.contains(&format!(
                "the log is truncated at byte {record} (cut mid-record); using the data before the cut"
            ))),
            "{:?}",
            imported.notes
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A record with a time stamp far in the future in the middle of a log: the readers give
/// every record in log order (the importer's series decide what to do with the spike).
#[test]
fn a_future_time_stamp_mid_log_does_not_hide_the_records_after_it() {
    let samples = flight(2.0);
    let n = samples.len();
    let future: u64 = 1 << 50;
    // DataFlash: the 50th ATT record's TimeUS.
    let mut log = synth::dataflash(&samples, true);
    let at = DF_DEFS + 50 * DF_SAMPLE + 3;
    log[at..at + 8].copy_from_slice(&future.to_le_bytes());
    let mut reader = dataflash::reader::Reader::new(log.as_slice());
    let mut times = Vec::new();
    while let Some(r) = reader.next_record().expect("reads") {
        if r.format.name == "ATT" {
            times.push(r.time_us().expect("TimeUS"));
        }
    }
    assert_eq!(times.len(), n);
    assert_eq!(times[50], future as f64);
    assert!(times[51] > times[49] && times[51] < 1e7, "{}", times[51]);

    // ULog: the 50th vehicle_attitude record's timestamp (subscription 0).
    let log = synth::ulog(&samples, true);
    let mut reader = ulog::reader::Reader::new(log.as_slice()).expect("header");
    let mut times = Vec::new();
    let mut offsets = Vec::new();
    while let Some(e) = reader.next_event().expect("reads") {
        if let ulog::reader::Event::Data {
            offset, msg_id: 0, ..
        } = e
        {
            offsets.push(offset as usize);
        }
    }
    let mut log = log;
    let at = offsets[50] + 5;
    log[at..at + 8].copy_from_slice(&future.to_le_bytes());
    let mut reader = ulog::reader::Reader::new(log.as_slice()).expect("header");
    while let Some(e) = reader.next_event().expect("reads") {
        if let ulog::reader::Event::Data {
            msg_id: 0, data, ..
        } = e
        {
            times.push(u64::from_le_bytes(data[..8].try_into().expect("8 bytes")));
        }
    }
    assert_eq!(times.len(), n);
    assert_eq!(times[50], future);
    assert!(times[51] > times[49] && times[51] < 10_000_000);

    // Through the importers: no panic, and an error names the file.
    let dir = tmpdir("future");
    for (name, bytes) in [
        ("future.ulg", log),
        ("future.bin", {
            let mut l = synth::dataflash(&samples, true);
            l[at_df(50)..at_df(50) + 8].copy_from_slice(&future.to_le_bytes());
            l
        }),
    ] {
        if let Err(e) = import_bytes(&dir, name, &bytes) {
            assert!(e.to_string().contains(name), "{e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn at_df(sample: usize) -> usize {
    DF_DEFS + sample * DF_SAMPLE + 3
}

#[test]
fn git_lfs_pointers_and_binary_files_are_named_for_what_they_are() {
    let dir = tmpdir("foreign");
    let pointer = b"version https://git-lfs.github.com/spec/v1\noid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\nsize 12345\n";
    let e = import_bytes(&dir, "flight.ulg", pointer).expect_err("a pointer");
    assert!(matches!(e, ImportError::LfsPointer { .. }), "{e:?}");
    let e = e.to_string();
    assert!(
        e.contains("flight.ulg") && e.contains("git lfs pull") && !e.contains('\n'),
        "{e}"
    );
    let mut binary = vec![0u8, 1, 2, 3, 0xFF, 0xFE];
    binary.extend((0..500u32).map(|k| (k * 37 % 256) as u8));
    let e = import_bytes(&dir, "blob.ulg", &binary).expect_err("binary");
    assert!(matches!(e, ImportError::NotALog { .. }), "{e:?}");
    assert!(e.to_string().contains("not a ULog, DataFlash or CSV log"));
    // ArduPilot's text log and JSON exports are named, not read as a CSV missing `time_s`.
    let text_log = b"58\n\nArduCopter V3.0.1\nFree RAM: 1273\nFMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\nFMT, 129, 23, PARM, Nf, Name,Value\n";
    let e = import_bytes(&dir, "flight.log", text_log).expect_err("text DataFlash");
    assert!(matches!(e, ImportError::TextDataFlash { .. }), "{e:?}");
    assert!(e.to_string().contains(".bin") && !e.to_string().contains("time_s"));
    let json = b"{\"meta\": {\"timestamp\": 1.0, \"type\": \"ATT\"}, \"data\": {\"Roll\": 0.1}}\n";
    let e = import_bytes(&dir, "flight.json", json).expect_err("JSON");
    assert!(matches!(e, ImportError::Json { .. }), "{e:?}");
    assert_eq!(
        import::detect(b"\n# comment\nFMT,1\n"),
        Err(NotALog::TextDataFlash)
    );
    // Text stays CSV (and its error is the CSV reader's).
    assert_eq!(import::detect(b"time_s,u_col\n0,0.5\n"), Ok(LogFormat::Csv));
    // UTF-8 cut inside a character at the end of the head, or Latin-1, is still text.
    assert_eq!(import::detect(b"# caf\xe9\ntime_s\n"), Ok(LogFormat::Csv));
    assert_eq!(
        import::detect("a,é".as_bytes().split_last().expect("bytes").1),
        Ok(LogFormat::Csv)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn real_sdlog2() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/trex550_cut.px4log")
}

#[test]
fn a_real_sdlog2_log_is_told_from_dataflash_and_imported() {
    let bytes = std::fs::read(real_sdlog2()).expect("fixture");
    assert_eq!(
        import::detect(&bytes[..import::HEAD_LEN.min(bytes.len())]),
        Ok(LogFormat::Sdlog2)
    );
    let imported = import::import(&real_sdlog2()).expect("imports");
    assert_eq!(imported.format, LogFormat::Sdlog2);
    // The fixture is cut mid-record: a note, and the data before the cut.
    assert!(
        imported
            .notes
            .iter()
            .any(|n| n.contains("truncated at byte")),
        "{:?}",
        imported.notes
    );
    let seg = imported.longest().expect("a segment");
    // At the rate the log supports (its records come at about 16 Hz here): over 5 s.
    assert!(
        seg.len() as f64 / imported.rate_hz >= 5.0,
        "{} samples at {} Hz",
        seg.len(),
        imported.rate_hz
    );
    assert!((seg[0].t - 85.0).abs() < 0.1, "{}", seg[0].t);
    // Radians and rad/s as logged: a helicopter on its skids.
    assert!(seg
        .iter()
        .all(|s| s.roll.abs() < 0.3 && s.pitch.abs() < 0.3 && s.q.abs() < 0.5));
    // The log has STAT (ArmS) and LAND (Landed): an in-air channel.
    let (channels, _) = sdlog2::channels("trex550_cut.px4log", bytes.as_slice()).expect("channels");
    assert!(!channels.in_air.t.is_empty());
    assert!(channels.in_air.v.iter().all(|v| v[0] == 0.0 || v[0] == 1.0));
}

#[test]
fn generated_sdlog2_logs_round_trip_and_name_what_is_missing() {
    let samples = flight(4.0);
    let dir = tmpdir("sdlog2");
    let imported =
        import_bytes(&dir, "heli.px4log", &synth::sdlog2(&samples, true)).expect("imports");
    assert_eq!(imported.format, LogFormat::Sdlog2);
    assert_eq!(imported.segments.len(), 1);
    let seg = &imported.segments[0];
    assert_eq!(seg.len(), samples.len());
    for (a, b) in seg.iter().zip(&samples) {
        assert!((a.t - 1.0 - b.t).abs() < 1e-9);
        // Every value but the time (after the writer's 1 s boot, checked above).
        for (x, y) in rotorid_cli::log::values(a)
            .iter()
            .zip(rotorid_cli::log::values(b))
            .skip(1)
        {
            assert!(
                (x - y).abs() <= 2e-5 * y.abs().max(1.0),
                "t={}: {x} vs {y}",
                b.t
            );
        }
    }
    let e = import_bytes(&dir, "quad.px4log", &synth::sdlog2(&samples, false))
        .expect_err("no ATTC")
        .to_string();
    assert!(
        e.contains("quad.px4log")
            && e.contains("PX4 sdlog2 log")
            && e.contains("no helicopter controls"),
        "{e}"
    );
    // Without its TIME messages the log is still told as sdlog2 (its ATT has no time field,
    // as ArduPilot's always has), and the error names the missing time, not the ATT rows
    // that are there.
    let untimed = synth::sdlog2_with(&samples, true, false);
    assert_eq!(import::detect(&untimed), Ok(LogFormat::Sdlog2));
    let e = import_bytes(&dir, "untimed.bin", &untimed)
        .expect_err("no TIME")
        .to_string();
    assert!(
        e.contains("untimed.bin")
            && e.contains("PX4 sdlog2 log")
            && e.contains("no time stamps")
            && e.contains("`TIME` `StartTime`")
            && !e.contains("no attitude"),
        "{e}"
    );
    // The same messages with ArduPilot time stamps are DataFlash, not sdlog2.
    assert_eq!(
        import::detect(&synth::dataflash(&samples, true)),
        Ok(LogFormat::DataFlash)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn in_air_comes_from_the_autopilots_own_state() {
    let samples = flight(2.0);
    let t = |k: usize| (samples[k].t * 1e6) as u64 + 1_000_000;
    // ULog: vehicle_land_detected after the data: landed, then flying, then landed.
    let mut log = synth::ulog(&samples, true);
    log.extend(ulog_msg(
        b'F',
        b"vehicle_land_detected:uint64_t timestamp;bool landed;",
    ));
    log.extend(ulog_msg(b'A', b"\x00\x09\x00vehicle_land_detected"));
    for (k, landed) in [(0, 1u8), (10, 0), (90, 1)] {
        let mut d = vec![9u8, 0];
        d.extend_from_slice(&t(k).to_le_bytes());
        d.push(landed);
        log.extend(ulog_msg(b'D', &d));
    }
    let (ch, notes) = ulog::channels("x.ulg", log.as_slice()).expect("reads");
    assert!(notes.is_empty(), "{notes:?}");
    assert_eq!(ch.in_air.v, vec![[0.0], [1.0], [0.0]]);
    // Without it, vehicle_status arming_state (2 = armed).
    let mut log = synth::ulog(&samples, true);
    log.extend(ulog_msg(
        b'F',
        b"vehicle_status:uint64_t timestamp;uint8_t arming_state;",
    ));
    log.extend(ulog_msg(b'A', b"\x00\x09\x00vehicle_status"));
    for (k, state) in [(0, 1u8), (10, 2)] {
        let mut d = vec![9u8, 0];
        d.extend_from_slice(&t(k).to_le_bytes());
        d.push(state);
        log.extend(ulog_msg(b'D', &d));
    }
    let (ch, _) = ulog::channels("x.ulg", log.as_slice()).expect("reads");
    assert_eq!(ch.in_air.v, vec![[0.0], [1.0]]);
    // None of them: empty.
    let (ch, _) = ulog::channels("x.ulg", synth::ulog(&samples, true).as_slice()).expect("reads");
    assert!(ch.in_air.t.is_empty());

    // DataFlash: EV armed (10), land complete (18), disarmed (11); ARM ArmState.
    let mut log = synth::dataflash(&samples, true);
    log.extend(fmt(0x90, 3 + 9, b"EV", b"QB", b"TimeUS,Id"));
    log.extend(fmt(0x91, 3 + 9, b"ARM", b"QB", b"TimeUS,ArmState"));
    for (kind, k, v) in [
        (0x90u8, 5, 10u8),
        (0x90, 50, 18),
        (0x91, 60, 0),
        (0x90, 70, 11),
    ] {
        log.extend_from_slice(&[0xA3, 0x95, kind]);
        log.extend_from_slice(&t(k).to_le_bytes());
        log.push(v);
    }
    let (ch, _) = dataflash::channels("x.bin", log.as_slice()).expect("reads");
    assert_eq!(ch.in_air.v, vec![[1.0], [0.0], [0.0], [0.0]]);
    let (ch, _) =
        dataflash::channels("x.bin", synth::dataflash(&samples, true).as_slice()).expect("reads");
    assert!(ch.in_air.t.is_empty());

    // sdlog2: STAT ArmS = 2 throughout.
    let (ch, _) =
        sdlog2::channels("x.px4log", synth::sdlog2(&samples, true).as_slice()).expect("reads");
    assert_eq!(ch.in_air.t.len(), samples.len());
    assert!(ch.in_air.v.iter().all(|v| v[0] == 1.0));
}

/// Writes the fuzz targets' seed corpora (`host-tests/fuzz/corpus/{ulog_log,dataflash_log}/`,
/// each file under 20 KB): generated logs, the real fixtures cut small, and the edge cases
/// above. Run: `cargo test -p rotorid-cli --test integration -- --ignored corrupt_logs::write_fuzz_seeds`.
#[test]
#[ignore = "writes the fuzz seed corpora"]
fn write_fuzz_seeds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus");
    let short = flight(0.4);
    let with_defs = |log: Vec<u8>, extra: &[u8], at: usize| {
        let mut log = log;
        log.splice(at..at, extra.iter().copied());
        log
    };
    let real_ulog =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/logs/esc_status_log.ulg"))
            .expect("fixture");
    let mut nested = synth::ulog(&short, true);
    nested.extend(ulog_msg(b'F', b"inner:uint8_t a;float[2] b;"));
    nested.extend(ulog_msg(
        b'F',
        b"vehicle_land_detected:uint64_t timestamp;inner[2] in;bool landed;uint8_t[3] _padding0;",
    ));
    nested.extend(ulog_msg(b'A', b"\x00\x09\x00vehicle_land_detected"));
    nested.extend(ulog_msg(b'O', &100u16.to_le_bytes()));
    nested.extend(ulog_msg(b'S', &ulog::reader::SYNC));
    let mut d = vec![9u8, 0];
    d.extend_from_slice(&2_000_000u64.to_le_bytes());
    d.extend_from_slice(&[0; 18]);
    d.push(1);
    nested.extend(ulog_msg(b'D', &d));
    let mut flags = synth::ulog(&short, true);
    flags[16 + 3 + 8] = 0x02;
    let ulog_seeds: Vec<(&str, Vec<u8>)> = vec![
        ("synth_heli.ulg", synth::ulog(&short, true)),
        ("synth_quad.ulg", synth::ulog(&short, false)),
        ("real_cut.ulg", real_ulog[..19_000].to_vec()),
        ("nested_dropout_sync.ulg", nested),
        (
            "empty_p.ulg",
            with_defs(synth::ulog(&short, true), &ulog_msg(b'P', &[]), ULOG_DEFS),
        ),
        (
            "long_key_p.ulg",
            with_defs(
                synth::ulog(&short, true),
                &ulog_msg(b'P', b"\xc8int32_t x"),
                ULOG_DEFS,
            ),
        ),
        ("flags.ulg", flags),
    ];
    let mut small = fmt(1, 0, b"BAD", b"B", b"x");
    small.extend_from_slice(&[0xA3, 0x95, 1]);
    let real_sd = std::fs::read(real_sdlog2()).expect("fixture");
    let fmts = real_sd
        .chunks(89)
        .take_while(|c| c.starts_with(&[0xA3, 0x95, 0x80]))
        .count()
        * 89;
    let mut events = synth::dataflash(&short, true);
    events.extend(fmt(0x90, 3 + 9, b"EV", b"QB", b"TimeUS,Id"));
    events.extend([&[0xA3, 0x95, 0x90][..], &1_100_000u64.to_le_bytes(), &[10]].concat());
    // ArduCopter 3.3: an untimed `MSG` naming it, `STRT` without fields, the velocity in
    // `EKF1`, `RATE` in its old units, an untimed `EV`.
    let mut ac33 = fmt(0x81, 3 + 8 + 12, b"ATT", b"Qfff", b"TimeUS,Roll,Pitch,Yaw");
    ac33.extend(fmt(0x82, 3 + 8 + 12, b"EKF1", b"Qfff", b"TimeUS,VN,VE,VD"));
    ac33.extend(fmt(
        0x83,
        3 + 8 + 28,
        b"RATE",
        b"Qfffffff",
        b"TimeUS,R,P,Y,ROut,POut,YOut,AOut",
    ));
    ac33.extend(fmt(0x84, 3 + 64, b"MSG", b"Z", b"Message"));
    ac33.extend(fmt(0x85, 3 + 1, b"EV", b"B", b"Id"));
    ac33.extend(fmt(0x86, 3, b"STRT", b"", b""));
    let mut message = b"APM:Copter V3.3.3 (d6053245)".to_vec();
    message.resize(64, 0);
    ac33.extend([&[0xA3, 0x95, 0x84][..], &message, &[0xA3, 0x95, 0x86]].concat());
    for k in 0..40u64 {
        let t = (1_000_000 + k * 20_000).to_le_bytes();
        let row = |kind: u8, values: &[f32]| {
            let mut r = vec![0xA3, 0x95, kind];
            r.extend_from_slice(&t);
            values
                .iter()
                .for_each(|v| r.extend_from_slice(&v.to_le_bytes()));
            r
        };
        ac33.extend(row(0x81, &[1.0, -2.0, 90.0]));
        ac33.extend(row(0x82, &[0.5, 0.0, -0.1]));
        ac33.extend(row(0x83, &[100.0, -50.0, 25.0, 450.0, -900.0, 10.0, 600.0]));
        if k == 5 {
            ac33.extend([0xA3, 0x95, 0x85, 10]);
        }
    }
    let full_df = synth::dataflash(&short, true);
    let dataflash_seeds: Vec<(&str, Vec<u8>)> = vec![
        ("synth_heli.bin", full_df.clone()),
        ("arducopter33.bin", ac33),
        ("synth_heli.px4log", synth::sdlog2(&short, true)),
        ("events.bin", events),
        ("92.bin", small),
        (
            "fmt_len0.bin",
            with_defs(
                synth::dataflash(&short, true),
                &fmt(0x81, 0, b"ATT", b"Qfff", b"TimeUS,Roll,Pitch,Yaw"),
                DF_DEFS,
            ),
        ),
        ("truncated.bin", full_df[..full_df.len() - 7].to_vec()),
        (
            "real_sdlog2_cut.px4log",
            [&real_sd[..fmts], &real_sd[20_557..20_557 + 12_000]].concat(),
        ),
    ];
    for (target, seeds) in [("ulog_log", ulog_seeds), ("dataflash_log", dataflash_seeds)] {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir).expect("corpus dir");
        for (name, bytes) in seeds {
            assert!(bytes.len() < 20_000, "{name}: {} bytes", bytes.len());
            std::fs::write(dir.join(name), bytes).expect("write");
        }
    }
}
