//! The reference tracer against the oracle's prediction (release mode).
//!
//! Each point runs the real estimator M times with a fixed seed and compares
//! the ensemble mean and variance of L with the oracle's ⟨⟨L⟩⟩ and Var L:
//!
//!   |tracer − oracle| ≤ 4·√(se² + bar²) + ε(R)·|oracle|,
//!
//! se the tracer's standard error (variance: from the fourth moment), bar the
//! oracle's error bar, the prediction the library's `check::predict` (the
//! one a renderer's test gets) and ε its model bar over the value. Every
//! point is now predicted by the finite-sphere model, exact at the point's
//! R, so ε = 0 everywhere (asserted): uncollided light (order 0), and
//! single-scattered light in the isotropic medium of the two order-1
//! points, whose q < 1 makes Var L weigh the correlations of two spheres
//! (`Scope::ExactPrediction`, `docs/model.md` §9.7; until December 2026
//! these two carried the small-sphere model's measured error as ε).
//! That measurement is kept, for the small-sphere model that still serves
//! order-1 scenes the finite model does not cover (Henyey–Greenstein
//! media): |tracer/small-sphere − 1| at R = 0.1 with the order-1 points'
//! q, N_F, N_B (4·10⁷ trials), plus two standard errors, is
//! `mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE`; at the order-1
//! points the small-sphere model of the same report is also checked
//! against the tracer with that allowance carried to the point's R by
//! `prec::model_error_scale` (R ln(1/R)); the ignored test
//! `model_error_at_the_reference_radius` re-measures it
//! (`cargo test --release --test tracer_vs_oracle -- --ignored --nocapture model_error`,
//! ~3 min). More points, without any allowance, in `tests/tracer_vs_finite.rs`
//! and `tests/finite_order1*.rs`.
//! Every point also states its resolution (relative standard errors), so
//! that it cannot pass by being noisy: a point whose se exceeds its stated
//! resolution fails.

use mcrt_noise::check::{predict, Model};
use mcrt_noise::oracle::{run, Precision};
use mcrt_noise::prec::{model_error_scale, MODEL_ERROR_RADIUS};
use mcrt_noise::reports::compare::{sides, small_sphere_sides, Side};
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{Phase, ScatteringOrders, Scene};
use std::path::Path;

/// A comparison point: a bundled scene with its estimator parameters set.
struct Point {
    scene: &'static str,
    q: f64,
    radius: f64,
    forward_rays: u64,
    camera_rays: u64,
    /// Henyey–Greenstein g instead of the scene's phase function.
    hg: Option<f64>,
    trials: u64,
    /// Largest relative standard errors this point may have (mean, variance).
    resolution: (f64, f64),
    /// Order 1: measured |tracer/small-sphere − 1| + 2 se at R = 0.1 (mean,
    /// variance), and the trials of that measurement: the library's
    /// allowance for the scenes the finite model does not cover, not this
    /// point's (which is predicted by the finite model). Order 0: `None`.
    model_at_r0: Option<((f64, f64), u64)>,
}

fn scene_of(p: &Point) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{}.toml", p.scene));
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.q = p.q;
    s.estimator.radius = p.radius;
    s.estimator.forward_rays = p.forward_rays;
    s.estimator.camera_rays = p.camera_rays;
    if let Some(g) = p.hg {
        s.medium.phase = Phase::HenyeyGreenstein { g };
    }
    s
}

/// (|tracer − oracle|, allowed): the file's criterion, four standard
/// errors of the difference (the tracer's and the quadrature bar) plus the
/// model's allowance `model`.
fn gap(side: &Side, model: f64) -> (f64, f64) {
    let allowed = 4.0 * (side.tracer_se.powi(2) + side.oracle_error.powi(2)).sqrt() + model;
    ((side.tracer - side.oracle).abs(), allowed)
}

/// That the tracer resolved the point's mean and Var L as stated.
fn assert_resolved(p: &Point, mean: &Side, var: &Side) {
    let (rm, rv) = (mean.tracer_se / mean.tracer, var.tracer_se / var.tracer);
    assert!(
        rm <= p.resolution.0 && rv <= p.resolution.1,
        "{}: resolution {rm:.2e}, {rv:.2e} worse than stated",
        p.scene
    );
}

