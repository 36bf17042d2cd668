//! The update kernels of [`Rls`](super::Rls): one covariance-form and one U-D measurement
//! update, written once over slices ([`RlsSlices`]) and over the parameters an update may touch
//! ([`ParameterSupport`]), so that a firmware carries one copy for every model size.

use core::ops::Range;

use super::{col, column, column_mut, Algorithm, RlsConfig, RlsCounters, RlsView, PARAMETER_LIMIT};
use crate::scalar::{within, Real};

/// A run `start..end` of consecutive parameter indices (see `Rls::update_row`'s support).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Run {
    pub(crate) start: u16,
    pub(crate) end: u16,
}

/// One scalar measurement as an update takes it.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Measurement<T> {
    /// The prior innovation `y − ξᵀθ`.
    pub(crate) e: T,
    /// The measurement's variance, in units of the estimator's noise variance, times the
    /// forgetting factor it is updated with: `λ` for an ordinary row (the paper's
    /// `λ + ξᵀPξ`), `λ/w` for a row of weight w (weighted least squares: the same update as
    /// the row and innovation scaled by `√w`, without the square root).
    pub(crate) variance: T,
    /// The forgetting factor λ applied after the update (`P ← P/λ`).
    pub(crate) lambda: T,
}

impl<T: Real> Measurement<T> {
    /// An ordinary row (unit weight) with forgetting factor λ.
    #[inline(always)]
    pub(crate) fn row(e: T, lambda: T) -> Self {
        Self {
            e,
            variance: lambda,
            lambda,
        }
    }

    /// A row of weight `w` (0 < w ≤ 1) with forgetting factor λ: variance `λ/w`
    /// (`λ` exactly for `w = 1`).
    #[inline(always)]
    pub(crate) fn weighted(e: T, w: T, lambda: T) -> Self {
        Self {
            e,
            variance: lambda / w,
            lambda,
        }
    }
}

/// The parameters an update may change, as ascending disjoint runs of indices.
///
/// A trait rather than a slice so that the dense case ([`AllParameters`], what a bare [`Rls`]
/// knows) compiles to plain loops over `0..N`, as fast as if runs did not exist.
pub(crate) trait ParameterSupport: Copy {
    /// Whether the sums over ξ run over every entry rather than over a list of the non-zero
    /// ones (the same bits: a zero ξ_i adds ±0). Worth it only for a few parameters.
    fn dense_sums(self) -> bool;

    fn runs(self) -> impl Iterator<Item = Range<usize>>;

    /// A bound on the length of every run, if one is known at compile time (N for
    /// [`AllParameters`]): the U-D update's inner loop takes it as its upper trip count, which
    /// lets the compiler unroll the short loops of a small N instead of unrolling them by 4
    /// plus a remainder (the flight identifier's step, 7-parameter updates, is 5 % cheaper on
    /// the Cortex-M4F).
    fn max_len(self) -> Option<usize>;

    /// `RlsSlices::update` over this support (scratch `s` of length N).
    fn update<T: Real>(
        self,
        w: &mut RlsSlices<'_, T>,
        xi: &[T],
        nz: &[u16],
        m: Measurement<T>,
        s: [&mut [T]; 3],
    ) -> bool;
}

/// All N parameters.
#[derive(Copy, Clone)]
pub(crate) struct AllParameters(pub(crate) usize);

/// Up to this many parameters, a bare [`Rls`] sums over every ξ entry: the list of the
/// non-zero entries costs more than it saves (about 8 % at N = 2 on x86_64; on the Cortex-M4F
/// local rules' 7-parameter updates, whose regressors are rarely zero anywhere, make the
/// flight identifier's step 11 % cheaper with dense sums than with the list).
pub(crate) const DENSE_SUMS_UP_TO: usize = 16;

impl ParameterSupport for AllParameters {
    #[inline(always)]
    fn dense_sums(self) -> bool {
        self.0 <= DENSE_SUMS_UP_TO
    }

    #[inline(always)]
    fn runs(self) -> impl Iterator<Item = Range<usize>> {
        core::iter::once(0..self.0)
    }

