//! Helpers shared by the plant test files.
#![allow(dead_code)]

use nalgebra::Vector3;
use rotorid_sim::envelope::{envelope_flight_with, operating_points, EnvelopeKind};
use rotorid_sim::plant::{
    derivative, simulate, trim_hover, Channel, Excitation, FlightConfig, Helicopter, SensorSample,
    State,
};

/// Largest |f| over a flight.
pub fn max_abs(s: &[SensorSample], f: impl Fn(&SensorSample) -> f64) -> f64 {
    s.iter().map(|x| f(x).abs()).fold(0.0, f64::max)
}

/// `|x − reference| / |reference|`.
pub fn rel_err(x: f64, reference: f64) -> f64 {
    (x - reference).abs() / reference.abs()
}

/// `∂(ω̇_i)/∂x` of `p` by central differences at `state` (hover trim sticks, still air), where
/// `perturb` moves one state component by `h`.
pub fn derivative_of_rate(
    p: &Helicopter,
    state: &State,
    axis: usize,
    h: f64,
    perturb: impl Fn(&mut State, f64),
) -> f64 {
    let t = trim_hover(p, 0.0).expect("trim converges");
    let pitch = p.blade_pitch(&t.sticks);
    let eval = |d: f64| {
        let mut s = *state;
        perturb(&mut s, d);
        derivative(p, &s, &pitch, &Vector3::zeros()).0.omega[axis]
    };
    (eval(h) - eval(-h)) / (2.0 * h)
}

/// Yaw damping `N_r`, weathercock `N_v`, pitch damping `M_q` and roll damping `L_p` (flapping
/// held) of `p` at hover and at 10 m/s forward: `[(name, at hover, at 10 m/s)]`.
pub fn local_derivatives_hover_and_10_mps(p: &Helicopter) -> [(&'static str, f64, f64); 4] {
    let hover = trim_hover(p, 0.0).expect("trim converges").state;
    let mut fast = hover;
    fast.vel_body.x = 10.0;
    let (pa, qa, ra) = (0, 1, 2);
    let damping =
        |s: &State, axis: usize| derivative_of_rate(p, s, axis, 1e-3, |s, d| s.omega[axis] += d);
    let side =
        |s: &State, axis: usize| derivative_of_rate(p, s, axis, 1e-3, |s, d| s.vel_body.y += d);
    [
        ("N_r", damping(&hover, ra), damping(&fast, ra)),
        ("N_v", side(&hover, ra), side(&fast, ra)),
        ("M_q", damping(&hover, qa), damping(&fast, qa)),
        ("L_p", damping(&hover, pa), damping(&fast, pa)),
    ]
}

/// Doublets of opposite sign from trim (`lon` on the longitudinal, `lat` on the lateral cyclic,
/// 0.5 s each way) give opposite rates of nearly equal size over the first 0.2 s: within 3 % of
/// the peak, which must exceed 0.1 rad/s. See the X-Cell test for why 3 %.
pub fn assert_opposite_doublets_give_opposite_rates(config: &FlightConfig, lon: f64, lat: f64) {
    let q = |s: &SensorSample| s.q;
    let p = |s: &SensorSample| s.p;
    for (ch, amplitude, rate) in [
        (Channel::Lon, lon, &q as &dyn Fn(&SensorSample) -> f64),
        (Channel::Lat, lat, &p),
    ] {
        let fly = |a: f64| {
            simulate(config, &mut |_, t| {
                Excitation::on(ch, if t < 0.5 { a } else { -a })
            })
            .expect("bounded")
        };
        let (plus, minus) = (fly(amplitude), fly(-amplitude));
        let early: Vec<(f64, f64)> = plus
            .iter()
            .zip(&minus)
            .filter(|(s, _)| s.t <= 0.2 + 1e-9)
            .map(|(a, b)| (rate(a), rate(b)))
            .collect();
        assert_eq!(early.len(), 11);
        let peak = early.iter().map(|(a, _)| a.abs()).fold(0.0, f64::max);
        assert!(peak > 0.1, "{ch:?} peak {peak}");
        for (a, b) in &early {
            assert!((a + b).abs() <= 0.03 * peak, "{ch:?}: {a} vs {b}");
        }
    }
}

/// The identification envelope flight with `config` reaches its operating points from hover to
/// 12 m/s forward and ±5 m/s sideways, and ±3 m/s vertical at hover: the mean over the last 5 s
/// of each dwell within 0.75 m/s of the set-point, with the collective positive throughout. (The
/// climb and the descent at 12 m/s are not reached in their 25 s on either airframe: the pilot's
/// tilt limit and slow trim integrators; not asserted. The X-Cell drifts ≈ 4.5 m/s sideways in
/// that descent and is still ≈ 0.56 m/s off sideways at the end of the next point, 6 m/s.)
pub fn assert_envelope_reaches_level_points(config: &FlightConfig) {
    let kind = EnvelopeKind::Identification;
    let s = envelope_flight_with(config, kind).expect("bounded");
    let per_point = s.len() / operating_points(kind).len();
    let mut checked = 0;
    for (i, goal) in operating_points(kind).iter().enumerate() {
        if goal[0] != 0.0 && goal[2] != 0.0 {
            continue;
        }
        let dwell_end = &s[(i + 1) * per_point - 250..(i + 1) * per_point];
        let mean = |f: &dyn Fn(&SensorSample) -> f64| {
            dwell_end.iter().map(f).sum::<f64>() / dwell_end.len() as f64
        };
        let got = [
            mean(&|x| x.yaw.cos() * x.v_north + x.yaw.sin() * x.v_east),
            mean(&|x| -x.yaw.sin() * x.v_north + x.yaw.cos() * x.v_east),
            mean(&|x| x.v_down),
        ];
        for (g, w) in got.iter().zip(goal) {
            assert!((g - w).abs() < 0.75, "point {i}: {got:?} vs {goal:?}");
        }
        checked += 1;
    }
    assert_eq!(checked, 10);
    assert!(s.iter().all(|x| x.sticks.col > 0.0));
}
