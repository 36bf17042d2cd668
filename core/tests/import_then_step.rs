//! Check, then write, whatever an import brought in: after an import of a damaged state, every
//! `step`, `resume` and `compensate` either succeeds with a finite prediction or leaves every
//! bit of the identifier as it was (issue 33).
//!
//! Each case learns a short flight, exports the state, damages one to four words of it (huge,
//! tiny, non-finite, random bit patterns, values at and just past the import bounds; θ, the
//! diagonal and, above all, the off-diagonal factor entries), imports it and drives the
//! identifier with legal and extreme samples, gaps and resumes. Deterministic (xorshift).
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use rotorid::hover::{flight_sets, Attitude, Controls, HoverSnapshot, StateModel};
use rotorid::rls::{RlsState, COVARIANCE_LIMIT, FACTOR_ENTRY_LIMIT, PARAMETER_LIMIT};
use rotorid::{
    Error, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig, HoverIdentifier, HoverSample,
    PaperLocalIdentifier, PaperPlainIdentifier,
};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in [−1, 1).
    fn u(&mut self) -> f32 {
        ((self.next() >> 11) as f64 / (1u64 << 52) as f64 - 1.0) as f32
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Visits every float word of an exported state (θ, then the packed factor).
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

/// Every bit the identifier's behaviour depends on: θ, factors and counters of every
/// estimator, the end of the sample chain, the settings.
fn fingerprint<V, Q, R, P>(id: &HoverIdentifier<f32, V, Q, R, P>) -> Vec<u64>
where
    V: StateModel<f32>,
    Q: StateModel<f32>,
    R: StateModel<f32>,
    P: StateModel<f32>,
{
    let mut out = Vec::new();
    id.for_each_rls(|m, i, v| {
        out.push(u64::from(m.index()) << 32 | i as u64);
        out.extend(v.parameters().iter().map(|x| u64::from(x.to_bits())));
        out.extend(v.packed_factor().iter().map(|x| u64::from(x.to_bits())));
        let c = v.counters();
        out.extend([c.updates, c.windup_guards, c.numerical_skips].map(u64::from));
    });
    match id.previous_sample() {
        None => out.push(u64::MAX),
        Some(s) => {
            out.push(s.time_us);
            out.extend(s.state().to_array().iter().map(|x| u64::from(x.to_bits())));
            out.extend(s.attitude.to_array().map(|x| u64::from(x.to_bits())));
            out.extend(s.controls.to_array().map(|x| u64::from(x.to_bits())));
        }
    }
    out.push(u64::from(id.config().sample_period_us));
    out
}

/// A legal sample at `time_us`: smooth motion, or (sometimes) every field at a random value
/// up to its limit.
fn sample(rng: &mut Rng, k: u64, time_us: u64, extreme: bool) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    if extreme {
        return HoverSample {
            time_us,
            attitude: Attitude {
                roll: 3.2 * rng.u(),
                pitch: 1.6 * rng.u(),
                yaw: 6.3 * rng.u(),
            },
            velocity: [100.0 * rng.u(), 100.0 * rng.u(), 100.0 * rng.u()],
            rates: [2000.0 * rng.u(), 2000.0 * rng.u(), 2000.0 * rng.u()],
            controls: Controls {
                col: rng.u(),
                ped: rng.u(),
                lon: rng.u(),
                lat: rng.u(),
            },
        };
    }
    HoverSample {
        time_us,
        attitude: Attitude {
            roll: 0.05 * (0.7 * t).sin(),
            pitch: -0.03 * (0.5 * t).cos(),
            yaw: 0.1 * t.sin(),
        },
        velocity: [
            5.0 * (0.2 * t).sin() + 0.05 * rng.u(),
            0.5 * (0.3 * t).cos(),
            -0.2 + 0.05 * rng.u(),
        ],
        rates: [
            10.0 * (1.3 * t).sin() + rng.u(),
            8.0 * (1.7 * t).cos() + rng.u(),
            12.0 * (2.1 * t).sin() + rng.u(),
        ],
        controls: Controls {
            col: 0.5 + 0.1 * (1.1 * t).sin(),
            ped: 0.1 * (1.9 * t).sin(),
            lon: 0.1 * (0.9 * t).sin(),
            lat: 0.1 * (2.3 * t).cos(),
        },
    }
}

/// A damaging value: beyond every bound, at the bounds, non-finite or any bit pattern.
fn hostile(rng: &mut Rng, old: f32) -> f32 {
    let sign = if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
    match rng.below(12) {
        0 => f32::MAX * sign,
        1 => f32::NAN,
        2 => f32::INFINITY * sign,
        3 => f32::from_bits(rng.next() as u32),
        4 => (PARAMETER_LIMIT as f32) * sign,
        5 => (FACTOR_ENTRY_LIMIT as f32) * sign,
        6 => (COVARIANCE_LIMIT as f32) * sign,
        7 => 2.0 * COVARIANCE_LIMIT as f32 * sign,
        8 => 10f32.powi(rng.below(38) as i32) * sign,
        9 => f32::MIN_POSITIVE * sign,
        10 => old * 10f32.powi(rng.below(30) as i32),
        _ => f32::from_bits(old.to_bits() ^ (1 << rng.below(32))),
    }
}

/// Damages 1 to 4 words of one model's state.
fn damage<S: Words>(rng: &mut Rng, s: &mut S) {
    let mut len = 0;
    s.words(&mut |_| len += 1);
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(len);
        let mut i = 0;
        let value = rng.next();
        let mut r = Rng(value | 1);
        s.words(&mut |w| {
            if i == at {
                *w = hostile(&mut r, *w);
            }
            i += 1;
        });
    }
}

