//! Single-scattered light of a beam (`model::beam_source`,
//! `model::finite::scattered_beam`, `docs/model.md` §9.8): the finite-sphere
//! model's μ, M₂ and P — all of Var L at q = 1, N_B = 1 — against the tracer
//! with no allowance, and against the small-sphere model as R → 0.

use mcrt_noise::oracle::{run_scoped, Precision, Report, Scope};
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light, Scene};
use std::path::Path;

mod common;

/// `beam-isotropic` (a beam of radius 0.5 crossing the camera ray at right
/// angles, σ = 1) with scattering order 1, q = 1, N_B = 1 and the given R,
/// N_F and albedo.
fn scene(radius: f64, n_f: u64, albedo: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/beam-isotropic.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
    s.estimator.radius = radius;
    s.estimator.q = 1.0;
    s.estimator.forward_rays = n_f;
    s.estimator.camera_rays = 1;
    s.medium.albedo = albedo;
    s
}

/// A value with its bar (or standard error).
#[derive(Debug, Clone, Copy)]
struct Barred(f64, f64);

/// (tracer − model)/√(se² + bar²).
fn z(tracer: Barred, model: Barred) -> f64 {
    (tracer.0 - model.0) / (tracer.1 * tracer.1 + model.1 * model.1).sqrt()
}

/// The oracle's prediction at 10⁻⁴ (its bars then stay under a tenth of
/// the tracer's standard errors here), which must be the finite-sphere
/// model's.
fn predict(s: &Scene) -> Report {
    let report = run_scoped(s, Precision::F64, Some(1e-4), Scope::Prediction).unwrap();
    assert_eq!(report.prediction.model, "finite-sphere", "{}", report.prediction.note);
    report
}

struct Point {
    name: &'static str,
    scene: Scene,
    trials: u64,
    seed: u64,
    /// Whether the small-sphere model must be rejected here (|z| > 6), with
    /// the tracer's Var L resolved to 0.3 % (issue 20's acceptance).
    rejects_small_sphere: bool,
}

/// |z| of the mean and Var L against the finite model, the small-sphere z.
fn check(p: &Point) {
    let report = predict(&p.scene);
    let mu = Barred(report.prediction.mean.value, report.prediction.mean.error);
    let var = Barred(report.prediction.variance.value, report.prediction.variance.error);
    let small = Barred(report.variance.as_ref().unwrap().exact.value, report.variance.as_ref().unwrap().exact.error);
    let t = trace(&Tracer::new(&p.scene).unwrap(), p.seed, 0..p.trials, HitMethod::Sorted, &|_| {});
    let t = t.summary().unwrap();
    let (t_mu, t_var) = (Barred(t.mean.value, t.mean.se), Barred(t.variance.value, t.variance.se));
    let (z_mu, z_var, z_small) = (z(t_mu, mu), z(t_var, var), z(t_var, small));
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
        small.0
    );
    assert!(z_mu.abs() <= 4.0 && z_var.abs() <= 4.0, "{}: the finite model disagrees with the tracer", p.name);
    if p.rejects_small_sphere {
        assert!(z_small.abs() > 6.0, "{}: the small-sphere Var L is not rejected (z = {z_small})", p.name);
        let resolution = t_var.1 / t_var.0;
        assert!(resolution <= 3e-3, "{}: Var L's standard error {resolution:.2e} exceeds 0.3 %", p.name);
    }
}

#[test]
fn tracer_agrees_with_a_beams_order1_variance() {
    let mut both = scene(0.1, 20, 0.3);
    both.lights.push(Light::Point { position: DVec3::new(0.7, 0.4, 1.6), flux: 0.5 });
    let points = [
        Point {
            name: "beam, R 0.2, N_F 20",
            scene: scene(0.2, 20, 0.8),
            trials: 4_000_000,
            seed: 31,
            rejects_small_sphere: true,
        },
        Point {
            name: "beam, R 0.5, N_F 1, albedo 1",
            scene: scene(0.5, 1, 1.0),
            trials: 4_000_000,
            seed: 32,
            rejects_small_sphere: true,
        },
        Point {
            name: "point plus beam, R 0.1, N_F 20, albedo 0.3",
            scene: both,
            trials: 2_000_000,
            seed: 33,
            rejects_small_sphere: false,
        },
    ];
    for p in &points {
        check(p);
    }
}

