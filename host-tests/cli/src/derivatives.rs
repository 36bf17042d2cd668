//! Body-axis stability and control derivatives with honest standard errors (issue 34, part 7):
//! the identified dynamics as numbers a helicopter user knows (`X_u`, `Z_col`, `L_p`, `M_lon`,
//! `N_ped` …), per operating region, each with a standard error corrected for coloured
//! residuals, so that the verdict can say which numbers the log really determined.
//!
//! # Method
//!
//! Equation-error least squares per axis (Morelli & Klein, *Aircraft System Identification*,
//! 2nd ed., ch. 5–6; the SIDPAC practice), body axes FRD (`u` forward, `v` right, `w` down),
//! SI units, sticks normalised (`lon`, `lat`, `ped` in −1…1, `col` thrust-like):
//!
//! | axis | left side (measured) | = regressors |
//! |---|---|---|
//! | u | `u̇ − (r v − q w) + g sinθ` | `X_u u + X_q q + X_lon δlon + X_0` |
//! | v | `v̇ − (p w − r u) − g cosθ sinφ` | `Y_v v + Y_p p + Y_lat δlat + Y_ped δped + Y_0` |
//! | w | `ẇ − (q u − p v) − g cosθ cosφ` | `Z_w w + Z_col δcol + Z_0` |
//! | p | `ṗ` | `L_p p + L_v v + L_lat δlat + L_lon δlon + L_0` |
//! | q | `q̇` | `M_q q + M_u u + M_lon δlon + M_lat δlat + M_0` |
//! | r | `ṙ` | `N_r r + N_v v + N_ped δped + N_col δcol + N_0` |
//!
//! The term lists are those of a hover/low-speed linear model with the usual cross-couplings
//! (lateral–directional `L_v`, `N_v`; speed stability `M_u`; collective-to-yaw torque `N_col`).
//! `X_q` and `Y_p` are added to the issue's lists because the rotor's thrust tilts with the
//! tip-path plane, and the flapping lags the body rate (`a1 ≈ A_lon δlon − τ_e q`, so
//! `X ≈ −g a1` has a `q` term): on the X-Cell simulator `X_q` comes out determined on every
//! flight tried, and without it its share leaks into `X_u` and `X_lon`.
//! The intercepts `X_0 … N_0` absorb trim (stick and force offsets), so the derivatives are
//! slopes about the region's mean condition. `g` is standard gravity, 9.80665 m/s².
//! Body velocity comes from NED velocity by the ZYX Euler rotation.
//!
//! **Differentiator and consistent regressors.** Time derivatives come from a 5-point local
//! quadratic (Savitzky–Golay) differentiator, `ẋ_k ≈ (−2x_{k−2} − x_{k−1} + x_{k+1} +
//! 2x_{k+2}) / (10 Δt)`, at rates of 25 Hz and above; below 25 Hz (a 10 Hz log) its 0.4 s
//! window would cut the response (−20 % at 1 Hz), so the 3-point central difference is used.
//! Both are weighted sums of the sample increments `x_{j+1} − x_j` (5-point: weights
//! 0.2, 0.3, 0.3, 0.2 over `j = k−2 … k+1`). The increment over one sample is the integral of
//! `ẋ` over that interval, in which a logged stick is held (zero-order hold) and a state is
//! close to the mean of its end values. So the regressors are passed through the *same*
//! window: a stick gets the increment weights, a state (and each kinematic/gravity term) the
//! trapezoidal version of them (5-point: 0.1, 0.25, 0.3, 0.25, 0.1). A linear system then
//! satisfies the equation exactly between the filtered signals, instead of leaving a residual
//! of about half a stick step at every step of a multistep input (a bias of the control
//! derivatives that grows with how often the stick moves). Samples within the window's half
//! width of a segment end, a non-finite sample or a time gap are not used as centres, so no
//! derivative reaches across a boundary.
//!
//! **Standard errors corrected for coloured residuals** (Morelli & Klein, ch. 5):
//! `Cov(θ̂) = (XᵀX)⁻¹ [Σ_i Σ_j x(i) R̂_vv(i−j) x(j)ᵀ] (XᵀX)⁻¹` with
//! `R̂_vv(l) = (1/N) Σ_i v(i) v(i+l)` from the residuals, pairs taken only within a stretch of
//! consecutive samples. The double sum is truncated at lag `L = 2 l₀`, `l₀` being the first lag
//! at which the residual autocorrelation `R̂_vv(l)/R̂_vv(0)` falls below
//! [`ACF_NEGLIGIBLE`] (0.05): beyond it the terms are noise about zero, and summing all `N`
//! lags of noise gives a variance estimate that is itself noise (with an intercept in the
//! model the residuals sum to zero, so the full sum tends to zero). Doubling `l₀` keeps the
//! tail (for AR(1) residuals of ρ = 0.9, `l₀ = 29`, it leaves out ≈ 0.2 % of the sum); no
//! taper is applied, since a Bartlett taper over those 58 lags would understate that same
//! AR(1) long-run variance by ≈ 16 %.
//! The lag is capped at [`MAX_LAG_S`] seconds and at a quarter of the fitted samples (reported
//! when reached). Even white equation noise gives coloured residuals here (the differentiator
//! is a moving average over 4 increments), which is why the ordinary SE `σ̂ √((XᵀX)⁻¹)` is
//! reported only for reference.
//!
//! A derivative is **determined** when `|value| ≥ 2 · SE_corrected` ([`DETERMINED_SE_MULTIPLE`]):
//! its 95 % interval excludes zero, i.e. the log says at least which sign it has.
//!
//! What the corrected SE does not cover: coloured *process* noise (turbulence) that drives the
//! states also correlates the state regressors with the residual and biases the damping
//! derivatives; the SE describes scatter, not that bias.
//!
//! **Sample rate.** The model is quasi-steady (no rotor flapping state), so a rate axis whose
//! time constant is near the sample period cannot be fitted from the samples: on the X-Cell
//! simulator the roll axis (`τ ≈ 0.05 s` at 50 Hz) comes out with the wrong sign at 10 Hz.
//! A rate axis therefore carries a note when its damping is determined positive ("unstable,
//! or faster than the log resolves") or its time constant is under two sample periods.
//! For the same reason the quasi-steady rate derivatives of a helicopter depend on the input's
//! frequency content (on the X-Cell the roll time constant comes out 0.05 s from the
//! identification sweeps and 0.12 s from the verification multisteps; `cargo test -p
//! rotorid-cli --release --test derivatives xcell -- --nocapture` prints both): they describe
//! the log's flight, not the rotor. Heave and yaw do not go through the flapping: there the
//! noise-free estimates agree with the simulator's own linearisation within 1 %.
//!
//! **Operating regions**: `all` (every usable sample: one linearisation of the whole log, the
//! model an identifier trained on the log sees; where the trim forces change with speed its
//! slopes mix the trims, which is why the regions are also fitted apart), `hover` (horizontal
//! ground speed < [`HOVER_MAX_GROUND_SPEED_MPS`]) and `forward` (body forward speed `u` ≥
//! [`FORWARD_MIN_BODY_SPEED_MPS`]). A region's axis is fitted only with at least
//! [`SAMPLES_PER_PARAMETER`] (20) samples per parameter (1–2 s of a 50 Hz log for 4–5
//! parameters): below that the corrected SE, which itself needs the residual autocorrelation,
//! is not trustworthy. Region membership is per sample (its derivative window may straddle
//! the region's edge); residual autocorrelation pairs are taken only within a region's
//! consecutive samples. A region that holds every sample reuses the `all` fit.
//!
//! **Excitation**: for each stick its standard deviation over the region's samples; "never
//! excited" when it is below [`NEVER_EXCITED_FRACTION`] (0.02) of full travel, taken as one
//! stick unit (centre to full deflection; 0 to 1 for the collective). The X-Cell
//! identification flight's pedal sweep, one quarter of the flight, gives a pedal std of ≈ 0.036
//! over the whole flight, which determines `N_ped` well; a threshold of 2 % of the −1…1 span
//! (0.04) would have flagged it. A never-excited stick's column is left out of every fit of
//! the region (a constant stick is collinear with the intercept) and its derivatives are
//! reported as not determined, naming the stick.
//!
//! Written here rather than taken from a crate: no maintained Rust crate does equation-error
//! identification with the coloured-residual covariance; the linear algebra is nalgebra's.

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rotorid_sim::plant::SensorSample;
use serde::{Deserialize, Serialize};

