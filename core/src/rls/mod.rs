//! Recursive least squares (paper Section 4), statically sized.
//!
//! The settings are in `config.rs`, the update kernels in `update.rs`, the read-only view in
//! `view.rs`, the unit tests in `tests.rs`.
//!
//! The estimator solves `y(k) ≈ ξ(k)ᵀθ` for the parameter vector θ ∈ ℝᴺ, one scalar
//! measurement at a time. Only the `NP = N(N+1)/2` distinct entries of the symmetric
//! covariance P (or of its U-D factors) are stored, packed column by column: entry (i, j) with
//! i ≤ j lives at `j(j+1)/2 + i`.
//!
//! Two algebraically equivalent [`Algorithm`]s are offered:
//!
//! * [`Algorithm::Covariance`]: the textbook form the paper prints,
//!   `K = Pξ/(λ + ξᵀPξ)`, `P ← (P − K ξᵀP)/λ`, `θ ← θ + K(y − ξᵀθ)`. With λ = 1 and
//!   `P(0) = αI` ([`RlsConfig::paper`]) it reproduces the paper exactly. In `f32` with the
//!   paper's "very large" α the subtraction `P − KξᵀP` loses most digits to cancellation and
//!   P can drift indefinite.
//! * [`Algorithm::UdFactor`]: Bierman's U-D factorised update (`P = U D Uᵀ`, U unit upper
//!   triangular, D diagonal). It propagates the factors instead of P, so P stays symmetric
//!   positive semi-definite by construction and keeps about twice the significant digits.
//!   This is the default ([`RlsConfig::default`]).
//!
//! Exponential forgetting (λ < 1) discounts old data so that slowly varying parameters can be
//! tracked; without excitation it makes P grow without bound ("covariance windup"). The guard
//! here: a step whose division by λ would push trace(P) above [`RlsConfig::max_trace`] is not
//! divided (λ = 1 for that step), and the event is counted.
//!
//! Regressor entries that are exactly zero (rules that do not fire) are skipped wherever that
//! saves work without changing the result: the products `Pξ`, `Uᵀξ` and `ξᵀθ` only visit the
//! non-zero entries, and a U-D column whose `(Uᵀξ)_j` is zero is left untouched.
//!
//! Every update checks its inputs completely before it writes anything: on `Err` the
//! estimator is unchanged, bit for bit.
//!
//! ```
//! use rotorid::rls::{Rls, RlsConfig};
//!
//! // y = 2 x₁ − 0.5 x₂, learnt from four measurements (U-D form, P(0) = 10⁶ I).
//! let mut rls = Rls::<f32, 2, 3>::new(RlsConfig::default())?;
//! for x in [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, -1.0]] {
//!     let innovation = rls.update(&x, 2.0 * x[0] - 0.5 * x[1])?; // y − ξᵀθ before the step
//!     assert!(innovation.is_finite());
//! }
//! let [a, b] = *rls.parameters();
//! assert!((a - 2.0).abs() < 1e-3 && (b + 0.5).abs() < 1e-3);
//! // A NaN is refused, and nothing changes.
//! let before = rls.clone();
//! assert!(rls.update(&[f32::NAN, 0.0], 1.0).is_err());
//! assert_eq!(rls, before);
//! # Ok::<(), rotorid::Error>(())
//! ```

use crate::error::{Error, Quantity};
use crate::scalar::{within, Real};

mod config;
pub mod errors_in_variables;
mod update;
mod view;

pub use config::{Algorithm, RlsConfig};

pub use errors_in_variables::{Compensation, NotCompensated, PairedNoise, RegressorNoise};
use update::RlsSlices;
use update::{ud_update_unrolled, UNROLLED_UP_TO};
pub(crate) use update::{AllParameters, Measurement, ParameterSupport, Run, DENSE_SUMS_UP_TO};
pub use view::RlsView;

