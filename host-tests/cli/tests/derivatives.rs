//! Body-axis derivatives (issue 34 part 7): the estimates and their corrected standard errors
//! on a synthetic linear system with known derivatives (white and coloured equation noise,
//! Monte Carlo), the signs physics dictates on the X-Cell simulator, and inputs that cannot be
//! fitted (a stick that never moves, no samples, a NaN sample) giving reasons, not panics.
//!
//! `cargo test -p rotorid-cli --release --test integration derivatives:: -- --nocapture` prints the Monte
//! Carlo table and the run time of `derivatives()` on a 300 s 50 Hz flight.
//!
//! (Over 700 lines: the synthetic systems, the simulator's flights and the refusals share one
//! set of generators and tolerances.)

use rotorid_cli::derivatives::{derivatives, format_derivatives, Derivative, Derivatives, Region};
use rotorid_sim::flights;
use rotorid_sim::plant::{FlightConfig, SensorSample, Sticks};

// ---------------------------------------------------------------------------------------------
// A small deterministic generator (the crate has no rand dependency).

struct Rng(u64);

impl Rng {
    /// SplitMix64.
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

// ---------------------------------------------------------------------------------------------
// The synthetic system: the module's six equations with known derivatives.

const G: f64 = 9.80665;
const RATE_HZ: f64 = 50.0;

/// True derivatives, per equation, in the module's order (terms, then the intercept).
const TRUTH: [(&str, f64); 27] = [
    ("X_u", -0.5),
    ("X_q", 1.0),
    ("X_lon", -4.0),
    ("X_0", 0.1),
    ("Y_v", -0.6),
    ("Y_p", 0.5),
    ("Y_lat", 4.0),
    ("Y_ped", 1.5),
    ("Y_0", -0.2),
    ("Z_w", -1.0),
    ("Z_col", -20.0),
    ("Z_0", 10.0 - G),
    ("L_p", -4.0),
    ("L_v", 0.1),
    ("L_lat", 30.0),
    ("L_lon", 2.0),
    ("L_0", 0.05),
    ("M_q", -3.0),
    ("M_u", 0.2),
    ("M_lon", 25.0),
    ("M_lat", -1.5),
    ("M_0", -0.05),
    ("N_r", -1.5),
    ("N_v", 0.3),
    ("N_ped", 35.0),
    ("N_col", 5.0),
    ("N_0", -2.5),
];

fn truth(sym: &str) -> f64 {
    TRUTH
        .iter()
        .find(|(s, _)| *s == sym)
        .map(|(_, v)| *v)
        .expect("a true value")
}

/// Known attitude (rad): sums of sinusoids (a few degrees) and a slow turn.
struct Attitude {
    roll: [(f64, f64, f64); 3],
    pitch: [(f64, f64, f64); 3],
    /// Pitch offset (rad).
    pitch0: f64,
}

impl Attitude {
    fn new(rng: &mut Rng) -> Self {
        let mut comp = || {
            let a = (1.0 + 1.5 * rng.uniform()).to_radians();
            let w = 0.2 + 1.3 * rng.uniform();
            let ph = 2.0 * std::f64::consts::PI * rng.uniform();
            (a, w, ph)
        };
        Self {
            roll: [comp(), comp(), comp()],
            pitch: [comp(), comp(), comp()],
            pitch0: 0.0,
        }
    }
    fn at(&self, t: f64) -> (f64, f64, f64) {
        let s = |c: &[(f64, f64, f64); 3]| c.iter().map(|(a, w, p)| a * (w * t + p).sin()).sum();
        (s(&self.roll), self.pitch0 + s(&self.pitch), 0.05 * t)
    }
}

/// Body-frame state `u v w p q r`.
type State = [f64; 6];

/// The right-hand side: the module's equations solved for the derivatives, plus the
/// equation noise `e` (held over the sample).
fn rhs(x: &State, s: &Sticks, att: (f64, f64, f64), e: &[f64; 6]) -> State {
    let [u, v, w, p, q, r] = *x;
    let (phi, th, _) = att;
    let t = truth;
    [
        (r * v - q * w) - G * th.sin()
            + t("X_u") * u
            + t("X_q") * q
            + t("X_lon") * s.lon
            + t("X_0")
            + e[0],
        (p * w - r * u)
            + G * th.cos() * phi.sin()
            + t("Y_v") * v
            + t("Y_p") * p
            + t("Y_lat") * s.lat
            + t("Y_ped") * s.ped
            + t("Y_0")
            + e[1],
        (q * u - p * v)
            + G * th.cos() * phi.cos()
            + t("Z_w") * w
            + t("Z_col") * s.col
            + t("Z_0")
            + e[2],
        t("L_p") * p + t("L_v") * v + t("L_lat") * s.lat + t("L_lon") * s.lon + t("L_0") + e[3],
        t("M_q") * q + t("M_u") * u + t("M_lon") * s.lon + t("M_lat") * s.lat + t("M_0") + e[4],
        t("N_r") * r + t("N_v") * v + t("N_ped") * s.ped + t("N_col") * s.col + t("N_0") + e[5],
    ]
}

/// Equation noise: white, or AR(1) with coefficient `rho` per sample; same stationary std.
#[derive(Clone, Copy)]
enum Noise {
    White,
    Ar1(f64),
}

/// `seconds` of the synthetic system at 50 Hz: random multistep sticks (dwell 0.2–1 s), known
/// attitude, equation noise held over each sample, RK4 with 10 steps per sample.
fn synthetic_flight(seed: u64, seconds: f64, noise: Noise) -> Vec<SensorSample> {
    synthetic_flight_trimmed(seed, seconds, noise, 0.0)
}

/// [`synthetic_flight`] with the pitch attitude offset by `pitch0` (rad): nose down gives a
/// forward trim speed `g sin(pitch0) / X_u` (m/s), where the flight starts.
fn synthetic_flight_trimmed(
    seed: u64,
    seconds: f64,
    noise: Noise,
    pitch0: f64,
) -> Vec<SensorSample> {
    let mut rng = Rng(seed);
    let att = Attitude {
        pitch0,
        ..Attitude::new(&mut rng)
    };
    let n = (seconds * RATE_HZ) as usize;
    let dt = 1.0 / RATE_HZ;
    let sub = 10;
    let h = dt / sub as f64;
    // Equation-noise std: m/s² for u, v, w; rad/s² for p, q, r.
    let sigma = [0.03, 0.03, 0.03, 0.05, 0.05, 0.05];
    let trim = [0.5, 0.0, 0.0, 0.0]; // col, ped, lon, lat
    let mut level = trim;
    let mut until = [0usize; 4];
    let mut e = [0.0; 6];
    for (ek, s) in e.iter_mut().zip(sigma) {
        *ek = s * rng.normal();
    }
    let mut x: State = [G * pitch0.sin() / truth("X_u"), 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        for c in 0..4 {
            if k >= until[c] {
                level[c] = trim[c] + 0.06 * (2.0 * rng.uniform() - 1.0);
                until[c] = k + (10.0 + 40.0 * rng.uniform()) as usize;
            }
        }
        let sticks = Sticks {
            col: level[0],
            ped: level[1],
            lon: level[2],
            lat: level[3],
        };
        let t = k as f64 * dt;
        let (roll, pitch, yaw) = att.at(t);
        // Record: NED velocity from body velocity by the transposed ZYX rotation.
        let (sf, cf) = roll.sin_cos();
        let (st, ct) = pitch.sin_cos();
        let (sp, cp) = yaw.sin_cos();
        let [u, v, w, p, q, r] = x;
        out.push(SensorSample {
            t,
            sticks,
            roll,
            pitch,
            yaw,
            v_north: ct * cp * u + (sf * st * cp - cf * sp) * v + (cf * st * cp + sf * sp) * w,
            v_east: ct * sp * u + (sf * st * sp + cf * cp) * v + (cf * st * sp - sf * cp) * w,
            v_down: -st * u + sf * ct * v + cf * ct * w,
            p,
            q,
            r,
        });
        for i in 0..sub {
            let ti = t + i as f64 * h;
            let add = |a: &State, b: &State, c: f64| -> State {
                std::array::from_fn(|j| a[j] + c * b[j])
            };
            let k1 = rhs(&x, &sticks, att.at(ti), &e);
            let k2 = rhs(&add(&x, &k1, h / 2.0), &sticks, att.at(ti + h / 2.0), &e);
            let k3 = rhs(&add(&x, &k2, h / 2.0), &sticks, att.at(ti + h / 2.0), &e);
            let k4 = rhs(&add(&x, &k3, h), &sticks, att.at(ti + h), &e);
            x = std::array::from_fn(|j| {
                x[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
            });
        }
        for (ek, s) in e.iter_mut().zip(sigma) {
            *ek = match noise {
                Noise::White => s * rng.normal(),
                Noise::Ar1(rho) => rho * *ek + s * (1.0 - rho * rho).sqrt() * rng.normal(),
            };
        }
    }
    out
}

fn region<'a>(d: &'a Derivatives, name: &str) -> &'a Region {
    d.regions.iter().find(|r| r.name == name).expect("region")
}

