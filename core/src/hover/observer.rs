//! One-step prediction through a fixed-gain observer ([`Observer`]) and the search for its
//! gain ([`GainSearch`]).

use crate::error::{ConfigError, Error};
use crate::hover::identifier::HoverIdentifier;
use crate::hover::models::StateModel;
use crate::hover::sample::{HoverSample, HoverState, SampleLimits};
use crate::scalar::Real;

/// The identified model as a one-step predictor from a filtered state: it predicts the next
/// sample from an estimate of this one that weighs the measurement against the model's own
/// prediction, with a gain `K` per state `[v_x v_y v_z q r p]`, each in [0, 1].
///
/// At 50 Hz most of a body rate's one-step change is the gyro's white noise. A model that
/// reads the measured rate `y(k)` (its damping term, and the flight structure's second-order
/// term `η (ω(k) − ω(k−1))`) passes that noise on to its prediction, the more so the better it
/// models the rotor's second-order response. The optimal predictor of a measurement
/// `y = x + v` of a state `x` with dynamics `f` is a Kalman predictor, which predicts from a
/// filtered estimate `x̂(k)`:
///
/// ```text
/// x̂(k)    = K y(k) + (1 − K) ŷ(k)          (per state, 0 ≤ K ≤ 1)
/// ŷ(k+1) = f(x̂(k), x̂(k−1), u(k), attitude(k); θ)
/// ```
///
/// `Observer` is that predictor with a constant gain (the steady-state Kalman gain, which
/// depends on the ratio of the model's process noise to the sensor's noise). `K = 1` on every
/// state is the prediction from the measured state ([`Observer::measured`]; the predictor of an
/// equation-error model, Table 4's definition); `K = 0` is the free run (the model fed its own
/// predictions). [`GainSearch`] identifies `K` from a training flight as the gain of least
/// one-step squared error: a prediction-error estimate of the noise model, in which the data
/// decide, per state, how far the model is trusted over the sensor.
///
/// The observer reads the identifier and never changes it: it runs beside a frozen identifier
/// (after training) or beside one that keeps learning (call it after
/// [`HoverIdentifier::step`]). Parameters compensated for the gyro noise
/// ([`HoverIdentifier::compensate`]) describe the noise-free rates, which is what an observer
/// filters towards.
///
/// 88 bytes in `f32` (`cargo run -p rotorid --example memory`). Every call that returns `Err`
/// leaves it exactly as it was.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Observer<T> {
    gain: [T; 6],
    track: Option<Track<T>>,
}

/// What an observer carries from one sample to the next.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct Track<T> {
    /// Time stamp of the last sample (µs).
    time_us: u64,
    /// `x̂(k)`: the filtered state of the last sample.
    estimate: HoverState<T>,
    /// `ŷ(k+1)`: the prediction of the next sample.
    prediction: HoverState<T>,
}

impl<T: Real> Observer<T> {
    /// An observer with gain `K = gain[i]` on state i of `[v_x v_y v_z q r p]`.
    ///
    /// Errors: [`ConfigError::ObserverGain`] for a gain that is not finite or not in [0, 1].
    pub fn new(gain: [T; 6]) -> Result<Self, Error> {
        for (i, &k) in gain.iter().enumerate() {
            if !(k.is_finite() && k >= T::zero() && k <= T::one()) {
                return Err(ConfigError::ObserverGain { index: i as u8 }.into());
            }
        }
        Ok(Self { gain, track: None })
    }

    /// `K = 1` on every state: the prediction from the measured state, as
    /// [`HoverIdentifier::predict_after`] given the measured sample before.
    pub fn measured() -> Self {
        Self::uniform(T::one())
    }

    /// The same gain on every state (`k` already known to be in [0, 1]).
    fn uniform(k: T) -> Self {
        Self {
            gain: [k; 6],
            track: None,
        }
    }

    /// The gain `K` per state `[v_x v_y v_z q r p]`.
    pub fn gain(&self) -> [T; 6] {
        self.gain
    }