/// Largest accepted magnitude of a regressor entry `ξ_j`.
///
/// With `α ≤ 1e12` and `N ≤ 512` this keeps every intermediate of an update far from `f32`
/// overflow, so an accepted input can never produce ∞ or NaN.
pub const REGRESSOR_LIMIT: f64 = 1e7;
/// Largest accepted magnitude of a target `y` and of the prior innovation `y − ξᵀθ`.
pub const TARGET_LIMIT: f64 = 1e9;
/// Largest accepted initial covariance α and trace bound.
pub const COVARIANCE_LIMIT: f64 = 1e12;
/// Largest magnitude of an imported parameter θ_i (in the estimator's, possibly scaled,
/// coordinates). Learning never comes near it; a state beyond it would make predictions
/// overflow.
pub const PARAMETER_LIMIT: f64 = 1e12;
/// Largest magnitude of an imported off-diagonal factor entry (`P_ij` in the covariance form,
/// `U_ij` in the U-D form). Learning keeps `|P_ij| ≤ √(P_ii P_jj)` ≤ [`COVARIANCE_LIMIT`];
/// `U_ij` can exceed it where `D_j` is tiny, hence the wider bound. Within it `Uᵀξ` and `Pξ`
/// stay finite in f32 for every N ≤ 512 (`512 · 1e18 · 1e7 ≈ 5e27`).
pub const FACTOR_ENTRY_LIMIT: f64 = 1e18;

/// AllParameters an [`Rls`] has learnt, for export and warm start (import).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RlsState<T, const N: usize, const NP: usize> {
    /// How `factor` is to be read.
    pub algorithm: Algorithm,
    /// Parameter estimate θ.
    pub theta: [T; N],
    /// Packed covariance P (Covariance) or packed U with D on the diagonal (UdFactor).
    pub factor: [T; NP],
    /// Number of updates made.
    pub updates: u32,
}

impl<T, const N: usize, const NP: usize> RlsState<T, N, NP> {
    /// Parameters N of this state's estimator.
    pub const PARAMETERS: usize = N;
    /// Packed covariance (or U-D factor) entries, N(N+1)/2.
    pub const FACTOR_LEN: usize = NP;
}

/// Counters of an [`Rls`]. (The last prior innovation is what
/// [`update`](Rls::update) returns; it is not kept.)
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RlsCounters {
    /// Rank-one measurement updates made since construction or reset (outputs that
    /// [`TsRls`](crate::ts::TsRls) combines into one row count once).
    pub updates: u32,
    /// Steps in which forgetting was suspended by the trace bound.
    pub windup_guards: u32,
    /// Covariance-form updates skipped because P had lost positive definiteness (a
    /// non-positive `λ + ξᵀPξ`) or the step would take a parameter beyond [`PARAMETER_LIMIT`]. Always 0 for the U-D form.
    pub numerical_skips: u32,
}

impl RlsCounters {
    /// Nothing counted yet.
    const NONE: Self = Self {
        updates: 0,
        windup_guards: 0,
        numerical_skips: 0,
    };
}

/// Recursive least squares over `N` parameters with `NP = N(N+1)/2` packed covariance entries.
#[derive(Clone, Debug, PartialEq)]
pub struct Rls<T, const N: usize, const NP: usize> {
    config: RlsConfig<T>,
    core: RlsCore<T, N, NP>,
}

/// What an estimator learns, without its settings: θ, the packed covariance (or U-D) factor
/// and the counters. [`Rls`] is one of these with its [`RlsConfig`]; a
/// [`LocalTsRls`](crate::ts::local::LocalTsRls) keeps one per rule beside the one config that
/// every rule shares (a copy per rule would cost 16 B each in f32). Every operation takes the
/// settings it runs with.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RlsCore<T, const N: usize, const NP: usize> {
    theta: [T; N],
    factor: [T; NP],
    counters: RlsCounters,
}

/// Column j of a packed upper triangle: its diagonal entry and the j entries above it.
#[inline(always)]
fn column<T>(packed: &[T], j: usize) -> Option<(&T, &[T])> {
    let start = col(j);
    packed.get(start..=start + j)?.split_last()
}

