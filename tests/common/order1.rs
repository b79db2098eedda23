//! The order-1 finite-sphere model's μ and Var L assembled from the
//! library's integrals, and its comparison with the tracer, for the tests
//! of single-scattered light with two spheres per camera ray.

use mcrt_noise::model::field::Field;
use mcrt_noise::model::finite::{FiniteField, FiniteIntegrals};
use mcrt_noise::quad::{Budget, Estimate, Options};
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::Scene;

/// A value with its bar (or standard error).
#[derive(Debug, Clone, Copy)]
pub struct Barred(pub f64, pub f64);

/// (tracer − model)/√(se² + bar²).
pub fn z(tracer: Barred, model: Barred) -> f64 {
    (tracer.0 - model.0) / (tracer.1 * tracer.1 + model.1 * model.1).sqrt()
}

/// μ and Var L of the order-1 finite-sphere model, absolute, with bars
/// (each integral's bar carried linearly through (7)–(9)).
pub fn finite_prediction(s: &Scene, goal: f64) -> (Barred, Barred) {
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    let o = Options::rel(goal).declared().with_budget(Budget::new(40_000_000_000));
    let k = (-ff.shift).exp();
    let FiniteIntegrals { mean, m2, p, q, c23, c24 } = ff.order1_integrals(&o).unwrap();
    let g = |e: &Estimate<f64>| Barred(e.value * k, e.error * k);
    let (q, c23, c24) = (q.unwrap(), c23.unwrap(), c24.unwrap());
    let (mu, m2, p, qq, c23, c24) = (g(&mean), g(&m2), g(&p), g(&q), g(&c23), g(&c24));
    let (q, nf, nb) = (s.estimator.q, s.estimator.forward_rays as f64, s.estimator.camera_rays as f64);
    let a = q * m2.0 + 2.0 * (1.0 - q) * c23.0;
    let b = q * p.0 + 2.0 * (1.0 - q) * qq.0;
    let mu2 = mu.0 * mu.0;
    let var = (a - mu2) / (nf * nb) + (1.0 - 1.0 / nf) * (b - mu2) / nb + (1.0 - 1.0 / nb) * (c24.0 - mu2) / nf;
    let bar = (q * m2.1 + 2.0 * (1.0 - q) * c23.1) / (nf * nb)
        + (1.0 - 1.0 / nf) * (q * p.1 + 2.0 * (1.0 - q) * qq.1) / nb
        + (1.0 - 1.0 / nb) * c24.1 / nf
        + (1.0 / nf + 1.0 / nb - 1.0 / (nf * nb)) * 2.0 * mu.0 * mu.1;
    (mu, Barred(var, bar))
}

/// The model's μ and Var L at the quadrature goal `goal` against `trials`
/// trials of the tracer (seed `seed`): (mean z, Var L z, the model's
/// Var L, the tracer's), printed with `label`.
pub fn against_tracer(label: &str, s: &Scene, goal: f64, trials: u64, seed: u64) -> (f64, f64, Barred, Barred) {
    let (mu, var) = finite_prediction(s, goal);
    let t = trace(&Tracer::new(s).unwrap(), seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let (tm, tv) = (Barred(t.mean.value, t.mean.se), Barred(t.variance.value, t.variance.se));
    let (zm, zv) = (z(tm, mu), z(tv, var));
    println!(
        "{label}: Var L {:.6e} ± {:.1e} (model) vs {:.6e} ± {:.1e} ({:.2} %): z {zv:+.2}; mean {:.6e} ± {:.1e} vs {:.6e} ± {:.1e}: z {zm:+.2}",
        var.0,
        var.1,
        tv.0,
        tv.1,
        100.0 * tv.1 / tv.0,
        mu.0,
        mu.1,
        tm.0,
        tm.1
    );
    (zm, zv, var, tv)
}

/// `Scope::FinitePairs` runs its costly finite-sphere integrals after
/// everything else: given what `Scope::Everything` used plus `extra`
/// evaluations (far below their billions), they spend the budget, and the
/// report stands with the small-sphere prediction, the exact finite-sphere
/// mean, and their failure in `finite_not_used` and `finite_error` — the
/// same prediction and mean as `Scope::Everything` gives. Returns the
/// failure's text and what `Everything` used.
pub fn costly_part_spends_the_budget(s: &Scene, extra: u64) -> (String, u64) {
    use mcrt_noise::oracle::{run_within_scoped, Precision, Scope};
    let first = Budget::new(1_000_000_000);
    let everything = run_within_scoped(s, Precision::F64, Some(1e-3), &first, Scope::Everything).unwrap();
    let used = first.used();
    let asked =
        run_within_scoped(s, Precision::F64, Some(1e-3), &Budget::new(used + extra), Scope::FinitePairs).unwrap();
    assert_eq!(asked.prediction.model, "small-sphere");
    let why = asked.finite_not_used.clone().unwrap();
    assert!(why.contains("its computation failed") && why.contains("budget"), "{why}");
    assert!(asked.finite_error.is_some());
    assert_eq!(asked.prediction.variance.value, everything.prediction.variance.value);
    assert_eq!(asked.prediction.mean.value, everything.prediction.mean.value);
    let (a, e) = (asked.finite_mean.unwrap().mean.unwrap(), everything.finite_mean.unwrap().mean.unwrap());
    assert_eq!((a.value, a.error), (e.value, e.error));
    (why, used)
}