    #[inline(always)]
    fn max_len(self) -> Option<usize> {
        Some(self.0)
    }

    /// Inlined into the estimator of each size: the loops are over constant lengths, which
    /// the compiler unrolls for small N. Built for small code (`core/build.rs`), one copy
    /// for every size instead ([`RlsSlices::update_shared`]).
    #[inline(always)]
    fn update<T: Real>(
        self,
        w: &mut RlsSlices<'_, T>,
        xi: &[T],
        nz: &[u16],
        m: Measurement<T>,
        s: [&mut [T]; 3],
    ) -> bool {
        let [s1, s2, s3] = s;
        if cfg!(rotorid_small_code) {
            w.update_shared(xi, nz, self, m, s1, s2, s3)
        } else {
            w.update(xi, nz, self, m, s1, s2, s3)
        }
    }
}

impl ParameterSupport for &[Run] {
    #[inline(always)]
    fn dense_sums(self) -> bool {
        false
    }

    #[inline(always)]
    fn max_len(self) -> Option<usize> {
        None
    }

    #[inline(always)]
    fn runs(self) -> impl Iterator<Item = Range<usize>> {
        self.iter()
            .map(|r| usize::from(r.start)..usize::from(r.end))
    }

    /// The shared routine: one copy for every model.
    #[inline(always)]
    fn update<T: Real>(
        self,
        w: &mut RlsSlices<'_, T>,
        xi: &[T],
        nz: &[u16],
        m: Measurement<T>,
        s: [&mut [T]; 3],
    ) -> bool {
        let [s1, s2, s3] = s;
        w.update_shared(xi, nz, self, m, s1, s2, s3)
    }
}

/// The part of `run` below `j`.
#[inline(always)]
fn below(run: Range<usize>, j: usize) -> Range<usize> {
    run.start..run.end.min(j)
}

/// An estimator's storage as slices (`theta.len() = N`, `factor.len() = N(N+1)/2`).
pub(crate) struct RlsSlices<'a, T> {
    pub(super) config: &'a RlsConfig<T>,
    pub(super) theta: &'a mut [T],
    pub(super) factor: &'a mut [T],
    pub(super) counters: &'a mut RlsCounters,
}