/// The finite-sphere mean and Var L of a beam's order-1 scene tend to the
/// small-sphere ones (the beam's fluence, an independent quadrature of the
/// same volume with the kernel e^{−σd}/d², and §3b's same-path hits) as
/// R → 0; the fitted orders of the relative gaps are printed, and must lie
/// in [1.5, 2.2] (second order for the mean; Var L's gap carries the
/// R² ln(1/R) of the same-path hits, as for a point light, §9.6).
/// (Ignored in CI for its ~2 minutes, like the other R → 0 limits.)
#[test]
#[ignore = "~2 min: the R → 0 limit at three radii (`--ignored moments_tend_to`)"]
fn a_beams_order1_moments_tend_to_the_small_sphere_ones() {
    let radii = [0.04, 0.02, 0.01];
    let gaps: Vec<(f64, f64)> = radii
        .iter()
        .map(|&r| {
            let report = predict(&scene(r, 20, 0.8));
            let gap_mean = report.prediction.mean.value / report.mean_luminance.value - 1.0;
            let gap_var = report.prediction.variance.value / report.variance.as_ref().unwrap().exact.value - 1.0;
            println!("R {r}: mean gap {gap_mean:+.4e}, Var L gap {gap_var:+.4e}");
            (gap_mean.abs(), gap_var.abs())
        })
        .collect();
    for w in gaps.windows(2) {
        let order = |a: f64, b: f64| (a / b).ln() / 2f64.ln();
        let (om, ov) = (order(w[0].0, w[1].0), order(w[0].1, w[1].1));
        println!("fitted orders: mean {om:.3}, Var L {ov:.3}");
        assert!((1.5..=2.2).contains(&om) && (1.5..=2.2).contains(&ov), "orders {om}, {ov}");
    }
}

/// Hard cases of a beam's order-1 moments in CI: μ, M₂ and P converge with
/// bars ≤ 10⁻⁶ of their values at R = 10 (the sphere holds the camera and
/// the beam's crossing), a camera ray tangent to the beam (every sphere's
/// edge across the beam's surface), and a dense medium with σ·(distance to
/// the disk) = 598, near the scene bound (600); two more, ~2.5 minutes,
/// are ignored in CI (below).
#[test]
fn a_beams_order1_moments_converge_in_hard_cases() {
    let mut cases: Vec<(&str, Scene)> = vec![("R 10", scene(10.0, 1, 0.8))];
    let mut tangent = scene(0.2, 1, 0.8);
    if let Light::Beam { center, .. } = &mut tangent.lights[0] {
        *center = DVec3::new(-2.0, 0.5, 1.0);
    }
    cases.push(("camera ray tangent to the beam", tangent));
    let mut dense = scene(0.01, 1, 0.8);
    dense.medium.sigma_ext = 290.0;
    cases.push(("σ·distance 598", dense));
    for (name, s) in cases {
        moments_converge(name, &s);
    }
}

