//! What a `Sample` message does to an identifier: the meaning of each
//! [`SampleMode`](crate::msg::SampleMode), written once for the firmware and for the host
//! that mirrors it bit for bit.
//!
//! Beside the identifier's own learning chain, each identifier answering `Sample` has a
//! [`SampleChain`]: the state (`v^s`, `ω`) its last prediction started from and that
//! prediction. `Predict` reads the first as the state before its sample (the second-order rate
//! terms of `RateStructure::Flight` and the horizontal drag of `VelocityStructure::Flight` need
//! it; the paper's structures ignore it), and `FreeRun`
//! continues from the second: the frozen model fed its own `v^s` and `ω` with the measured
//! attitude and controls, as a flight computer would run it. This is
//! `rotorid_cli::experiments::evaluation`'s `predict_after(before, sample)`, onboard.

use rotorid::hover::{HoverIdentifier, HoverSample, HoverState, StateModel};
use rotorid::Error;

use crate::msg::ident::{SampleMode, SampleMsg};

/// A prediction and the state it started from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Link {
    from: HoverState<f32>,
    next: HoverState<f32>,
}

/// The end of one identifier's prediction chain (see the module docs). Starts empty; every
/// accepted sample of any mode extends it; a sample the identifier rejects leaves it as it
/// was (like the identifier itself).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampleChain {
    last: Option<Link>,
}

/// The prediction `[v_x v_y v_z q r p]` and, for `Learn`, the innovation; or the core's error.
pub type Answer = Result<([f32; 6], Option<[f32; 6]>), Error>;

impl SampleChain {
    /// An empty chain (after a `Reset`).
    pub const fn new() -> Self {
        Self { last: None }
    }

    /// Whether there is a prediction for `FreeRun` to continue from.
    pub fn can_free_run(&self) -> bool {
        self.last.is_some()
    }