/// Standard gravity (m/s²).
pub const G_MPS2: f64 = 9.80665;
/// Upper bound of horizontal ground speed for the `hover` region (m/s).
pub const HOVER_MAX_GROUND_SPEED_MPS: f64 = 3.0;
/// Lower bound of body forward speed for the `forward` region (m/s).
pub const FORWARD_MIN_BODY_SPEED_MPS: f64 = 3.0;
/// A region's axis is fitted only with at least this many samples per parameter.
pub const SAMPLES_PER_PARAMETER: usize = 20;
/// A stick whose standard deviation is below this fraction of full travel (one stick unit:
/// centre to full deflection, or 0 to 1 for the collective) is "never excited".
pub const NEVER_EXCITED_FRACTION: f64 = 0.02;
/// A derivative is determined when `|value| ≥ DETERMINED_SE_MULTIPLE · SE_corrected`.
pub const DETERMINED_SE_MULTIPLE: f64 = 2.0;
/// Residual autocorrelation below which a lag no longer matters (see the module doc).
pub const ACF_NEGLIGIBLE: f64 = 0.05;
/// Longest residual-autocorrelation lag summed (s).
pub const MAX_LAG_S: f64 = 20.0;
/// Smallest eigenvalue of the normalised information matrix, relative to the largest, below
/// which the regressors are treated as collinear (the axis is not fitted).
const COLLINEAR_RATIO: f64 = 1e-9;
/// Lowest rate (Hz) at which the 5-point differentiator is used.
const FIVE_POINT_MIN_RATE_HZ: f64 = 25.0;

