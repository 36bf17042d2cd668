//! Full-matrix recursive least squares of Section 4.

/// Full-matrix recursive least squares, exactly as Section 4 prints it, optionally with an
/// exponential forgetting factor `λ`:
///
/// ```text
/// Kw(k+1)   = P(k) ξ(k) [ξᵀ(k) P(k) ξ(k) + λ]⁻¹
/// P(k+1)    = [I − Kw(k+1) ξᵀ(k)] P(k) / λ
/// θ̂(k+1)    = θ̂(k) + Kw(k+1) [y(k+1) − ξᵀ(k) θ̂(k)]
/// ```
///
/// with `P(0) = α I`, `θ̂(0) = 0` (or given). The paper uses `λ = 1` (NOTES.md item 8).
///
/// `P` is stored as a full row-major `n × n` matrix. `[I − Kξᵀ] P` is evaluated as
/// `P − K (ξᵀP)`, which is the same product re-associated (`(Kξᵀ)P = K(ξᵀP)`); no symmetry of
/// `P` is assumed and `P` is never symmetrised, so any asymmetry from rounding is visible.
#[derive(Clone, Debug, PartialEq)]
pub struct Rls {
    n: usize,
    theta: Vec<f64>,
    p: Vec<f64>,
    lambda: f64,
}

impl Rls {
    /// `n` parameters, `P(0) = α I`, `θ̂(0) = 0`, no forgetting (`λ = 1`), as in the paper.
    pub fn new(n: usize, alpha: f64) -> Self {
        Self::with_forgetting(n, alpha, 1.0)
    }

    /// As [`Rls::new`] with a forgetting factor `λ ∈ (0, 1]`.
    ///
    /// # Panics
    /// If `n == 0`, `α ≤ 0` or `λ ∉ (0, 1]`.
    pub fn with_forgetting(n: usize, alpha: f64, lambda: f64) -> Self {
        assert!(n > 0, "RLS needs at least one parameter");
        assert!(alpha > 0.0, "P(0) = alpha I needs alpha > 0");
        assert!(lambda > 0.0 && lambda <= 1.0, "lambda must be in (0, 1]");
        let mut p = vec![0.0; n * n];
        for i in 0..n {
            p[i * n + i] = alpha;
        }
        Self {
            n,
            theta: vec![0.0; n],
            p,
            lambda,
        }
    }

    /// Replace `θ̂` (e.g. a "good initial guess", Section 4).
    ///
    /// # Panics
    /// If the length is not `n`.
    pub fn set_theta(&mut self, theta: &[f64]) {
        assert_eq!(theta.len(), self.n, "theta length");
        self.theta.copy_from_slice(theta);
    }

    /// Number of parameters `n = d·R`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Forgetting factor `λ`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// Current estimate `θ̂`.
    pub fn theta(&self) -> &[f64] {
        &self.theta
    }

    /// Current covariance `P`, full row-major `n × n` (`P[i][j]` at `i·n + j`).
    pub fn p(&self) -> &[f64] {
        &self.p
    }

    /// Element `P[i][j]`.
    pub fn p_at(&self, i: usize, j: usize) -> f64 {
        self.p[i * self.n + j]
    }

    /// Output `ξᵀ θ̂`.
    pub fn predict(&self, xi: &[f64]) -> f64 {
        assert_eq!(xi.len(), self.n, "regressor length");
        xi.iter().zip(&self.theta).map(|(a, b)| a * b).sum()
    }

    /// One RLS step with regressor `ξ(k)` and target `y(k+1)`. Returns the a-priori innovation
    /// `y(k+1) − ξᵀ(k) θ̂(k)`.
    ///
    /// Order of computation as in the paper: `P(k) → Kw(k+1) → P(k+1) → θ̂(k+1)`.
    // Index loops on purpose: they read like the matrix formulas they implement.
    pub fn update(&mut self, xi: &[f64], y: f64) -> f64 {
        self.update_with_forgetting(xi, y, self.lambda)
    }

    /// [`Rls::update`] with forgetting factor `lambda` for this step only. A sample with
    /// several outputs forgets once: `λ = 1` for all but its last measurement.
    #[allow(clippy::needless_range_loop)]
    pub fn update_with_forgetting(&mut self, xi: &[f64], y: f64, lambda: f64) -> f64 {
        let n = self.n;
        assert_eq!(xi.len(), n, "regressor length");
        let innovation = y - self.predict(xi);

        // P ξ (column) and ξᵀ P (row).
        let mut p_xi = vec![0.0; n];
        let mut xi_p = vec![0.0; n];
        for i in 0..n {
            for j in 0..n {
                p_xi[i] += self.p[i * n + j] * xi[j];
                xi_p[j] += xi[i] * self.p[i * n + j];
            }
        }
        // ξᵀ P ξ + λ.
        let denom: f64 = lambda + xi.iter().zip(&p_xi).map(|(a, b)| a * b).sum::<f64>();
        let k: Vec<f64> = p_xi.iter().map(|v| v / denom).collect();

        // P ← [I − K ξᵀ] P / λ = (P − K (ξᵀ P)) / λ.
        for i in 0..n {
            for j in 0..n {
                let v = self.p[i * n + j] - k[i] * xi_p[j];
                self.p[i * n + j] = v / lambda;
            }
        }
        // θ̂ ← θ̂ + K e.
        for i in 0..n {
            self.theta[i] += k[i] * innovation;
        }
        innovation
    }
}

/// Lower Cholesky factor `L` (`A = L Lᵀ`) of a full row-major `n × n` matrix, or `None` if a
/// pivot is not strictly positive (or not finite): a positive-definiteness check. Reads the
/// lower triangle only; check symmetry separately.
pub fn cholesky_lower(a: &[f64], n: usize) -> Option<Vec<f64>> {
    assert_eq!(a.len(), n * n, "matrix size");
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let d = d.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / d;
        }
    }
    Some(l)
}
