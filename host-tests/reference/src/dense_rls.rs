//! Naive dense RLS on nalgebra, the benchmark's "straightforward implementation" competitor.
//!
//! [`DenseRls`] is the RLS of Section 4 of the paper with a fixed-size dense covariance
//! `SMatrix<T, N, N>`, generic over nalgebra's [`RealField`] (so `f32` and `f64`). It is written
//! the way one would first write it with nalgebra, without any numerical safeguard
//! (no symmetrisation, no clamping, no factorised form).

use nalgebra::{RealField, SMatrix, SVector};

/// Dense-covariance RLS (Section 4 of the paper), optionally with a forgetting factor `λ`:
///
/// ```text
/// K = P ξ / (λ + ξᵀ P ξ)
/// P ← (I − K ξᵀ) P / λ
/// θ ← θ + K (y − ξᵀ θ)
/// ```
///
/// `P(0) = α I`, `θ(0) = 0`; the paper has `λ = 1`.
///
/// [`DenseRls::update`] evaluates `(I − K ξᵀ) P` as the rank-one downdate `P − K (Pξ)ᵀ`
/// (`O(N²)`, equal to the printed form because `P` is symmetric); [`DenseRls::update_literal`]
/// forms `I − K ξᵀ` and multiplies it by `P` (`O(N³)`, the formula typed in verbatim).
#[derive(Clone, Debug, PartialEq)]
pub struct DenseRls<T: RealField + Copy, const N: usize> {
    theta: SVector<T, N>,
    p: SMatrix<T, N, N>,
    lambda: T,
}

impl<T: RealField + Copy, const N: usize> DenseRls<T, N> {
    /// `P(0) = α I`, `θ(0) = 0`, `λ = 1` (the paper's setting).
    pub fn new(alpha: T) -> Self {
        Self::with_forgetting(alpha, T::one())
    }

    /// `P(0) = α I`, `θ(0) = 0`, forgetting factor `λ ∈ (0, 1]`.
    pub fn with_forgetting(alpha: T, lambda: T) -> Self {
        Self::from_state(SVector::zeros(), SMatrix::identity() * alpha, lambda)
    }

    /// Arbitrary initial state `θ(0)`, `P(0)`, forgetting factor `λ`.
    pub fn from_state(theta: SVector<T, N>, p: SMatrix<T, N, N>, lambda: T) -> Self {
        Self { theta, p, lambda }
    }

    /// Current estimate `θ`.
    pub fn theta(&self) -> &SVector<T, N> {
        &self.theta
    }

    /// Current covariance `P`.
    pub fn covariance(&self) -> &SMatrix<T, N, N> {
        &self.p
    }

    /// Forgetting factor `λ`.
    pub fn lambda(&self) -> T {
        self.lambda
    }

    /// Output `ξᵀ θ`.
    pub fn predict(&self, xi: &SVector<T, N>) -> T {
        xi.dot(&self.theta)
    }

    /// One scalar RLS step; returns the a-priori innovation `y − ξᵀ θ`.
    /// `P ← (P − K (Pξ)ᵀ) / λ`.
    #[inline]
    pub fn update(&mut self, xi: &SVector<T, N>, y: T) -> T {
        let p_xi = self.p * xi;
        let k = p_xi / (self.lambda + xi.dot(&p_xi));
        let e = y - xi.dot(&self.theta);
        self.p = (self.p - k * p_xi.transpose()) / self.lambda;
        self.theta += k * e;
        e
    }

    /// One scalar RLS step computed literally as printed: `P ← (I − K ξᵀ) P / λ` with a dense
    /// `N × N` product (`O(N³)`). Returns the a-priori innovation.
    pub fn update_literal(&mut self, xi: &SVector<T, N>, y: T) -> T {
        let k =
            self.p * xi / (xi.transpose() * self.p * xi + SMatrix::<T, 1, 1>::new(self.lambda))[0];
        let e = y - xi.dot(&self.theta);
        self.p = (SMatrix::<T, N, N>::identity() - k * xi.transpose()) * self.p / self.lambda;
        self.theta += k * e;
        e
    }
}