/// One stability or control derivative.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Derivative {
    /// Symbol, e.g. `L_p`, `Z_col`, `M_0` (intercept).
    pub symbol: String,
    /// Unit, e.g. `1/s`, `rad/s² per unit stick`.
    pub unit: String,
    /// Estimate (`None` when not fitted).
    pub value: Option<f64>,
    /// Standard error corrected for coloured residuals.
    pub se: Option<f64>,
    /// Ordinary least-squares standard error (white residuals assumed), for reference.
    pub se_ols: Option<f64>,
    /// `|value| ≥ 2 · se`.
    pub determined: bool,
    /// Why it is not fitted, if it is not.
    pub note: Option<String>,
}

/// The fit of one axis' equation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisFit {
    /// The state whose derivative is explained: `u`, `v`, `w`, `p`, `q` or `r`.
    pub axis: String,
    /// The equation fitted.
    pub equation: String,
    /// Samples used.
    pub samples: usize,
    /// Whether the equation was fitted.
    pub fitted: bool,
    /// Why not, if not.
    pub reason: Option<String>,
    /// The derivatives, in the order of the equation, intercept last.
    pub derivatives: Vec<Derivative>,
    /// Coefficient of determination of the left side (–).
    pub r_squared: Option<f64>,
    /// RMS of the residual (m/s² for u, v, w; rad/s² for p, q, r).
    pub residual_rms: Option<f64>,
    /// Residual-autocorrelation lags summed in the corrected covariance.
    pub lags: Option<usize>,
}

/// Control power and time constant of one rate axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RateAxis {
    /// `roll`, `pitch` or `yaw`.
    pub axis: String,
    /// The control derivative's symbol (`L_lat`, `M_lon`, `N_ped`).
    pub control: String,
    /// Control power (deg/s² per unit stick).
    pub control_power_deg_s2: Option<f64>,
    /// Control power per 10 % of stick (deg/s²).
    pub control_power_deg_s2_per_10pct: Option<f64>,
    /// Corrected SE of the control power (deg/s² per unit stick).
    pub control_power_se_deg_s2: Option<f64>,
    /// Whether the control power is determined.
    pub control_determined: bool,
    /// The damping derivative's symbol (`L_p`, `M_q`, `N_r`).
    pub damping: String,
    /// Time constant `τ = −1/damping` (s), when the damping is negative and determined.
    pub time_constant_s: Option<f64>,
    /// Its SE by the delta method, `SE(damping) / damping²` (s).
    pub time_constant_se_s: Option<f64>,
    /// `determined`, `unstable` (damping determined and positive), `undetermined` or
    /// `not fitted`.
    pub time_constant_status: String,
    /// What the user should know when the numbers are missing.
    pub note: Option<String>,
}

/// How much one stick moved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StickExcitation {
    /// `col`, `ped`, `lon` or `lat`.
    pub stick: String,
    /// Standard deviation over the region's samples (stick units).
    pub std: Option<f64>,
    /// Threshold below which it counts as never excited (stick units).
    pub threshold: f64,
    /// `std < threshold` (or no samples).
    pub never_excited: bool,
}

/// The derivatives of one operating region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// `all`, `hover` or `forward`.
    pub name: String,
    /// Which samples belong to it.
    pub definition: String,
    /// Usable samples in it.
    pub samples: usize,
    /// Whether any axis was fitted.
    pub fitted: bool,
    /// Why not, if not.
    pub reason: Option<String>,
    /// Each stick's excitation, order `col, ped, lon, lat`.
    pub excitation: Vec<StickExcitation>,
    /// The six equations, order `u, v, w, p, q, r`.
    pub axes: Vec<AxisFit>,
    /// Roll, pitch, yaw control power and time constant.
    pub rate_axes: Vec<RateAxis>,
}

/// Everything [`derivatives`] found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Derivatives {
    /// Sample rate (Hz) given, if finite.
    pub rate_hz: Option<f64>,
    /// The differentiator used.
    pub differentiator: String,
    /// Samples that could be used as derivative centres (all segments).
    pub usable_samples: usize,
    /// What was left out and why.
    pub notes: Vec<String>,
    /// Regions `all`, `hover`, `forward`.
    pub regions: Vec<Region>,
}

// ---------------------------------------------------------------------------------------------
// Equations

/// A regressor column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Term {
    State(usize),
    Stick(usize),
}

/// State indices in [`Point::x`].
const U: usize = 0;
const V: usize = 1;
const W: usize = 2;
const P: usize = 3;
const Q: usize = 4;
const R: usize = 5;
/// Stick indices in [`Point::sticks`], order `col, ped, lon, lat`.
const COL: usize = 0;
const PED: usize = 1;
const LON: usize = 2;
const LAT: usize = 3;
const STICK_NAMES: [&str; 4] = ["col", "ped", "lon", "lat"];

struct Equation {
    axis: &'static str,
    equation: &'static str,
    /// Unit of the left side.
    lhs_unit: &'static str,
    terms: &'static [(Term, &'static str, &'static str)],
    intercept: &'static str,
}

const PER_STICK_ACC: &str = "m/s² per unit stick";
const PER_STICK_ANG: &str = "rad/s² per unit stick";
const PER_SPEED_ANG: &str = "rad/s² per m/s";