impl<T: Real> RlsSlices<'_, T> {
    /// [`update`](Self::update) as one shared routine per kind of support: over runs, the copy
    /// that every model of an identifier calls, whatever its size (a firmware carries 8
    /// models); over every parameter, the copy every estimator size calls when the build asks
    /// for small code (`core/build.rs`).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn update_shared<S: ParameterSupport>(
        &mut self,
        xi: &[T],
        nz: &[u16],
        support: S,
        m: Measurement<T>,
        s1: &mut [T],
        s2: &mut [T],
        s3: &mut [T],
    ) -> bool {
        self.update(xi, nz, support, m, s1, s2, s3)
    }

    /// One update with the measurement `m` (see [`Measurement`]); scratch slices of
    /// length N. Returns whether it was applied.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn update<S: ParameterSupport>(
        &mut self,
        xi: &[T],
        nz: &[u16],
        support: S,
        m: Measurement<T>,
        s1: &mut [T],
        s2: &mut [T],
        s3: &mut [T],
    ) -> bool {
        match self.config.algorithm {
            Algorithm::Covariance => self.covariance_update(xi, nz, support, m, s1, s2),
            Algorithm::UdFactor => {
                self.ud_update(xi, nz, support, m, s1, s2, s3);
                true
            }
        }
    }

    /// `K = Pξ/(r + ξᵀPξ)`, `P ← (P − K (Pξ)ᵀ)/λ`, `θ ← θ + K e` (`r` the measurement's
    /// variance, λ for an ordinary row). Returns whether the
    /// update was applied (see [`RlsCounters::numerical_skips`]). `g`, `k`: zeroed scratch.
    #[allow(clippy::too_many_arguments)]
    fn covariance_update<S: ParameterSupport>(
        &mut self,
        xi: &[T],
        nz: &[u16],
        support: S,
        m: Measurement<T>,
        g: &mut [T],
        k: &mut [T],
    ) -> bool {
        // g = P ξ, one column of the packed triangle at a time: column j holds P(i, j) for
        // i ≤ j, which gives g_i += P(i, j) ξ_j for i < j and g_j = Σ_{i ≤ j} P(i, j) ξ_i
        // (g_j is untouched before column j). Each g_i therefore sums its terms in ascending
        // j from +0, as P ξ written out. Terms that are exact zeros are skipped (zero ξ_j, `nz`
        // lists the others; P(i, j) outside the support): adding ±0 to a sum from +0 changes
        // nothing. Outside the support g stays 0.
        for run in support.runs() {
            for j in run.clone() {
                let (Some((&pjj, above)), Some(&xj)) = (column(self.factor, j), xi.get(j)) else {
                    break;
                };
                let mut s = T::zero();
                if xj == T::zero() {
                    s = sum_below(support, s, above, xi, nz);
                } else {
                    for r in support.runs() {
                        let rows = below(r, j);
                        let (Some(gs), Some(ps), Some(xs)) = (
                            g.get_mut(rows.clone()),
                            above.get(rows.clone()),
                            xi.get(rows),
                        ) else {
                            break;
                        };
                        for ((gi, &p), &x) in gs.iter_mut().zip(ps).zip(xs) {
                            *gi += p * xj;
                            s += p * x;
                        }
                    }
                    s += pjj * xj;
                }
                if let Some(gj) = g.get_mut(j) {
                    *gj = s;
                }
            }
        }
        let Measurement {
            e,
            variance,
            lambda,
        } = m;
        let mut denom = variance;
        if support.dense_sums() {
            for (&x, &gi) in xi.iter().zip(g.iter()) {
                denom += x * gi;
            }
        } else {
            for &i in nz {
                let i = usize::from(i);
                if let (Some(&x), Some(&gi)) = (xi.get(i), g.get(i)) {
                    denom += x * gi;
                }
            }
        }
        // In f32 with a large α this form can lose positive definiteness (the reason the U-D
        // form exists): an update whose denominator is not positive, or whose step would take
        // a parameter beyond PARAMETER_LIMIT, is skipped and counted rather than allowed to
        // produce ∞, NaN or a parameter that no prediction survives.
        if !(denom > T::zero() && denom.is_finite()) {
            self.counters.numerical_skips = self.counters.numerical_skips.wrapping_add(1);
            return false;
        }
        // K = g / (λ + ξᵀPξ), divided entry by entry exactly as the paper writes it (0
        // outside the support, where g is 0).
        for run in support.runs() {
            let r = run;
            let (Some(ks), Some(gs), Some(ts)) =
                (k.get_mut(r.clone()), g.get(r.clone()), self.theta.get(r))
            else {
                break;
            };
            for ((ki, &gi), &t) in ks.iter_mut().zip(gs).zip(ts) {
                *ki = gi / denom;
                // Within the import bound, not only finite: a finite θ near f32::MAX would
                // make the next prediction overflow after this step had been written.
                if !within(t + *ki * e, T::lit(PARAMETER_LIMIT)) {
                    self.counters.numerical_skips = self.counters.numerical_skips.wrapping_add(1);
                    return false;
                }
            }
        }
        // Forgetting with the windup guard: trace(P⁺)/λ must stay within the bound.
        let mut scale = None;
        if lambda < T::one() {
            let mut trace = T::zero();
            for (j, (&kj, &gj)) in k.iter().zip(g.iter()).enumerate() {
                trace += self.factor.get(col(j) + j).copied().unwrap_or_else(T::zero) - kj * gj;
            }
            if trace / lambda <= self.config.max_trace {
                scale = Some(T::one() / lambda);
            } else {
                self.counters.windup_guards = self.counters.windup_guards.wrapping_add(1);
            }
        }
        match scale {
            // P − K gᵀ: only columns j and rows i in the support change (K and g are 0
            // elsewhere), and only columns with g_j ≠ 0.
            None => {
                for run in support.runs() {
                    for j in run.clone() {
                        let gj = g.get(j).copied().unwrap_or_else(T::zero);
                        if gj == T::zero() {
                            continue; // P_ij − K_i·0 = P_ij
                        }
                        let start = col(j);
                        let Some(column) = self.factor.get_mut(start..=start + j) else {
                            break;
                        };
                        for r in support.runs() {
                            let rows = below(r, j + 1);
                            let (Some(ps), Some(ks)) = (column.get_mut(rows.clone()), k.get(rows))
                            else {
                                break;
                            };
                            for (p, &ki) in ps.iter_mut().zip(ks) {
                                *p -= ki * gj;
                            }
                        }
                    }
                }
            }
            // (P − K gᵀ)/λ scales every entry: all of P.
            Some(s) => {
                for (j, &gj) in g.iter().enumerate() {
                    let start = col(j);
                    let Some(column) = self.factor.get_mut(start..=start + j) else {
                        continue;
                    };
                    for (p, &ki) in column.iter_mut().zip(k.iter()) {
                        *p = (*p - ki * gj) * s;
                    }
                }
            }
        }
        for run in support.runs() {
            let r = run;
            let (Some(ts), Some(ks)) = (self.theta.get_mut(r.clone()), k.get(r)) else {
                break;
            };
            for (t, &ki) in ts.iter_mut().zip(ks) {
                *t += ki * e;
            }
        }
        true
    }

    /// Bierman's U-D measurement update with the measurement's variance `r` (λ for an ordinary
    /// row), then `D ← D/λ`.
    /// `f`, `v`, `b`: zeroed scratch.
    ///
    /// Always inlined: into `update_shared` (one copy for the runs of every model) and into
    /// each bare estimator's `update_row`, where N is a constant and the loops get its
    /// bounds (LLVM left it out of line, so the bare estimators of every size shared one copy
    /// that knew no N; inlined, the flight identifier's step is 13 % cheaper on the
    /// Cortex-M4F).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn ud_update<S: ParameterSupport>(
        &mut self,
        xi: &[T],
        nz: &[u16],
        support: S,
        m: Measurement<T>,
        f: &mut [T],
        v: &mut [T],
        b: &mut [T],
    ) {
        // f = Uᵀ ξ (U unit upper triangular); v = D f. The sums visit the non-zero ξ_i only
        // (`nz`, ascending): a zero term would add ±0, which changes no non-zero sum and at
        // most the sign of a zero f_j (whose column is skipped either way). Outside the
        // support f is 0 (ξ_j = 0 and column j of U is zero above the diagonal).
        for run in support.runs() {
            let r = run.clone();
            let (Some(fs), Some(vs), Some(xs)) =
                (f.get_mut(r.clone()), v.get_mut(r.clone()), xi.get(r))
            else {
                break;
            };
            for (j, ((fj, vj), &xj)) in run.zip(fs.iter_mut().zip(vs).zip(xs)) {
                let Some((&dj, above)) = column(self.factor, j) else {
                    break;
                };
                let s = sum_below(support, xj, above, xi, nz);
                *fj = s;
                *vj = dj * s;
            }
        }
        // b accumulates the unnormalised gain U D f = P ξ.
        let Measurement {
            e,
            variance,
            lambda,
        } = m;
        let mut alpha = variance;
        // 1/α₀, without a division in the usual case α₀ = 1 (1/1 = 1 exactly).
        let mut inv_alpha = if variance == T::one() {
            T::one()
        } else {
            T::one() / variance
        };
        for run in support.runs() {
            for j in run.clone() {
                let (Some(&fj), Some(&vj)) = (f.get(j), v.get(j)) else {
                    break;
                };
                if fj == T::zero() {
                    continue; // v_j = 0: column j and D_j unchanged, b unchanged
                }
                let alpha_prev = alpha;
                let inv_prev = inv_alpha;
                alpha = alpha_prev + fj * vj;
                // One division per column: 1/α_j serves this column's D update and the next p.
                inv_alpha = T::one() / alpha;
                let p = -fj * inv_prev;
                let Some((dj, above)) = column_mut(self.factor, j) else {
                    break;
                };
                *dj *= alpha_prev * inv_alpha;
                // Rows outside the support have U_ij = 0 and b_i = 0: unchanged.
                for r in support.runs() {
                    let rows = below(r, j);
                    let (Some(us), Some(bs)) = (above.get_mut(rows.clone()), b.get_mut(rows))
                    else {
                        break;
                    };
                    // (A `for` loop over `take`: `for_each` on it loses the gain, see
                    // `ParameterSupport::max_len`.)
                    let row = |(u, bi): (&mut T, &mut T)| {
                        let u_old = *u;
                        *u = u_old + *bi * p;
                        *bi += u_old * vj;
                    };
                    let rows = us.iter_mut().zip(bs.iter_mut());
                    match support.max_len() {
                        Some(n) => {
                            for x in rows.take(n) {
                                row(x);
                            }
                        }
                        None => {
                            for x in rows {
                                row(x);
                            }
                        }
                    }
                }
                if let Some(bj) = b.get_mut(j) {
                    *bj = vj;
                }
            }
        }
        // K = b/α; θ += K e, with the scalar e/α formed once (b is 0 outside the support).
        let gain = e * inv_alpha;
        for run in support.runs() {
            let r = run;
            let (Some(ts), Some(bs)) = (self.theta.get_mut(r.clone()), b.get(r)) else {
                break;
            };
            for (t, &bi) in ts.iter_mut().zip(bs) {
                *t += bi * gain;
            }
        }
        ud_forget(self.config, self.theta, self.factor, self.counters, lambda);
    }
}

