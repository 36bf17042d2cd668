//! The RLS estimator on its own.
use rotorid::rls::{Algorithm, Rls, RlsConfig};
use rotorid::{Error, Quantity};

/// A small deterministic generator (xorshift) so the test needs no dependency.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

const TRUE: [f64; 6] = [0.5, -1.25, 2.0, 0.0, 3.5, -0.75];

fn data(n: usize, seed: u64) -> Vec<([f64; 6], f64)> {
    let mut g = Lcg(seed);
    (0..n)
        .map(|_| {
            let mut x = [0.0; 6];
            for v in x.iter_mut() {
                // Sparse like a TS regressor: about a third of the entries are exactly zero.
                let r = g.next();
                *v = if r.abs() < 0.33 { 0.0 } else { g.next() * 3.0 };
            }
            let y = x.iter().zip(TRUE).map(|(a, b)| a * b).sum();
            (x, y)
        })
        .collect()
}

#[test]
fn both_algorithms_recover_known_parameters_in_f64() {
    for cfg in [RlsConfig::paper(1e6), RlsConfig::robust(1e6)] {
        let mut rls = Rls::<f64, 6, 21>::new(cfg).unwrap();
        for (x, y) in data(400, 7) {
            rls.update(&x, y).unwrap();
        }
        for (t, e) in rls.parameters().iter().zip(TRUE) {
            assert!((t - e).abs() < 1e-6, "{:?}: {t} vs {e}", cfg.algorithm);
        }
        assert_eq!(rls.counters().updates, 400);
    }
}

#[test]
fn ud_keeps_f32_accurate_where_the_covariance_form_degrades() {
    // The paper's α = 1e6 in f32: the U-D form still recovers θ closely.
    let mut ud = Rls::<f32, 6, 21>::new(RlsConfig::robust(1e6)).unwrap();
    for (x, y) in data(2000, 11) {
        ud.update(&x.map(|v| v as f32), y as f32).unwrap();
    }
    for (t, e) in ud.parameters().iter().zip(TRUE) {
        assert!((f64::from(*t) - e).abs() < 1e-3, "{t} vs {e}");
    }
    // P stays positive definite: every diagonal entry positive.
    assert!(ud.covariance_diagonal().iter().all(|&d| d > 0.0));
}

#[test]
fn the_two_forms_agree_in_f64() {
    let mut a = Rls::<f64, 6, 21>::new(RlsConfig::paper(1e3)).unwrap();
    let mut b = Rls::<f64, 6, 21>::new(RlsConfig::robust(1e3)).unwrap();
    for (x, y) in data(300, 3) {
        let ea = a.update(&x, y + 0.01).unwrap();
        let eb = b.update(&x, y + 0.01).unwrap();
        assert!((ea - eb).abs() <= 1e-9 * (1.0 + ea.abs()));
    }
    for (pa, pb) in a.parameters().iter().zip(b.parameters()) {
        assert!((pa - pb).abs() < 1e-9, "{pa} {pb}");
    }
    for i in 0..6 {
        for j in 0..6 {
            let (x, y) = (a.covariance(i, j).unwrap(), b.covariance(i, j).unwrap());
            assert!(
                (x - y).abs() <= 1e-9 * (1.0 + x.abs()),
                "P[{i}][{j}] {x} {y}"
            );
        }
    }
}

