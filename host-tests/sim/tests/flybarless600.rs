//! Tests of the second plant, the flybarless 600 ([`Helicopter::flybarless_600`]): its
//! derivation, trim, response symmetry, the scaled pilot and flights, and that its dynamics are
//! both speed-dependent and different from the X-Cell 60's.

mod common;

use common::{local_derivatives_hover_and_10_mps, max_abs, rel_err};
use rotorid_sim::flights::{identification_flight_with, verification_flight_with};
use rotorid_sim::plant::*;

fn fbl() -> Helicopter {
    Helicopter::flybarless_600()
}

fn config(seed: u64, duration: f64) -> FlightConfig {
    FlightConfig::realistic(seed, duration)
        .for_airframe(Airframe::Flybarless600)
        .expect("trims")
}

/// Froude scaling keeps the non-dimensional dynamics: the scaled X-Cell trims at the same
/// sticks, attitude, `C_T` and inflow, while its weight and rotor speed scale as s³ and s^−½.
#[test]
fn froude_scaling_keeps_the_trim() {
    let x = XCell60::default();
    let s = 0.7;
    let y = x.froude_scaled(s);
    let (tx, ty) = (
        trim_hover(&x, 0.0).expect("trim"),
        trim_hover(&y, 0.0).expect("trim"),
    );
    for ch in Channel::ALL {
        assert!(
            (tx.sticks.get(ch) - ty.sticks.get(ch)).abs() < 1e-8,
            "{ch:?}"
        );
    }
    assert!((tx.roll - ty.roll).abs() < 1e-8 && (tx.pitch - ty.pitch).abs() < 1e-8);
    assert!(rel_err(ty.c_t, tx.c_t) < 1e-8 && rel_err(ty.lambda0, tx.lambda0) < 1e-8);
    assert!(rel_err(ty.thrust, tx.thrust * s * s * s) < 1e-8);
    assert!(rel_err(y.tau_e(), x.tau_e() * s.sqrt()) < 1e-12);
}

/// Hover trim of the flybarless 600 balances like the X-Cell's: thrust a little above the
/// weight (fuselage download), the momentum inflow, the tail rotor carrying the main torque,
/// sticks well inside their range with the collective clearly positive.
#[test]
fn trim_is_physical() {
    let p = fbl();
    let t = trim_hover(&p, 0.0).expect("trim converges");
    let weight = p.mass * p.g;
    assert!(
        t.thrust > weight && rel_err(t.thrust, weight) < 0.03,
        "{}",
        t.thrust
    );
    // Hover momentum theory: λ0 = sqrt(C_T / (2 η_w)).
    assert!(rel_err(t.lambda0, (t.c_t / (2.0 * p.main.eta_w)).sqrt()) < 1e-9);
    assert!(rel_err(t.tail_thrust * p.l_tr, t.main_torque) < 0.02);
    assert!(t.sticks.col > 0.3 && t.sticks.col < 0.6, "{:?}", t.sticks);
    assert!(t.sticks.ped.abs() < 0.7);
    assert!(t.sticks.lon.abs() < 0.2 && t.sticks.lat.abs() < 0.2);
    // Hangs rolled right against the tail rotor's side force, level in pitch.
    assert!(
        t.roll > 0.03 && t.roll < 0.15 && t.pitch.abs() < 0.02,
        "{t:?}"
    );
    assert!((t.a1 - p.a_lon * t.blade_pitch.delta_lon).abs() < 1e-15);
}

/// The stated physical differences from the X-Cell: faster flapping (no bar), a bare-rotor
/// cyclic gain, more blow-back with speed, a stiffer hub; and the stick scaling that follows
/// from them.
#[test]
fn differs_from_the_x_cell_as_stated() {
    let (x, p) = (XCell60::default(), fbl());
    assert!(p.tau_e() < 0.25 * x.tau_e(), "tau_e {}", p.tau_e());
    assert!(p.tau_e() > 0.01, "still far slower than the 1 ms step");
    assert!(p.a_lon == 1.0 && p.k_mu > x.k_mu);
    assert!(p.k_beta > x.froude_scaled(p.main.radius / x.main.radius).k_beta);
    let s = Airframe::Flybarless600.stick_scale().expect("trims");
    // The cyclic is a much stronger rate command without the bar: scaled down.
    assert!(s.lon < 0.5 && s.lat < 0.5, "{s:?}");
    // Scaling makes the steady responses equal to the X-Cell's.
    let (rx, rp) = (
        steady_response_per_stick(&x).expect("trim"),
        steady_response_per_stick(&p).expect("trim"),
    );
    for ch in Channel::ALL {
        assert!(
            rel_err(rp.get(ch) * s.get(ch), rx.get(ch)) < 1e-12,
            "{ch:?}"
        );
    }
    assert_eq!(
        Airframe::XCell60.stick_scale().expect("x"),
        StickScale::default()
    );
}