const EQUATIONS: [Equation; 6] = [
    Equation {
        axis: "u",
        equation: "u̇ − (r v − q w) + g sinθ = X_u u + X_lon δlon + X_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(U), "X_u", "1/s"),
            (Term::State(Q), "X_q", "m/s² per rad/s"),
            (Term::Stick(LON), "X_lon", PER_STICK_ACC),
        ],
        intercept: "X_0",
    },
    Equation {
        axis: "v",
        equation: "v̇ − (p w − r u) − g cosθ sinφ = Y_v v + Y_lat δlat + Y_ped δped + Y_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(V), "Y_v", "1/s"),
            (Term::State(P), "Y_p", "m/s² per rad/s"),
            (Term::Stick(LAT), "Y_lat", PER_STICK_ACC),
            (Term::Stick(PED), "Y_ped", PER_STICK_ACC),
        ],
        intercept: "Y_0",
    },
    Equation {
        axis: "w",
        equation: "ẇ − (q u − p v) − g cosθ cosφ = Z_w w + Z_col δcol + Z_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(W), "Z_w", "1/s"),
            (Term::Stick(COL), "Z_col", PER_STICK_ACC),
        ],
        intercept: "Z_0",
    },
    Equation {
        axis: "p",
        equation: "ṗ = L_p p + L_v v + L_lat δlat + L_lon δlon + L_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(P), "L_p", "1/s"),
            (Term::State(V), "L_v", PER_SPEED_ANG),
            (Term::Stick(LAT), "L_lat", PER_STICK_ANG),
            (Term::Stick(LON), "L_lon", PER_STICK_ANG),
        ],
        intercept: "L_0",
    },
    Equation {
        axis: "q",
        equation: "q̇ = M_q q + M_u u + M_lon δlon + M_lat δlat + M_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(Q), "M_q", "1/s"),
            (Term::State(U), "M_u", PER_SPEED_ANG),
            (Term::Stick(LON), "M_lon", PER_STICK_ANG),
            (Term::Stick(LAT), "M_lat", PER_STICK_ANG),
        ],
        intercept: "M_0",
    },
    Equation {
        axis: "r",
        equation: "ṙ = N_r r + N_v v + N_ped δped + N_col δcol + N_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(R), "N_r", "1/s"),
            (Term::State(V), "N_v", PER_SPEED_ANG),
            (Term::Stick(PED), "N_ped", PER_STICK_ANG),
            (Term::Stick(COL), "N_col", PER_STICK_ANG),
        ],
        intercept: "N_0",
    },
];

/// Rate axes: name, equation index, damping symbol, control symbol.
const RATE_AXES: [(&str, usize, &str, &str); 3] = [
    ("roll", 3, "L_p", "L_lat"),
    ("pitch", 4, "M_q", "M_lon"),
    ("yaw", 5, "N_r", "N_ped"),
];

// ---------------------------------------------------------------------------------------------
// Differentiator

/// A differentiator written as weights on the sample increments `x_{j+1} − x_j`,
/// `j = k − m … k + m − 1` (see the module doc).
struct Differentiator {
    name: &'static str,
    increments: &'static [f64],
}

const SAVITZKY_GOLAY_5: Differentiator = Differentiator {
    name: "5-point Savitzky–Golay (local quadratic) derivative, regressors through the same window",
    increments: &[0.2, 0.3, 0.3, 0.2],
};
const CENTRAL_3: Differentiator = Differentiator {
    name: "3-point central difference (rate below 25 Hz), regressors through the same window",
    increments: &[0.5, 0.5],
};

impl Differentiator {
    fn for_rate(rate_hz: f64) -> &'static Differentiator {
        if rate_hz >= FIVE_POINT_MIN_RATE_HZ {
            &SAVITZKY_GOLAY_5
        } else {
            &CENTRAL_3
        }
    }

    /// Half width `m` of the window (samples).
    fn half(&self) -> usize {
        self.increments.len() / 2
    }

    /// Derivative at centre `k` (needs `m ≤ k < len − m`).
    fn derivative(&self, x: &[f64], k: usize, dt: f64) -> f64 {
        let j0 = k - self.half();
        self.increments
            .iter()
            .enumerate()
            .map(|(i, c)| c * (x[j0 + i + 1] - x[j0 + i]))
            .sum::<f64>()
            / dt
    }

    /// A state (continuous signal) through the window: trapezoidal increment weights.
    fn state(&self, x: &[f64], k: usize) -> f64 {
        let j0 = k - self.half();
        self.increments
            .iter()
            .enumerate()
            .map(|(i, c)| c * 0.5 * (x[j0 + i] + x[j0 + i + 1]))
            .sum()
    }

    /// A held stick through the window: the increment weights.
    fn held(&self, x: &[f64], k: usize) -> f64 {
        let j0 = k - self.half();
        self.increments
            .iter()
            .enumerate()
            .map(|(i, c)| c * x[j0 + i])
            .sum()
    }
}

// ---------------------------------------------------------------------------------------------
// Preprocessing

/// One derivative centre.
#[derive(Debug, Clone, Copy)]
struct Point {
    /// Consecutive centres have consecutive `index`; a boundary skips at least one.
    index: usize,
    /// Left sides, order `u, v, w, p, q, r`.
    y: [f64; 6],
    /// Filtered states `u, v, w, p, q, r`.
    x: [f64; 6],
    /// Filtered sticks `col, ped, lon, lat`.
    sticks: [f64; 4],
    /// Raw sticks at the centre (for the excitation).
    raw_sticks: [f64; 4],
    /// Horizontal ground speed (m/s).
    ground_speed: f64,
    /// Body forward speed (m/s).
    u: f64,
}