fn check(p: Point, seed: u64) {
    assert!(p.radius <= MODEL_ERROR_RADIUS);
    let scene = scene_of(&p);
    let prediction = predict(&scene).unwrap_or_else(|e| panic!("{}: predict: {e}", p.scene));
    assert_eq!(prediction.model, Model::FiniteSphere, "{}: {}", p.scene, prediction.model_bar_basis);
    let oracle = prediction.report.up_to_order_one().unwrap().clone();
    let tracer = Tracer::new(&scene).unwrap();
    let measured = trace(&tracer, seed, 0..p.trials, HitMethod::Sorted, &|_| {});
    let s = measured.summary().unwrap();
    let (mean, var) = sides(&oracle, &s);
    let order = match scene.effects.scattering_orders {
        ScatteringOrders::Limited(k) => k,
        ScatteringOrders::All => u32::MAX,
    };
    // The finite-sphere model's model bar is 0: no allowance.
    let eps = (prediction.mean.model_bar, prediction.variance.model_bar);
    assert_eq!(eps, (0.0, 0.0), "{}: a model bar", p.scene);
    assert!(oracle.finite.is_some(), "{}: no finite-sphere report", p.scene);
    let line = |name: &str, side: &Side, model: f64| {
        let (diff, allowed) = gap(side, model);
        println!(
            "{} order {order} q={} R={} NF={} NB={}: {name} ratio {:.5} z {:+.2}, |diff| {:.2e} allowed {:.2e} \
             (model {:.1e})",
            p.scene, p.q, p.radius, p.forward_rays, p.camera_rays, side.ratio, side.z, diff, allowed, model
        );
        (diff, allowed)
    };
    let (dm, am) = line("mean", &mean, eps.0);
    let (dv, av) = line("variance", &var, eps.1);
    assert!(dm <= am, "{}: mean disagrees: {mean:?}", p.scene);
    assert!(dv <= av, "{}: variance disagrees: {var:?}", p.scene);
    // The small-sphere model beside it (the same report), with the
    // allowance measured for these q, N_F, N_B at R = 0.1 and carried to
    // the point's R: the check of that carrying, which serves
    // Henyey–Greenstein media at order 1.
    if let Some(((m, v), _)) = p.model_at_r0 {
        let scale = model_error_scale(p.radius);
        let (small_mean, small_var) = small_sphere_sides(&oracle, &s).unwrap();
        let (dm, am) = line("small-sphere mean", &small_mean, m * scale * small_mean.oracle.abs());
        let (dv, av) = line("small-sphere variance", &small_var, v * scale * small_var.oracle.abs());
        assert!(dm <= am, "{}: the small-sphere mean is beyond its allowance: {small_mean:?}", p.scene);
        assert!(dv <= av, "{}: the small-sphere Var L is beyond its allowance: {small_var:?}", p.scene);
    }
    assert_resolved(&p, &mean, &var);
}

