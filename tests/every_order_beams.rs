//! A beam's every scattering order (`docs/model.md` §10.5, §10.6): the
//! exact mean at any R of scenes with a beam and `scattering_orders` ≥ 2
//! or `"all"` (isotropic media), and at q = 1 and N_B = 1 its exact Var L
//! with the same-path pairs of the beam's paths, against the reference
//! tracer with no allowance; its small-sphere mean μ(0) as the limit of
//! the exact one (ignored in CI), hard cases (ignored).

use mcrt_noise::oracle::{every_order_mean, EveryOrderMean};
use mcrt_noise::{ScatteringOrders, Scene};
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light};
use std::path::Path;

/// The bundled `beam-isotropic` scene (σ = 1, a beam of radius 0.5 from
/// (−2, 0, 1) along x, crossing the camera ray at right angles) with the
/// given orders, albedo, R, q, N_F and N_B.
fn beam_scene(orders: ScatteringOrders, albedo: f64, radius: f64, (q, forward, camera): (f64, u64, u64)) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/beam-isotropic.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.effects.scattering_orders = orders;
    s.medium.albedo = albedo;
    s.estimator.radius = radius;
    s.estimator.q = q;
    s.estimator.forward_rays = forward;
    s.estimator.camera_rays = camera;
    s
}

/// The exact mean at 10⁻⁴ (its bar far below the tracer's standard errors
/// of ~0.2–0.8 %; at the default 10⁻⁶ a beam's `"all"` takes 42 s, at
/// 10⁻⁴ 23 s) and, at q = 1 and N_B = 1, Var L (a beam's `"all"` ~30 s
/// more, its order 5 beside a point light ~70 s).
fn mean(s: &Scene) -> EveryOrderMean {
    every_order_mean(s, Some(1e-4), &mcrt_noise::quad::Budget::new(2_000_000_000)).unwrap()
}

/// One tracer estimate against the exact value: z (no allowance) and the
/// tracer's relative standard error.
struct Agreement {
    z: f64,
    rel_se: f64,
}