fn derivative<'a>(r: &'a Region, sym: &str) -> &'a Derivative {
    r.axes
        .iter()
        .flat_map(|a| a.derivatives.iter())
        .find(|d| d.symbol == sym)
        .unwrap_or_else(|| panic!("{sym} reported"))
}

fn value(r: &Region, sym: &str) -> f64 {
    derivative(r, sym)
        .value
        .unwrap_or_else(|| panic!("{sym} fitted"))
}

/// Over ≥ 30 Monte-Carlo runs: estimates within 3 SE of the truth, and the corrected SE
/// matching the scatter of the estimates, where the ordinary SE under-states it for coloured
/// residuals.
fn monte_carlo(noise: Noise, label: &str) -> (Vec<f64>, Vec<f64>, f64) {
    const RUNS: u64 = 30;
    let mut est: Vec<Vec<f64>> = vec![Vec::new(); TRUTH.len()];
    let mut se: Vec<Vec<f64>> = vec![Vec::new(); TRUTH.len()];
    let mut se_ols: Vec<Vec<f64>> = vec![Vec::new(); TRUTH.len()];
    let (mut inside, mut total) = (0usize, 0usize);
    for run in 0..RUNS {
        let flight = synthetic_flight(1000 + run, 120.0, noise);
        let d = derivatives(&[&flight], RATE_HZ);
        let all = region(&d, "all");
        for (i, (sym, t)) in TRUTH.iter().enumerate() {
            let dv = derivative(all, sym);
            let (v, s, so) = (
                dv.value.expect("fitted"),
                dv.se.expect("se"),
                dv.se_ols.expect("se_ols"),
            );
            est[i].push(v);
            se[i].push(s);
            se_ols[i].push(so);
            total += 1;
            if (v - t).abs() <= 3.0 * s {
                inside += 1;
            }
        }
    }
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let sd = |x: &[f64]| {
        let m = mean(x);
        (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64).sqrt()
    };
    println!("{label}: symbol truth mean-estimate scatter mean-SE(corr) mean-SE(ols) corr/scatter ols/scatter");
    let mut ratio = Vec::new();
    let mut ratio_ols = Vec::new();
    for (i, (sym, t)) in TRUTH.iter().enumerate() {
        let scatter = sd(&est[i]);
        let rc = mean(&se[i]) / scatter;
        let ro = mean(&se_ols[i]) / scatter;
        println!(
            "  {sym:6} {t:9.4} {:9.4} {scatter:9.5} {:9.5} {:9.5} {rc:5.2} {ro:5.2}",
            mean(&est[i]),
            mean(&se[i]),
            mean(&se_ols[i])
        );
        ratio.push(rc);
        ratio_ols.push(ro);
    }
    let coverage = inside as f64 / total as f64;
    println!("  {label}: {inside} of {total} estimates within 3 corrected SE of the truth");
    (ratio, ratio_ols, coverage)
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "60 simulated flights: runs in the release pass of scripts/test.sh"
)]
fn corrected_se_matches_the_scatter_for_white_and_coloured_equation_noise() {
    for (noise, label) in [(Noise::White, "white"), (Noise::Ar1(0.9), "AR(1) rho 0.9")] {
        let (ratio, ratio_ols, coverage) = monte_carlo(noise, label);
        // Within 3 SE of the truth: 99.7 % expected; allow a few misses among 810.
        assert!(coverage >= 0.98, "{label}: coverage {coverage}");
        for ((sym, _), r) in TRUTH.iter().zip(&ratio) {
            assert!(
                (0.6..=1.6).contains(r),
                "{label}: corrected SE / scatter of {sym} = {r:.2}"
            );
        }
        if let Noise::Ar1(_) = noise {
            // The ordinary SE clearly under-states the scatter.
            let m = median(ratio_ols.clone());
            assert!(m < 0.5, "{label}: median ordinary SE / scatter {m:.2}");
            assert!(
                ratio_ols.iter().all(|r| *r < 0.8),
                "{label}: ordinary SE / scatter {ratio_ols:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The X-Cell simulator.

fn identification(seed: u64) -> Vec<SensorSample> {
    flights::identification_flight_with(&FlightConfig::realistic(seed, 0.0), f64::INFINITY)
        .expect("simulates")
}

fn determined(r: &Region, sym: &str) -> bool {
    derivative(r, sym).determined
}

#[test]
fn regions_are_fitted_from_their_own_samples_across_segments() {
    // Two segments: one about hover, one nose down 15° (5 m/s forward).
    let hover = synthetic_flight(7, 120.0, Noise::Ar1(0.9));
    let fast = synthetic_flight_trimmed(8, 120.0, Noise::Ar1(0.9), -15f64.to_radians());
    let d = derivatives(&[&hover, &fast], RATE_HZ);
    println!("{}", format_derivatives(&d));
    let all = region(&d, "all");
    let h = region(&d, "hover");
    let f = region(&d, "forward");
    assert!(h.fitted && f.fitted);
    assert!(h.samples < all.samples && f.samples < all.samples);
    assert!(h.samples + f.samples <= all.samples);
    // The system is linear: every region finds the same derivatives.
    let within = |r: &Region, sym: &str, t: f64| {
        let dv = derivative(r, sym);
        let (v, se) = (dv.value.expect("fitted"), dv.se.expect("se"));
        assert!(
            (v - t).abs() <= 3.0 * se,
            "{}: {sym} {v} ± {se}, truth {t}",
            r.name
        );
    };
    for r in [all, h, f] {
        for sym in [
            "X_0", "X_u", "Z_col", "L_p", "L_lat", "M_q", "M_lon", "N_r", "N_ped",
        ] {
            within(r, sym, truth(sym));
        }
    }
}

#[test]
fn the_off_axis_control_derivatives_a_log_determines_are_shown_against_the_axis_own() {
    // The synthetic helicopter pitches with lateral cyclic (M_lat = −1.5 against M_lon = 25
    // rad/s² per unit stick) and rolls with longitudinal (L_lon = 2 against L_lat = 30).
    let flight = synthetic_flight(7, 120.0, Noise::White);
    let d = derivatives(&[&flight], RATE_HZ);
    let all = region(&d, "all");
    let text = format_derivatives(&d);
    println!("{text}");
    assert!(text.lines().count() <= 14);
    let line = text
        .lines()
        .find(|l| l.contains("off-axis cyclic"))
        .expect("an off-axis line");
    for (cross, own) in [("M_lat", "M_lon"), ("L_lon", "L_lat")] {
        assert!(determined(all, cross) && determined(all, own), "{cross}");
        // In deg/s² per 10 % stick, with its share of the axis' own control power.
        let per_10pct = value(all, cross).to_degrees() * 0.1;
        let share = 100.0 * (value(all, cross) / value(all, own)).abs();
        let shown = format!("{cross} {per_10pct:+.0}±");
        assert!(line.contains(&shown), "{shown} in {line}");
        assert!(line.contains(&format!("({share:.0} % of {own})")), "{line}");
        // The share is the truth's within the fit's error.
        let truth_share = 100.0 * (truth(cross) / truth(own)).abs();
        assert!(
            (share - truth_share).abs() < 3.0,
            "{cross}: {share} vs {truth_share}"
        );
    }
}

#[test]
fn xcell_identification_flight_has_the_signs_physics_dictates() {
    // Conventions (host-tests/sim/src/plant/params.rs, StickMap): + lon tilts the disc back,
    // nose up (q > 0); + lat rolls right (p > 0); + ped = more tail thrust, nose right
    // (r > 0); + col = more thrust, upward, so w (down) decreases.
    let flight = identification(1);
    let d = derivatives(&[&flight], 50.0);
    println!("{}", format_derivatives(&d));
    for e in &region(&d, "all").excitation {
        println!("  stick {} std {:?}", e.stick, e.std);
    }
    for name in ["all", "hover"] {
        let r = region(&d, name);
        assert!(r.fitted, "{name}: {:?}", r.reason);
        for (sym, positive) in [
            ("L_lat", true),
            ("M_lon", true),
            ("N_ped", true),
            ("Z_col", false),
        ] {
            let v = value(r, sym);
            assert_eq!(v > 0.0, positive, "{name}: {sym} = {v}");
            assert!(determined(r, sym), "{name}: {sym} not determined");
        }
        let damped = ["L_p", "M_q", "N_r"]
            .iter()
            .filter(|s| value(r, s) < 0.0 && determined(r, s))
            .count();
        assert!(
            damped >= 2,
            "{name}: {damped} rate axes damped and determined"
        );
        // Those give time constants; the control powers are in deg/s² per unit stick.
        let with_tau = r
            .rate_axes
            .iter()
            .filter(|a| a.time_constant_s.is_some_and(|t| t > 0.0))
            .count();
        assert!(with_tau >= 2, "{name}: {with_tau} time constants");
        let roll = &r.rate_axes[0];
        let l_lat = value(r, "L_lat");
        let power = roll.control_power_deg_s2.expect("roll control power");
        assert!((power - l_lat.to_degrees()).abs() < 1e-9 * power.abs());
        let per10 = roll.control_power_deg_s2_per_10pct.expect("per 10 %");
        assert!((per10 - 0.1 * power).abs() < 1e-9 * power.abs());
    }
    // The identification flight stays within ≈ 2 m/s of hover: nothing in forward flight.
    let fwd = region(&d, "forward");
    assert!(!fwd.fitted);
    assert!(fwd.reason.as_deref().unwrap_or("").contains("samples"));
    assert!(format_derivatives(&d).lines().count() <= 14);
}

/// The X-Cell's own heave and yaw derivatives at hover trim
/// ([`rotorid_sim::plant::heave_and_yaw_at_hover`]): `[Z_w, Z_col, N_r, N_ped]`. Heave and yaw
/// do not go through the flapping, so the quasi-steady model holds for them and the estimates
/// must agree.
fn xcell_heave_and_yaw() -> [f64; 4] {
    let d =
        rotorid_sim::plant::heave_and_yaw_at_hover(&FlightConfig::default().params).expect("trims");
    [d.z_w, d.z_col, d.n_r, d.n_ped]
}

#[test]
fn xcell_heave_and_yaw_derivatives_match_the_simulators_linearisation() {
    let truth = xcell_heave_and_yaw();
    // Noise-free: within 3 %. Realistic (turbulence, noise): the gusts drive the states and
    // bias the damping (module doc), so wider; the SE covers the scatter, not that bias.
    for (label, config, tol) in [
        ("noise-free", FlightConfig::ideal(0.0), [0.03; 4]),
        (
            "realistic",
            FlightConfig::realistic(5, 0.0),
            [0.1, 0.1, 0.3, 0.15],
        ),
    ] {
        let flight =
            flights::identification_flight_with(&config, f64::INFINITY).expect("simulates");
        let d = derivatives(&[&flight], 50.0);
        let all = region(&d, "all");
        for (i, sym) in ["Z_w", "Z_col", "N_r", "N_ped"].iter().enumerate() {
            let dv = derivative(all, sym);
            let v = dv.value.expect("fitted");
            println!(
                "{label}: {sym} {v:.3} ± {:.3} (ordinary {:.3}), simulator at trim {:.3}",
                dv.se.unwrap_or(0.0),
                dv.se_ols.unwrap_or(0.0),
                truth[i]
            );
            assert!(
                (v / truth[i] - 1.0).abs() < tol[i],
                "{label}: {sym} {v} against {}",
                truth[i]
            );
        }
    }
}

#[test]
fn xcell_verification_flight_has_negative_speed_damping() {
    // The X-Cell's hover X_u is the rotor's blow-back alone (a few 0.01 1/s); the
    // identification flight's sweeps, within ≈ 2 m/s of hover, do not determine it (see the
    // report). The verification flight's doublets and multisteps move the speed more.
    let mut elapsed = Vec::new();
    for seed in 1..=3 {
        let flight = flights::verification_flight(seed, 300.0).expect("simulates");
        let t0 = std::time::Instant::now();
        let d = derivatives(&[&flight], 50.0);
        elapsed.push(t0.elapsed());
        if seed == 1 {
            println!("{}", format_derivatives(&d));
        }
        let all = region(&d, "all");
        let x_u = derivative(all, "X_u");
        println!(
            "seed {seed}: X_u {:?} ± {:?} (determined {})",
            x_u.value, x_u.se, x_u.determined
        );
        assert!(x_u.value.expect("fitted") < 0.0);
        for (sym, positive) in [
            ("L_lat", true),
            ("M_lon", true),
            ("N_ped", true),
            ("Z_col", false),
        ] {
            assert_eq!(value(all, sym) > 0.0, positive, "seed {seed}: {sym}");
        }
    }
    println!(
        "derivatives() on a 300 s 50 Hz flight (15 000 samples): {:?}",
        elapsed
    );
}

#[test]
fn a_10_hz_log_uses_the_central_difference_and_flags_what_it_cannot_resolve() {
    // Every fifth sample of the 50 Hz flight: a 10 Hz log (snapshots, as ArduPilot logs them).
    let flight = identification(2);
    let decimated: Vec<SensorSample> = flight.iter().step_by(5).copied().collect();
    let d = derivatives(&[&decimated], 10.0);
    assert!(d.differentiator.contains("central"), "{}", d.differentiator);
    println!("{}", format_derivatives(&d));
    let r = region(&d, "all");
    for (sym, positive) in [("M_lon", true), ("N_ped", true), ("Z_col", false)] {
        assert_eq!(value(r, sym) > 0.0, positive, "{sym}");
    }
    // The X-Cell's roll axis (τ ≈ 0.05 s at 50 Hz, half a 10 Hz sample) is beyond this rate:
    // whatever the fit gives, a wrong-signed control power must not stand without a note.
    let roll = &r.rate_axes[0];
    if value(r, "L_lat") <= 0.0 {
        let note = roll.note.as_deref().unwrap_or("");
        assert!(note.contains("faster than the log"), "{note}");
    }
}

// ---------------------------------------------------------------------------------------------
// What cannot be fitted.

#[test]
fn a_stick_that_never_moves_leaves_its_derivatives_undetermined_with_the_reason() {
    let mut flight = identification(3);
    for s in &mut flight {
        s.sticks.ped = 0.4;
    }
    let d = derivatives(&[&flight], 50.0);
    let r = region(&d, "all");
    let ped = r.excitation.iter().find(|e| e.stick == "ped").expect("ped");
    assert!(ped.never_excited);
    assert!(ped.std.is_some_and(|s| s < 1e-12), "{:?}", ped.std);
    for sym in ["N_ped", "Y_ped"] {
        let dv = derivative(r, sym);
        assert!(!dv.determined && dv.value.is_none(), "{sym}");
        let note = dv.note.as_deref().unwrap_or("");
        assert!(
            note.contains("ped") && note.contains("never excited"),
            "{note}"
        );
    }
    let yaw = r.rate_axes.iter().find(|a| a.axis == "yaw").expect("yaw");
    assert!(!yaw.control_determined && yaw.control_power_deg_s2.is_none());
    assert!(yaw.note.as_deref().unwrap_or("").contains("never excited"));
    // The other axes are still fitted.
    assert!(determined(r, "L_lat") && determined(r, "M_lon"));
    assert!(format_derivatives(&d).contains("never excited: ped"));
}

#[test]
fn empty_input_and_bad_samples_give_reasons_not_panics() {
    // Nothing at all.
    let d = derivatives(&[], 50.0);
    assert_eq!(d.usable_samples, 0);
    assert!(d.notes.iter().any(|n| n.contains("no usable samples")));
    assert!(d.regions.iter().all(|r| !r.fitted && r.reason.is_some()));
    serde_json::to_string(&d).expect("serialises");
    assert!(format_derivatives(&d).lines().count() <= 14);

    // A rate that is not a rate.
    let flight = identification_flight_60s();
    for rate in [f64::NAN, 0.0, -50.0] {
        let d = derivatives(&[&flight], rate);
        assert!(d.regions.iter().all(|r| !r.fitted), "{rate}");
        assert!(d.notes.iter().any(|n| n.contains("not a positive number")));
        let json = serde_json::to_string(&d).expect("serialises");
        assert!(json.contains("\"rate_hz\":null"));
    }

    // One NaN sample and one infinite one: left out with a note, the rest fitted.
    let mut bad = flight.clone();
    bad[1000].p = f64::NAN;
    bad[2000].v_north = f64::INFINITY;
    let d = derivatives(&[&bad], 50.0);
    assert!(d
        .notes
        .iter()
        .any(|n| n.contains("2 sample(s) with a non-finite value")));
    let all = region(&d, "all");
    assert!(all.axes.iter().all(|a| a.fitted));
    // 3000 samples in three stretches, each losing 2 at either end, the bad two left out.
    assert_eq!(d.usable_samples, 3000 - 2 - 3 * 4);
    serde_json::to_string(&d).expect("no NaN reaches the output");

    // Too short for the differentiator, and a segment too short to fit anything.
    let d = derivatives(&[&flight[..3], &flight[..40]], 50.0);
    assert!(d.notes.iter().any(|n| n.contains("shorter than")));
    let all = region(&d, "all");
    assert!(!all.fitted);
    assert!(all.axes[3]
        .reason
        .as_deref()
        .unwrap_or("")
        .contains("per parameter"));

    // A time gap inside a segment splits it.
    let mut gap = flight.clone();
    for s in &mut gap[1500..] {
        s.t += 1.0;
    }
    let d = derivatives(&[&gap], 50.0);
    assert!(d.notes.iter().any(|n| n.contains("split at 1 time step")));
    assert_eq!(d.usable_samples, 3000 - 2 * 4);

    // Every stick frozen and the vehicle at rest: collinear regressors, named.
    let still: Vec<SensorSample> = (0..500)
        .map(|k| SensorSample {
            t: k as f64 * 0.02,
            ..Default::default()
        })
        .collect();
    let d = derivatives(&[&still], 50.0);
    let all = region(&d, "all");
    assert!(all.excitation.iter().all(|e| e.never_excited));
    for a in &all.axes {
        assert!(!a.fitted);
        let why = a.reason.as_deref().unwrap_or("");
        assert!(
            why.contains("zero throughout") || why.contains("collinear"),
            "{why}"
        );
    }
    serde_json::to_string(&d).expect("serialises");
}

#[test]
fn huge_finite_values_give_reasons_not_panics_or_nan() {
    let flight = identification_flight_60s();
    let mut huge = flight.clone();
    for s in &mut huge[100..200] {
        s.v_north = 1e300;
        s.sticks.lat = -1e300;
    }
    let d = derivatives(&[&huge], 50.0);
    serde_json::to_string(&d).expect("no NaN or infinity reaches the output");
    for r in &d.regions {
        for a in &r.axes {
            assert!(a.fitted || a.reason.is_some(), "{}", a.axis);
        }
    }
}

fn identification_flight_60s() -> Vec<SensorSample> {
    flights::identification_flight_with(&FlightConfig::realistic(4, 0.0), 60.0).expect("simulates")
}