/// Opposite cyclic doublets from trim give opposite rates over the first 0.2 s (odd on-axis
/// response at hover, as for the X-Cell; 3 % of the peak bounds the even-order effects).
#[test]
fn opposite_doublets_give_opposite_rates() {
    let scale = Airframe::Flybarless600.stick_scale().expect("trims");
    let cfg = FlightConfig::ideal(1.0)
        .for_airframe(Airframe::Flybarless600)
        .expect("trims");
    common::assert_opposite_doublets_give_opposite_rates(&cfg, 0.2 * scale.lon, 0.2 * scale.lat);
}

/// The scaled pilot holds hover for 20 s in turbulence as it does the X-Cell.
#[test]
fn scaled_pilot_holds_hover() {
    let cfg = config(5, 20.0);
    let t = trim_hover(&cfg.params, 0.0).expect("trim");
    let s = simulate(&cfg, &mut |_, _| Excitation::none()).expect("bounded");
    assert!(max_abs(&s, |x| x.v_north) < 0.5 && max_abs(&s, |x| x.v_east) < 0.5);
    assert!(max_abs(&s, |x| x.v_down) < 0.5);
    assert!(max_abs(&s, |x| x.roll - t.roll) < 0.05 && max_abs(&s, |x| x.pitch - t.pitch) < 0.05);
    assert!(max_abs(&s, |x| x.p) < 0.2 && max_abs(&s, |x| x.q) < 0.2 && max_abs(&s, |x| x.r) < 0.5);
}

/// The identification sweeps (scaled) stay near hover, as on the X-Cell (≈ 2 m/s), and the
/// verification manoeuvres stay bounded.
#[test]
fn hover_flights_stay_near_hover() {
    let ident = identification_flight_with(&config(1, 0.0), f64::INFINITY).expect("bounded");
    assert_eq!(ident.len(), 12_750);
    for v in [
        max_abs(&ident, |x| x.v_north),
        max_abs(&ident, |x| x.v_east),
        max_abs(&ident, |x| x.v_down),
    ] {
        assert!(v < 2.5, "{v}");
    }
    assert!(ident.iter().all(|x| x.sticks.col > 0.2));
    let verify = verification_flight_with(&config(2, 120.0)).expect("bounded");
    assert!(max_abs(&verify, |x| x.v_north) < 5.0 && max_abs(&verify, |x| x.v_east) < 5.0);
    assert!(max_abs(&verify, |x| x.v_down) < 5.0);
    assert!(max_abs(&verify, |x| x.p) < 4.0 && max_abs(&verify, |x| x.q) < 4.0);
    assert!(max_abs(&verify, |x| x.r) < 4.0);
    assert!(max_abs(&verify, |x| x.roll) < 0.6 && max_abs(&verify, |x| x.pitch) < 0.6);
}

/// The envelope flight reaches its level and hover operating points
/// ([`common::assert_envelope_reaches_level_points`]).
#[test]
fn envelope_flight_reaches_its_operating_points() {
    common::assert_envelope_reaches_level_points(&config(1, 0.0));
}

/// The local dynamics change across the envelope on this airframe too. With the flapping held,
/// yaw damping and weathercock stiffness grow with the fin's dynamic pressure, the body's roll
/// damping with the fuselage's; stable damping at both points.
#[test]
fn local_dynamics_differ_between_hover_and_ten_metres_per_second() {
    let d = local_derivatives_hover_and_10_mps(&fbl());
    eprintln!("{d:?}");
    let [n_r, n_v, m_q, l_p] = d;
    assert!(n_r.1 < 0.0 && m_q.1 < 0.0 && l_p.1 < 0.0);
    for (name, at0, at10) in [n_r, n_v, m_q, l_p] {
        assert!(
            at10.abs() > 1.5 * at0.abs(),
            "{name}: {at0} at hover, {at10} at 10 m/s"
        );
    }
}
