//! Least squares with the coloured-residual covariance (Morelli & Klein, ch. 5–6; see the
//! [module docs](super)).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::samples::Point;
use super::{ACF_NEGLIGIBLE, COLLINEAR_RATIO};

pub(super) struct Fit {
    pub(super) theta: Vec<f64>,
    pub(super) se: Vec<f64>,
    pub(super) se_ols: Vec<f64>,
    pub(super) r_squared: f64,
    pub(super) residual_rms: f64,
    pub(super) lags: usize,
    pub(super) note: Option<String>,
}

/// Maximal stretches `[a, b)` of consecutive `index` in `points`.
pub(super) fn stretches(points: &[&Point]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut a = 0;
    for i in 1..=points.len() {
        if i == points.len() || points[i].index != points[i - 1].index + 1 {
            if i > a {
                out.push((a, i));
            }
            a = i;
        }
    }
    out
}

/// Least squares `y = X θ` with the corrected covariance; `Err(reason)` when it cannot be done.
pub(super) fn fit(
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    runs: &[(usize, usize)],
    names: &[&str],
    max_lag: usize,
) -> Result<Fit, String> {
    let (n, p) = x.shape();
    if n <= p {
        return Err(format!("{n} samples for {p} parameters"));
    }
    // Normalise the columns so the conditioning test is about collinearity, not units.
    let scale: Vec<f64> = (0..p)
        .map(|c| (x.column(c).norm_squared() / n as f64).sqrt())
        .collect();
    if let Some(c) = scale.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(format!(
            "the {} regressor is zero throughout or overflows",
            names.get(c).unwrap_or(&"?")
        ));
    }
    let mut xs = x.clone();
    for (c, s) in scale.iter().enumerate() {
        xs.column_mut(c).scale_mut(1.0 / s);
    }
    let gram = xs.transpose() * &xs;
    let eig = SymmetricEigen::new(gram);
    let (mut lo, mut hi) = (0usize, 0usize);
    for i in 0..p {
        if eig.eigenvalues[i] < eig.eigenvalues[lo] {
            lo = i;
        }
        if eig.eigenvalues[i] > eig.eigenvalues[hi] {
            hi = i;
        }
    }
    let (lmin, lmax) = (eig.eigenvalues[lo], eig.eigenvalues[hi]);
    if !(lmin.is_finite() && lmax.is_finite()) || lmin <= COLLINEAR_RATIO * lmax {
        // Name the terms that make up the near-null direction.
        let dir = eig.eigenvectors.column(lo);
        let mut involved: Vec<&str> = (0..p)
            .filter(|&i| dir[i].abs() > 0.3)
            .filter_map(|i| names.get(i).copied())
            .collect();
        involved.truncate(4);
        return Err(format!(
            "the regressors of {} cannot be told apart in these samples (collinear)",
            involved.join(", ")
        ));
    }
    let inv_eig = eig.eigenvalues.map(|l| 1.0 / l);
    let ginv = &eig.eigenvectors * DMatrix::from_diagonal(&inv_eig) * eig.eigenvectors.transpose();
    let theta_s = &ginv * (xs.transpose() * y);
    let resid = y - &xs * &theta_s;
    let sse = resid.norm_squared();
    let sigma2 = sse / (n - p) as f64;

    // Residual autocorrelation within stretches, lags until negligible (module doc).
    let nf = n as f64;
    let autocov = |l: usize| -> f64 {
        runs.iter()
            .filter(|(a, b)| b - a > l)
            .map(|&(a, b)| (a..b - l).map(|i| resid[i] * resid[i + l]).sum::<f64>())
            .sum::<f64>()
            / nf
    };
    let r0 = autocov(0);
    // An exact fit has no residual to correlate.
    let max_lag = if r0 > 0.0 { max_lag } else { 0 };
    let longest = runs.iter().map(|(a, b)| b - a).max().unwrap_or(0);
    let cap = max_lag.min(n / 4).min(longest.saturating_sub(1));
    let mut rhat = vec![r0];
    let mut l0 = None;
    for l in 1..=cap {
        let rl = autocov(l);
        rhat.push(rl);
        if r0 > 0.0 && (rl / r0).abs() < ACF_NEGLIGIBLE {
            l0 = Some(l);
            break;
        }
    }
    let mut note = None;
    let lags = match l0 {
        Some(l) => {
            let lags = (2 * l).min(cap);
            for k in rhat.len()..=lags {
                rhat.push(autocov(k));
            }
            lags
        }
        None => {
            if cap == 0 && max_lag > 0 {
                note = Some(
                    "no two consecutive samples: the residual correlation cannot be estimated and \
                     the corrected SE is the ordinary one"
                        .to_string(),
                );
            } else if cap > 0 {
                note = Some(format!(
                    "residuals still correlated at the {cap}-lag cap (ρ = {:.2}); the corrected SE \
                     may still be low",
                    rhat.last().copied().unwrap_or(0.0) / r0
                ));
            }
            cap
        }
    };
    rhat.truncate(lags + 1);

    // Z = R̂ ∗ X within stretches, then S = Xᵀ Z = Σ_i Σ_j x(i) R̂(i−j) x(j)ᵀ.
    let mut z = DMatrix::<f64>::zeros(n, p);
    for c in 0..p {
        let xc = xs.column(c);
        for &(a, b) in runs {
            for i in a..b {
                let lo_j = i.saturating_sub(lags).max(a);
                let hi_j = (i + lags + 1).min(b);
                let mut acc = 0.0;
                for j in lo_j..hi_j {
                    acc += rhat[i.abs_diff(j)] * xc[j];
                }
                z[(i, c)] = acc;
            }
        }
    }
    let s = xs.transpose() * z;
    let cov_s = &ginv * s * &ginv;

    let ss_tot = {
        let mean = y.mean();
        y.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
    };
    let mut fit = Fit {
        theta: Vec::with_capacity(p),
        se: Vec::with_capacity(p),
        se_ols: Vec::with_capacity(p),
        r_squared: if ss_tot > 0.0 {
            1.0 - sse / ss_tot
        } else {
            0.0
        },
        residual_rms: (sse / nf).sqrt(),
        lags,
        note,
    };
    for c in 0..p {
        let var = cov_s[(c, c)];
        fit.theta.push(theta_s[c] / scale[c]);
        fit.se_ols.push((sigma2 * ginv[(c, c)]).sqrt() / scale[c]);
        if var > 0.0 {
            fit.se.push(var.sqrt() / scale[c]);
        } else {
            // The truncated sum can lose positive definiteness; never report a zero SE.
            fit.se.push(fit.se_ols[c]);
            fit.note = Some(
                "corrected variance not positive for a parameter; its ordinary SE is given"
                    .to_string(),
            );
        }
    }
    let all_finite = fit
        .theta
        .iter()
        .chain(&fit.se)
        .chain(&fit.se_ols)
        .chain([&fit.r_squared, &fit.residual_rms])
        .all(|v| v.is_finite());
    if !all_finite {
        return Err("the least-squares solution is not finite".to_string());
    }
    Ok(fit)
}