/// [`column`], mutable.
#[inline(always)]
fn column_mut<T>(packed: &mut [T], j: usize) -> Option<(&mut T, &mut [T])> {
    let start = col(j);
    packed.get_mut(start..=start + j)?.split_last_mut()
}

/// Start of column j of the packed upper triangle.
#[inline(always)]
pub(crate) const fn col(j: usize) -> usize {
    j * (j + 1) / 2
}

impl<T: Real, const N: usize, const NP: usize> Rls<T, N, NP> {
    /// Compile-time size check: evaluated when `new` is instantiated.
    const SIZES_OK: () = assert!(
        NP == N * (N + 1) / 2 && N >= 1 && N <= 512,
        "Rls<N, NP> needs NP = N(N+1)/2 and 1 <= N <= 512"
    );

    /// A fresh estimator: θ(0) = 0, P(0) = αI.
    pub fn new(config: RlsConfig<T>) -> Result<Self, Error> {
        Self::check_new(&config)?;
        Ok(Self::new_unchecked(config))
    }

    /// The checks of [`new`](Self::new).
    pub(crate) fn check_new(config: &RlsConfig<T>) -> Result<(), Error> {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_OK;
        config.validate()
    }

    /// [`new`](Self::new) for settings that passed [`check_new`](Self::check_new). Inlined so
    /// that a caller building a large identifier writes the arrays in place (no stack copy).
    #[inline(always)]
    pub(crate) fn new_unchecked(config: RlsConfig<T>) -> Self {
        // Reset in place: building a fresh core and moving it in would put a copy of a large
        // estimator on the stack.
        let mut rls = Self {
            config,
            core: RlsCore::zeroed(),
        };
        rls.reset();
        rls
    }

    /// A fresh estimator starting from a given θ(0) (the paper's "good initial guess").
    pub fn with_initial_parameters(config: RlsConfig<T>, theta0: [T; N]) -> Result<Self, Error> {
        for (i, t) in theta0.iter().enumerate() {
            if !t.is_finite() {
                return Err(Error::NonFinite(Quantity::Parameter(i as u16)));
            }
        }
        let mut rls = Self::new(config)?;
        rls.core.theta = theta0;
        Ok(rls)
    }

    /// Back to θ = 0, P = αI, counters cleared.
    pub fn reset(&mut self) {
        self.core.reset(&self.config);
    }

    /// The settings.
    pub fn config(&self) -> &RlsConfig<T> {
        &self.config
    }

    /// Parameter estimate θ.
    pub fn parameters(&self) -> &[T; N] {
        &self.core.theta
    }

    /// Counters.
    pub fn counters(&self) -> &RlsCounters {
        &self.core.counters
    }

    /// The raw packed covariance (or U-D factor) storage.
    pub fn packed_factor(&self) -> &[T; NP] {
        &self.core.factor
    }

    /// Diagonal of P: the current variance of each parameter.
    ///
    /// For the U-D form `P_ii = D_i + Σ_{j>i} U_ij² D_j` (O(N²); meant for diagnostics).
    pub fn covariance_diagonal(&self) -> [T; N] {
        let mut diag = [T::zero(); N];
        for (d, v) in diag.iter_mut().zip(self.view().covariance_diagonal()) {
            *d = v;
        }
        diag
    }

    /// trace(P) (O(N) for the covariance form, O(N²) for U-D).
    pub fn trace(&self) -> T {
        self.view().trace()
    }