/// |tracer/oracle − 1| + 2 se at R = 0.1 for a point (mean, variance), and
/// the relative standard errors.
fn model_error_at_r0(p: &Point, trials: u64, seed: u64) -> ((f64, f64), (f64, f64)) {
    let mut scene = scene_of(p);
    scene.estimator.radius = MODEL_ERROR_RADIUS;
    let oracle = run(&scene, Precision::F64, None).unwrap();
    let tracer = Tracer::new(&scene).unwrap();
    let s = trace(&tracer, seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let rel = |o: f64, t: f64, se: f64| ((t / o - 1.0).abs() + 2.0 * se / o, se / o);
    let m = rel(oracle.mean_luminance.value, s.mean.value, s.mean.se);
    let v = rel(oracle.variance.as_ref().unwrap().exact.value, s.variance.value, s.variance.se);
    ((m.0, v.0), (m.1, v.1))
}

/// The comparison points: q ∈ {1, 0.5, 0.2}, R ∈ {0.05, 0.02}, N_F ∈ {1, 200},
/// N_B ∈ {1, 8}, orders 0 and 1, point light and beam, isotropic and HG.
fn points() -> Vec<Point> {
    let p = |scene, q, radius, forward_rays, camera_rays, trials, resolution, model_at_r0| Point {
        scene,
        q,
        radius,
        forward_rays,
        camera_rays,
        hg: None,
        trials,
        resolution,
        model_at_r0,
    };
    vec![
        p("point-isotropic", 1.0, 0.05, 200, 8, 1_000_000, (0.003, 0.01), None),
        p("point-isotropic", 0.5, 0.02, 1, 1, 30_000_000, (0.03, 0.04), None),
        p("point-hg-forward", 0.2, 0.02, 200, 1, 1_000_000, (0.01, 0.02), None),
        p("point-hg-backward", 0.5, 0.05, 1, 8, 10_000_000, (0.02, 0.03), None),
        p("beam-isotropic", 0.2, 0.02, 200, 8, 500_000, (0.005, 0.01), None),
        p("beam-isotropic", 1.0, 0.05, 1, 8, 10_000_000, (0.01, 0.02), None),
        p("point-isotropic-order1", 0.5, 0.05, 200, 8, 500_000, (0.005, 0.01), Some(((3.1e-03, 1.2e-02), 4_000_000))),
        p("point-isotropic-order1", 0.2, 0.02, 1, 1, 30_000_000, (0.03, 0.04), Some(((1.1e-02, 2.1e-02), 40_000_000))),
        p("point-hg-forward", 1.0, 0.05, 1, 1, 20_000_000, (0.03, 0.04), None),
    ]
}

fn point(k: usize) {
    let p = points().into_iter().nth(k).unwrap();
    check(p, 2026 + k as u64);
}

#[test]
fn point_0_isotropic_q1_r005_many_rays() {
    point(0);
}
#[test]
fn point_1_isotropic_q05_r002_single_rays() {
    point(1);
}
#[test]
fn point_2_hg_forward_q02_r002_one_camera_ray() {
    point(2);
}
#[test]
fn point_3_hg_backward_q05_r005_one_forward_ray() {
    point(3);
}
#[test]
fn point_4_beam_q02_r002_many_rays() {
    point(4);
}
#[test]
fn point_5_beam_q1_r005_one_forward_ray() {
    point(5);
}
#[test]
fn point_6_order1_q05_r005_many_rays() {
    point(6);
}
/// (Ignored in CI for its ~2 minutes — 3·10⁷ tracer trials and the
/// order-1 correlations: q = 0.2 with N_F = 1 is checked against the
/// tracer in CI by `finite_order1_pairs`'s second point, and the
/// small-sphere allowance against the tracer by point 6.)
#[test]
#[ignore = "~2 min: 3·10⁷ tracer trials and the order-1 correlations (`--ignored point_7`)"]
fn point_7_order1_q02_r002_single_rays() {
    point(7);
}
#[test]
fn point_8_hg_forward_q1_r005_single_rays() {
    point(8);
}

/// Re-measures the small-sphere model's error at R = 0.1 (seed 1) for every
/// point that carries one (order 1) and checks the stored constant: at least
/// the measurement, and at most 10 % + 10⁻⁴ above it (stored values are the
/// measurement rounded up to two digits).
#[test]
#[ignore = "measurement of the model-error constants, ~3 min in release mode"]
fn model_error_at_the_reference_radius() {
    let mut wrong = Vec::new();
    for (k, p) in points().iter().enumerate() {
        let Some((stored, trials)) = p.model_at_r0 else { continue };
        let (bound, se) = model_error_at_r0(p, trials, 1);
        println!(
            "point {k} {} q={} NF={} NB={}: mean {:.2e} (se {:.1e}), variance {:.2e} (se {:.1e}); stored {:?}",
            p.scene, p.q, p.forward_rays, p.camera_rays, bound.0, se.0, bound.1, se.1, stored
        );
        for (stored, measured) in [(stored.0, bound.0), (stored.1, bound.1)] {
            if !(stored >= measured && stored <= 1.1 * measured + 1e-4) {
                wrong.push(format!("point {k}: stored {stored}, measured {measured}"));
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// The correlation the model is built on, measured directly: the tracer's
/// ⟨𝒞(s)𝒞(s+t)⟩ over t-bins (2·10⁷ forward rays) against the oracle's
/// corrected (21)–(22). Pure statistics, no allowance: the chi-square of
/// the z-scores over the non-empty bins must have p ≥ 10⁻³ (at R = 0.05 the
/// model's own error is still below this resolution, `docs/tracer-checks.md`).
/// The paper's (21) as printed is half the curve at t = 0: rejected there.
#[test]
fn correlation_of_two_spheres_matches_the_corrected_model() {
    use mcrt_noise::reports::tracer_checks::{correlation_rows, CORR_RADIUS, CORR_S};
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let mut scene = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    scene.estimator.radius = CORR_RADIUS;
    let rows = correlation_rows(&scene, CORR_S, 2.4 * CORR_RADIUS, 12, 20_000_000).unwrap();
    let zs: Vec<f64> = rows
        .iter()
        .filter(|r| r.tracer.se > 0.0)
        .map(|r| (r.tracer.value - r.oracle) / (r.tracer.se.powi(2) + r.oracle_error.powi(2)).sqrt())
        .collect();
    assert!(zs.len() >= 10, "too few non-empty bins: {}", zs.len());
    let chi2: f64 = zs.iter().map(|z| z * z).sum();
    let p = 1.0 - ChiSquared::new(zs.len() as f64).unwrap().cdf(chi2);
    println!("z per bin: {zs:.2?}; chi2 = {chi2:.1} on {} bins, p = {p:.3}", zs.len());
    assert!(p >= 1e-3, "the measured correlation departs from the model: p = {p:e}");
    let first = &rows[0];
    let paper = 0.5 * first.oracle;
    assert!((first.tracer.value - paper) / first.tracer.se > 20.0, "the paper's (21) at t = 0 is not rejected");
}

/// What `predict` gives Var L of an order-1 scene in a Henyey–Greenstein
/// medium, which the finite-sphere model does not cover yet: the
/// small-sphere model with the allowance measured on an isotropic scene
/// without the cross-segment terms (which are not derived for these media);
/// its mean is the exact one (`docs/model.md` §9.9, checked here with no
/// allowance), and the small-sphere mean's allowance is checked on the
/// report's small-sphere mean. Checked
/// against the tracer where it can be resolved, g = −0.5 at R = 0.1 (the
/// allowance's own radius), q 0.5, N_F 200, N_B 8, 7·10⁶ trials (Var L to
/// 0.3 %): measured 5 December 2026, the small-sphere mean 0.52 % and Var L
/// 3.67 % below the tracer (each ± 2 se: 0.63 %, 4.30 %), within the
/// allowance (1.1 %, 4.9 %). At g = 0.9 the tracer cannot resolve Var L
/// there (22 % with 10⁶ trials: a rare photon running along the camera
/// ray hits every sphere on it near the phase function's peak), so the
/// allowance is unchecked in forward-peaked media. ~5 minutes on two
/// cores (`cargo test --release --test tracer_vs_oracle -- --ignored
/// --nocapture`).
#[test]
#[ignore = "the small-sphere allowance in a Henyey–Greenstein medium, ~5 min in release mode"]
fn the_small_sphere_allowance_holds_in_a_backward_peaked_medium() {
    let p = Point {
        scene: "point-isotropic-order1",
        q: 0.5,
        radius: MODEL_ERROR_RADIUS,
        forward_rays: 200,
        camera_rays: 8,
        hg: Some(-0.5),
        trials: 7_000_000,
        resolution: (0.001, 0.004),
        model_at_r0: None,
    };
    let scene = scene_of(&p);
    let prediction = predict(&scene).unwrap();
    assert_eq!(prediction.model, Model::SmallSphere, "{}", prediction.model_bar_basis);
    let (m, v) = mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS;
    // The prediction's mean is the exact one (`docs/model.md` §9.9); the
    // small-sphere mean's allowance is checked on the report's.
    assert_eq!(prediction.mean.model_bar, 0.0);
    let small_mean_bar = m * prediction.report.up_to_order_one().unwrap().prediction.mean.value;
    assert_eq!(prediction.variance.model_bar, v * prediction.variance.value);
    let s = trace(&Tracer::new(&scene).unwrap(), 11, 0..p.trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let (mean, var) = sides(prediction.report.up_to_order_one().unwrap(), &s);
    let z_exact =
        (s.mean.value - prediction.mean.value) / (s.mean.se.powi(2) + prediction.mean.quadrature_bar.powi(2)).sqrt();
    println!("g −0.5, R 0.1: the exact mean's z {z_exact:+.2}");
    assert!(z_exact.abs() <= 4.0, "the exact mean disagrees: z {z_exact}");
    for (name, side, model) in [("mean", &mean, small_mean_bar), ("Var L", &var, prediction.variance.model_bar)] {
        let (diff, allowed) = gap(side, model);
        println!(
            "g −0.5, R 0.1: {name} ratio {:.5} z {:+.2}, |diff| {diff:.2e} allowed {allowed:.2e}",
            side.ratio, side.z
        );
        assert!(diff <= allowed, "{name} beyond the allowance: {side:?}");
    }
    assert_resolved(&p, &mean, &var);
}

/// The library's model bar for scattered light (`check::predict`) is the
/// largest allowance measured here.
#[test]
fn the_library_model_bar_is_the_largest_measured_allowance() {
    let measured = points()
        .iter()
        .filter_map(|p| p.model_at_r0.map(|(e, _)| e))
        .fold((0.0f64, 0.0f64), |a, e| (a.0.max(e.0), a.1.max(e.1)));
    assert_eq!(measured, mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE);
}
