//! Flight regimes of a verification log, and each model's one-step **bias** in each: the mean
//! signed error of its predictions there, in units per second (m/s² for the velocities,
//! deg/s² for the rates). A model whose trim is wrong in a regime predicts an acceleration
//! that is not there, step after step; the one-step mean absolute error hides it under the
//! sensor noise, but a free run integrates it into a drift. This table shows where.

use rotorid::hover::{BodyFrame, HoverSample, HoverState, Premise};
use serde::{Deserialize, Serialize};

/// Forward speed from which a sample counts as forward flight (m/s): the flight default's
/// middle set is centred at 5 m/s; below 3 m/s its hover set dominates.
const FORWARD: f32 = 3.0;
/// Side speed from which a sample below [`FORWARD`] counts as sideways flight (m/s): ten times
/// the turbulence the simulator's hover carries.
const SIDEWAYS: f32 = 2.0;
/// Vertical speed from which the remaining samples count as climb or descent (m/s).
const VERTICAL: f32 = 1.0;

/// A flight regime, from the heading-frame velocity `[forward, right, up]` of a sample.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Regime {
    /// None of the others.
    Hover,
    /// Forward speed ≥ 3 m/s.
    Forward,
    /// Below 3 m/s forward, ≥ 2 m/s to the left.
    Left,
    /// Below 3 m/s forward, ≥ 2 m/s to the right.
    Right,
    /// None of the above, vertical speed ≥ 1 m/s either way.
    Vertical,
}

impl Regime {
    /// Every regime, in report order.
    pub const ALL: [Regime; 5] = [
        Regime::Hover,
        Regime::Forward,
        Regime::Left,
        Regime::Right,
        Regime::Vertical,
    ];

    /// The regime of sample `s`.
    pub fn of(s: &HoverSample<f32>) -> Self {
        let [forward, right, up] = Premise::HeadingVelocity.of(s, &BodyFrame::of(&s.attitude));
        if forward >= FORWARD {
            Regime::Forward
        } else if right <= -SIDEWAYS {
            Regime::Left
        } else if right >= SIDEWAYS {
            Regime::Right
        } else if up.abs() >= VERTICAL {
            Regime::Vertical
        } else {
            Regime::Hover
        }
    }

    /// How the report names it.
    pub fn label(self) -> &'static str {
        match self {
            Regime::Hover => "hover (below the others)",
            Regime::Forward => "forward ≥ 3 m/s",
            Regime::Left => "left ≥ 2 m/s",
            Regime::Right => "right ≥ 2 m/s",
            Regime::Vertical => "climb or descent ≥ 1 m/s",
        }
    }
}

/// One regime's one-step bias.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RegimeBias {
    /// The regime.
    pub regime: Regime,
    /// Predictions scored in it.
    pub samples: usize,
    /// Mean signed one-step error `x̂(k+1) − x(k+1)` per state divided by the sample period:
    /// m/s² for `v_x, v_y, v_z`, deg/s² for `q, r, p`; 0 where `samples` is 0.
    pub bias_per_s: [f64; 6],
}

/// The one-step bias of `predictions` (`predictions[k]` predicts `samples[k + 1]`; `None`
/// where refused) per regime of the sample predicted from, at `period_s` seconds per sample.
pub fn one_step_bias(
    samples: &[HoverSample<f32>],
    predictions: &[Option<HoverState<f32>>],
    period_s: f64,
) -> Vec<RegimeBias> {
    let mut sums = [[0.0f64; 6]; 5];
    let mut counts = [0usize; 5];
    for (k, prediction) in predictions.iter().enumerate() {
        let (Some(p), Some(from), Some(to)) = (prediction, samples.get(k), samples.get(k + 1))
        else {
            continue;
        };
        let i = Regime::ALL
            .iter()
            .position(|&r| r == Regime::of(from))
            .unwrap_or(0);
        let (p, x) = (p.to_array(), to.state().to_array());
        for (sum, (a, b)) in sums[i].iter_mut().zip(p.iter().zip(x.iter())) {
            *sum += f64::from(*a) - f64::from(*b);
        }
        counts[i] += 1;
    }
    Regime::ALL
        .iter()
        .zip(sums.iter().zip(counts.iter()))
        .map(|(&regime, (sum, &n))| RegimeBias {
            regime,
            samples: n,
            bias_per_s: if n > 0 {
                sum.map(|s| s / n as f64 / period_s)
            } else {
                [0.0; 6]
            },
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotorid::hover::Attitude;

    fn sample(k: u64, yaw: f32, velocity: [f32; 3], q: f32) -> HoverSample<f32> {
        HoverSample {
            time_us: 1_000_000 + k * 20_000,
            attitude: Attitude {
                yaw,
                ..Attitude::default()
            },
            velocity,
            rates: [q, 0.0, 0.0],
            ..HoverSample::default()
        }
    }

    /// The regime follows the heading: 4 m/s east is forward flight heading east, sideways
    /// flight heading north (paper axes: x east, y up, z south).
    #[test]
    fn regimes_are_taken_in_the_heading_frame() {
        let east = [4.0, 0.0, 0.0];
        let half_pi = core::f32::consts::FRAC_PI_2;
        assert_eq!(Regime::of(&sample(0, half_pi, east, 0.0)), Regime::Forward);
        assert_eq!(Regime::of(&sample(0, 0.0, east, 0.0)), Regime::Right);
        assert_eq!(
            Regime::of(&sample(0, 0.0, [-4.0, 0.0, 0.0], 0.0)),
            Regime::Left
        );
        assert_eq!(
            Regime::of(&sample(0, 0.0, [0.0, 1.5, 0.0], 0.0)),
            Regime::Vertical
        );
        assert_eq!(
            Regime::of(&sample(0, 0.0, [0.5, 0.2, 0.5], 0.0)),
            Regime::Hover
        );
    }

    /// A prediction 0.1 deg/s above every sample at 50 Hz is a bias of +5 deg/s² on q in the
    /// regime of the sample predicted from, and nothing elsewhere; refused predictions and
    /// the last sample (nothing to compare with) are skipped.
    #[test]
    fn bias_is_the_mean_signed_error_per_second_in_each_regime() {
        let samples: Vec<_> = (0..5)
            .map(|k| {
                let v = if k < 3 { [0.0; 3] } else { [4.0, 0.0, 0.0] };
                sample(k, 0.0, v, k as f32)
            })
            .collect();
        let mut predictions: Vec<_> = samples
            .iter()
            .skip(1)
            .map(|s| {
                let mut x = s.state();
                x.rates[0] += 0.1;
                Some(x)
            })
            .collect();
        predictions[1] = None;
        let table = one_step_bias(&samples, &predictions, 0.02);
        assert_eq!(table.len(), Regime::ALL.len());
        let hover = &table[0];
        assert_eq!((hover.regime, hover.samples), (Regime::Hover, 2));
        assert!((hover.bias_per_s[3] - 5.0).abs() < 1e-3, "{hover:?}");
        assert_eq!(hover.bias_per_s[4], 0.0);
        // Samples 3 and 4 fly 4 m/s east heading north: sideways to the right; only sample 3
        // is predicted from.
        let right = &table[3];
        assert_eq!((right.regime, right.samples), (Regime::Right, 1));
        assert!((right.bias_per_s[3] - 5.0).abs() < 1e-3, "{right:?}");
        assert_eq!(table[1].samples + table[2].samples + table[4].samples, 0);
        assert_eq!(table.iter().map(|r| r.samples).sum::<usize>(), 3);
    }
}
