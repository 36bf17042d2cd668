//! One scalar RLS update (Section 4 of the paper, `λ = 1`, `P(0) = αI`) at the parameter
//! counts of the paper's models: `N = 2` (single-rule baselines, Eqs. 19/26), 18 (`r̂`, `p̂`,
//! 9 rules), 36 (`q̂`, 18 rules) and 54 (translational, 27 rules).
//!
//! # Rows
//!
//! - `dense-f32`, `dense-f64`: [`DenseRls`], the naive nalgebra implementation with a dense
//!   `SMatrix<T, N, N>` covariance and the rank-one downdate `P − K(Pξ)ᵀ` (`O(N²)`).
//! - `dense-f64-literal`: [`DenseRls::update_literal`], `(I − Kξᵀ)P` typed in verbatim
//!   (`O(N³)`), to show what the printed formula costs if taken literally.
//! - `flight-solver-f32`: `flight_solver::rls::RlsParallel<N, 1>` (covariance form, f32) with
//!   its numerical guards switched off so that it computes the paper's RLS exactly (see
//!   [`FlightSolverRls`]).
//! - `flight-solver-iqr-f32`: `flight_solver::rls::InverseQrRls<N, 1>` (inverse QR / information
//!   square-root form, Givens rotations): the same estimator in exact arithmetic, different
//!   numerics.
//!
//! # Stream
//!
//! Every row is fed the same pre-generated stream ([`bench_stream`]): [`STREAM_LEN`] samples
//! shaped like a Takagi-Sugeno regressor `[Δ₁ξ₁ … Δ₁ξ_R, Δ₂ξ₁ … Δ₂ξ_R]` with `R = N/2` rules, of
//! which 1 to [`MAX_ACTIVE`] are active per sample (random rules, strengths `U(0.05, 1)`
//! normalised to 1, all other `ξ_i` exactly zero), `Δ₁, Δ₂ ~ U(−1, 1)`, and a noise-free target
//! `y = ξᵀθ*`. Each row converts the stream to its own input type once, outside the timing.
//!
//! # Timing
//!
//! An estimator starts from `P(0) = αI` ([`ALPHA`]) and processes the stream in order; after
//! [`STREAM_LEN`] updates it is replaced by a fresh one (not timed), so every row times the
//! same sequence of updates and `P` never runs down to denormals. Reported time = one update.
//!
//! # Adding rows
//!
//! Add the core's RLS forms at `// rotorid rows go here` in [`bench_n`] with [`bench_row`]:
//! a name, the stream in whatever form the row wants (`stream.samples`, `samples_f32()`,
//! `arrays_f32()`, `arrays_f64()`), a constructor of a fresh estimator and one update call.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion};
use flight_solver::rls::{CovarianceGuards, InverseQrRls, RlsParallel};
use host_tests::golden;
use rotorid::hover::HoverSample;
use rotorid::rls::{Rls, RlsConfig};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, HoverConfig, PaperFuzzyIdentifier,
    PaperPlainIdentifier,
};
use rotorid_reference::dense_rls::{DenseRls, TsLikeStream};

/// Samples in the stream, and updates between two resets of the estimator.
pub const STREAM_LEN: usize = 1000;
/// Largest number of simultaneously active rules in a stream sample.
pub const MAX_ACTIVE: usize = 4;
/// `P(0) = αI` for every row. Moderate on purpose: with the paper's "very large" α the f32
/// covariance forms lose positive definiteness on this stream (NOTES.md item 8).
pub const ALPHA: f64 = 1e4;
/// Seed of the stream generator (plus `N`).
pub const SEED: u64 = 0x0123_4567;

/// The benchmark stream for `N` parameters (see the module docs).
pub fn bench_stream<const N: usize>() -> TsLikeStream<N> {
    TsLikeStream::generate(STREAM_LEN, MAX_ACTIVE, 0.0, SEED + N as u64)
}

/// Time `update` over `stream`, restarting from `fresh()` every `stream.len()` updates (the
/// restart is not timed). Criterion reports the time of one update.
pub fn bench_row<S, X>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    n: usize,
    stream: &[X],
    fresh: impl Fn() -> S,
    mut update: impl FnMut(&mut S, &X),
) {
    group.bench_function(BenchmarkId::new(name, n), |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            let mut done = 0u64;
            while done < iters {
                let len = (iters - done).min(stream.len() as u64) as usize;
                let mut est = fresh();
                let start = Instant::now();
                for x in &stream[..len] {
                    update(&mut est, black_box(x));
                }
                total += start.elapsed();
                black_box(&mut est);
                done += len as u64;
            }
            total
        })
    });
}

/// Thin adapter around `flight_solver::rls::RlsParallel<N, 1>` (flight-solver 0.2.2).
///
/// flight-solver's covariance-form RLS computes `k = Pa/(λ + aᵀPa)`,
/// `P ← (KAPmult·P − k(Pa)ᵀ)/λ`, `x ← x + k(y − aᵀx)`, i.e. the paper's RLS when `λ = 1` and
/// `KAPmult = 1`. Its `CovarianceGuards` (defaults from indiflight) change that:
///
/// - `cov_max` (1e10): if any `P_ii > cov_max`, λ is replaced for that step by
///   `1 + 0.1(1 − λ)`; a no-op at `λ = 1`. Set to `∞`.
/// - `max_order_decrement` (0.1) with `cov_min` (1e-10): "order decrement limiting" sets
///   `KAPmult = min(1, 0.9 · max_i P_ii/(k_i (Pa)_i))` when that maximum exceeds `cov_min`;
///   with a sparse regressor and a large α this rescales `P` and can make it indefinite, so it
///   is not the paper's RLS. `cov_min = ∞` disables the branch (`KAPmult = 1` exactly).
///
/// There is no separate noise term: the `1` in the paper's denominator is `λ`.
pub struct FlightSolverRls<const N: usize>(pub RlsParallel<N, 1>);