/// A pre-generated regressor/target stream shaped like a Takagi-Sugeno regressor, used by the
/// RLS benchmark (`benches/rls.rs`) and the convergence tests.
///
/// `N = 2R` parameters, laid out as the paper's `[Δ₁ξ₁ … Δ₁ξ_R, Δ₂ξ₁ … Δ₂ξ_R]`. Each sample
/// has between 1 and `max_active` (capped at `R`) distinct active rules chosen uniformly at
/// random; their strengths `ξ_i` are drawn from `U(0.05, 1)` and normalised to sum to 1, and
/// every other `ξ_i` is exactly zero. `Δ₁, Δ₂ ~ U(−1, 1)`. The target is `y = ξᵀθ* + ε`, with
/// `θ*` drawn once from `U(−1, 1)` and `ε ~ N(0, noise_std²)` (noise-free when `noise_std = 0`).
#[derive(Clone, Debug)]
pub struct TsLikeStream<const N: usize> {
    /// The true parameter vector `θ*`.
    pub theta_true: SVector<f64, N>,
    /// `(ξ(k), y(k+1))` pairs.
    pub samples: Vec<(SVector<f64, N>, f64)>,
}

impl<const N: usize> TsLikeStream<N> {
    /// Generate `len` samples with a seeded ChaCha8 generator (see the type's docs).
    ///
    /// # Panics
    /// If `N` is odd or zero, or `max_active == 0`.
    pub fn generate(len: usize, max_active: usize, noise_std: f64, seed: u64) -> Self {
        use rand::{RngExt, SeedableRng};
        use rand_distr::{Distribution, Normal};
        assert!(N > 0 && N.is_multiple_of(2), "N = 2R must be even");
        assert!(max_active > 0, "at least one active rule");
        let r = N / 2;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let theta_true = SVector::<f64, N>::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let noise = Normal::new(0.0, noise_std).expect("noise_std must be finite and >= 0");
        let samples = (0..len)
            .map(|_| {
                let m = rng.random_range(1..=max_active.min(r));
                let mut active: Vec<usize> = Vec::with_capacity(m);
                while active.len() < m {
                    let i = rng.random_range(0..r);
                    if !active.contains(&i) {
                        active.push(i);
                    }
                }
                let w: Vec<f64> = active.iter().map(|_| rng.random_range(0.05..1.0)).collect();
                let sum: f64 = w.iter().sum();
                let d1: f64 = rng.random_range(-1.0..1.0);
                let d2: f64 = rng.random_range(-1.0..1.0);
                let mut xi = SVector::<f64, N>::zeros();
                for (&i, &wi) in active.iter().zip(&w) {
                    xi[i] = d1 * wi / sum;
                    xi[r + i] = d2 * wi / sum;
                }
                let y = xi.dot(&theta_true) + noise.sample(&mut rng);
                (xi, y)
            })
            .collect();
        Self {
            theta_true,
            samples,
        }
    }

    /// The stream in `f32` (each value rounded once).
    pub fn samples_f32(&self) -> Vec<(SVector<f32, N>, f32)> {
        self.samples
            .iter()
            .map(|(xi, y)| (xi.map(|v| v as f32), *y as f32))
            .collect()
    }

    /// The stream as plain arrays, for implementations that do not take nalgebra 0.35 types.
    pub fn arrays_f32(&self) -> Vec<([f32; N], f32)> {
        self.samples
            .iter()
            .map(|(xi, y)| (core::array::from_fn(|i| xi[i] as f32), *y as f32))
            .collect()
    }

    /// The stream as plain `f64` arrays.
    pub fn arrays_f64(&self) -> Vec<([f64; N], f64)> {
        self.samples
            .iter()
            .map(|(xi, y)| (core::array::from_fn(|i| xi[i]), *y))
            .collect()
    }
}