    /// The answer of `id` to `m`, or `None` for a `FreeRun` without a prediction to
    /// continue from (the caller refuses the sample; nothing changed).
    ///
    /// * `Learn`: [`HoverIdentifier::step`].
    /// * `Resume`: [`HoverIdentifier::resume`].
    /// * `Predict`: [`HoverIdentifier::predict_after`] with the state this chain's last
    ///   prediction started from (`None` on an empty chain): after `Resume` or `Predict` on
    ///   the previous sample, the measured previous state. No time check: send `Resume`
    ///   after a gap.
    /// * `FreeRun`: `predict_after(from, s')` where `s'` is the sample with `v^s`, `ω`
    ///   replaced by the last prediction and `from` the state that prediction started from.
    pub fn answer<Vm, Qm, Rm, Pm>(
        &mut self,
        id: &mut HoverIdentifier<f32, Vm, Qm, Rm, Pm>,
        m: &SampleMsg,
    ) -> Option<Answer>
    where
        Vm: StateModel<f32>,
        Qm: StateModel<f32>,
        Rm: StateModel<f32>,
        Pm: StateModel<f32>,
    {
        let s = &m.sample;
        let (from, result) = match m.mode {
            SampleMode::Learn => (s.state(), id.step(s).map(|o| (o.prediction, o.innovation))),
            SampleMode::Resume => (s.state(), id.resume(s).map(|p| (p, None))),
            SampleMode::Predict => {
                let before = self.last.map(|l| l.from);
                (
                    s.state(),
                    id.predict_after(before.as_ref(), s).map(|p| (p, None)),
                )
            }
            // `FreeRun` (and any mode added later, which must say here what it does).
            _ => {
                let l = self.last?;
                let own = HoverSample {
                    velocity: l.next.velocity,
                    rates: l.next.rates,
                    ..*s
                };
                (
                    l.next,
                    id.predict_after(Some(&l.from), &own).map(|p| (p, None)),
                )
            }
        };
        Some(result.map(|(next, innovation)| {
            self.last = Some(Link { from, next });
            (
                next.to_array(),
                innovation.as_ref().map(HoverState::to_array),
            )
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotorid::hover::{flight_sets, Attitude, Controls};
    use rotorid::{FlightIdentifier, HoverConfig};

    /// A short chain of samples at 50 Hz with moving states and controls.
    fn samples(n: usize) -> [HoverSample<f32>; 8] {
        core::array::from_fn(|k| {
            let x = k.min(n) as f32;
            HoverSample {
                time_us: 20_000 * (k as u64 + 1),
                attitude: Attitude {
                    roll: 0.01 * x,
                    pitch: -0.02 * x,
                    yaw: 0.1,
                },
                velocity: [2.0 + 0.3 * x, -0.2 * x, 0.1],
                rates: [1.0 - 0.5 * x, 0.3 * x, -2.0 + x],
                controls: Controls {
                    col: 0.1,
                    ped: 0.02 * x,
                    lon: -0.03 * x,
                    lat: 0.01,
                },
            }
        })
    }

    fn msg(mode: SampleMode, sample: HoverSample<f32>) -> SampleMsg {
        SampleMsg { mode, sample }
    }

    /// `s` with the model's own state `x`.
    fn fed(s: &HoverSample<f32>, x: &HoverState<f32>) -> HoverSample<f32> {
        HoverSample {
            velocity: x.velocity,
            rates: x.rates,
            ..*s
        }
    }

    fn bits(a: [f32; 6]) -> [u32; 6] {
        a.map(f32::to_bits)
    }

    #[test]
    fn predict_and_free_run_are_predict_after_with_the_right_states() {
        let mut id =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        let s = samples(8);
        let mut chain = SampleChain::new();
        // Learn a little so that θ (and with it the second-order term) is not zero.
        for x in &s[..5] {
            chain
                .answer(&mut id, &msg(SampleMode::Learn, *x))
                .unwrap()
                .unwrap();
        }
        let frozen = id.clone();
        // Resume on s5, Predict on s6: the state before s6 is s5's, measured.
        chain
            .answer(&mut id, &msg(SampleMode::Resume, s[5]))
            .unwrap()
            .unwrap();
        let p = chain
            .answer(&mut id, &msg(SampleMode::Predict, s[6]))
            .unwrap()
            .unwrap();
        let want = frozen.predict_after(Some(&s[5].state()), &s[6]).unwrap();
        assert_eq!(bits(p.0), bits(want.to_array()));
        assert!(p.1.is_none());
        // The measured previous state matters (else this test could not tell).
        let without = frozen.predict(&s[6]).unwrap();
        assert_ne!(bits(without.to_array()), bits(want.to_array()));
        // FreeRun on s7: s7's attitude and controls with the model's own state, the state
        // before being s6's measured one.
        let f = chain
            .answer(&mut id, &msg(SampleMode::FreeRun, s[7]))
            .unwrap()
            .unwrap();
        let want_f = frozen
            .predict_after(Some(&s[6].state()), &fed(&s[7], &want))
            .unwrap();
        assert_eq!(bits(f.0), bits(want_f.to_array()));
        // A second FreeRun continues from the first one's own state.
        let g = chain
            .answer(&mut id, &msg(SampleMode::FreeRun, s[7]))
            .unwrap()
            .unwrap();
        let want_g = frozen.predict_after(Some(&want), &fed(&s[7], &want_f));
        assert_eq!(bits(g.0), bits(want_g.unwrap().to_array()));
        // Prediction-only modes learn nothing.
        assert_eq!(id.export(), frozen.export());
    }

    #[test]
    fn free_run_needs_a_start_and_rejections_change_nothing() {
        let mut id =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        let s = samples(8);
        let mut chain = SampleChain::new();
        assert!(!chain.can_free_run());
        assert!(chain
            .answer(&mut id, &msg(SampleMode::FreeRun, s[0]))
            .is_none());
        assert_eq!(chain, SampleChain::new());
        chain
            .answer(&mut id, &msg(SampleMode::Resume, s[0]))
            .unwrap()
            .unwrap();
        assert!(chain.can_free_run());
        let before = chain;
        let mut bad = s[1];
        bad.rates[0] = f32::NAN;
        assert!(chain
            .answer(&mut id, &msg(SampleMode::Predict, bad))
            .unwrap()
            .is_err());
        assert_eq!(chain, before);
    }
}