    /// A size-erased read view ([`RlsView`]): θ, the packed factor, counters and settings,
    /// for code that serves estimators of every size with one copy.
    pub fn view(&self) -> RlsView<'_, T> {
        self.core.view(&self.config)
    }

    /// Entry `P_ij` of the covariance (`None` outside N×N). O(1) for the covariance form,
    /// O(N) for U-D (`P_ij = Σ_{k ≥ max(i,j)} U_ik D_k U_jk`).
    pub fn covariance(&self, i: usize, j: usize) -> Option<T> {
        if i >= N || j >= N {
            return None;
        }
        let (a, b) = if i <= j { (i, j) } else { (j, i) };
        let factor = &self.core.factor;
        match self.config.algorithm {
            Algorithm::Covariance => factor.get(col(b) + a).copied(),
            Algorithm::UdFactor => {
                let u = |r: usize, k: usize| -> T {
                    if r == k {
                        T::one()
                    } else {
                        factor.get(col(k) + r).copied().unwrap_or_else(T::zero)
                    }
                };
                let mut s = T::zero();
                for k in b..N {
                    let dk = factor.get(col(k) + k).copied().unwrap_or_else(T::zero);
                    s += u(a, k) * dk * u(b, k);
                }
                Some(s)
            }
        }
    }

    /// The full symmetric P, row-major (for tests and reports; N² values on the stack).
    pub fn covariance_matrix(&self) -> [[T; N]; N] {
        let mut p = [[T::zero(); N]; N];
        for (i, row) in p.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = self.covariance(i, j).unwrap_or_else(T::zero);
            }
        }
        p
    }

    /// Prediction `ξᵀθ` for a regressor (checked like an update's regressor).
    pub fn predict(&self, regressor: &[T; N]) -> Result<T, Error> {
        check_regressor(regressor)?;
        Ok(dot(regressor, &self.core.theta))
    }

    /// One scalar update with regressor ξ and target y. Returns the prior innovation
    /// `y − ξᵀθ(k)`. On `Err` nothing changed.
    pub fn update(&mut self, regressor: &[T; N], target: T) -> Result<T, Error> {
        let [e] = self.check(core::array::from_ref(regressor), &[target])?;
        self.update_row(
            regressor,
            AllParameters(N),
            Measurement::row(e, self.config.forgetting),
        );
        Ok(e)
    }

    /// M scalar measurements that share θ, taken at the same time, processed one after another
    /// (exact for RLS with unit measurement weights). Forgetting is applied once per call,
    /// after the last measurement: `P⁻¹ ← λ (P⁻¹ + Σ_m ξ_m ξ_mᵀ)`, so λ discounts per sample,
    /// however many outputs a sample has. All inputs are checked first; the returned
    /// innovations are the prior ones, `y_m − ξ_mᵀθ(k)`, all taken with θ before this call.
    pub fn update_many<const M: usize>(
        &mut self,
        regressors: &[[T; N]; M],
        targets: &[T; M],
    ) -> Result<[T; M], Error> {
        let innovations = self.check(regressors, targets)?;
        if let Some(&first) = innovations.first() {
            self.apply(regressors, targets, first);
        }
        Ok(innovations)
    }

    /// The checks of [`update_many`](Self::update_many) without the update: every regressor
    /// entry within [`REGRESSOR_LIMIT`], every target and prior innovation within
    /// [`TARGET_LIMIT`]. Returns the prior innovations.
    pub fn check<const M: usize>(
        &self,
        regressors: &[[T; N]; M],
        targets: &[T; M],
    ) -> Result<[T; M], Error> {
        let limit = T::lit(TARGET_LIMIT);
        let mut innovations = [T::zero(); M];
        for (m, ((xi, &y), e)) in regressors
            .iter()
            .zip(targets.iter())
            .zip(innovations.iter_mut())
            .enumerate()
        {
            check_regressor(xi)?;
            if !within(y, limit) {
                let at = Quantity::Target(m as u8);
                return Err(if y.is_finite() {
                    Error::OutOfRange(at)
                } else {
                    Error::NonFinite(at)
                });
            }
            *e = y - dot(xi, &self.core.theta);
            if !within(*e, limit) {
                return Err(Error::OutOfRange(Quantity::Target(m as u8)));
            }
        }
        Ok(innovations)
    }

    /// The update of [`update_many`](Self::update_many) for rows that passed
    /// [`check`](Self::check), `first` being the prior innovation it returned for row 0. Infallible: within those limits no intermediate can overflow.
    fn apply(&mut self, regressors: &[[T; N]], targets: &[T], first: T) {
        let last = regressors.len().saturating_sub(1);
        for (m, (xi, &y)) in regressors.iter().zip(targets.iter()).enumerate() {
            // Row 0's innovation was computed by `check` with this very θ (the same dot
            // product, the same bits); later rows see θ after the earlier rows of this sample
            // and are recomputed.
            let e = if m == 0 {
                first
            } else {
                y - dot(xi, &self.core.theta)
            };
            // λ once per sample: the earlier rows are plain measurement updates.
            let lambda = if m == last {
                self.config.forgetting
            } else {
                T::one()
            };
            self.update_row(xi, AllParameters(N), Measurement::row(e, lambda));
        }
    }

    /// `ξᵀθ` without checks (for regressors whose entries are known to be within the limits).
    pub(crate) fn dot(&self, xi: &[T; N]) -> T {
        dot(xi, &self.core.theta)
    }

    /// Exports everything learnt (θ, packed factor, update count).
    pub fn export(&self) -> RlsState<T, N, NP> {
        self.core.export(&self.config)
    }

    /// Imports a state exported by an estimator of the same algorithm and size (warm start).
    /// The state is checked first ([`check_import`](Self::check_import)); on `Err` nothing
    /// changed.
    pub fn import(&mut self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        self.core.import(&self.config, state)
    }

    /// The checks of [`import`](Self::import): the same algorithm, every entry finite, every
    /// parameter within [`PARAMETER_LIMIT`], every diagonal entry within [`COVARIANCE_LIMIT`]
    /// (for the U-D form `0 ≤ D_j`, an invariant of that form; the covariance form in f32 may
    /// legitimately have lost definiteness), every off-diagonal entry within
    /// [`FACTOR_ENTRY_LIMIT`], and for the U-D form every `P_ii = D_i + Σ U_ij² D_j` within
    /// twice [`COVARIANCE_LIMIT`]. An accepted state cannot make a later step fail after it
    /// started writing.
    pub fn check_import(&self, state: &RlsState<T, N, NP>) -> Result<(), Error> {
        RlsCore::check_import(&self.config, state)
    }

    /// Replaces the settings and starts afresh (θ = 0, P = αI), in place. On `Err` nothing
    /// changed.
    pub fn reconfigure(&mut self, config: RlsConfig<T>) -> Result<(), Error> {
        config.validate()?;
        self.config = config;
        self.reset();
        Ok(())
    }

    /// One scalar update whose inputs passed the checks of `update_many` (see
    /// [`RlsCore::update_row`]).
    pub(crate) fn update_row<S: ParameterSupport>(
        &mut self,
        xi: &[T; N],
        support: S,
        m: Measurement<T>,
    ) {
        self.core.update_row(&self.config, xi, support, m);
    }
}

