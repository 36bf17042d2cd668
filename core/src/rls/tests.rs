//! Unit tests of the estimator: shortcuts that must not change a bit.

use super::*;

/// The dense sums of a small bare estimator and the sums over the non-zero entries give
/// the same bits (both forms; regressors with zero entries, and with all entries zero).
#[test]
fn dense_sums_equal_sums_over_the_non_zero_entries() {
    for algorithm in [Algorithm::UdFactor, Algorithm::Covariance] {
        let config = RlsConfig {
            algorithm,
            ..RlsConfig::paper(1e4)
        };
        let mut dense = Rls::<f32, 4, 10>::new(config).unwrap();
        let mut listed = dense.clone();
        assert!(AllParameters(4).dense_sums());
        let all = [Run { start: 0, end: 4 }];
        let mut state = 0x9e37_79b9u32;
        for k in 0..500u32 {
            let mut xi = [0.0f32; 4];
            for (i, x) in xi.iter_mut().enumerate() {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                // About half the entries zero, some of them -0.
                if (state >> (i * 3)) & 1 == 0 {
                    *x = (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5;
                } else if k % 3 == 0 {
                    *x = -0.0;
                }
            }
            let e = xi[0] - 0.25 * xi[3];
            dense.update_row(&xi, AllParameters(4), Measurement::row(e, 1.0));
            listed.update_row(&xi, &all[..], Measurement::row(e, 1.0));
            let bits = |r: &Rls<f32, 4, 10>| {
                let s = r.export();
                (s.theta.map(f32::to_bits), s.factor.map(f32::to_bits))
            };
            assert_eq!(bits(&dense), bits(&listed), "{algorithm:?} update {k}");
        }
        assert_eq!(dense.counters(), listed.counters());
    }
}

/// The unrolled U-D kernel (every parameter, N ≤ `UNROLLED_UP_TO`) and the slice kernel
/// (a support of runs) give the same bits: regressors with zero and -0 entries (columns
/// skipped), with and without forgetting, the windup guard holding forgetting off at
/// times; f32 and f64, several N.
fn unrolled_equals_slices<T: Real, const N: usize, const NP: usize>() {
    for lambda in [1.0, 0.97] {
        // A trace bound that the forgetting reaches: the guard holds at times.
        let bound = T::lit(0.5 * N as f64);
        let config = RlsConfig::robust(T::lit(1e3)).with_forgetting(T::lit(lambda), bound);
        let mut unrolled = Rls::<T, N, NP>::new(config).unwrap();
        let mut slices = unrolled.clone();
        let all = [Run {
            start: 0,
            end: N as u16,
        }];
        let mut state = 0x2545_f491u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        for k in 0..400u32 {
            let mut xi = [T::zero(); N];
            for x in xi.iter_mut() {
                let r = next();
                *x = match r % 4 {
                    0 => T::zero(),
                    1 if k % 2 == 0 => -T::zero(),
                    _ => T::lit(f64::from(r >> 8) / f64::from(1u32 << 24) - 0.5),
                };
            }
            let e = T::lit(f64::from(next() >> 8) / f64::from(1u32 << 24) - 0.5);
            let l = if k % 3 == 2 { T::lit(lambda) } else { T::one() };
            unrolled.update_row(&xi, AllParameters(N), Measurement::row(e, l));
            slices.update_row(&xi, &all[..], Measurement::row(e, l));
            let bits = |r: &Rls<T, N, NP>| {
                let s = r.export();
                (s.theta.map(T::to_bits_u64), s.factor.map(T::to_bits_u64))
            };
            assert_eq!(
                bits(&unrolled),
                bits(&slices),
                "N {N}, λ {lambda}, update {k}"
            );
        }
        assert_eq!(unrolled.counters(), slices.counters());
        if lambda < 1.0 {
            let c = unrolled.counters();
            assert!(
                c.windup_guards > 0 && c.windup_guards < c.updates / 3,
                "N {N}: the guard held {} times in {} updates",
                c.windup_guards,
                c.updates
            );
        }
    }
}

#[test]
fn unrolled_ud_kernel_equals_the_slice_kernel() {
    unrolled_equals_slices::<f32, 1, 1>();
    unrolled_equals_slices::<f32, 2, 3>();
    unrolled_equals_slices::<f32, 5, 15>();
    unrolled_equals_slices::<f32, 7, 28>();
    unrolled_equals_slices::<f32, 8, 36>();
    unrolled_equals_slices::<f64, 2, 3>();
    unrolled_equals_slices::<f64, 7, 28>();
}
