//! A short soak in CI (the full day: `scripts/soak.sh`, docs/soak.md): everything stays finite,
//! the covariance positive and within the windup bound, and the rate error comes back after the
//! quiet period.
use host_tests::soak::{run, SoakPlan, MAX_TRACE};

#[test]
fn short_soak_stays_finite_bounded_and_recovers() {
    let steps = if cfg!(debug_assertions) {
        30_000
    } else {
        90_000
    };
    let plan = SoakPlan {
        steps,
        quiet_start: steps / 3,
        quiet_steps: steps / 6,
    };
    let r = run(plan, &mut |_| {}).unwrap();
    eprintln!("{r:?}");
    assert_eq!(r.steps, steps);
    assert_eq!(r.non_finite, 0);
    assert_eq!(r.rejected, 0);
    assert!(r.min_diagonal > 0.0, "{}", r.min_diagonal);
    assert!(r.max_trace <= MAX_TRACE * 1.01, "{}", r.max_trace);
    assert!(
        r.max_parameter.is_finite() && r.max_parameter < 1e4,
        "{}",
        r.max_parameter
    );
    assert!(r.recovery_s.is_some(), "the error never came back: {r:?}");
}
