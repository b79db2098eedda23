//! The finite-sphere model of single-scattered light (`model::finite::order1`,
//! `docs/model.md` §9.6): the estimator's second moment M₂ (with the
//! same-path double hits at finite R) and P of (17), exact at any R for an
//! isotropic medium with point lights, against the tracer with no
//! allowance.
//!
//! With q = 1 and N_B = 1 (one sphere per camera ray, one camera ray) the
//! variance of L is M₂/N_F + (1 − 1/N_F)P − μ² ((7)–(9)): no correlation of
//! two spheres enters, so these points test μ, M₂ and P alone.

use mcrt_noise::model::field::Field;
use mcrt_noise::model::finite::{FiniteField, Functional};
use mcrt_noise::oracle::{run, Precision};
use mcrt_noise::quad::Options;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light, Scene};
use std::path::Path;

mod common;

/// `point-isotropic-order1` with q = 1, N_B = 1 and the given R, N_F, albedo.
fn scene(radius: f64, n_f: u64, albedo: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic-order1.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.radius = radius;
    s.estimator.q = 1.0;
    s.estimator.forward_rays = n_f;
    s.estimator.camera_rays = 1;
    s.medium.albedo = albedo;
    s
}

/// A value with its bar.
#[derive(Debug, Clone, Copy)]
struct Barred(f64, f64);

/// μ and Var L of the order-1 finite-sphere model for q = 1, N_B = 1,
/// absolute, with bars.
fn finite_prediction(s: &Scene) -> (Barred, Barred) {
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    let o = Options::rel(1e-6).declared();
    let k = (-ff.shift).exp();
    let (mean0, mean1) = rayon::join(|| ff.ray_total(Functional::Mean, &o), || ff.scattered_mean(&o));
    let (second0, second1) = rayon::join(|| ff.ray_total(Functional::Second, &o), || ff.order1_second_added(&o));
    let p = ff.order1_p_and_q(&o).0.unwrap();
    let (mean0, mean1, second0, second1) = (mean0.unwrap(), mean1.unwrap(), second0.unwrap(), second1.unwrap());
    let mu = Barred((mean0.value + mean1.value) * k, (mean0.error + mean1.error) * k);
    let m2 = Barred((second0.value + second1.value) * k, (second0.error + second1.error) * k);
    let p = Barred(p.value * k, p.error * k);
    let nf = s.estimator.forward_rays as f64;
    let var = m2.0 / nf + (1.0 - 1.0 / nf) * p.0 - mu.0 * mu.0;
    let var_bar = m2.1 / nf + (1.0 - 1.0 / nf) * p.1 + 2.0 * mu.0 * mu.1;
    (mu, Barred(var, var_bar))
}

/// (tracer − model)/√(se² + bar²).
fn z(tracer: Barred, model: Barred) -> f64 {
    (tracer.0 - model.0) / (tracer.1 * tracer.1 + model.1 * model.1).sqrt()
}

struct Point {
    name: &'static str,
    scene: Scene,
    trials: u64,
    seed: u64,
    /// Whether the small-sphere model must be rejected here (|z| > 6), with
    /// the tracer's Var L resolved to 0.3 % (issue 20's acceptance: the
    /// rejection stands on a tight point, not a loose one).
    rejects_small_sphere: bool,
}