#[test]
fn rejected_updates_change_nothing() {
    for alg in [Algorithm::Covariance, Algorithm::UdFactor] {
        let cfg = RlsConfig {
            algorithm: alg,
            ..RlsConfig::paper(100.0f32)
        };
        let mut rls = Rls::<f32, 6, 21>::new(cfg).unwrap();
        for (x, y) in data(20, 5) {
            rls.update(&x.map(|v| v as f32), y as f32).unwrap();
        }
        let before = rls.clone();
        let good = [1.0f32; 6];
        let mut nan = good;
        nan[3] = f32::NAN;
        assert_eq!(
            rls.update(&nan, 0.0),
            Err(Error::NonFinite(Quantity::Regressor(3)))
        );
        let mut huge = good;
        huge[5] = 1e30;
        assert_eq!(
            rls.update(&huge, 0.0),
            Err(Error::OutOfRange(Quantity::Regressor(5)))
        );
        assert_eq!(
            rls.update(&good, f32::INFINITY),
            Err(Error::NonFinite(Quantity::Target(0)))
        );
        assert_eq!(
            rls.update(&good, -1e20),
            Err(Error::OutOfRange(Quantity::Target(0)))
        );
        // Second of two measurements bad: the first must not have been applied either.
        assert!(rls.update_many(&[good, nan], &[1.0, 1.0]).is_err());
        assert_eq!(rls, before);
    }
}

#[test]
fn forgetting_windup_is_bounded_without_excitation() {
    for alg in [Algorithm::Covariance, Algorithm::UdFactor] {
        let cfg = RlsConfig {
            algorithm: alg,
            ..RlsConfig::paper(1.0f64)
        }
        .with_forgetting(0.95, 50.0);
        let mut rls = Rls::<f64, 6, 21>::new(cfg).unwrap();
        // Only the first parameter is ever excited: the others' variance would grow as λ⁻ᵏ.
        for k in 0..2000 {
            let x = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            rls.update(&x, 0.5 + 1e-3 * f64::from(k % 3)).unwrap();
            assert!(
                rls.trace() <= 50.0 * (1.0 + 1e-12),
                "{alg:?} step {k}: {}",
                rls.trace()
            );
        }
        assert!(rls.counters().windup_guards > 0);
        assert!((rls.parameters()[0] - 0.501).abs() < 0.01);
    }
}

#[test]
fn export_import_continues_bit_for_bit() {
    let cfg = RlsConfig::robust(1e6f32);
    let d = data(200, 9);
    let mut a = Rls::<f32, 6, 21>::new(cfg).unwrap();
    for (x, y) in &d[..100] {
        a.update(&x.map(|v| v as f32), *y as f32).unwrap();
    }
    let mut b = Rls::<f32, 6, 21>::new(cfg).unwrap();
    b.import(&a.export()).unwrap();
    for (x, y) in &d[100..] {
        let x = x.map(|v| v as f32);
        assert_eq!(
            a.update(&x, *y as f32).unwrap().to_bits(),
            b.update(&x, *y as f32).unwrap().to_bits()
        );
    }
    assert_eq!(a.export(), b.export());
    // A state of the other algorithm, a negative D in a U-D state, or a NaN, is refused.
    let mut c = Rls::<f32, 6, 21>::new(RlsConfig::paper(1e6)).unwrap();
    assert_eq!(c.import(&a.export()), Err(Error::Incompatible));
    let mut bad = a.export();
    bad.factor[0] = -1.0;
    assert_eq!(
        b.import(&bad),
        Err(Error::OutOfRange(Quantity::Covariance(0)))
    );
    let mut bad = c.export();
    bad.factor[4] = f32::NAN;
    assert_eq!(
        c.import(&bad),
        Err(Error::NonFinite(Quantity::Covariance(4)))
    );
    assert_eq!(b.export(), a.export());
}

#[test]
fn bad_configurations_are_refused() {
    assert!(Rls::<f32, 2, 3>::new(RlsConfig::paper(0.0)).is_err());
    assert!(Rls::<f32, 2, 3>::new(RlsConfig::paper(f32::NAN)).is_err());
    assert!(Rls::<f32, 2, 3>::new(RlsConfig::paper(1e13)).is_err());
    assert!(Rls::<f32, 2, 3>::new(RlsConfig::paper(1.0).with_forgetting(0.5, 1.0)).is_err());
    assert!(Rls::<f32, 2, 3>::new(RlsConfig::paper(1.0).with_forgetting(0.99, -1.0)).is_err());
}