/// The other hard cases (ignored in CI for their ~2.5 minutes: `cargo test
/// --release --test finite_order1_beams -- --ignored more_hard_cases`): R = 10⁻⁸,
/// where the prediction also agrees with the small-sphere mean and Var L
/// within their bars (the gaps are O(R² ln(1/R))), and a tilted beam at
/// σ·distance 539 behind a point light at the camera.
#[test]
#[ignore = "~2.5 min: R = 1e-8 with its prediction, and a far beam behind a light (`--ignored more_hard_cases`)"]
fn a_beams_order1_moments_converge_in_more_hard_cases() {
    let tiny = scene(1e-8, 1, 0.8);
    moments_converge("R 1e-8", &tiny);
    // The models differ by O(R² ln(1/R)) ~ 10⁻¹⁵ here: within the bars
    // of the oracle at 10⁻⁶ (the default; bars ~5·10⁻⁶ relative).
    let report = run_scoped(&tiny, Precision::F64, Some(1e-6), Scope::Prediction).unwrap();
    assert_eq!(report.prediction.model, "finite-sphere", "{}", report.prediction.note);
    let within = |finite: mcrt_noise::oracle::ValueWithBar, small: mcrt_noise::oracle::ValueWithBar| {
        let gap = (finite.value / small.value - 1.0).abs();
        (gap, finite.error / finite.value + small.error / small.value)
    };
    let gaps = [
        within(report.prediction.mean, report.mean_luminance),
        within(report.prediction.variance, report.variance.as_ref().unwrap().exact),
    ];
    println!("R 1e-8: relative gaps to the small-sphere mean, Var L (and their bars): {gaps:?}");
    assert!(gaps.iter().all(|(gap, bar)| gap <= bar), "R 1e-8: gaps {gaps:?}");
    // A point light next to the camera sets c₀ ≈ 0 while a tilted beam
    // lies at σ·distance 539: the beam's tables carry its own shift
    // (without, its values near their range's end fell below f64's range),
    // and the camera ray crosses its disk's plane ahead (graded there).
    let mut far = scene(0.01, 1, 0.8);
    far.medium.sigma_ext = 100.0;
    far.lights = vec![
        Light::Point { position: DVec3::new(0.02, 0.0, 0.03), flux: 1.0 },
        Light::Beam {
            center: DVec3::new(-1.0, 0.0, 5.8),
            direction: DVec3::new(1.0, 0.0, 0.3).normalize(),
            radius: 0.5,
            flux: 1.0,
        },
    ];
    moments_converge("a beam at σ·distance 539 behind a light at the camera", &far);
}

/// μ, M₂ and P of `s`'s order-1 finite-sphere model at 10⁻⁶: finite,
/// positive, with bars ≤ 10⁻⁶ of their values.
fn moments_converge(name: &str, s: &Scene) {
    use mcrt_noise::model::field::Field;
    use mcrt_noise::model::finite::FiniteField;
    use mcrt_noise::quad::Options;
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    let t0 = std::time::Instant::now();
    let ints = ff.order1_unpaired(&Options::rel(1e-6)).unwrap_or_else(|e| panic!("{name}: {e}"));
    for (what, e) in [("μ", &ints.mean), ("M₂", &ints.m2), ("P", &ints.p)] {
        println!("{name}: {what}·e^(c₀) = {:.6e} ± {:.1e} ({} evaluations)", e.value, e.error, e.evaluations);
        assert!(e.value.is_finite() && e.value > 0.0, "{name}: {what} = {}", e.value);
        assert!(e.error <= 1e-6 * e.value, "{name}: {what}: bar {} of {}", e.error, e.value);
    }
    println!("{name}: {:.1} s", t0.elapsed().as_secs_f64());
}

/// What a renderer developer gets for a beam's order-1 scene with q = 1,
/// N_B = 1 at R = 0.2, which `predict` refused before: the finite-sphere
/// model at the default tolerance (10⁻⁶), model bar 0, the bias predicted;
/// a right renderer (the reference tracer, 10⁶ iterations) passes `check`
/// against it, while the small-sphere Var L (8.5 % above) could not be
/// used at all. The `finite` object is pinned at 6 significant digits (the
/// bars are ≤ 10⁻⁶ of each value).
#[test]
fn library_predicts_a_beams_order1_scene_exactly() {
    use mcrt_noise::{check, predict, CheckOptions, Model, Samples};
    use rayon::prelude::*;
    let s = scene(0.2, 20, 0.8);
    let prediction = predict(&s).unwrap();
    assert_eq!(prediction.model, Model::FiniteSphere);
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0));
    assert!(prediction.bias.is_some(), "the bias of an order-1 scene is predicted");
    assert_eq!(
        prediction.report.up_to_order_one().unwrap().finite.as_ref().unwrap().covers,
        "uncollided and single-scattered"
    );
    for (what, v) in [("mean", prediction.mean), ("Var L", prediction.variance)] {
        assert!(v.quadrature_bar <= 1e-6 * v.value, "{what}: {v:?}");
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("finite_beam-isotropic-order1-q1", common::finite_text(prediction.report.up_to_order_one().unwrap(), 6));
    });
    let tracer = Tracer::new(&s).unwrap();
    let values: Vec<f64> =
        (0..1_000_000u64).into_par_iter().map(|i| tracer.trial(34, i, HitMethod::Sorted).0).collect();
    let mut samples = Samples::new();
    samples.extend(values).unwrap();
    let verdict = check(&prediction, &samples, &CheckOptions::default());
    println!("{verdict}");
    verdict.assert_pass();
}