fn check(p: &Point) -> (f64, f64) {
    let (mu, var) = finite_prediction(&p.scene);
    let t = trace(&Tracer::new(&p.scene).unwrap(), p.seed, 0..p.trials, HitMethod::Sorted, &|_| {});
    let t = t.summary().unwrap();
    let (t_mu, t_var) = (Barred(t.mean.value, t.mean.se), Barred(t.variance.value, t.variance.se));
    let (z_mu, z_var) = (z(t_mu, mu), z(t_var, var));
    // The small-sphere model (§3a, E9), which must compute everywhere here
    // (for a light 0.1 from the camera line its (23) met an infinite
    // integrand until the angular frame formed ϑ − ψ_u from ϑ′ = π − ϑ).
    // To 10⁻⁴: its bar then stays under a tenth of the tracer's relative
    // standard error (0.16 % or more at every point), and the run is
    // faster than at its default 10⁻⁶; the bar enters z all the same.
    let (small_var, z_small) = match run(&p.scene, Precision::F64, Some(1e-4)) {
        Ok(small) => {
            let v = Barred(small.variance.as_ref().unwrap().exact.value, small.variance.as_ref().unwrap().exact.error);
            (v, z(t_var, v))
        }
        Err(e) => panic!("{}: small-sphere model: {e}", p.name),
    };
    println!(
        "{}: μ {:.6e} ± {:.1e}, tracer {:.6e} ± {:.1e} (z {z_mu:+.2}); Var L {:.6e} ± {:.1e}, tracer {:.6e} ± {:.1e} \
         ({:.2} %, z {z_var:+.2}); small-sphere Var L {:.6e} (z {z_small:+.1})",
        p.name,
        mu.0,
        mu.1,
        t_mu.0,
        t_mu.1,
        var.0,
        var.1,
        t_var.0,
        t_var.1,
        100.0 * t_var.1 / t_var.0,
        small_var.0
    );
    assert!(z_mu.abs() <= 4.0 && z_var.abs() <= 4.0, "{}: the finite model disagrees with the tracer", p.name);
    if p.rejects_small_sphere {
        assert!(z_small.abs() > 6.0, "{}: the small-sphere Var L is not rejected (z = {z_small})", p.name);
        let resolution = t_var.1 / t_var.0;
        assert!(resolution <= 3e-3, "{}: Var L's standard error {resolution:.2e} exceeds 0.3 %", p.name);
    }
    (t_var.1 / t_var.0, z_small)
}

#[test]
fn tracer_agrees_with_the_order1_variance_at_one_sphere_per_camera_ray() {
    let mut near = scene(0.2, 1, 0.8);
    near.lights = vec![Light::Point { position: DVec3::new(0.1, 0.0, 1.0), flux: 1.0 }];
    let points = [
        Point {
            name: "R 0.5, N_F 1",
            scene: scene(0.5, 1, 0.8),
            trials: 10_000_000,
            seed: 21,
            rejects_small_sphere: true,
        },
        Point {
            name: "R 0.2, N_F 20",
            scene: scene(0.2, 20, 0.8),
            trials: 2_000_000,
            seed: 22,
            rejects_small_sphere: true,
        },
        Point {
            name: "R 0.1, N_F 1, albedo 0.3",
            scene: scene(0.1, 1, 0.3),
            trials: 4_000_000,
            seed: 23,
            rejects_small_sphere: false,
        },
        Point {
            name: "R 0.03, N_F 200, albedo 1",
            scene: scene(0.03, 200, 1.0),
            trials: 100_000,
            seed: 24,
            rejects_small_sphere: false,
        },
        Point {
            name: "R 0.2, light 0.1 from the line",
            scene: near,
            trials: 4_000_000,
            seed: 25,
            rejects_small_sphere: true,
        },
    ];
    for p in &points {
        check(p);
    }
}

/// M₂ and P of the finite model tend to the small-sphere ones (§3a with the
/// same-path hits of §3b, an independent computation: L₁ integrated over
/// directions) as R → 0, the fitted orders of their relative gaps printed:
/// P's is second order (measured 2.00, 2.00); M₂'s rises towards 2 (1.67,
/// 1.73 at R = 0.04 → 0.01: gap/(R² ln(1/R)) = 0.34, 0.35, 0.36), the
/// same-path hits of §3b adding a term like R² ln(1/R) (grazing first
/// segments), so orders below 1.6 or above 2.1 fail, and so does a gap above
/// 2·10⁻⁴ at R = 0.01 (a regression pin 18 % above the measured 1.7·10⁻⁴,
/// not a derived bound).
#[test]
fn order1_second_moment_and_p_tend_to_the_small_sphere_ones() {
    use mcrt_noise::model::moments;
    let radii = [0.04, 0.02, 0.01];
    let mut gaps = Vec::new();
    for &r in &radii {
        let s = scene(r, 1, 0.8);
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        let o = Options::rel(1e-9).declared();
        let (k, k_small) = ((-ff.shift).exp(), (-field.shift).exp());
        let m2 = ff.ray_total(Functional::Second, &o).unwrap().value + ff.order1_second_added(&o).unwrap().value;
        let p = ff.order1_p_and_q(&Options::rel(1e-7).declared()).0.unwrap().value;
        let rr = r;
        let small_m2 =
            moments::m2(&field, &rr, &o).unwrap().value + moments::m2_same_path(&field, &rr, &o).unwrap().value;
        let small_p = moments::p_single(&field, &o).unwrap().value;
        gaps.push(((m2 * k) / (small_m2 * k_small) - 1.0, (p * k) / (small_p * k_small) - 1.0));
    }
    let order = |f: &dyn Fn(&(f64, f64)) -> f64| -> Vec<f64> {
        gaps.windows(2).map(|w| (f(&w[0]) / f(&w[1])).abs().log2()).collect()
    };
    let (m2_orders, p_orders) = (order(&|g| g.0), order(&|g| g.1));
    println!("relative gaps (M₂, P) {gaps:?} at R = {radii:?}; fitted orders M₂ {m2_orders:.3?}, P {p_orders:.3?}");
    for p in &p_orders {
        assert!((p - 2.0).abs() < 0.1, "order of P's gap {p}");
    }
    for p in &m2_orders {
        assert!((1.6..2.1).contains(p), "order of M₂'s gap {p}");
    }
    assert!(m2_orders[1] > m2_orders[0], "M₂'s order does not rise towards 2: {m2_orders:?}");
    assert!(gaps[2].0.abs() < 2e-4 && gaps[2].1.abs() < 2e-4, "gaps at R = 0.01: {:?}", gaps[2]);
}