    /// Takes sample k and predicts sample k+1 from the filtered `x̂(k)` with `id`'s current
    /// parameters. The first sample (and the first after [`restart`](Self::restart)) is taken
    /// as measured, with no sample before it.
    ///
    /// Errors (nothing changes): a field of `sample` out of range or not finite
    /// ([`SampleLimits`]); a time stamp that does not increase, or an interval outside `id`'s
    /// sample period ± tolerance (after a gap, [`restart`](Self::restart)); a filtered state
    /// beyond [`SampleLimits`] (possible only where the model's last prediction left them, and
    /// then the observer should be restarted); a prediction that is not finite.
    pub fn predict<Vm, Qm, Rm, Pm>(
        &mut self,
        id: &HoverIdentifier<T, Vm, Qm, Rm, Pm>,
        sample: &HoverSample<T>,
    ) -> Result<HoverState<T>, Error>
    where
        Vm: StateModel<T>,
        Qm: StateModel<T>,
        Rm: StateModel<T>,
        Pm: StateModel<T>,
    {
        SampleLimits::check(sample)?;
        let measured = sample.state();
        let (estimate, before) = match &self.track {
            Some(track) => {
                id.check_interval(track.time_us, sample.time_us)?;
                (
                    self.filter(&measured, &track.prediction),
                    Some(track.estimate),
                )
            }
            None => (measured, None),
        };
        let filtered = HoverSample {
            velocity: estimate.velocity,
            rates: estimate.rates,
            ..*sample
        };
        let prediction = id.predict_after(before.as_ref(), &filtered)?;
        self.track = Some(Track {
            time_us: sample.time_us,
            estimate,
            prediction,
        });
        Ok(prediction)
    }

    /// `x̂ = K y + (1 − K) ŷ` per state: exactly `y` where `K = 1` and `ŷ` where `K = 0` (up
    /// to the sign of a zero), and never outside the two.
    fn filter(&self, measured: &HoverState<T>, predicted: &HoverState<T>) -> HoverState<T> {
        let (y, p) = (measured.to_array(), predicted.to_array());
        let mut x = [T::zero(); 6];
        for (((x, &k), &y), &p) in x.iter_mut().zip(&self.gain).zip(&y).zip(&p) {
            *x = k * y + (T::one() - k) * p;
        }
        HoverState::from_array(x)
    }

    /// The next sample does not follow the last one (a gap, or a new flight): it is taken as
    /// measured.
    pub fn restart(&mut self) {
        self.track = None;
    }

    /// `x̂(k)`: the filtered state of the last sample taken (`None` before the first).
    pub fn estimate(&self) -> Option<HoverState<T>> {
        self.track.map(|t| t.estimate)
    }

    /// `ŷ(k+1)`: the prediction of the next sample (`None` before the first).
    pub fn prediction(&self) -> Option<HoverState<T>> {
        self.track.map(|t| t.prediction)
    }
}

/// Identifies an [`Observer`]'s gain from a flight: runs `N` observers side by side, candidate
/// gain `K_n` on every state, sums each one's squared one-step error per state, and
/// [`best`](Self::best) takes per state the candidate of least error (the prediction-error
/// estimate of the gain, on a grid).
///
/// Feed it the samples of a training flight with the identifier frozen at its trained
/// parameters (or learning: each prediction uses the parameters of its time). Its cost per
/// sample is `N` predictions; a ground replay of the training log is the natural place, and
/// the gain found travels to the flight computer as six numbers.
///
/// ```
/// use rotorid::hover::{flight_sets, Attitude, Controls, GainSearch, HoverSample};
/// use rotorid::{FlightIdentifier, HoverConfig};
///
/// let flight: Vec<HoverSample<f32>> = (0..500u64)
///     .map(|k| {
///         let t = k as f32 * 0.02;
///         HoverSample {
///             time_us: k * 20_000,
///             attitude: Attitude { roll: 0.02, pitch: -0.01, yaw: 0.0 },
///             velocity: [0.1 * t.sin(), 0.0, -2.0],
///             rates: [5.0 * (3.0 * t).sin(), 2.0 * t.cos(), 1.0],
///             controls: Controls { col: 0.5, ped: 0.0, lon: 0.05 * (3.0 * t).cos(), lat: 0.0 },
///         }
///     })
///     .collect();
/// let mut id = FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets())?;
/// for s in &flight {
///     id.step(s)?;
/// }
/// // Replay the training flight with the learnt parameters, one observer per candidate gain.
/// let mut search = GainSearch::<f32, 10>::grid();
/// for s in &flight {
///     search.push(&id, s)?;
/// }
/// let mut observer = search.best().expect("predictions were scored");
/// let gain = observer.gain(); // K per state, to store with the parameters
/// // In flight: after each sample, the prediction of the next from the filtered state.
/// let next = observer.predict(&id, &flight[0])?;
/// # let _ = (gain, next);
/// # Ok::<(), rotorid::Error>(())
/// ```
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct GainSearch<T, const N: usize> {
    observers: [Observer<T>; N],
    /// `Σ (y(k) − ŷ(k))²` per candidate and state.
    squares: [[T; 6]; N],
    /// Predictions scored (samples that had one).
    count: u32,
}