impl<const N: usize> FlightSolverRls<N> {
    /// Guards that make flight-solver's update the paper's RLS (see the type docs).
    pub const PAPER_GUARDS: CovarianceGuards = CovarianceGuards {
        cov_max: f32::INFINITY,
        cov_min: f32::INFINITY,
        max_order_decrement: 0.0,
    };

    /// `P(0) = αI`, `θ(0) = 0`, `λ = 1`, guards off.
    pub fn new(alpha: f32) -> Self {
        Self(RlsParallel::new(alpha, 1.0, Self::PAPER_GUARDS))
    }
}

/// All rows at one `N`, in the shared group (benchmark ids `rls_update/<row>/<N>`).
fn bench_n<const N: usize, const NP: usize>(g: &mut BenchmarkGroup<'_, WallTime>) {
    let stream = bench_stream::<N>();
    let s64 = &stream.samples;
    let s32 = stream.samples_f32();
    let a32 = stream.arrays_f32();
    // flight-solver takes nalgebra 0.34 vectors; convert once, outside the timing (the types are
    // inferred from the update calls below).
    let fs: Vec<_> = a32
        .iter()
        .map(|(a, y)| ((*a).into(), [*y].into()))
        .collect();
    let fs_iqr: Vec<_> = a32
        .iter()
        .map(|(a, y)| ((*a).into(), [*y].into()))
        .collect();

    bench_row(
        g,
        "dense-f32",
        N,
        &s32,
        || DenseRls::<f32, N>::new(ALPHA as f32),
        |r, (xi, y)| {
            r.update(xi, *y);
        },
    );
    bench_row(
        g,
        "dense-f64",
        N,
        s64,
        || DenseRls::<f64, N>::new(ALPHA),
        |r, (xi, y)| {
            r.update(xi, *y);
        },
    );
    bench_row(
        g,
        "dense-f64-literal",
        N,
        s64,
        || DenseRls::<f64, N>::new(ALPHA),
        |r, (xi, y)| {
            r.update_literal(xi, *y);
        },
    );
    bench_row(
        g,
        "flight-solver-f32",
        N,
        &fs,
        || FlightSolverRls::<N>::new(ALPHA as f32),
        |r, (a, y)| {
            r.0.update(a, y);
        },
    );
    bench_row(
        g,
        "flight-solver-iqr-f32",
        N,
        &fs_iqr,
        || InverseQrRls::<N, 1>::new(ALPHA as f32, 1.0),
        |r, (a, y)| {
            r.update(a, y);
        },
    );

    // rotorid's RLS forms (packed covariance, zero regressor entries skipped).
    let r32 = stream.arrays_f32();
    let r64 = stream.arrays_f64();
    for (name, cfg) in [
        ("rotorid-paper-f32", RlsConfig::paper(ALPHA as f32)),
        ("rotorid-ud-f32", RlsConfig::robust(ALPHA as f32)),
    ] {
        bench_row(
            g,
            name,
            N,
            &r32,
            || Rls::<f32, N, NP>::new(cfg).expect("valid config"),
            |r, (xi, y)| {
                let _ = r.update(xi, *y);
            },
        );
    }
    for (name, cfg) in [
        ("rotorid-paper-f64", RlsConfig::paper(ALPHA)),
        ("rotorid-ud-f64", RlsConfig::robust(ALPHA)),
    ] {
        bench_row(
            g,
            name,
            N,
            &r64,
            || Rls::<f64, N, NP>::new(cfg).expect("valid config"),
            |r, (xi, y)| {
                let _ = r.update(xi, *y);
            },
        );
    }
}

/// One full `HoverIdentifier` step (all four models learn and predict), over the golden input
/// stream (it crosses the hover region and Table 3's shoulders).
fn bench_hover_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("hover_step");
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20);
    let inputs = golden::inputs(STREAM_LEN, golden::SEED);
    let in64: Vec<HoverSample<f64>> = inputs.iter().map(golden::convert::<f64>).collect();
    bench_row(
        &mut g,
        "fuzzy-ud-f32",
        0,
        &inputs,
        || PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::default()).expect("valid config"),
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "fuzzy-paper-f32",
        0,
        &inputs,
        || PaperFuzzyIdentifier::<f32>::paper_fuzzy(HoverConfig::paper()).expect("valid config"),
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "fuzzy-ud-f64",
        0,
        &in64,
        || PaperFuzzyIdentifier::<f64>::paper_fuzzy(HoverConfig::default()).expect("valid config"),
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "fuzzy-paper-f64",
        0,
        &in64,
        || PaperFuzzyIdentifier::<f64>::paper_fuzzy(HoverConfig::paper()).expect("valid config"),
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "extended-fuzzy-f32",
        0,
        &inputs,
        || {
            ExtendedFuzzyIdentifier::<f32>::extended_fuzzy(HoverConfig::default())
                .expect("valid config")
        },
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "extended-plain-f32",
        0,
        &inputs,
        || {
            ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default())
                .expect("valid config")
        },
        |id, s| {
            let _ = id.step(s);
        },
    );
    bench_row(
        &mut g,
        "plain-ud-f32",
        0,
        &inputs,
        || PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::default()).expect("valid config"),
        |id, s| {
            let _ = id.step(s);
        },
    );
    g.finish();
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("rls_update");
    g.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20);
    bench_n::<2, 3>(&mut g);
    bench_n::<18, 171>(&mut g);
    bench_n::<36, 666>(&mut g);
    bench_n::<54, 1485>(&mut g);
    g.finish();
}

criterion_group!(rls, benches, bench_hover_step);
criterion_main!(rls);