fn finite(s: &SensorSample) -> bool {
    crate::log::values(s).iter().all(|v| v.is_finite())
}

/// NED velocity to body FRD by the ZYX Euler rotation.
fn body_velocity(s: &SensorSample) -> [f64; 3] {
    let (sf, cf) = s.roll.sin_cos();
    let (st, ct) = s.pitch.sin_cos();
    let (sp, cp) = s.yaw.sin_cos();
    let (n, e, d) = (s.v_north, s.v_east, s.v_down);
    [
        ct * cp * n + ct * sp * e - st * d,
        (sf * st * cp - cf * sp) * n + (sf * st * sp + cf * cp) * e + sf * ct * d,
        (cf * st * cp + sf * sp) * n + (cf * st * sp - sf * cp) * e + cf * ct * d,
    ]
}

/// Splits the segments into runs of finite, evenly spaced samples, noting what was cut.
fn usable_runs<'a>(
    segments: &[&'a [SensorSample]],
    dt: f64,
    notes: &mut Vec<String>,
) -> Vec<&'a [SensorSample]> {
    let mut runs = Vec::new();
    for (si, seg) in segments.iter().enumerate() {
        let mut start = 0;
        let mut bad = 0usize;
        let mut first_bad_t: Option<f64> = None;
        let mut gaps = 0usize;
        for k in 0..seg.len() {
            let ok = finite(&seg[k]);
            if !ok {
                bad += 1;
                if first_bad_t.is_none() {
                    first_bad_t = Some(seg[k].t).filter(|t| t.is_finite());
                }
            }
            let gap = ok
                && k > start
                && finite(&seg[k - 1])
                && !((0.5 * dt)..=(1.5 * dt)).contains(&(seg[k].t - seg[k - 1].t));
            if !ok || gap {
                if k > start {
                    runs.push(&seg[start..k]);
                }
                if gap {
                    gaps += 1;
                    start = k;
                } else {
                    start = k + 1;
                }
            }
        }
        if seg.len() > start {
            runs.push(&seg[start..]);
        }
        if bad > 0 {
            let at = first_bad_t.map_or(String::new(), |t| format!(", first at t = {t:.3} s"));
            notes.push(format!(
                "segment {si}: {bad} sample(s) with a non-finite value left out{at}; no derivative \
                 is taken across them"
            ));
        }
        if gaps > 0 {
            notes.push(format!(
                "segment {si}: split at {gaps} time step(s) more than half a sample period off \
                 {:.4} s",
                dt
            ));
        }
    }
    runs
}

/// Derivative centres of one run, `index` continuing from `next_index`.
fn points_of_run(
    run: &[SensorSample],
    diff: &Differentiator,
    dt: f64,
    next_index: &mut usize,
    out: &mut Vec<Point>,
) {
    let m = diff.half();
    let n = run.len();
    if n < 2 * m + 1 {
        return;
    }
    let body: Vec<[f64; 3]> = run.iter().map(body_velocity).collect();
    let col = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { (0..n).map(f).collect() };
    let u = col(&|i| body[i][0]);
    let v = col(&|i| body[i][1]);
    let w = col(&|i| body[i][2]);
    let p = col(&|i| run[i].p);
    let q = col(&|i| run[i].q);
    let r = col(&|i| run[i].r);
    // Kinematic and gravity terms of u̇, v̇, ẇ (moved to the left side).
    let ku = col(&|i| r[i] * v[i] - q[i] * w[i] - G_MPS2 * run[i].pitch.sin());
    let kv = col(&|i| p[i] * w[i] - r[i] * u[i] + G_MPS2 * run[i].pitch.cos() * run[i].roll.sin());
    let kw = col(&|i| q[i] * u[i] - p[i] * v[i] + G_MPS2 * run[i].pitch.cos() * run[i].roll.cos());
    let sticks: [Vec<f64>; 4] = [
        col(&|i| run[i].sticks.col),
        col(&|i| run[i].sticks.ped),
        col(&|i| run[i].sticks.lon),
        col(&|i| run[i].sticks.lat),
    ];
    let states = [&u, &v, &w, &p, &q, &r];
    let kin = [&ku, &kv, &kw];
    for k in m..n - m {
        let mut y = [0.0; 6];
        for (a, yk) in y.iter_mut().enumerate() {
            *yk = diff.derivative(states[a], k, dt);
            if let Some(kt) = kin.get(a) {
                *yk -= diff.state(kt, k);
            }
        }
        let x = states.map(|s| diff.state(s, k));
        let f = [0, 1, 2, 3].map(|c| diff.held(&sticks[c], k));
        let raw = [0, 1, 2, 3].map(|c| sticks[c][k]);
        out.push(Point {
            index: *next_index,
            y,
            x,
            sticks: f,
            raw_sticks: raw,
            ground_speed: run[k].v_north.hypot(run[k].v_east),
            u: u[k],
        });
        *next_index += 1;
    }
    // A boundary: the next run's first centre does not follow this one's last.
    *next_index += 1;
}

