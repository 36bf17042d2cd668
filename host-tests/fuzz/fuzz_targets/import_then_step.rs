//! Check, then write, after any import (issue 33): a learnt identifier imports its own state
//! with words replaced by arbitrary values, then takes arbitrary samples, resumes and
//! compensations. Every refused call (the import included) leaves every bit as it was
//! (θ, factors, counters, chain); every accepted one returns finite numbers.
#![no_main]
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample, StateModel};
use rotorid::rls::RlsState;
use rotorid::{
    Error, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig, HoverIdentifier,
    PaperPlainIdentifier,
};

/// The float words of an exported state.
trait Words {
    fn words(&mut self, f: &mut dyn FnMut(&mut f32));
}
impl<const N: usize, const NP: usize> Words for RlsState<f32, N, NP> {
    fn words(&mut self, f: &mut dyn FnMut(&mut f32)) {
        self.theta
            .iter_mut()
            .chain(self.factor.iter_mut())
            .for_each(f);
    }
}
impl<S: Words, const R: usize> Words for [S; R] {
    fn words(&mut self, f: &mut dyn FnMut(&mut f32)) {
        for s in self {
            s.words(f);
        }
    }
}

struct Bytes<'a>(&'a [u8]);
impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// A sample field: mostly within `limit` (a byte's worth of resolution), at times any bits.
    fn field(&mut self, limit: f32) -> f32 {
        match self.u8() {
            0..=239 => (f32::from(self.u8()) / 128.0 - 1.0) * limit,
            240..=247 => limit * if self.u8() & 1 == 0 { 1.0 } else { -1.0 },
            _ => self.f32(),
        }
    }
}

fn fingerprint<V, Q, R, P>(id: &HoverIdentifier<f32, V, Q, R, P>) -> Vec<u64>
where
    V: StateModel<f32>,
    Q: StateModel<f32>,
    R: StateModel<f32>,
    P: StateModel<f32>,
{
    let mut out = Vec::new();
    id.for_each_rls(|_, _, v| {
        out.extend(
            v.parameters()
                .iter()
                .chain(v.packed_factor())
                .map(|x| u64::from(x.to_bits())),
        );
        let c = v.counters();
        out.extend([c.updates, c.windup_guards, c.numerical_skips].map(u64::from));
    });
    match id.previous_sample() {
        None => out.push(u64::MAX),
        Some(s) => {
            out.push(s.time_us);
            out.extend(s.state().to_array().iter().map(|x| u64::from(x.to_bits())));
        }
    }
    out
}

fn sample(d: &mut Bytes<'_>, k: u64) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    HoverSample {
        time_us: 0,
        attitude: Attitude {
            roll: 0.05 * t.sin(),
            pitch: d.field(1.6),
            yaw: d.field(6.3),
        },
        velocity: [d.field(100.0), d.field(100.0), d.field(100.0)],
        rates: [d.field(2000.0), d.field(2000.0), d.field(2000.0)],
        controls: Controls {
            col: d.field(1.0),
            ped: d.field(1.0),
            lon: d.field(1.0),
            lat: d.field(1.0),
        },
    }
}

/// A regular flight that the identifier learns before the damaged import.
fn learn<I>(mut step: impl FnMut(&HoverSample<f32>) -> Result<I, Error>) {
    for k in 0..300u64 {
        let t = k as f32 * 0.02;
        let s = HoverSample {
            time_us: 1_000_000 + 20_000 * k,
            attitude: Attitude {
                roll: 0.05 * (0.7 * t).sin(),
                pitch: -0.03 * (0.5 * t).cos(),
                yaw: 0.1 * t.sin(),
            },
            velocity: [5.0 * (0.2 * t).sin(), 0.5 * (0.3 * t).cos(), -0.2],
            rates: [
                10.0 * (1.3 * t).sin(),
                8.0 * (1.7 * t).cos(),
                12.0 * (2.1 * t).sin(),
            ],
            controls: Controls {
                col: 0.5 + 0.1 * (1.1 * t).sin(),
                ped: 0.1 * (1.9 * t).sin(),
                lon: 0.1 * (0.9 * t).sin(),
                lat: 0.1 * (2.3 * t).cos(),
            },
        };
        assert!(step(&s).is_ok());
    }
}

fn drive<V, Q, R, P>(learnt: &HoverIdentifier<f32, V, Q, R, P>, d: &mut Bytes<'_>)
where
    V: StateModel<f32, State: Words>,
    Q: StateModel<f32, State: Words>,
    R: StateModel<f32, State: Words>,
    P: StateModel<f32, State: Words>,
    HoverIdentifier<f32, V, Q, R, P>: Clone,
{
    let mut id = learnt.clone();
    let mut snap = id.export();
    // Replace up to 8 words, in any model, by any value.
    for _ in 0..d.u8() % 9 {
        let model = d.u8() % 4;
        let at = usize::from(d.u16());
        let value = if d.u8() < 128 {
            d.f32()
        } else {
            10f32.powi(i32::from(d.u8() % 39)) * if d.u8() & 1 == 0 { 1.0 } else { -1.0 }
        };
        let mut i = 0;
        let mut set = |w: &mut f32| {
            if i == at {
                *w = value;
            }
            i += 1;
        };
        match model {
            0 => snap.velocity.words(&mut set),
            1 => snap.pitch.words(&mut set),
            2 => snap.yaw.words(&mut set),
            _ => snap.roll.words(&mut set),
        }
    }
    let before = fingerprint(&id);
    if id.import(&snap).is_err() {
        assert!(
            before == fingerprint(&id),
            "a refused import changed the identifier"
        );
        return;
    }
    let mut time = 10_000_000u64;
    for k in 0..64u64 {
        if d.0.is_empty() {
            break;
        }
        let op = d.u8();
        time += match op % 16 {
            0 => 1_000_000,
            1 => 0,
            _ => 20_000,
        };
        let mut s = sample(d, k);
        s.time_us = time;
        let before = fingerprint(&id);
        let result = match op >> 4 {
            0 => id.resume(&s),
            1 => id
                .compensate(&[d.field(50.0), d.field(50.0), d.field(50.0)])
                .map(|_| rotorid::hover::HoverState::default()),
            _ => id.step(&s).map(|o| o.prediction),
        };
        match result {
            Ok(p) => assert!(
                p.to_array().iter().all(|x| x.is_finite()),
                "non-finite out of Ok"
            ),
            Err(e) => assert!(
                before == fingerprint(&id),
                "a refused call ({e:?}) changed the identifier"
            ),
        }
    }
}

type Plain = ExtendedPlainIdentifier<f32>;
type Paper = PaperPlainIdentifier<f32>;
type Flight = FlightIdentifier<f32>;

fn learnt() -> &'static (Plain, Paper, Flight) {
    static LEARNT: OnceLock<(Plain, Paper, Flight)> = OnceLock::new();
    LEARNT.get_or_init(|| {
        let mut a = Plain::extended_plain(HoverConfig::default()).unwrap();
        let mut b = Paper::paper_plain(HoverConfig::paper()).unwrap();
        let mut c = Flight::flight(HoverConfig::default(), flight_sets()).unwrap();
        learn(|s| a.step(s));
        learn(|s| b.step(s));
        learn(|s| c.step(s));
        (a, b, c)
    })
}

fuzz_target!(|data: &[u8]| {
    let mut d = Bytes(data);
    let (a, b, c) = learnt();
    match d.u8() % 3 {
        0 => drive(a, &mut d),
        1 => drive(b, &mut d),
        _ => drive(c, &mut d),
    }
});
