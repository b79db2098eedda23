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
    // The check happens between refinement steps and every CHECK_EVERY
    // calls of each level: the overrun is at most a batch of calls of each
    // running level.
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

/// A rule stopped by its level's evaluation budget while still refining
/// says where its error lay, as at the panel limit: here its truncation
/// (refining was paying), not bars carried in from inner levels.
#[test]
fn a_rule_stopped_by_its_budget_splits_its_error() {
    let kinked = |x: &f64| (x - std::f64::consts::FRAC_1_PI).abs().powf(0.3);
    let fail = integrate(kinked, &Domain::finite(0.0, 1.0), &Options::rel(1e-14).with_max_evals(3_000))
        .expect_err("a kink to 1e-14 in 3000 evaluations");
    assert!(fail.reason.contains("exhausted by"), "{}", fail.reason);
    assert!(fail.reason.contains("of which truncation"), "{}", fail.reason);
    assert!(!fail.reason.contains("refining does not shrink them"), "{}", fail.reason);
}

#[test]
fn a_deadline_ends_a_computation() {
    let budget = Budget::with_deadline(u64::MAX, std::time::Duration::from_millis(1));
    std::thread::sleep(std::time::Duration::from_millis(5));
    let opts = Options::rel(1e-12).declared().with_budget(budget);
    let fail = integrate(|x: &f64| noise(*x), &Domain::finite(0.0, 1.0), &opts).expect_err("past the deadline");
    assert!(fail.reason.contains("time limit"), "{}", fail.reason);
}

/// The outside probe, item 6: a computation that met its goal at its first
/// step (no refinement, so no check between steps) returned its value
/// whatever it had spent: `kernel --max-evals 1` printed I after 128
/// evaluations. No result may need more than its budget: an integral that
/// spent more fails naming it, with the value as its best guess; the same
/// budget plus what it spent converges.
#[test]
fn an_integral_that_converges_past_its_budget_fails() {
    let f = |x: &f64| (-x).exp();
    let ample = Budget::new(1_000_000);
    integrate(f, &Domain::finite(0.0, 1.0), &Options::rel(1e-10).with_budget(ample.clone())).expect("converges");
    let needed = ample.used();
    assert!(needed > 1, "needed {needed}");
    let exact = Budget::new(needed);
    integrate(f, &Domain::finite(0.0, 1.0), &Options::rel(1e-10).with_budget(exact)).expect("its own cost fits");
    let short = Budget::new(needed - 1);
    let fail = integrate(f, &Domain::finite(0.0, 1.0), &Options::rel(1e-10).with_budget(short))
        .expect_err("one evaluation short of what it needs");
    assert!(fail.reason.contains(&format!("evaluation budget of {}", needed - 1)), "{}", fail.reason);
    let guess = fail.best_guess.expect("the converged value as its best guess");
    assert!((guess - (1.0 - (-1f64).exp())).abs() <= 1e-10, "{guess}");
}

/// The outside probe, item 3: within one refinement step the budget and
/// the deadline were not looked at, so one step of a rule over many pieces
/// of an expensive integrand ran on past the deadline (`oracle --precision
/// 1024 --time-limit 5` ended after 48–90 s). Every level now looks every
/// `CHECK_EVERY` calls: an integrand that sleeps 1 ms per call on 1000
/// declared pieces (a first step of ≥ 7000 calls, ≥ 7 s), given a deadline
/// of 50 ms, ends within a batch of calls of each rule.
#[test]
fn a_deadline_is_checked_within_a_refinement_step() {
    let budget = Budget::with_deadline(u64::MAX, std::time::Duration::from_millis(50));
    let opts = Options::rel(1e-12).declared().with_budget(budget);
    let slow = |x: &f64| {
        std::thread::sleep(std::time::Duration::from_millis(1));
        x.exp()
    };
    let pieces = Domain::finite(0.0, 1.0).with_breakpoints((1..1000).map(|k| f64::from(k) / 1000.0));
    let t0 = std::time::Instant::now();
    let fail = integrate(slow, &pieces, &opts).expect_err("past the deadline");
    let secs = t0.elapsed().as_secs_f64();
    assert!(fail.reason.contains("time limit"), "{}", fail.reason);
    // The deadline plus at most one batch of checks on each of the two
    // rules' levels (CHECK_EVERY calls of ≥ 1 ms each), with room for a
    // loaded machine's sleeps overshooting.
    let batch = mcrt_noise::quad::CHECK_EVERY as f64 * 1e-3;
    assert!(secs <= 0.05 + 2.0 * batch * 1.5, "{secs:.2} s");
}
