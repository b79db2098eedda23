//! The finite-sphere model's single-scattered mean (`model::finite::scattered`,
//! `docs/model.md` §9.5): exact at any R for an isotropic medium with
//! point lights.
//!
//! - Tracer, no allowance: on `point-isotropic-order1` at R = 0.5 and 0.2
//!   the tracer's mean (2·10⁵ trials) agrees with μ₀(R) + μ₁(R) within
//!   4 standard errors, and rejects the small-sphere mean by more than 6.
//! - Henyey–Greenstein media (`model::finite::scattered_hg`, §9.9): at
//!   g = 0.9 with the light 0.3 from the camera line (R = 0.2) and at
//!   g = −0.5 (R = 0.5) the tracer's mean agrees with the finite-sphere one
//!   within 4 standard errors and rejects the small-sphere mean by more
//!   than 6.
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
    finite_mean_within(s, &Options::rel(1e-9).declared())
}

/// [`finite_mean`] with the options `o`.
fn finite_mean_within(s: &Scene, o: &Options) -> (f64, f64) {
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    let k = (-ff.shift).exp();
    let m0 = ff.ray_total(Functional::Mean, o).unwrap();
    let m1 = ff.scattered_mean(o).unwrap();
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

/// μ(R) of the finite-sphere model in a Henyey–Greenstein medium at the
/// goal `tol` (with a budget that lets it finish), absolute, with its bar.
fn finite_mean_hg(s: &Scene, tol: f64) -> (f64, f64) {
    finite_mean_within(s, &Options::rel(tol).declared().with_budget(mcrt_noise::quad::Budget::new(20_000_000_000)))
}

/// The Henyey–Greenstein route (three nested levels per camera-ray point)
/// against the tracer where it resolves the mean to 0.1–0.3 %: forward
/// peaked with the light 0.3 from the camera line (inside the cylinder
/// the spheres sweep at R = 0.2: the small-sphere mean is 35 % low) and
/// backward peaked at R = 0.5 (13 % low). ~40 s.
#[test]
fn in_henyey_greenstein_media_the_tracer_agrees_with_the_finite_mean_and_rejects_the_small_sphere_one() {
    use mcrt_scene::{DVec3, Light, Phase};
    let cases = [
        (0.9, 0.2, DVec3::new(0.3, 0.0, 1.0), 2_000_000u64, 21),
        (-0.5, 0.5, DVec3::new(1.0, 0.0, 1.0), 1_000_000, 22),
    ];
    for (g, r, position, trials, seed) in cases {
        let mut s = scene(r);
        s.medium.phase = Phase::HenyeyGreenstein { g };
        (s.estimator.q, s.estimator.forward_rays, s.estimator.camera_rays) = (0.5, 20, 2);
        let Light::Point { flux, .. } = s.lights[0] else { panic!("the scene has a point light") };
        s.lights[0] = Light::Point { position, flux };
        // The goal the oracle gives it.
        let (finite, bar) = finite_mean_hg(&s, mcrt_noise::prec::FINITE_HG_MEAN_TOL);
        let small = small_sphere_mean(&s).0;
        let t = trace(&Tracer::new(&s).unwrap(), seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap().mean;
        let z = (t.value - finite) / (t.se * t.se + bar * bar).sqrt();
        let z_small = (t.value - small) / t.se;
        println!("g = {g}, R = {r}: finite {finite:.6e} ± {bar:.1e}, small-sphere {small:.6e}, tracer {:.6e} ± {:.1e} ({:.2} %): z = {z:.2}, small-sphere z = {z_small:.1}", t.value, t.se, 100.0 * t.se / t.value);
        assert!(bar <= 1e-3 * finite, "g = {g}: bar {bar:e} above the goal");
        assert!(z.abs() <= 4.0, "g = {g}, R = {r}: the finite-sphere mean disagrees, z = {z}");
        assert!(z_small.abs() > 6.0, "g = {g}, R = {r}: the small-sphere mean is not rejected, z = {z_small}");
    }
}

/// R → 0 in a Henyey–Greenstein medium (g = 0.9 and −0.5): the finite
/// mean (§9.9's nested route) tends to the small-sphere one (§3a's L₁
/// integrated over directions: an independent computation), the gap's
/// fitted order printed and required within [1.8, 2.2] over R = 0.04 →
/// 0.01, each gap at least ten bars above zero. ~2 minutes
/// (`cargo test --release --test finite_scattered -- --ignored --nocapture`).
#[test]
#[ignore = "the R → 0 limit of the Henyey–Greenstein mean, ~3 min in release mode"]
fn in_henyey_greenstein_media_the_finite_mean_tends_to_the_small_sphere_one() {
    use mcrt_scene::Phase;
    for g in [0.9, -0.5] {
        let with_g = |r: f64| {
            let mut s = scene(r);
            s.medium.phase = Phase::HenyeyGreenstein { g };
            s
        };
        let small = small_sphere_mean(&with_g(0.01)).0;
        let radii = [0.04, 0.02, 0.01];
        let gaps: Vec<(f64, f64)> = radii
            .iter()
            .map(|&r| {
                let (m, bar) = finite_mean_hg(&with_g(r), 1e-4);
                (m / small - 1.0, bar / small)
            })
            .collect();
        for (r, (gap, bar)) in radii.iter().zip(&gaps) {
            println!("g = {g}, R = {r}: finite/small-sphere − 1 = {gap:.4e} ± {bar:.1e}");
            assert!(gap.abs() > 10.0 * bar, "g = {g}, R = {r}: the gap is not resolved");
        }
        for w in gaps.windows(2) {
            let order = (w[0].0 / w[1].0).log2();
            println!("g = {g}: fitted order {order:.3}");
            assert!((1.8..=2.2).contains(&order), "g = {g}: order {order}");
        }
    }
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