/// z of the tracer's mean against the exact one and, at q = 1 and
/// N_B = 1 (where the oracle has it), of its Var L against the exact one
/// and against that Var L without the same-path pairs (what the paper's
/// structure would give, §10.3, §10.6): (mean, Var L, Var L less its
/// pairs).
fn tracer_z(s: &Scene, seed: u64, trials: u64) -> (Agreement, Option<(Agreement, f64)>) {
    let m = mean(s);
    let summary = trace(&Tracer::new(s).unwrap(), seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let z_of = |t: &mcrt_reference::moments::WithError, exact: f64, bar: f64| {
        (t.value - exact) / (t.se * t.se + bar * bar).sqrt()
    };
    let t = &summary.mean;
    let z = z_of(t, m.mean.value, m.mean.error);
    println!(
        "{:?} albedo {} R {} lights {} N_F {}: exact {:.7e} ± {:.1e} (segments ≥ 2 {:.3e}, bias {:+.3e}), tracer {:.7e} ± {:.1e}: z {z:+.2}",
        s.effects.scattering_orders,
        s.medium.albedo,
        s.estimator.radius,
        s.lights.len(),
        s.estimator.forward_rays,
        m.mean.value,
        m.mean.error,
        m.beyond_first.value,
        m.bias.value,
        t.value,
        t.se
    );
    let mean = Agreement { z, rel_se: t.se / t.value };
    let modelled = s.estimator.q == 1.0 && s.estimator.camera_rays == 1;
    if !modelled {
        assert!(m.variance.is_none(), "{m:?}");
        let why = m.variance_missing.as_deref().unwrap_or_default();
        assert!(why.contains("correlations of two spheres of every order"), "{why}");
        return (mean, None);
    }
    let (v, pairs) = (m.variance.expect("Var L at q = 1, N_B = 1"), m.same_path_pairs.expect("the pairs"));
    let t = &summary.variance;
    let z = z_of(t, v.value, v.error);
    let without = v.value - pairs.value / s.estimator.forward_rays as f64;
    let z_without = z_of(t, without, v.error);
    println!(
        "  Var L exact {:.7e} ± {:.1e} (pairs in M₂ {:.3e}), tracer {:.7e} ± {:.1e}: z {z:+.2}; without the pairs z {z_without:+.1}",
        v.value, v.error, pairs.value, t.value, t.se
    );
    (mean, Some((Agreement { z, rel_se: t.se / t.value }, z_without)))
}

/// The tracer's mean and (at q = 1, N_B = 1) Var L agree with the exact
/// ones of every order of a beam, alone and beside a point light: `"all"`
/// at albedo 0.8, R 0.2, q 0.5, N_F 20, N_B 2 (the mean; Var L not
/// modelled, said); order 5 at albedo 0.95, R 0.05 with a point light
/// beside the beam, q 1, N_F 200; order 2 at albedo 0.5, R 0.2, N_F 1;
/// `"all"` with a beam of radius 0.3 running beside the camera ray, 1
/// from it (far down it most of the light comes from the disk, not from
/// the beam's nearest part: the shells' cut must reach past the disk;
/// before it did, the bar was e^{700}), N_F 20: |z| ≤ 4, no allowance,
/// each at a standard error below 1 % (Var L's: below 2 %), and Var L
/// without the same-path pairs rejected (|z| > 4) at each.
#[test]
fn the_tracer_agrees_with_a_beams_exact_mean_of_every_order() {
    use ScatteringOrders::{All, Limited};
    let alone = beam_scene(All, 0.8, 0.2, (0.5, 20, 2));
    let mut beside = beam_scene(Limited(5), 0.95, 0.05, (1.0, 200, 1));
    beside.lights.push(Light::Point { position: DVec3::new(1.0, 0.0, 1.0), flux: 1.0 });
    // 4·10⁷ trials (~8 s): Var L's se 0.2 %, so that a K_G of the wrong
    // level for the beam's ray (G = H alone at order 2) would not pass.
    let low = beam_scene(Limited(2), 0.5, 0.2, (1.0, 1, 1));
    let mut parallel = beam_scene(All, 0.8, 0.2, (1.0, 20, 1));
    parallel.lights = vec![Light::Beam {
        center: DVec3::new(1.0, 0.0, -0.5),
        direction: DVec3::new(0.0, 0.0, 1.0),
        radius: 0.3,
        flux: 1.0,
    }];
    let points = [(alone, 51, 300_000), (beside, 52, 100_000), (low, 53, 40_000_000), (parallel, 54, 1_000_000)];
    for (s, seed, trials) in points {
        let (mean, variance) = tracer_z(&s, seed, trials);
        assert!(mean.rel_se < 0.01, "the tracer's se {:e} is too wide to test anything", mean.rel_se);
        assert!(mean.z.abs() <= 4.0, "{:?}: z = {}", s.effects.scattering_orders, mean.z);
        if let Some((v, z_without)) = variance {
            assert!(v.rel_se < 0.02, "the tracer's se of Var L {:e} is too wide to test anything", v.rel_se);
            assert!(v.z.abs() <= 4.0, "{:?}: Var L's z = {}", s.effects.scattering_orders, v.z);
            assert!(z_without.abs() > 4.0, "{:?}: without the pairs z = {z_without}", s.effects.scattering_orders);
        }
    }
}

/// Var L of a beam's every order counts the same-path pairs of its paths
/// (§10.6: the beam ray with any later segment through K_G, two later
/// segments through the pair sum of the fresh path at the ray's first
/// scattering): at N_F = 1, where they weigh most, `"all"` at albedo 0.8,
/// R 0.2 (pairs ~17 % of Var L) and order 3 beside a point light (the
/// finite levels of the fresh path) agree with the tracer at |z| ≤ 4 with a
/// standard error of Var L below 0.8 %, and Var L without the pairs is
/// rejected (|z| > 8): the test can tell. `optimize` searches such a
/// scene with the exact model (`predict` and `check`:
/// `library_predicts_and_checks_a_beams_every_order_scene`).
#[test]
fn a_beams_var_l_of_every_order_counts_its_same_path_pairs() {
    use ScatteringOrders::{All, Limited};
    let alone = beam_scene(All, 0.8, 0.2, (1.0, 1, 1));
    let mut beside = beam_scene(Limited(3), 0.8, 0.2, (1.0, 1, 1));
    beside.lights.insert(0, Light::Point { position: DVec3::new(1.0, 0.0, 1.0), flux: 1.0 });
    for (s, seed, trials) in [(alone, 61, 20_000_000), (beside, 62, 4_000_000)] {
        let (mean, variance) = tracer_z(&s, seed, trials);
        let (v, z_without) = variance.expect("Var L at q = 1, N_B = 1");
        assert!(mean.z.abs() <= 4.0, "{:?}: z = {}", s.effects.scattering_orders, mean.z);
        assert!(v.rel_se < 0.008, "the tracer's se of Var L {:e} is too wide", v.rel_se);
        assert!(v.z.abs() <= 4.0, "{:?}: Var L's z = {}", s.effects.scattering_orders, v.z);
        assert!(z_without.abs() > 8.0, "{:?}: without the pairs z = {z_without}", s.effects.scattering_orders);
    }
    assert!(mcrt_noise::oracle::finite_sphere_covers_the_standard_method(&beam_scene(All, 0.8, 0.2, (1.0, 20, 1))));
}

/// What a renderer developer gets for a beam's scene of every order at
/// q = 1, N_B = 1, which `predict` refused before (§10.6): the
/// finite-sphere model, model bars 0, the bias predicted; a right renderer
/// (the reference tracer, 2·10⁵ iterations) passes `check`, and one that
/// averages pairs of its iterations (mean right, Var L halved) fails it.
#[test]
fn library_predicts_and_checks_a_beams_every_order_scene() {
    use mcrt_noise::check::{check, predict_with, CheckOptions, Samples, Status};
    use mcrt_noise::oracle::Precision;
    use rayon::prelude::*;
    let s = beam_scene(ScatteringOrders::All, 0.8, 0.2, (1.0, 20, 1));
    let prediction = predict_with(&s, Precision::F64, Some(1e-4)).unwrap();
    assert_eq!(prediction.model, mcrt_noise::Model::FiniteSphere);
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0));
    assert!(prediction.bias.is_some(), "the bias of every order is predicted");
    let tracer = Tracer::new(&s).unwrap();
    let values: Vec<f64> = (0..200_000u64).into_par_iter().map(|i| tracer.trial(63, i, HitMethod::Sorted).0).collect();
    let mut samples = Samples::new();
    samples.extend(values.iter().copied()).unwrap();
    let verdict = check(&prediction, &samples, &CheckOptions::default());
    println!("{verdict}");
    verdict.assert_pass();
    let mut halved = Samples::new();
    halved.extend(values.chunks(2).map(|p| 0.5 * (p[0] + p[1]))).unwrap();
    let verdict = check(&prediction, &halved, &CheckOptions::default());
    println!("{verdict}");
    assert_eq!(verdict.status, Status::Fail, "{verdict}");
}