/// `scene` with q = 0.5 and N_B = 8: (7)–(9) weigh both correlations.
fn paired_scene(radius: f64) -> Scene {
    let mut s = scene(radius, 20, 0.8);
    s.estimator.q = 0.5;
    s.estimator.camera_rays = 8;
    s
}

/// The small-sphere (23) of a beam's single-scattered light (`docs/model.md`
/// §3a: its radiance by direction, `model::beam_angular`) against the
/// finite-sphere model's share of C₂₃ that it models, one scattered segment
/// meeting both spheres (§9.11, the virtual-light average of the order-0
/// pair functional: no geometry shared), as R → 0: the relative gap must
/// fall at first order (fitted orders in [0.7, 1.3], printed). And the
/// whole Var L of both models, whose gap also holds the cross-segment
/// pairs (E10) that the small-sphere model has for point lights only: it
/// falls like R ln(1/R) (printed). `cargo test --release --test
/// finite_order1_beams -- --ignored --nocapture pairs_tend` (~4 minutes).
#[test]
#[ignore = "minutes: the finite-sphere correlations at three radii"]
fn a_beams_single_scattered_pairs_tend_to_the_small_sphere_ones() {
    use mcrt_noise::model::correlations::{exact, Which};
    use mcrt_noise::model::field::Field;
    use mcrt_noise::model::finite::{FiniteField, Functional};
    use mcrt_noise::quad::{Budget, Options};
    let opts =
        |tol: f64| Options { max_evals: 10_000_000_000, budget: Budget::new(10_000_000_000), ..Options::rel(tol) };
    let mut gaps = Vec::new();
    for r in [0.04, 0.02, 0.01] {
        let s = paired_scene(r);
        let mut uncollided = s.clone();
        uncollided.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(0);
        // Each field's values carry its own e^{c₀}.
        let small = |s: &Scene| {
            let field = Field::from_scene(s, &1.0f64).unwrap();
            let e = exact(&field, &r, Which::Eq23, &opts(1e-6)).unwrap();
            let k = (-field.shift).exp();
            (e.value * k, e.error * k)
        };
        let (all, all_bar) = small(&s);
        let (order0, order0_bar) = small(&uncollided);
        let small_one = (all - order0, all_bar + order0_bar);
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        // With the Gauss–Kronrod pair and the structure declared, as
        // `order1_integrals_weighed` runs it (a structure scan at each of
        // its levels spent 10¹⁰ evaluations at R = 0.04).
        let pair = Options { rule: mcrt_noise::quad::Rule::Kronrod, ..opts(1e-3) }.declared();
        let f = ff.order1_virtual(Functional::Pair23, &pair).unwrap();
        let k = (-ff.shift).exp();
        let finite_one = (f.value * k, f.error * k);
        let gap = small_one.0 / finite_one.0 - 1.0;
        let bar = small_one.1 / small_one.0 + finite_one.1 / finite_one.0;
        let report = run_scoped(&s, Precision::F64, Some(1e-3), Scope::FinitePairs).unwrap();
        let var_gap = report.variance.as_ref().unwrap().exact.value / report.prediction.variance.value - 1.0;
        println!(
            "R {r}: one segment, two spheres: small {:.6e} ± {:.1e}, finite {:.6e} ± {:.1e}, gap {gap:+.4e} \
             (± {bar:.1e}); Var L small/finite − 1 = {var_gap:+.4e}",
            small_one.0, small_one.1, finite_one.0, finite_one.1
        );
        assert!(gap.abs() > 3.0 * bar, "the gap must be resolved to fit its order");
        gaps.push((gap.abs(), var_gap.abs()));
    }
    for w in gaps.windows(2) {
        let order = |a: f64, b: f64| (a / b).ln() / 2f64.ln();
        let (o1, ov) = (order(w[0].0, w[1].0), order(w[0].1, w[1].1));
        println!("fitted orders: one-segment pairs {o1:.3}, Var L {ov:.3}");
        assert!((0.7..=1.3).contains(&o1), "order {o1}");
    }
}