// ---------------------------------------------------------------------------------------------
// Least squares with the coloured-residual covariance

struct Fit {
    theta: Vec<f64>,
    se: Vec<f64>,
    se_ols: Vec<f64>,
    r_squared: f64,
    residual_rms: f64,
    lags: usize,
    note: Option<String>,
}

/// Maximal stretches `[a, b)` of consecutive `index` in `points`.
fn stretches(points: &[&Point]) -> Vec<(usize, usize)> {
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
fn fit(
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

// ---------------------------------------------------------------------------------------------
// Regions

fn excitation(points: &[&Point]) -> Vec<StickExcitation> {
    (0..4)
        .map(|c| {
            let threshold = NEVER_EXCITED_FRACTION;
            let n = points.len() as f64;
            let std = (!points.is_empty())
                .then(|| {
                    let mean = points.iter().map(|p| p.raw_sticks[c]).sum::<f64>() / n;
                    (points
                        .iter()
                        .map(|p| (p.raw_sticks[c] - mean).powi(2))
                        .sum::<f64>()
                        / n)
                        .sqrt()
                })
                .filter(|s| s.is_finite());
            StickExcitation {
                stick: STICK_NAMES[c].to_string(),
                std,
                threshold,
                never_excited: std.is_none_or(|s| s < threshold),
            }
        })
        .collect()
}

fn not_fitted(eq: &Equation, samples: usize, reason: String) -> AxisFit {
    let mut derivatives: Vec<Derivative> = eq
        .terms
        .iter()
        .map(|(_, sym, unit)| Derivative {
            symbol: sym.to_string(),
            unit: unit.to_string(),
            value: None,
            se: None,
            se_ols: None,
            determined: false,
            note: Some(reason.clone()),
        })
        .collect();
    derivatives.push(Derivative {
        symbol: eq.intercept.to_string(),
        unit: eq.lhs_unit.to_string(),
        value: None,
        se: None,
        se_ols: None,
        determined: false,
        note: Some(reason.clone()),
    });
    AxisFit {
        axis: eq.axis.to_string(),
        equation: eq.equation.to_string(),
        samples,
        fitted: false,
        reason: Some(reason),
        derivatives,
        r_squared: None,
        residual_rms: None,
        lags: None,
    }
}

fn fit_axis(eq: &Equation, points: &[&Point], exc: &[StickExcitation], max_lag: usize) -> AxisFit {
    let n = points.len();
    // Columns kept: terms whose stick was excited, then the intercept.
    let kept: Vec<usize> = (0..eq.terms.len())
        .filter(|&i| match eq.terms[i].0 {
            Term::Stick(c) => exc.get(c).is_some_and(|e| !e.never_excited),
            Term::State(_) => true,
        })
        .collect();
    let p = kept.len() + 1;
    if n < SAMPLES_PER_PARAMETER * p {
        return not_fitted(
            eq,
            n,
            format!(
                "{n} samples, fewer than {SAMPLES_PER_PARAMETER} per parameter ({p} parameters)"
            ),
        );
    }
    let axis_index = EQUATIONS
        .iter()
        .position(|e| e.axis == eq.axis)
        .unwrap_or(0);
    let x = DMatrix::from_fn(n, p, |i, c| match kept.get(c) {
        Some(&t) => match eq.terms[t].0 {
            Term::State(s) => points[i].x[s],
            Term::Stick(s) => points[i].sticks[s],
        },
        None => 1.0,
    });
    let y = DVector::from_fn(n, |i, _| points[i].y[axis_index]);
    let mut names: Vec<&str> = kept.iter().map(|&t| eq.terms[t].1).collect();
    names.push(eq.intercept);
    let runs = stretches(points);
    let result = match fit(&x, &y, &runs, &names, max_lag) {
        Ok(f) => f,
        Err(reason) => return not_fitted(eq, n, reason),
    };
    let estimate = |col: usize, symbol: &str, unit: &str| {
        let (v, se, se_ols) = (result.theta[col], result.se[col], result.se_ols[col]);
        Derivative {
            symbol: symbol.to_string(),
            unit: unit.to_string(),
            value: Some(v),
            se: Some(se),
            se_ols: Some(se_ols),
            determined: v.abs() >= DETERMINED_SE_MULTIPLE * se,
            note: result.note.clone(),
        }
    };
    let mut derivatives = Vec::with_capacity(eq.terms.len() + 1);
    for (t, (term, sym, unit)) in eq.terms.iter().enumerate() {
        match kept.iter().position(|&k| k == t) {
            Some(col) => derivatives.push(estimate(col, sym, unit)),
            None => {
                let why = match term {
                    Term::Stick(c) => {
                        let e = &exc[*c];
                        format!(
                            "not determined: the {} stick was never excited (std {} < {:.3})",
                            e.stick,
                            e.std.map_or("n/a".to_string(), |s| format!("{s:.4}")),
                            e.threshold
                        )
                    }
                    Term::State(_) => "not fitted".to_string(),
                };
                derivatives.push(Derivative {
                    symbol: sym.to_string(),
                    unit: unit.to_string(),
                    value: None,
                    se: None,
                    se_ols: None,
                    determined: false,
                    note: Some(why),
                });
            }
        }
    }
    derivatives.push(estimate(kept.len(), eq.intercept, eq.lhs_unit));
    AxisFit {
        axis: eq.axis.to_string(),
        equation: eq.equation.to_string(),
        samples: n,
        fitted: true,
        reason: None,
        derivatives,
        r_squared: Some(result.r_squared),
        residual_rms: Some(result.residual_rms),
        lags: Some(result.lags),
    }
}

fn rate_axis(
    axes: &[AxisFit],
    (name, eq, damping, control): (&str, usize, &str, &str),
    dt: f64,
) -> RateAxis {
    let find = |sym: &str| {
        axes.get(eq)
            .and_then(|a| a.derivatives.iter().find(|d| d.symbol == sym))
    };
    let c = find(control);
    let d = find(damping);
    let deg = 180.0 / std::f64::consts::PI;
    let power = c.and_then(|c| c.value).map(|v| v * deg);
    let (tau, tau_se, status) = match d.and_then(|d| d.value.zip(d.se).map(|v| (v, d.determined))) {
        Some(((v, se), true)) if v < 0.0 => (Some(-1.0 / v), Some(se / (v * v)), "determined"),
        Some((_, true)) => (None, None, "unstable"),
        Some((_, false)) => (None, None, "undetermined"),
        None => (None, None, "not fitted"),
    };
    let mut notes: Vec<String> = Vec::new();
    if let Some(c) = c.filter(|c| !c.determined) {
        notes.push(match &c.note {
            Some(n) => format!("{control} {n}"),
            None => format!("{control} not determined (|value| < 2 SE)"),
        });
    }
    // A response faster than the sampling cannot be fitted by a derivative of the samples:
    // say so rather than let a fitted number stand alone (module doc, "Sample rate").
    match (status, tau) {
        ("unstable", _) => notes.push(format!(
            "{damping} determined positive: an unstable axis, or one faster than the log's \
             {:.0} Hz resolves (its other numbers are then not to be trusted)",
            1.0 / dt
        )),
        ("determined", Some(t)) if t < 2.0 * dt => notes.push(format!(
            "τ = {t:.3} s is under two sample periods ({:.3} s): the log's rate barely \
             resolves this axis; log faster",
            2.0 * dt
        )),
        _ => {}
    }
    let note = (!notes.is_empty()).then(|| notes.join("; "));
    RateAxis {
        axis: name.to_string(),
        control: control.to_string(),
        control_power_deg_s2: power,
        control_power_deg_s2_per_10pct: power.map(|p| 0.1 * p),
        control_power_se_deg_s2: c.and_then(|c| c.se).map(|s| s * deg),
        control_determined: c.is_some_and(|c| c.determined),
        damping: damping.to_string(),
        time_constant_s: tau,
        time_constant_se_s: tau_se,
        time_constant_status: status.to_string(),
        note,
    }
}

fn region(name: &str, definition: &str, points: &[&Point], max_lag: usize, dt: f64) -> Region {
    let exc = excitation(points);
    let axes: Vec<AxisFit> = EQUATIONS
        .iter()
        .map(|eq| fit_axis(eq, points, &exc, max_lag))
        .collect();
    let rate_axes = RATE_AXES
        .iter()
        .map(|&ra| rate_axis(&axes, ra, dt))
        .collect();
    let fitted = axes.iter().any(|a| a.fitted);
    let reason = (!fitted).then(|| {
        if points.len() < SAMPLES_PER_PARAMETER * 3 {
            format!(
                "{} samples, fewer than {SAMPLES_PER_PARAMETER} per parameter for any axis",
                points.len()
            )
        } else {
            "no axis could be fitted (see each axis' reason)".to_string()
        }
    });
    Region {
        name: name.to_string(),
        definition: definition.to_string(),
        samples: points.len(),
        fitted,
        reason,
        excitation: exc,
        axes,
        rate_axes,
    }
}

/// The body-axis derivatives of a log given as gap-free segments evenly sampled at `rate_hz`
/// (Hz), per operating region (see the module doc). Never panics; anything that cannot be
/// fitted carries its reason.
pub fn derivatives(segments: &[&[SensorSample]], rate_hz: f64) -> Derivatives {
    let mut notes = Vec::new();
    let rate_ok = rate_hz.is_finite() && rate_hz > 0.0;
    let rate = if rate_ok { rate_hz } else { 50.0 };
    if !rate_ok {
        notes.push(format!(
            "sample rate {rate_hz} Hz is not a positive number: nothing fitted (give the log's \
             rate in Hz)"
        ));
    }
    let diff = Differentiator::for_rate(rate);
    let dt = 1.0 / rate;
    let mut points = Vec::new();
    if rate_ok {
        let runs = usable_runs(segments, dt, &mut notes);
        let mut next = 0;
        for run in &runs {
            points_of_run(run, diff, dt, &mut next, &mut points);
        }
        let need = 2 * diff.half() + 1;
        let short = runs.iter().filter(|r| r.len() < need).count();
        if short > 0 {
            notes.push(format!(
                "{short} stretch(es) shorter than the differentiator's {need} samples left out"
            ));
        }
        if points.is_empty() {
            notes.push("no usable samples: nothing to fit".to_string());
        }
    }
    let max_lag = (MAX_LAG_S * rate).round() as usize;
    let all: Vec<&Point> = points.iter().collect();
    let hover: Vec<&Point> = points
        .iter()
        .filter(|p| p.ground_speed < HOVER_MAX_GROUND_SPEED_MPS)
        .collect();
    let forward: Vec<&Point> = points
        .iter()
        .filter(|p| p.u >= FORWARD_MIN_BODY_SPEED_MPS)
        .collect();
    let all_region = region(
        "all",
        "every usable sample (one linearisation of the whole log)",
        &all,
        max_lag,
        dt,
    );
    // A region holding every sample is the `all` fit under another name: reuse it.
    let sub = |name: &str, definition: &str, pts: &[&Point]| {
        if pts.len() == all.len() {
            Region {
                name: name.to_string(),
                definition: definition.to_string(),
                ..all_region.clone()
            }
        } else {
            region(name, definition, pts, max_lag, dt)
        }
    };
    let regions = vec![
        sub("hover", "horizontal ground speed < 3 m/s", &hover),
        sub("forward", "body forward speed u ≥ 3 m/s", &forward),
    ];
    let regions = std::iter::once(all_region).chain(regions).collect();
    Derivatives {
        rate_hz: rate_ok.then_some(rate_hz),
        differentiator: diff.name.to_string(),
        usable_samples: points.len(),
        notes,
        regions,
    }
}

// ---------------------------------------------------------------------------------------------
// Console

fn find<'a>(r: &'a Region, sym: &str) -> Option<&'a Derivative> {
    r.axes
        .iter()
        .flat_map(|a| a.derivatives.iter())
        .find(|d| d.symbol == sym)
}