/// Hard cases of a beam's every order finish within the budget of every
/// order (3·10⁹, `prec::EVERY_ORDER_PREDICTION_EVALUATIONS`), with a
/// result within its bars or an honest NOT CONVERGED, the mean and (q = 1,
/// N_B = 1) Var L (§10.6: albedo 0.99 and the far beam give it): albedo 0.99
/// (the diffusion mode decays over ~6 free paths, so the shells run ~300
/// of them; a result), a beam 300 free paths from the camera ray (its
/// light reaches the ray through the orders ≥ 2 alone at "all"; a result,
/// ~10⁻⁹⁸), and R = 10 (the sphere holds the camera and the beam's start:
/// G′'s bracket about d = R leaves its volume integrals' samples a bar of
/// 1.3·10⁻¹⁰ against their goal of 1.25·10⁻¹⁰, so NOT CONVERGED, said, in
/// ~40 s). Ignored in CI (~150 s): `cargo test --release --test
/// every_order_beams -- --ignored hard_cases`.
#[test]
#[ignore]
fn hard_cases_of_a_beams_every_order_finish() {
    use ScatteringOrders::All;
    let mut far = beam_scene(All, 0.8, 0.2, (1.0, 20, 1));
    far.lights = vec![Light::Beam {
        center: DVec3::new(-300.0, 0.0, 1.0),
        direction: DVec3::new(-1.0, 0.0, 0.0),
        radius: 0.5,
        flux: 1.0,
    }];
    for (s, what, converges) in [
        (beam_scene(All, 0.99, 0.2, (1.0, 20, 1)), "albedo 0.99", true),
        (far, "a beam 300 free paths away", true),
        (beam_scene(All, 0.8, 10.0, (1.0, 20, 1)), "R 10", false),
    ] {
        let started = std::time::Instant::now();
        // The budget `mcrt-noise oracle` and `predict` give every order.
        let budget = mcrt_noise::quad::Budget::new(mcrt_noise::prec::EVERY_ORDER_PREDICTION_EVALUATIONS);
        match every_order_mean(&s, None, &budget) {
            Ok(m) => {
                println!(
                    "{what}: {:.6e} ± {:.1e} (segments ≥ 2 {:.3e}), bias {:+.3e}, {} evaluations, {:.1?}",
                    m.mean.value,
                    m.mean.error,
                    m.beyond_first.value,
                    m.bias.value,
                    m.evaluations,
                    started.elapsed()
                );
                assert!(m.mean.value > 0.0 && m.mean.error <= 1e-6 * m.mean.value, "{what}: {m:?}");
                assert!(m.small_sphere_mean.error <= 1e-6 * m.small_sphere_mean.value, "{what}: {m:?}");
                // Var L (q = 1, N_B = 1, §10.6): a result within 10⁻⁴, or
                // an honest NOT CONVERGED or spent budget, said.
                match (&m.variance, &m.variance_missing) {
                    (Some(v), _) => {
                        println!("  Var L {:.6e} ± {:.1e}", v.value, v.error);
                        assert!(v.value > 0.0 && v.error <= 1e-4 * v.value, "{what}: {m:?}");
                    }
                    (None, Some(why)) => {
                        println!("  Var L: {why}");
                        assert!(!converges, "{what}: Var L {why}");
                        assert!(why.contains("NOT CONVERGED") || why.contains("budget"), "{what}: {why}");
                    }
                    (None, None) => panic!("{what}: neither Var L nor why not"),
                }
            }
            Err(e) => {
                println!("{what}: {e} ({:.1?})", started.elapsed());
                assert!(!converges, "{what}: {e}");
                assert!(matches!(e, mcrt_noise::model::OracleError::Quadrature { .. }), "{what}: {e}");
                assert!(e.to_string().contains("NOT CONVERGED"), "{what}: {e}");
            }
        }
    }
}

