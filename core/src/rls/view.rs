//! A size-erased read view of an estimator: what a firmware or a tool reads out of any
//! [`Rls`](super::Rls) (θ, the packed factor, the counters, the settings) without being generic
//! over its size, as `heapless`'s `VecView` is to `Vec`. One copy of the code that sends,
//! stores or prints an estimator then serves every model size.

use super::{col, Algorithm, RlsConfig, RlsCounters};
use crate::scalar::Real;

/// A read view of an estimator of any size (from [`Rls::view`](super::Rls::view)).
#[derive(Copy, Clone, Debug)]
pub struct RlsView<'a, T> {
    pub(super) config: &'a RlsConfig<T>,
    pub(super) theta: &'a [T],
    pub(super) factor: &'a [T],
    pub(super) counters: &'a RlsCounters,
}

impl<'a, T: Real> RlsView<'a, T> {
    /// Number of parameters N.
    pub fn len(&self) -> usize {
        self.theta.len()
    }

    /// Whether the estimator has no parameter (never: N ≥ 1).
    pub fn is_empty(&self) -> bool {
        self.theta.is_empty()
    }

    /// The parameter estimate θ (N entries).
    pub fn parameters(&self) -> &'a [T] {
        self.theta
    }

    /// The packed covariance P (covariance form) or U with D on the diagonal (U-D form):
    /// N(N+1)/2 entries, column by column.
    pub fn packed_factor(&self) -> &'a [T] {
        self.factor
    }

    /// The settings.
    pub fn config(&self) -> &'a RlsConfig<T> {
        self.config
    }

    /// How [`packed_factor`](Self::packed_factor) is to be read.
    pub fn algorithm(&self) -> Algorithm {
        self.config.algorithm
    }

    /// The counters.
    pub fn counters(&self) -> &'a RlsCounters {
        self.counters
    }

    /// `P_ii` (`None` past N): O(1) in the covariance form, O(N) in U-D form
    /// (`D_i + Σ_{j>i} U_ij² D_j`, in ascending j).
    pub fn covariance_diagonal_entry(&self, i: usize) -> Option<T> {
        if i >= self.len() {
            return None;
        }
        let at = |r: usize, c: usize| self.factor.get(col(c) + r).copied().unwrap_or_else(T::zero);
        Some(match self.config.algorithm {
            Algorithm::Covariance => at(i, i),
            Algorithm::UdFactor => {
                // The order of `Rls::covariance_diagonal` (same bits): from zero, D_i first.
                let mut d = T::zero();
                d += at(i, i);
                for j in i + 1..self.len() {
                    let u = at(i, j);
                    d += u * u * at(j, j);
                }
                d
            }
        })
    }

    /// diag(P), entry by entry.
    pub fn covariance_diagonal(&self) -> impl Iterator<Item = T> + '_ {
        (0..self.len()).filter_map(|i| self.covariance_diagonal_entry(i))
    }

    /// trace(P) (O(N) for the covariance form, O(N²) for U-D).
    pub fn trace(&self) -> T {
        let mut t = T::zero();
        for d in self.covariance_diagonal() {
            t += d;
        }
        t
    }
}