/// `X_u −0.31±0.05*` (value and corrected SE, `*` when determined), `X_u —` when not fitted.
fn short(d: Option<&Derivative>, sym: &str) -> String {
    match d.and_then(|d| d.value.zip(d.se).map(|v| (v, d.determined))) {
        Some(((v, se), det)) => format!("{sym} {v:+.3}±{se:.3}{}", if det { "*" } else { "" }),
        None => format!("{sym} —"),
    }
}

fn rate_text(a: &RateAxis) -> String {
    let power = match (a.control_power_deg_s2_per_10pct, a.control_power_se_deg_s2) {
        (Some(p), Some(se)) => format!(
            "{:+.0}±{:.0}{}",
            p,
            0.1 * se,
            if a.control_determined { "*" } else { "" }
        ),
        _ => "—".to_string(),
    };
    let tau = match (a.time_constant_s, a.time_constant_se_s) {
        (Some(t), Some(se)) if t < 1.0 => format!("τ {t:.3}±{se:.3} s"),
        (Some(t), Some(se)) => format!("τ {t:.2}±{se:.2} s"),
        _ => format!("τ {}", a.time_constant_status),
    };
    let flag = if a.note.is_some() { " !" } else { "" };
    format!("{} {} {power}, {tau}{flag}", a.axis, a.control)
}