/// The beam's small-sphere mean μ(0) of every order is the limit of its
/// exact mean: order 2 on `beam-isotropic` (albedo 0.8) at R = 0.2, 0.1,
/// 0.05, the bias b(R) = μ(R) − μ(0) fitted by cR² + dR⁴ + ε leaves ε
/// within 10⁻⁵ of μ(0) (measured 7 December 2026: ε = −1.5·10⁻⁹, 2·10⁻⁷
/// of the mean; a wrong prefactor or density in μ(0)'s segments ≥ 2,
/// 15 % of it, would leave ~10⁻¹), and the biases shrink about fourfold
/// as R halves. Ignored in CI (~2 min): `cargo test --release --test
/// every_order_beams -- --ignored small_sphere`.
#[test]
#[ignore]
fn a_beams_small_sphere_mean_is_the_limit_of_the_exact_one() {
    let at = |r: f64| {
        let m = every_order_mean(
            // q 0.5: the mean alone (no Var L to compute).
            &beam_scene(ScatteringOrders::Limited(2), 0.8, r, (0.5, 1, 1)),
            None,
            &mcrt_noise::quad::Budget::new(2_000_000_000),
        )
        .unwrap();
        println!(
            "R {r}: bias {:+.10e} ± {:.1e} of μ(0) {:.10e}",
            m.bias.value, m.bias.error, m.small_sphere_mean.value
        );
        (m.bias.value, m.small_sphere_mean.value)
    };
    let (radii, mut bias, mut small) = ([0.2f64, 0.1, 0.05], [0.0; 3], 0.0);
    for (i, r) in radii.iter().enumerate() {
        (bias[i], small) = at(*r);
    }
    // b = cR² + dR⁴ + ε through the three points (Cramer's rule).
    let rows = radii.map(|r| [r * r, r.powi(4), 1.0]);
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let mut last = rows;
    for (row, b) in last.iter_mut().zip(bias) {
        row[2] = b;
    }
    let epsilon = det(last) / det(rows);
    println!(
        "ε = {epsilon:+.3e} ({:+.2e} of μ(0)); ratios {:.3}, {:.3}",
        epsilon / small,
        bias[0] / bias[1],
        bias[1] / bias[2]
    );
    assert!(epsilon.abs() <= 1e-5 * small, "ε = {epsilon:e}");
    for pair in bias.windows(2) {
        assert!((3.5..4.5).contains(&(pair[0] / pair[1])), "{bias:?}");
    }
}

/// The finite field's public small-sphere mean of every order covers point
/// lights: with a beam it refuses, naming where a beam's μ(0) is (it
/// would otherwise return the beam's segments ≥ 2 alone).
#[test]
fn the_finite_fields_small_sphere_mean_refuses_a_beam() {
    use mcrt_noise::model::field::Field;
    use mcrt_noise::model::finite::FiniteField;
    let first = beam_scene(ScatteringOrders::Limited(1), 0.8, 0.2, (1.0, 1, 1));
    let field = Field::from_scene(&first, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(&first, &field);
    let err =
        ff.small_sphere_mean_every_order(ScatteringOrders::All, &mcrt_noise::quad::Options::rel(1e-6)).unwrap_err();
    assert!(err.to_string().contains("every_order_mean"), "{err}");
}