impl<T: Real, const N: usize, const NP: usize> RlsCore<T, N, NP> {
    /// Every entry zero (not a valid factor: [`reset`](Self::reset) it before use).
    #[inline(always)]
    fn zeroed() -> Self {
        Self {
            theta: [T::zero(); N],
            factor: [T::zero(); NP],
            counters: RlsCounters::NONE,
        }
    }

    /// `R` estimators with θ = 0, P = αI, counters cleared: zeroed as one array, then each
    /// reset where it lies (made one by one, each was copied into the array twice: 176 B more
    /// in the C interface's lean flight firmware).
    #[inline(always)]
    pub(crate) fn fresh_array<const R: usize>(config: &RlsConfig<T>) -> [Self; R] {
        let mut all = core::array::from_fn(|_| Self::zeroed());
        for core in &mut all {
            core.reset(config);
        }
        all
    }

    /// Back to θ = 0, P = αI, counters cleared.
    pub(crate) fn reset(&mut self, config: &RlsConfig<T>) {
        self.theta = [T::zero(); N];
        let diag = config.initial_covariance;
        for j in 0..N {
            if let Some((diagonal, above)) = column_mut(&mut self.factor, j) {
                for u in above {
                    *u = T::zero();
                }
                *diagonal = diag;
            }
        }
        self.counters = RlsCounters::NONE;
    }

    /// Parameter estimate θ.
    pub(crate) fn parameters(&self) -> &[T; N] {
        &self.theta
    }

