//! The finite-sphere model's single-scattered mean (`model::finite::scattered`,
//! `docs/model.md` §9.5): exact at any R for an isotropic medium with
//! point lights.
//!
//! - Tracer, no allowance: on `point-isotropic-order1` at R = 0.5 and 0.2
//!   the tracer's mean (2·10⁵ trials) agrees with μ₀(R) + μ₁(R) within
//!   4 standard errors, and rejects the small-sphere mean by more than 6.
//! - R → 0: the finite mean tends to the small-sphere one (§3a, an
//!   independent computation: the single-scattered field L₁ integrated
//!   over directions), their difference second order in R (fitted), below
//!   10⁻⁶ relative at R = 10⁻³.

use mcrt_noise::model::field::Field;
use mcrt_noise::model::finite::{FiniteField, Functional};
use mcrt_noise::model::moments::mean_luminance;
use mcrt_noise::quad::Options;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::Scene;
use std::path::Path;

fn scene(radius: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic-order1.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.radius = radius;
    s
}

/// μ(R) = μ₀(R) + μ₁(R) of the finite-sphere model, absolute, with its bar.
fn finite_mean(s: &Scene) -> (f64, f64) {
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    let o = Options::rel(1e-9).declared();
    let k = (-ff.shift).exp();
    let m0 = ff.ray_total(Functional::Mean, &o).unwrap();
    let m1 = ff.scattered_mean(&o).unwrap();
    ((m0.value + m1.value) * k, (m0.error + m1.error) * k)
}

/// The small-sphere mean (§3: uncollided plus L₁ integrated over
/// directions; independent of R), absolute, with its bar.
fn small_sphere_mean(s: &Scene) -> (f64, f64) {
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let m = mean_luminance(&field, &Options::rel(1e-9)).unwrap();
    let k = (-field.shift).exp();
    (m.value * k, m.error * k)
}

#[test]
fn tracer_agrees_with_the_finite_single_scattered_mean_and_rejects_the_small_sphere_one() {
    for (r, seed) in [(0.5, 5), (0.2, 6)] {
        let s = scene(r);
        let (finite, bar) = finite_mean(&s);
        let small = small_sphere_mean(&s).0;
        let t = trace(&Tracer::new(&s).unwrap(), seed, 0..200_000, HitMethod::Sorted, &|_| {}).summary().unwrap().mean;
        let z = (t.value - finite) / (t.se * t.se + bar * bar).sqrt();
        let z_small = (t.value - small) / t.se;
        println!("R = {r}: finite {finite:.6e} ± {bar:.1e}, small-sphere {small:.6e}, tracer {:.6e} ± {:.1e}: z = {z:.2}, small-sphere z = {z_small:.1}", t.value, t.se);
        assert!(z.abs() <= 4.0, "R = {r}: the finite-sphere mean disagrees, z = {z}");
        assert!(z_small.abs() > 6.0, "R = {r}: the small-sphere mean is not rejected, z = {z_small}");
    }
}

#[test]
fn finite_mean_tends_to_the_small_sphere_one_at_second_order() {
    let (small, small_bar) = small_sphere_mean(&scene(0.01));
    let radii = [0.04, 0.02, 0.01];
    let gaps: Vec<f64> = radii.iter().map(|&r| finite_mean(&scene(r)).0 / small - 1.0).collect();
    let orders: Vec<f64> = gaps.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    let shown: Vec<String> = gaps.iter().map(|g| format!("{g:.3e}")).collect();
    println!("relative gaps {shown:?} at R = {radii:?}; fitted orders {orders:.4?}");
    for p in &orders {
        assert!((p - 2.0).abs() < 0.1, "order of the gap {p}");
    }
    let (tiny, bar) = finite_mean(&scene(1e-3));
    let gap = (tiny / small - 1.0).abs();
    assert!(gap <= 1e-6 + (bar + small_bar) / small, "gap at R = 1e-3: {gap:e}");
}