/// Two routes to the single-scattered μ₁ that share no geometry:
/// sphere-centric (§9.5's I(D): the cap of the sphere seen from the
/// interaction point, bipolar coordinates) and ray-centric through virtual
/// lights (the order-0 hit intervals of §9.2 for a point light at the
/// interaction point, averaged over it; `finite::virtual_lights`). They
/// agree within their bars (measured: a gap of 5.6·10⁻⁸ relative against
/// bars of 5·10⁻⁶ and 6·10⁻⁶ relative, `docs/model.md` §9.6). In an
/// isotropic medium ⟨𝒞₁²⟩ = c f⟨𝒞₁⟩ at every sphere, so this checks the
/// I(D) behind M₂'s ⟨𝒞₁²⟩ too (its
/// prefactor is the tracer points' to check). ~3 minutes on two cores:
/// `cargo test --release --test finite_order1 -- --ignored`.
#[test]
#[ignore]
fn single_scattered_mean_by_two_routes() {
    let s = scene(0.2, 1, 0.8);
    let field = Field::from_scene(&s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(&s, &field);
    let o = Options::rel(1e-4).declared().with_budget(mcrt_noise::quad::Budget::new(20_000_000_000));
    let t = std::time::Instant::now();
    let sphere = ff.scattered_mean(&o).unwrap();
    let virtual_lights = ff.order1_virtual(Functional::Mean, &o).unwrap();
    let gap = (sphere.value - virtual_lights.value).abs();
    println!(
        "μ₁·e^(c₀): sphere-centric {:.10e} ± {:.1e}, virtual lights {:.10e} ± {:.1e} ({} evaluations), relative gap {:.1e} [{:.0?}]",
        sphere.value,
        sphere.error,
        virtual_lights.value,
        virtual_lights.error,
        virtual_lights.evaluations,
        gap / sphere.value,
        t.elapsed()
    );
    assert!(gap <= sphere.error + virtual_lights.error, "the routes disagree");
}

/// Hard cases of the order-1 moments: a sphere of radius 10 (holding light
/// and camera), R = 10⁻⁸, a light 10⁻⁶ from the camera line, σ × the
/// light's distance at 42, 424 and 693 (near the scene's bound, where
/// P·e^{c₀} ≈ 10⁻²⁸⁴ and P had failed, `docs/model.md` §9.6). Each
/// converges with a bar ≤ 10⁻⁶ relative and a finite, positive value; at
/// R = 10⁻⁸ M₂ and P agree with the small-sphere ones (§3a with E9) within
/// 10⁻⁶ relative.
#[test]
fn order1_moments_converge_in_hard_cases() {
    let mut cases: Vec<(&str, Scene)> = Vec::new();
    cases.push(("R 10", scene(10.0, 1, 0.8)));
    cases.push(("R 1e-8", scene(1e-8, 1, 0.8)));
    let mut near = scene(0.2, 1, 0.8);
    near.lights = vec![Light::Point { position: DVec3::new(1e-6, 0.0, 1.0), flux: 1.0 }];
    cases.push(("light 1e-6 from the line", near));
    for (name, sigma, r) in
        [("σ·|y − o| = 42", 30.0, 0.2), ("σ·|y − o| = 424", 300.0, 0.01), ("σ·|y − o| = 693", 490.0, 0.01)]
    {
        let mut dense = scene(r, 1, 0.8);
        dense.medium.sigma_ext = sigma;
        cases.push((name, dense));
    }
    for (name, s) in cases {
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        let o = Options::rel(1e-7).declared();
        let p = ff.order1_p(&o);
        if name == "R 1e-8" {
            use mcrt_noise::model::moments;
            let second =
                ff.ray_total(Functional::Second, &o).unwrap().value + ff.order1_second_added(&o).unwrap().value;
            let p = p.as_ref().unwrap().value;
            let r = s.estimator.radius;
            let small_m2 =
                moments::m2(&field, &r, &o).unwrap().value + moments::m2_same_path(&field, &r, &o).unwrap().value;
            let small_p = moments::p_single(&field, &o).unwrap().value;
            let (k, k_small) = ((-ff.shift).exp(), (-field.shift).exp());
            let gaps = ((second * k) / (small_m2 * k_small) - 1.0, (p * k) / (small_p * k_small) - 1.0);
            println!("{name}: relative gaps to the small-sphere M₂, P: {gaps:?}");
            assert!(gaps.0.abs() <= 1e-6 && gaps.1.abs() <= 1e-6, "{name}: gaps {gaps:?}");
        }
        // P and Q of the uncollided light alone (closed form, cheap): Q
        // carries the same power-of-two scale as P.
        let (p0, q0) = ff.p_and_q(&o);
        let parts = [
            ("μ₁", ff.scattered_mean(&o)),
            ("M₂ added", ff.order1_second_added(&o)),
            ("P", p),
            ("P of order 0", p0),
            ("Q of order 0", q0),
        ];
        for (what, e) in parts {
            let e = e.unwrap_or_else(|err| panic!("{name}: {what}: {err}"));
            println!("{name}: {what}·e^(c₀) = {:.6e} ± {:.1e} ({} evaluations)", e.value, e.error, e.evaluations);
            assert!(e.value.is_finite() && e.value > 0.0, "{name}: {what} = {}", e.value);
            assert!(e.error <= 1e-6 * e.value, "{name}: {what}: bar {} of {}", e.error, e.value);
        }
    }
}

/// What a renderer developer gets for an order-1 scene with q = 1, N_B = 1
/// (the standard method: one sphere per camera ray, one camera ray) at
/// R = 0.2, which `predict` refused before (the small-sphere allowance is
/// measured only for R ≤ 0.1): the finite-sphere model, model bar 0, the
/// bias predicted; a right renderer (the reference tracer, 2·10⁶
/// iterations) passes `check` against it, while the small-sphere Var L
/// (1.75 % above, ~6 standard errors) sits beyond 4, past the check's own
/// limit of ~3.5: the same renderer would fail against it unless an
/// allowance excused the model. The `finite` object is pinned at 6 significant
/// digits (the bars are ≤ 10⁻⁶ of each value).
#[test]
fn library_predicts_order1_exactly_at_one_sphere_per_camera_ray() {
    use mcrt_noise::{check, predict, CheckOptions, Model, Samples};
    use rayon::prelude::*;
    let s = scene(0.2, 20, 0.8);
    let prediction = predict(&s).unwrap();
    assert_eq!(prediction.model, Model::FiniteSphere);
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0));
    assert!(prediction.bias.is_some(), "the bias of an order-1 scene is predicted");
    let finite = prediction.report.up_to_order_one().unwrap().finite.as_ref().unwrap();
    assert_eq!(finite.covers, "uncollided and single-scattered");
    for (what, v) in [("mean", prediction.mean), ("Var L", prediction.variance)] {
        assert!(v.quadrature_bar <= 1e-6 * v.value, "{what}: {v:?}");
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("finite_point-isotropic-order1-q1", common::finite_text(prediction.report.up_to_order_one().unwrap(), 6));
    });

    let tracer = Tracer::new(&s).unwrap();
    let values: Vec<f64> =
        (0..2_000_000u64).into_par_iter().map(|i| tracer.trial(31, i, HitMethod::Sorted).0).collect();
    let mut samples = Samples::new();
    samples.extend(values).unwrap();
    let verdict = check(&prediction, &samples, &CheckOptions::default());
    println!("{verdict}");
    verdict.assert_pass();
    let var = samples.variance().unwrap();
    let small = prediction.report.up_to_order_one().unwrap().variance.as_ref().unwrap().exact;
    let se = var.standard_error;
    let z_small = (var.value - small.value) / (se * se + small.error * small.error).sqrt();
    println!("small-sphere Var L {:.6e}: z {z_small:+.1} against the tracer", small.value);
    assert!(z_small.abs() > 4.0, "the small-sphere Var L is not rejected here (z = {z_small:+.2})");
}