    /// A read view with the settings `config` ([`Rls::view`]).
    pub(crate) fn view<'a>(&'a self, config: &'a RlsConfig<T>) -> RlsView<'a, T> {
        RlsView {
            config,
            theta: &self.theta,
            factor: &self.factor,
            counters: &self.counters,
        }
    }

    /// [`Rls::export`].
    pub(crate) fn export(&self, config: &RlsConfig<T>) -> RlsState<T, N, NP> {
        RlsState {
            algorithm: config.algorithm,
            theta: self.theta,
            factor: self.factor,
            updates: self.counters.updates,
        }
    }

    /// [`Rls::import`].
    pub(crate) fn import(
        &mut self,
        config: &RlsConfig<T>,
        state: &RlsState<T, N, NP>,
    ) -> Result<(), Error> {
        Self::check_import(config, state)?;
        self.theta = state.theta;
        self.factor = state.factor;
        self.counters.updates = state.updates;
        Ok(())
    }

    /// [`Rls::check_import`].
    ///
    /// Bounds every word of the state, not only the diagonal, because an accepted import must
    /// leave every later step able to succeed or fail before it writes: with θ within
    /// [`PARAMETER_LIMIT`] and every regressor within [`REGRESSOR_LIMIT`] a prediction is at
    /// most `N·1e19` in magnitude (finite in f32 for every N ≤ 512), and with every factor
    /// entry and every `P_ii` bounded the first update's sums (`Pξ`, `ξᵀPξ`, `Uᵀξ`, `fᵀDf`)
    /// are finite too (Cauchy–Schwarz: `D_j f_j² ≤ |ξ|² Σ_i P_ii`).
    pub(crate) fn check_import(
        config: &RlsConfig<T>,
        state: &RlsState<T, N, NP>,
    ) -> Result<(), Error> {
        if state.algorithm != config.algorithm {
            return Err(Error::Incompatible);
        }
        check_state_words(config, &state.theta, &state.factor)
    }

    /// One scalar update whose inputs passed the checks of `update_many`.
    ///
    /// `support` lists, ascending and disjoint, the parameters outside of which every
    /// regressor entry and every off-diagonal entry of P (or U) is zero; [`AllParameters`] when
    /// nothing is known. Outside the support an update changes nothing (every term it would
    /// add there is an exact zero), so the loops visit the support only, with the same bits.
    ///
    /// The work is done by `RlsSlices::update`, generic over the scalar only: one copy of the
    /// update code serves every size N (a firmware with several models would otherwise carry
    /// one per size).
    pub(crate) fn update_row<S: ParameterSupport>(
        &mut self,
        config: &RlsConfig<T>,
        xi: &[T; N],
        support: S,
        m: Measurement<T>,
    ) {
        // Every parameter, few of them, U-D: the unrolled kernel (the same bits), unless the
        // build asks for small code (`core/build.rs`).
        if !cfg!(rotorid_small_code)
            && support.max_len() == Some(N)
            && N <= UNROLLED_UP_TO
            && config.algorithm == Algorithm::UdFactor
        {
            ud_update_unrolled(
                &mut self.theta,
                &mut self.factor,
                config,
                &mut self.counters,
                xi,
                m,
            );
            self.counters.updates = self.counters.updates.wrapping_add(1);
            return;
        }
        let mut s1 = [T::zero(); N];
        let mut s2 = [T::zero(); N];
        let mut s3 = [T::zero(); N];
        // Indices of the non-zero ξ_j, ascending: the sums over ξ visit only these (unless
        // they run over every entry, see `ParameterSupport::dense_sums`).
        let mut nz = [0u16; N];
        let mut nnz = 0;
        if !support.dense_sums() {
            for run in support.runs() {
                let Some(xs) = xi.get(run.clone()) else {
                    continue;
                };
                for (j, &x) in run.zip(xs) {
                    if x != T::zero() {
                        if let Some(slot) = nz.get_mut(nnz) {
                            // N ≤ 512 (`SIZES_OK`): the index fits.
                            *slot = j as u16;
                            nnz += 1;
                        }
                    }
                }
            }
        }
        let mut w = RlsSlices {
            config,
            theta: &mut self.theta,
            factor: &mut self.factor,
            counters: &mut self.counters,
        };
        let nz = nz.get(..nnz).unwrap_or(&[]);
        let applied = support.update(&mut w, xi, nz, m, [&mut s1, &mut s2, &mut s3]);
        if applied {
            self.counters.updates = self.counters.updates.wrapping_add(1);
        }
    }
}