/// A compact console summary (at most 14 lines): per fitted region the control power per 10 %
/// of stick (deg/s²) and time constant of each rate axis, the translational derivatives, and
/// the sticks that were never excited.
pub fn format_derivatives(d: &Derivatives) -> String {
    let mut lines = vec![
        "Body-axis derivatives (± corrected SE; * = determined, |value| ≥ 2 SE; control power in \
         deg/s² per 10 % stick; ! = see the axis' note):"
            .to_string(),
    ];
    let all_samples = d.regions.first().map(|r| r.samples);
    for (i, r) in d.regions.iter().enumerate() {
        if i > 0 && r.fitted && Some(r.samples) == all_samples {
            lines.push(format!(
                "  {} ({}): the same {} samples as {}",
                r.name,
                r.definition,
                r.samples,
                d.regions.first().map_or("", |a| a.name.as_str())
            ));
            continue;
        }
        if !r.fitted {
            lines.push(format!(
                "  {} ({}): not fitted: {}",
                r.name,
                r.definition,
                r.reason.as_deref().unwrap_or("")
            ));
            continue;
        }
        lines.push(format!(
            "  {} ({} samples): {}",
            r.name,
            r.samples,
            r.rate_axes
                .iter()
                .map(rate_text)
                .collect::<Vec<_>>()
                .join("; ")
        ));
        let mut trans: Vec<String> = ["X_u", "Y_v", "Z_w", "Z_col"]
            .iter()
            .map(|s| short(find(r, s), s))
            .collect();
        trans[0].insert_str(0, "    ");
        let idle: Vec<&str> = r
            .excitation
            .iter()
            .filter(|e| e.never_excited)
            .map(|e| e.stick.as_str())
            .collect();
        let mut line = format!("{} (1/s, m/s² per stick)", trans.join(", "));
        if !idle.is_empty() {
            line.push_str(&format!("; never excited: {}", idle.join(", ")));
        }
        lines.push(line);
    }
    for n in d.notes.iter().take(2) {
        lines.push(format!("  note: {n}"));
    }
    if d.notes.len() > 2 {
        lines.push(format!(
            "  … {} more notes in metrics.json",
            d.notes.len() - 2
        ));
    }
    lines.join("\n")
}
