//! One evaluation budget per computation, shared by every level (issue 11):
//! a computation that cannot converge ends as `NOT CONVERGED` naming the
//! budget or the panel limit, within the budget, never as a stall.

use mcrt_noise::quad::{integrate, integrate_nested, Budget, Domain, Options};

/// Deterministic noise of size 1 (a hash of the abscissa's bits): no rule
/// converges on it, however often it bisects.
fn noise(x: f64) -> f64 {
    let mut h = x.to_bits().wrapping_mul(0x9E37_79B9_7F4A_7C15);
    h ^= h >> 29;
    (h % 1000) as f64 / 1000.0
}

#[test]
fn a_plain_integrand_that_cannot_converge_ends_loudly() {
    let budget = Budget::new(5_000_000);
    let opts = Options::rel(1e-10).declared().with_budget(budget.clone());
    let fail = integrate(|x: &f64| noise(*x), &Domain::finite(0.0, 1.0), &opts).expect_err("noise cannot converge");
    assert!(fail.reason.contains("panels") || fail.reason.contains("budget"), "{}", fail.reason);
    assert!(budget.used() <= 5_000_000, "used {}", budget.used());
}

/// Before the shared budget, each inner integral had 2·10⁶ evaluations of
/// its own and the outer level another 2·10⁶ calls: up to 4·10¹² in all.
#[test]
fn an_inner_level_that_cannot_converge_spends_the_one_budget() {
    let budget = Budget::new(3_000_000);
    let opts = Options::rel(1e-10).declared().with_budget(budget.clone());
    let inner = |s: &f64, o: &Options| integrate(|t: &f64| noise(s + t), &Domain::finite(0.0, 1.0), o);
    let fail = integrate_nested(inner, &Domain::finite(0.0, 1.0), &opts).expect_err("noise cannot converge");
    assert!(fail.reason.contains("panels") || fail.reason.contains("budget"), "{}", fail.reason);
    // The check happens between refinement steps: the overrun is at most a
    // few steps of each running pass (a tanh–sinh level of a few hundred
    // nodes, or 2000 panels' bisections of 20 evaluations).
    assert!(budget.used() <= 3_000_000 + 200_000, "used {}", budget.used());
}

#[test]
fn a_smooth_nested_integral_over_its_budget_fails_naming_it() {
    let smooth = |s: &f64, o: &Options| integrate(|t: &f64| (-(s * t)).exp(), &Domain::finite(0.0, 1.0), o);
    let big = Budget::new(100_000_000);
    let ok = integrate_nested(smooth, &Domain::finite(0.0, 1.0), &Options::rel(1e-12).with_budget(big.clone()))
        .expect("converges within a large budget");
    let needed = big.used();
    assert!(ok.error <= 1e-12 * ok.value.abs());
    let small = Budget::new(needed / 4);
    let fail = integrate_nested(smooth, &Domain::finite(0.0, 1.0), &Options::rel(1e-12).with_budget(small.clone()))
        .expect_err("a quarter of the evaluations is not enough");
    assert!(fail.reason.contains("evaluation budget"), "{}", fail.reason);
}

#[test]
fn a_deadline_ends_a_computation() {
    let budget = Budget::with_deadline(u64::MAX, std::time::Duration::from_millis(1));
    std::thread::sleep(std::time::Duration::from_millis(5));
    let opts = Options::rel(1e-12).declared().with_budget(budget);
    let fail = integrate(|x: &f64| noise(*x), &Domain::finite(0.0, 1.0), &opts).expect_err("past the deadline");
    assert!(fail.reason.contains("time limit"), "{}", fail.reason);
}
