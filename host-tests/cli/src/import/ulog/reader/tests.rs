use super::*;

fn msg(kind: u8, payload: &[u8]) -> Vec<u8> {
    let mut m = (payload.len() as u16).to_le_bytes().to_vec();
    m.push(kind);
    m.extend_from_slice(payload);
    m
}

fn header() -> Vec<u8> {
    let mut h = MAGIC.to_vec();
    h.push(1);
    h.extend_from_slice(&0u64.to_le_bytes());
    h
}

#[test]
fn nested_formats_arrays_and_padding_are_located() {
    let mut log = header();
    log.extend(msg(b'F', b"inner:uint8_t a;float[2] b;"));
    log.extend(msg(
        b'F',
        b"outer:uint64_t timestamp;inner[2] in;int16_t z;uint8_t[3] _padding0;",
    ));
    log.extend(msg(b'A', b"\x00\x07\x00outer"));
    // 8 + 2 * 9 + 2 = 28 bytes, trailing padding left out.
    let mut d = vec![7u8, 0];
    d.extend_from_slice(&5u64.to_le_bytes());
    for k in 0..2u8 {
        d.push(k);
        d.extend_from_slice(&f32::from(k).to_le_bytes());
        d.extend_from_slice(&(10.0f32 + f32::from(k)).to_le_bytes());
    }
    d.extend_from_slice(&(-3i16).to_le_bytes());
    log.extend(msg(b'D', &d));
    let mut r = Reader::new(log.as_slice()).expect("header");
    let Some(Event::Subscribed { msg_id: 7, .. }) = r.next_event().expect("reads") else {
        panic!("subscription first")
    };
    let at = |path: &str| r.locate(7, path);
    assert_eq!(at("in[1].b[1]").map(|f| f.offset), Some(8 + 9 + 1 + 4));
    assert_eq!(at("z").map(|f| f.offset), Some(26));
    assert_eq!(at("in[2].a"), None, "index past the array");
    assert_eq!(at("in"), None, "not a primitive");
    let fields: Vec<Field> = ["timestamp", "in[1].b[1]", "in[0].a", "z"]
        .iter()
        .map(|p| at(p).expect(p))
        .collect();
    let Some(Event::Data { data, .. }) = r.next_event().expect("reads") else {
        panic!("data")
    };
    let v: Vec<Option<f64>> = fields.iter().map(|f| f.read(data)).collect();
    assert_eq!(v, vec![Some(5.0), Some(11.0), Some(0.0), Some(-3.0)]);
    assert!(r.next_event().expect("reads").is_none());
    assert!(r.issues().items().is_empty(), "{:?}", r.issues());
}

#[test]
fn a_cycle_of_formats_is_a_remark_not_a_hang() {
    let mut log = header();
    log.extend(msg(b'F', b"a:uint64_t timestamp;b x;"));
    log.extend(msg(b'F', b"b:a y;"));
    log.extend(msg(b'A', b"\x00\x01\x00a"));
    let mut r = Reader::new(log.as_slice()).expect("header");
    assert!(r.next_event().expect("reads").is_none());
    assert!(r.issues().has("bad layout"));
}

#[test]
fn corrupt_data_resumes_after_the_next_sync_marker() {
    let mut log = header();
    log.extend(msg(b'F', b"t:uint64_t timestamp;"));
    log.extend(msg(b'A', b"\x00\x00\x00t"));
    log.extend(msg(b'D', b"\x09\x00garbage!"));
    log.extend(msg(b'S', &SYNC));
    log.extend(msg(b'D', b"\x00\x00\x01\x00\x00\x00\x00\x00\x00\x00"));
    let mut r = Reader::new(log.as_slice()).expect("header");
    assert!(matches!(r.next_event(), Ok(Some(Event::Subscribed { .. }))));
    let Ok(Some(Event::Data { data, .. })) = r.next_event() else {
        panic!("the record after the sync marker")
    };
    assert_eq!(data[0], 1);
    assert!(r.issues().has("bad data"));
}