/// The value checks of [`RlsCore::check_import`], over slices: one copy of the code per
/// scalar type, not one per estimator size (a firmware holds eight sizes or more).
#[inline(never)]
fn check_state_words<T: Real>(
    config: &RlsConfig<T>,
    theta: &[T],
    factor: &[T],
) -> Result<(), Error> {
    for (i, t) in theta.iter().enumerate() {
        if !t.is_finite() {
            return Err(Error::NonFinite(Quantity::Parameter(i as u16)));
        }
        if !within(*t, T::lit(PARAMETER_LIMIT)) {
            return Err(Error::OutOfRange(Quantity::Parameter(i as u16)));
        }
    }
    let limit = T::lit(COVARIANCE_LIMIT);
    let entry_limit = T::lit(FACTOR_ENTRY_LIMIT);
    let ud = config.algorithm == Algorithm::UdFactor;
    for j in 0..theta.len() {
        let Some((&d, above)) = column(factor, j) else {
            return Err(Error::Incompatible);
        };
        for (i, &p) in above.iter().enumerate() {
            let at = Quantity::Covariance((col(j) + i) as u16);
            if !p.is_finite() {
                return Err(Error::NonFinite(at));
            }
            if !within(p, entry_limit) {
                return Err(Error::OutOfRange(at));
            }
        }
        let at = Quantity::Covariance((col(j) + j) as u16);
        if !d.is_finite() {
            return Err(Error::NonFinite(at));
        }
        // The covariance form in f32 may legitimately have lost definiteness (a slightly
        // negative diagonal); the U-D form keeps D ≥ 0 by construction.
        let negative = if ud { d < T::zero() } else { d < -limit };
        if negative || d > limit {
            return Err(Error::OutOfRange(at));
        }
    }
    if ud {
        // P_ii = D_i + Σ_{j>i} U_ij² D_j: bounded D and U do not bound P (U = 1e12 with D = 1
        // is P_ii = 1e24). Learning never lets P_ii grow past max(α, trace bound) ≤ 1e12 (up
        // to rounding: hence twice the limit).
        let view = RlsView {
            config,
            theta,
            factor,
            counters: &RlsCounters::NONE,
        };
        for (i, p) in view.covariance_diagonal().enumerate() {
            if !within(p, limit + limit) {
                return Err(Error::OutOfRange(Quantity::Covariance((col(i) + i) as u16)));
            }
        }
    }
    Ok(())
}

/// Checks every regressor entry: finite and within [`REGRESSOR_LIMIT`].
fn check_regressor<T: Real, const N: usize>(xi: &[T; N]) -> Result<(), Error> {
    let limit = T::lit(REGRESSOR_LIMIT);
    for (j, &x) in xi.iter().enumerate() {
        if !within(x, limit) {
            let at = Quantity::Regressor(j as u16);
            return Err(if x.is_finite() {
                Error::OutOfRange(at)
            } else {
                Error::NonFinite(at)
            });
        }
    }
    Ok(())
}

/// `ξᵀθ` in index order, skipping zero ξ_j (bit-identical to the dense sum: θ is finite, so a
/// zero ξ_j adds ±0, which leaves a sum from +0 as it is).
#[inline]
fn dot<T: Real, const N: usize>(xi: &[T; N], theta: &[T; N]) -> T {
    let mut s = T::zero();
    for (&x, &t) in xi.iter().zip(theta.iter()) {
        if x != T::zero() {
            s += x * t;
        }
    }
    s
}

#[cfg(test)]
mod tests;