/// `start + Σ_{i<j} a_i ξ_i` (j = `above.len()`) in ascending i: over every i if the
/// support says so ([`ParameterSupport::dense_sums`]), else over the non-zero ξ_i only (`nz`, ascending). The same bits either way: a
/// zero ξ_i adds ±0, which changes no non-zero sum and at most the sign of a zero one.
#[inline(always)]
fn sum_below<T: Real>(
    support: impl ParameterSupport,
    start: T,
    above: &[T],
    xi: &[T],
    nz: &[u16],
) -> T {
    let mut s = start;
    if support.dense_sums() {
        for (&a, &x) in above.iter().zip(xi) {
            s += a * x;
        }
    } else {
        let j = above.len();
        for &i in nz {
            let i = usize::from(i);
            if i >= j {
                break;
            }
            let (Some(&a), Some(&x)) = (above.get(i), xi.get(i)) else {
                break;
            };
            s += a * x;
        }
    }
    s
}

/// Up to this many parameters, an update over all of them in U-D form runs
/// [`ud_update_unrolled`]: loops over constant bounds that the compiler unrolls completely
/// (registers instead of scratch slices, no bounds checks left). Beyond it the slice kernel's
/// loops keep the code small.
pub(crate) const UNROLLED_UP_TO: usize = 8;
// `ud_update_unrolled` calls `Column::update` for columns 0 to 7.
const _: () = assert!(UNROLLED_UP_TO == 8);