/// Hard cases of a beam's small-sphere pair integrals (`docs/model.md` §3a,
/// q = 0.5, N_B = 8, so that (23), (24) and their R → 0 forms count): R =
/// 10, R = 10⁻⁸ and a camera ray tangent to the beam (where one of the
/// planes touching the cylinder is, at s = 0.5, the equator of the
/// directions, and the pair integrand along the ray bends where the rim's
/// directions cross it) converge at the oracle's default goal, 10⁻⁶, with
/// Var L's bar ≤ 10⁻⁶ of it. Each needs ~6·10⁸ counted evaluations but
/// more than the default budget of 10⁹ in all: given 10¹⁰. ~2 minutes.
#[test]
#[ignore = "~2 minutes: three oracle runs at 10⁻⁶"]
fn a_beams_small_sphere_pairs_converge_in_hard_cases() {
    let mut tangent = paired_scene(0.2);
    let Light::Beam { direction, radius, flux, .. } = tangent.lights[0] else { panic!("a beam") };
    tangent.lights[0] = Light::Beam { center: DVec3::new(-2.0, 0.5, 1.0), direction, radius, flux };
    for (name, s) in [("R = 10", paired_scene(10.0)), ("R = 1e-8", paired_scene(1e-8)), ("tangent", tangent)] {
        let t = std::time::Instant::now();
        let budget = mcrt_noise::quad::Budget::new(10_000_000_000);
        let report =
            mcrt_noise::oracle::run_within(&s, Precision::F64, None, &budget).unwrap_or_else(|e| panic!("{name}: {e}"));
        let var = &report.variance.as_ref().expect("the small-sphere Var L").exact;
        println!(
            "{name}: Var L {:.9e} ± {:.1e}, {} evaluations [{:.1?}]",
            var.value,
            var.error,
            report.evaluations,
            t.elapsed()
        );
        assert!(var.error <= 1e-6 * var.value, "{name}: {var:?}");
    }
}

/// A thin beam's single-scattered light in the small-sphere model
/// (`model::beam_source`, the fluence along the camera ray as a Chebyshev
/// table): radius 10⁻⁵ crossing the camera ray, R = 0.01, q = 0.5, N_B = 8,
/// the whole oracle at 10⁻⁴ within its default budget, each bar within the
/// goal. Until December 2026 the table's pieces were graded by decades
/// towards the beam's surface out to 4a only, and the fluence's ~1/p fall
/// beyond (a line source's) spanned decades in one piece: the run spent
/// the 10⁹ evaluations. It now takes 5.55·10⁸ (~45 s on two cores; the
/// count is deterministic), held under 8·10⁸ here so that a lost grading
/// shows.
#[test]
#[ignore = "~45 s: a thin beam's order-1 oracle"]
fn a_thin_beams_small_sphere_model_converges() {
    let mut s = paired_scene(0.01);
    s.estimator.forward_rays = 200;
    let Light::Beam { center, direction, flux, .. } = s.lights[0] else { panic!("a beam") };
    s.lights[0] = Light::Beam { center, direction, radius: 1e-5, flux };
    let report = mcrt_noise::oracle::run(&s, Precision::F64, Some(1e-4)).unwrap_or_else(|e| panic!("{e}"));
    let var = &report.variance.as_ref().expect("the small-sphere Var L").exact;
    let mean = &report.mean_luminance;
    println!(
        "a = 1e-5: mean {:.9e} ± {:.1e}, Var L {:.9e} ± {:.1e}, {} evaluations",
        mean.value, mean.error, var.value, var.error, report.evaluations
    );
    assert!(report.evaluations <= 800_000_000, "{} evaluations", report.evaluations);
    assert!(mean.error <= 1e-4 * mean.value, "{mean:?}");
    assert!(var.error <= 1e-4 * var.value, "{var:?}");
}
