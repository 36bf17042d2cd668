//! A scale-free convergence indicator: "has the model stopped learning?" without thresholds
//! on raw covariance entries.
//!
//! Autotuners commonly declare convergence when covariance entries fall below fixed
//! thresholds; those thresholds depend on the units and magnitudes of the regressors, so they
//! must be retuned for every vehicle and every unit convention. This indicator instead
//! compares what the model fails to predict with what there was to predict, per output and
//! over a window of W samples:
//!
//! ```text
//! ρ = Σ_window e(k)² / Σ_window Δy(k)²        e: prior innovation, Δy = y(k+1) − y(k)
//! ```
//!
//! ρ is a pure number: multiplying an output and its predictions by any unit factor leaves it
//! unchanged (bit for bit when the factor is a power of two). ρ ≈ 1 means the model predicts
//! the increments no better than "hold"; it falls as the model learns and levels off at the
//! share of the increments that is noise. The model is reported converged on an output when ρ
//! has changed by at most a relative tolerance over `settle` consecutive windows. Windows in
//! which the output did not move at all (ΣΔy² = 0) carry no information and are skipped.

use crate::error::{Error, Quantity};
use crate::hover::{HoverSample, HoverState};
use crate::scalar::Real;

/// Convergence indicator over M outputs (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConvergenceMonitor<T, const M: usize> {
    window: u32,
    tolerance: T,
    settle: u16,
    filled: u32,
    innovation_energy: [T; M],
    increment_energy: [T; M],
    status: ConvergenceStatus<T, M>,
}

/// The indicator after the last completed window.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConvergenceStatus<T, const M: usize> {
    /// ρ of the last informative window per output (1 before the first).
    pub ratio: [T; M],
    /// `|ρ − ρ_prev| / max(ρ, ρ_prev)` of the last informative window per output (1 before
    /// the second).
    pub change: [T; M],
    /// Consecutive informative windows whose change was within the tolerance.
    pub settled: [u16; M],
    /// Whether each output has settled for the required number of windows.
    pub converged: [bool; M],
    /// Completed windows.
    pub windows: u32,
}

impl<T: Real, const M: usize> ConvergenceMonitor<T, M> {
    /// A monitor over windows of `window` samples (≥ 2), reporting convergence once ρ changed
    /// by at most `tolerance` (relative, in (0, 1)) for `settle` (≥ 1) consecutive windows.
    pub fn new(window: u32, tolerance: T, settle: u16) -> Result<Self, Error> {
        let tol_ok = tolerance.is_finite() && tolerance > T::zero() && tolerance < T::one();
        if window < 2 || settle == 0 || !tol_ok {
            return Err(Error::OutOfRange(Quantity::Config));
        }
        Ok(Self {
            window,
            tolerance,
            settle,
            filled: 0,
            innovation_energy: [T::zero(); M],
            increment_energy: [T::zero(); M],
            status: ConvergenceStatus {
                ratio: [T::one(); M],
                change: [T::one(); M],
                settled: [0; M],
                converged: [false; M],
                windows: 0,
            },
        })
    }

    /// The indicator after the last completed window.
    pub fn status(&self) -> &ConvergenceStatus<T, M> {
        &self.status
    }

    /// Adds one step's prior innovations and increments. Returns the new status when this
    /// sample completes a window. A non-finite value is rejected and changes nothing.
    pub fn observe(
        &mut self,
        innovation: &[T; M],
        increment: &[T; M],
    ) -> Result<Option<ConvergenceStatus<T, M>>, Error> {
        for (i, (&e, &d)) in innovation.iter().zip(increment.iter()).enumerate() {
            if !(e.is_finite() && d.is_finite()) {
                return Err(Error::NonFinite(Quantity::Target(i as u8)));
            }
        }
        for ((ie, de), (&e, &d)) in self
            .innovation_energy
            .iter_mut()
            .zip(self.increment_energy.iter_mut())
            .zip(innovation.iter().zip(increment.iter()))
        {
            *ie += e * e;
            *de += d * d;
        }
        self.filled += 1;
        if self.filled < self.window {
            return Ok(None);
        }
        self.close_window();
        Ok(Some(self.status))
    }

    fn close_window(&mut self) {
        let s = &mut self.status;
        s.windows = s.windows.saturating_add(1);
        let first = s.windows == 1;
        for m in 0..M {
            let (Some(ie), Some(de)) =
                (self.innovation_energy.get(m), self.increment_energy.get(m))
            else {
                continue;
            };
            if *de <= T::zero() {
                continue; // the output did not move: no information in this window
            }
            let rho = *ie / *de;
            if !rho.is_finite() {
                continue;
            }
            let (Some(ratio), Some(change), Some(settled), Some(converged)) = (
                s.ratio.get_mut(m),
                s.change.get_mut(m),
                s.settled.get_mut(m),
                s.converged.get_mut(m),
            ) else {
                continue;
            };
            if !first {
                let big = if rho > *ratio { rho } else { *ratio };
                *change = if big > T::zero() {
                    (rho - *ratio).abs() / big
                } else {
                    T::zero()
                };
                *settled = if *change <= self.tolerance {
                    settled.saturating_add(1)
                } else {
                    0
                };
                *converged = *settled >= self.settle;
            }
            *ratio = rho;
        }
        self.filled = 0;
        self.innovation_energy = [T::zero(); M];
        self.increment_energy = [T::zero(); M];
    }
}

impl<T: Real> ConvergenceMonitor<T, 6> {
    /// Adds one [`HoverIdentifier::step`](crate::HoverIdentifier::step): the innovation it
    /// reported and the increment from the previous sample to this one, over the six states
    /// `[v_x v_y v_z q r p]`.
    pub fn observe_step(
        &mut self,
        previous: &HoverSample<T>,
        current: &HoverSample<T>,
        innovation: &HoverState<T>,
    ) -> Result<Option<ConvergenceStatus<T, 6>>, Error> {
        let (a, b) = (previous.state().to_array(), current.state().to_array());
        let mut increment = [T::zero(); 6];
        for ((d, &x), &y) in increment.iter_mut().zip(a.iter()).zip(b.iter()) {
            *d = y - x;
        }
        self.observe(&innovation.to_array(), &increment)
    }
}
