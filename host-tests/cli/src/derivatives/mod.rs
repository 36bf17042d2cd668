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
//! `X_q` and `Y_p` are added to the lists because the rotor's thrust tilts with the
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
//! rotorid-cli --release --test integration derivatives::xcell -- --nocapture` prints both): they describe
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
//! excited" when it is below [`NEVER_EXCITED_FRACTION`] (0.001) of full travel, taken as one
//! stick unit (centre to full deflection; 0 to 1 for the collective): the stick did not move.
//! A never-excited stick's column is left out of every fit of the region (a constant stick is
//! collinear with the intercept) and its derivatives are reported as not determined, naming
//! the stick. Any stick that moved is fitted, and whether the log determines its derivative
//! is the fit's to say (`|value| ≥ 2 SE`), not a threshold on the stick's deviation: the
//! deviation of a few doublets is diluted by the hover between them (the flybarless 600's
//! verification flight, doublets and 3-2-1-1 multisteps on every stick: lateral cyclic
//! σ = 0.8 % of travel, and `L_lat` = 451 ± 10 deg/s² per unit stick, determined), and the
//! information a fit gets grows with the number of samples as well as with the deviation.
//! (With a 2 % threshold that flight's `L_lat`, `M_lon` and `N_ped` were reported "never
//! excited".)
//!
//! Written here rather than taken from a crate: no maintained Rust crate does equation-error
//! identification with the coloured-residual covariance; the linear algebra is nalgebra's.

use serde::{Deserialize, Serialize};

mod equations;
mod fit;
mod regions;
mod samples;
mod text;

pub use regions::derivatives;
pub use text::format_derivatives;

/// Standard gravity (m/s²).
pub const G_MPS2: f64 = 9.80665;
/// Upper bound of horizontal ground speed for the `hover` region (m/s).
pub const HOVER_MAX_GROUND_SPEED_MPS: f64 = 3.0;
/// Lower bound of body forward speed for the `forward` region (m/s).
pub const FORWARD_MIN_BODY_SPEED_MPS: f64 = 3.0;
/// A region's axis is fitted only with at least this many samples per parameter.
pub const SAMPLES_PER_PARAMETER: usize = 20;
/// A stick whose standard deviation is below this fraction of full travel (one stick unit:
/// centre to full deflection, or 0 to 1 for the collective) is "never excited": one step of a
/// 1000-step PWM range, the verdict's "did not move at all"
/// ([`STILL_STICK_STD`](crate::verdict::STILL_STICK_STD)). Above it the stick's column is
/// fitted and its standard error says whether the log determines its derivative.
pub const NEVER_EXCITED_FRACTION: f64 = crate::verdict::STILL_STICK_STD;
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

/// An angular acceleration (or a derivative of one) in rad/s² as deg/s²: the unit the
/// control powers are reported in.
pub(super) fn deg_s2(rad_s2: f64) -> f64 {
    rad_s2 * (180.0 / std::f64::consts::PI)
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

impl Region {
    /// The derivative `symbol` (e.g. `L_lat`) of any of the region's equations.
    pub fn derivative(&self, symbol: &str) -> Option<&Derivative> {
        self.axes
            .iter()
            .flat_map(|a| a.derivatives.iter())
            .find(|d| d.symbol == symbol)
    }
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