/// Bierman's U-D update over all N parameters with the sizes as constants: the very
/// arithmetic of [`RlsSlices::ud_update`] with [`AllParameters`] and dense sums, in the same
/// order, so the same bits (`rls::tests` compares the two). Only for `N ≤`
/// [`UNROLLED_UP_TO`] (the caller checks): the column loop is written out as one call per
/// column (`Column::update::<J>`), so that each column's row loop has the constant length J
/// and the compiler unrolls it. On the Cortex-M4F a 7-parameter update costs about 290
/// instructions this way, 600 through the slice kernel (docs/cost.md).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn ud_update_unrolled<T: Real, const N: usize, const NP: usize>(
    theta: &mut [T; N],
    factor: &mut [T; NP],
    config: &RlsConfig<T>,
    counters: &mut RlsCounters,
    xi: &[T; N],
    m: Measurement<T>,
) {
    let Measurement {
        e,
        variance,
        lambda,
    } = m;
    let zero = T::zero();
    let at = |packed: &[T; NP], k: usize| packed.get(k).copied().unwrap_or(zero);
    // f = Uᵀ ξ (f_j = ξ_j + Σ_{i<j} U_ij ξ_i, ascending i); v = D f.
    let mut f = [zero; N];
    let mut v = [zero; N];
    for j in 0..N {
        let c = col(j);
        let mut s = xi.get(j).copied().unwrap_or(zero);
        for (i, &x) in xi.iter().enumerate().take(j) {
            s += at(factor, c + i) * x;
        }
        if let (Some(fj), Some(vj)) = (f.get_mut(j), v.get_mut(j)) {
            *fj = s;
            *vj = at(factor, c + j) * s;
        }
    }
    // b accumulates the unnormalised gain U D f = P ξ; see `RlsSlices::ud_update`. The
    // columns one call each, so that every column's loop has a constant length.
    let mut column = Column {
        f,
        v,
        b: [zero; N],
        alpha: variance,
        inv_alpha: if variance == T::one() {
            T::one()
        } else {
            T::one() / variance
        },
    };
    column.update::<0, NP>(factor);
    column.update::<1, NP>(factor);
    column.update::<2, NP>(factor);
    column.update::<3, NP>(factor);
    column.update::<4, NP>(factor);
    column.update::<5, NP>(factor);
    column.update::<6, NP>(factor);
    column.update::<7, NP>(factor);
    let Column { b, inv_alpha, .. } = column;
    let gain = e * inv_alpha;
    for (t, &bi) in theta.iter_mut().zip(b.iter()) {
        *t += bi * gain;
    }
    ud_forget(config, theta, factor, counters, lambda);
}

