//! From log samples to regression points: the differentiator and the regressors passed through
//! the same window, body velocity, the usable runs (see the [module docs](super)).

use rotorid_sim::plant::SensorSample;

use super::{FIVE_POINT_MIN_RATE_HZ, G_MPS2};

/// A differentiator written as weights on the sample increments `x_{j+1} − x_j`,
/// `j = k − m … k + m − 1` (see the module doc).
pub(super) struct Differentiator {
    pub(super) name: &'static str,
    pub(super) increments: &'static [f64],
}

pub(super) const SAVITZKY_GOLAY_5: Differentiator = Differentiator {
    name: "5-point Savitzky–Golay (local quadratic) derivative, regressors through the same window",
    increments: &[0.2, 0.3, 0.3, 0.2],
};
pub(super) const CENTRAL_3: Differentiator = Differentiator {
    name: "3-point central difference (rate below 25 Hz), regressors through the same window",
    increments: &[0.5, 0.5],
};

impl Differentiator {
    pub(super) fn for_rate(rate_hz: f64) -> &'static Differentiator {
        if rate_hz >= FIVE_POINT_MIN_RATE_HZ {
            &SAVITZKY_GOLAY_5
        } else {
            &CENTRAL_3
        }
    }

    /// Half width `m` of the window (samples).
    pub(super) fn half(&self) -> usize {
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
pub(super) struct Point {
    /// Consecutive centres have consecutive `index`; a boundary skips at least one.
    pub(super) index: usize,
    /// Left sides, order `u, v, w, p, q, r`.
    pub(super) y: [f64; 6],
    /// Filtered states `u, v, w, p, q, r`.
    pub(super) x: [f64; 6],
    /// Filtered sticks `col, ped, lon, lat`.
    pub(super) sticks: [f64; 4],
    /// Raw sticks at the centre (for the excitation).
    pub(super) raw_sticks: [f64; 4],
    /// Horizontal ground speed (m/s).
    pub(super) ground_speed: f64,
    /// Body forward speed (m/s).
    pub(super) u: f64,
}

pub(super) fn finite(s: &SensorSample) -> bool {
    crate::log::values(s).iter().all(|v| v.is_finite())
}

/// NED velocity to body FRD by the ZYX Euler rotation.
pub(super) fn body_velocity(s: &SensorSample) -> [f64; 3] {
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
pub(super) fn usable_runs<'a>(
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
pub(super) fn points_of_run(
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
