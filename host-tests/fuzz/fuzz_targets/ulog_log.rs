//! Arbitrary bytes into the ULog reader and importer (`import::ulog::channels`): an error or
//! channels, never a panic, a hang or an unbounded allocation; on success every series has
//! finite, increasing time stamps and as many values as times.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rotorid_cli::import::{ulog, Channels, Series};

fn check<const N: usize>(s: &Series<N>) {
    assert_eq!(s.t.len(), s.v.len());
    assert!(s.t.iter().all(|t| t.is_finite()));
    assert!(s.t.windows(2).all(|w| w[0] < w[1]));
}

fn check_all(c: &Channels) {
    check(&c.attitude);
    check(&c.velocity_ned);
    check(&c.rates_frd);
    check(&c.controls);
    check(&c.in_air);
}

fuzz_target!(|data: &[u8]| {
    if let Ok((channels, _notes)) = ulog::channels("fuzz.ulg", data) {
        check_all(&channels);
    }
});
