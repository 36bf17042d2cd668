//! Arbitrary payloads into every message parser: no panic, and whatever parses writes back to
//! exactly the same bytes (layouts are fixed, trailing bytes are refused).
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_link::msg::*;
use rotorid_link::{Reader, Writer, MAX_PAYLOAD};

macro_rules! round_trip {
    ($data:expr, $($t:ty),+) => {$(
        if let Ok(m) = <$t>::read($data) {
            let mut buf = [0u8; MAX_PAYLOAD + 64];
            let mut w = Writer::new(&mut buf);
            m.write(&mut w).expect(concat!(stringify!($t), " writes what it read"));
            assert_eq!(w.written(), $data, "{}", stringify!($t));
        }
    )+};
}

fuzz_target!(|data: &[u8]| {
    // A frame carries at most MAX_PAYLOAD bytes: nothing longer ever reaches a parser.
    if data.len() > MAX_PAYLOAD {
        return;
    }
    round_trip!(
        data,
        Hello,
        StatsReport,
        CostRequest,
        CostReport,
        Ack,
        Nack,
        SampleMsg,
        Estimate,
        ResetMsg,
        IdentRequest,
        ParamsChunk,
        DataChunk,
        SweepStart,
        SweepSample,
        MemoryReport
    );
    // The exported-state reader and the error decoder on their own.
    let mut r = Reader::new(data);
    let _ = read_rls_state::<5, 15>(&mut r);
    let mut r = Reader::new(data);
    let _ = read_error(&mut r);
});