/// `D ← D/λ` after a U-D update with forgetting (λ < 1), unless trace(P)/λ would pass the
/// windup guard's bound ([`RlsConfig::max_trace`]), which is then counted instead. trace(P)
/// is summed as [`RlsView::trace`] sums it (the same code).
#[inline(always)]
fn ud_forget<T: Real>(
    config: &RlsConfig<T>,
    theta: &[T],
    factor: &mut [T],
    counters: &mut RlsCounters,
    lambda: T,
) {
    if lambda >= T::one() {
        return;
    }
    let view = RlsView {
        config,
        theta,
        factor,
        counters,
    };
    if view.trace() / lambda <= config.max_trace {
        let s = T::one() / lambda;
        for j in 0..theta.len() {
            if let Some(d) = factor.get_mut(col(j) + j) {
                *d *= s;
            }
        }
    } else {
        counters.windup_guards = counters.windup_guards.wrapping_add(1);
    }
}

/// The running state of [`ud_update_unrolled`]'s column loop.
struct Column<T, const N: usize> {
    f: [T; N],
    v: [T; N],
    b: [T; N],
    alpha: T,
    inv_alpha: T,
}

impl<T: Real, const N: usize> Column<T, N> {
    /// Column J of the U-D update (nothing for J ≥ N): the loop body of
    /// [`RlsSlices::ud_update`]'s column loop, its row loop `0..J` of constant length.
    #[inline(always)]
    fn update<const J: usize, const NP: usize>(&mut self, factor: &mut [T; NP]) {
        let (Some(&fj), Some(&vj)) = (self.f.get(J), self.v.get(J)) else {
            return;
        };
        if fj == T::zero() {
            return; // v_j = 0: column j and D_j unchanged, b unchanged
        }
        let alpha_prev = self.alpha;
        let inv_prev = self.inv_alpha;
        self.alpha = alpha_prev + fj * vj;
        self.inv_alpha = T::one() / self.alpha;
        let p = -fj * inv_prev;
        let c = col(J);
        if let Some(dj) = factor.get_mut(c + J) {
            *dj *= alpha_prev * self.inv_alpha;
        }
        for i in 0..J {
            if let (Some(u), Some(bi)) = (factor.get_mut(c + i), self.b.get_mut(i)) {
                let u_old = *u;
                *u = u_old + *bi * p;
                *bi += u_old * vj;
            }
        }
        if let Some(bj) = self.b.get_mut(J) {
            *bj = vj;
        }
    }
}