impl<T: Real, const N: usize> GainSearch<T, N> {
    /// Candidates `K_n = (n + 1)/N`, n = 0 … N−1: an even grid over (0, 1] that includes the
    /// measured state's predictor (`K = 1`). Ten candidates resolve the gain to 0.1.
    pub fn grid() -> Self {
        let n = T::lit(N as f64);
        let mut observers = [Observer::measured(); N];
        for (i, o) in observers.iter_mut().enumerate() {
            *o = Observer::uniform(T::lit((i + 1) as f64) / n);
        }
        Self::of(observers)
    }

    /// The given candidate gains, each applied to every state.
    ///
    /// Errors: [`ConfigError::ObserverGain`] for a candidate that is not finite or not in
    /// [0, 1].
    pub fn new(candidates: [T; N]) -> Result<Self, Error> {
        let mut observers = [Observer::measured(); N];
        for (n, (o, &k)) in observers.iter_mut().zip(&candidates).enumerate() {
            *o = Observer::new([k; 6]).map_err(|_| ConfigError::ObserverGain { index: n as u8 })?;
        }
        Ok(Self::of(observers))
    }

    fn of(observers: [Observer<T>; N]) -> Self {
        Self {
            observers,
            squares: [[T::zero(); 6]; N],
            count: 0,
        }
    }

    /// Takes the next sample: scores every candidate's prediction of it, then lets each
    /// predict the one after. Errors as [`Observer::predict`]'s; on any, nothing changes.
    pub fn push<Vm, Qm, Rm, Pm>(
        &mut self,
        id: &HoverIdentifier<T, Vm, Qm, Rm, Pm>,
        sample: &HoverSample<T>,
    ) -> Result<(), Error>
    where
        Vm: StateModel<T>,
        Qm: StateModel<T>,
        Rm: StateModel<T>,
        Pm: StateModel<T>,
    {
        let mut observers = self.observers;
        let mut squares = self.squares;
        let measured = sample.state().to_array();
        let mut scored = false;
        for (o, sums) in observers.iter_mut().zip(squares.iter_mut()) {
            let due = o.prediction();
            o.predict(id, sample)?;
            if let Some(p) = due {
                for ((sum, &y), &p) in sums.iter_mut().zip(&measured).zip(&p.to_array()) {
                    let e = y - p;
                    *sum += e * e;
                }
                scored = true;
            }
        }
        self.observers = observers;
        self.squares = squares;
        if scored {
            self.count = self.count.saturating_add(1);
        }
        Ok(())
    }

    /// The next sample does not follow the last one (a gap, or the next training log). What
    /// was scored is kept.
    pub fn restart(&mut self) {
        for o in &mut self.observers {
            o.restart();
        }
    }

    /// Predictions scored so far.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Candidate n's gain (the same on every state; `None` for n ≥ N).
    pub fn candidate(&self, n: usize) -> Option<T> {
        self.observers.get(n).map(|o| o.gain[0])
    }

    /// Candidate n's mean squared one-step error per state `[v_x v_y v_z q r p]` (`None` for
    /// n ≥ N or before the first scored prediction).
    pub fn mean_square(&self, n: usize) -> Option<[T; 6]> {
        let sums = self.squares.get(n)?;
        (self.count > 0).then(|| {
            let count = T::lit(f64::from(self.count));
            sums.map(|s| s / count)
        })
    }

    /// An observer (with no track yet) whose gain on each state is the candidate of least
    /// squared error on that state; among equals, the first. `None` before the first scored
    /// prediction, or with no candidates.
    pub fn best(&self) -> Option<Observer<T>> {
        if self.count == 0 {
            return None;
        }
        let first = self.observers.first()?;
        let mut gain = first.gain;
        let mut least = *self.squares.first()?;
        for (o, sums) in self.observers.iter().zip(&self.squares).skip(1) {
            for (((g, l), &s), &k) in gain.iter_mut().zip(&mut least).zip(sums).zip(&o.gain) {
                if s < *l {
                    *l = s;
                    *g = k;
                }
            }
        }
        Some(Observer { gain, track: None })
    }
}