/// Runs `call` on `id`; on `Err` asserts that nothing changed; returns the result.
fn checked<I: Clone, T>(
    id: &mut I,
    print: impl Fn(&I) -> Vec<u64>,
    what: &str,
    call: impl FnOnce(&mut I) -> Result<T, Error>,
) -> Result<T, Error> {
    let before = print(id);
    let r = call(id);
    if let Err(e) = &r {
        assert!(
            before == print(id),
            "a refused {what} ({e:?}) changed the identifier"
        );
    }
    r
}

fn campaign<V, Q, R, P>(fresh: HoverIdentifier<f32, V, Q, R, P>, seed: u64, cases: usize)
where
    V: StateModel<f32, State: Words>,
    Q: StateModel<f32, State: Words>,
    R: StateModel<f32, State: Words>,
    P: StateModel<f32, State: Words>,
    HoverIdentifier<f32, V, Q, R, P>: Clone,
{
    let mut rng = Rng(seed);
    let mut learnt = fresh;
    for k in 0..300u64 {
        let s = sample(&mut rng, k, 1_000_000 + 20_000 * k, false);
        learnt.step(&s).expect("a legal flight is learnt");
    }
    let exported = learnt.export();
    let (mut accepted, mut refused_calls, mut ok_calls) = (0, 0, 0);
    for case in 0..cases {
        let mut snap: HoverSnapshot<_, _, _, _> = exported;
        match rng.below(4) {
            0 => damage(&mut rng, &mut snap.velocity),
            1 => damage(&mut rng, &mut snap.pitch),
            2 => damage(&mut rng, &mut snap.yaw),
            _ => damage(&mut rng, &mut snap.roll),
        }
        let mut id = learnt.clone();
        if checked(&mut id, fingerprint, "import", |id| id.import(&snap)).is_err() {
            continue;
        }
        accepted += 1;
        let mut time = 5_000_000u64;
        for k in 0..40u64 {
            time += match rng.below(10) {
                0 => 1_000_000, // a gap: TIME_STEP, then resume
                1 => 0,         // not monotonic
                _ => 20_000,
            };
            let extreme = rng.below(3) == 0;
            let s = sample(&mut rng, k, time, extreme);
            let result = match rng.below(12) {
                0 => checked(&mut id, fingerprint, "resume", |id| id.resume(&s)),
                1 => checked(&mut id, fingerprint, "compensate", |id| {
                    id.compensate(&[50.0 * rng.u().abs(), 1.0, 0.0])
                        .map(|_| rotorid::hover::HoverState::default())
                }),
                _ => checked(&mut id, fingerprint, "step", |id| {
                    id.step(&s).map(|o| o.prediction)
                }),
            };
            match result {
                Ok(p) => {
                    ok_calls += 1;
                    assert!(
                        p.to_array().iter().all(|x| x.is_finite()),
                        "case {case}: a non-finite prediction out of an Ok"
                    );
                }
                Err(Error::TimeStep { .. }) => {
                    refused_calls += 1;
                    let _ = checked(&mut id, fingerprint, "resume", |id| id.resume(&s));
                }
                Err(_) => refused_calls += 1,
            }
        }
    }
    // The campaign is not vacuous: damaged imports were accepted and then both accepted and
    // refused calls happened on them.
    assert!(
        accepted >= cases / 20,
        "only {accepted} of {cases} imports accepted"
    );
    assert!(
        ok_calls > 0 && refused_calls > 0,
        "{ok_calls} ok, {refused_calls} refused"
    );
}

#[test]
fn paper_plain_covariance_form() {
    let id = PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::paper()).unwrap();
    campaign(id, 0x9e37_79b9_7f4a_7c15, 400);
}

#[test]
fn extended_plain_u_d_form() {
    let id = ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()).unwrap();
    campaign(id, 0x2545_f491_4f6c_dd1d, 400);
}

#[test]
fn flight_local_rules() {
    let id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
    campaign(id, 0x1234_5678_9abc_def1, 200);
}

#[test]
fn paper_local_covariance_form() {
    let id = PaperLocalIdentifier::<f32>::paper_local(HoverConfig::paper()).unwrap();
    campaign(id, 0x0bad_cafe_dead_beef, 200);
}

/// The case: an off-diagonal factor word at f32::MAX (only the diagonal used to be
/// bounded) is refused, as is a U-D factor whose bounded words make an unbounded P_ii.
#[test]
fn an_unbounded_off_diagonal_or_p_ii_is_refused() {
    let mut id = ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()).unwrap();
    let before = id.clone();
    let mut snap = id.export();
    snap.velocity.factor[1] = f32::MAX; // U_01
    assert_eq!(
        id.import(&snap),
        Err(Error::OutOfRange(rotorid::Quantity::Covariance(1)))
    );
    let mut snap = id.export();
    snap.velocity.factor[1] = 1e12; // U_01 within the entry bound, D_1 = 1e6: P_00 = 1e30
    assert_eq!(
        id.import(&snap),
        Err(Error::OutOfRange(rotorid::Quantity::Covariance(0)))
    );
    assert!(id == before);
    // Paper (covariance form): P_01 beyond the entry bound.
    let mut id = PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::paper()).unwrap();
    let mut snap = id.export();
    snap.pitch.factor[1] = 2e18;
    assert_eq!(
        id.import(&snap),
        Err(Error::OutOfRange(rotorid::Quantity::Covariance(1)))
    );
}
