//! A beam's every scattering order (`docs/model.md` §10.5): the exact mean
//! at any R of scenes with a beam and `scattering_orders` ≥ 2 or `"all"`
//! (isotropic media) against the reference tracer with no allowance, its
//! small-sphere mean μ(0) as the limit of the exact one (ignored in CI),
//! hard cases (ignored), and Var L refused naming the light.

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
/// 10⁻⁴ 23 s).
fn mean(s: &Scene) -> EveryOrderMean {
    every_order_mean(s, Some(1e-4), &mcrt_noise::quad::Budget::new(2_000_000_000)).unwrap()
}

/// z of the tracer's mean against the exact one, and the tracer's
/// relative standard error.
fn tracer_z(s: &Scene, seed: u64, trials: u64) -> (f64, f64) {
    let m = mean(s);
    let summary = trace(&Tracer::new(s).unwrap(), seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let t = summary.mean;
    let z = (t.value - m.mean.value) / (t.se * t.se + m.mean.error * m.mean.error).sqrt();
    println!(
        "{:?} albedo {} R {} lights {}: exact {:.7e} ± {:.1e} (segments ≥ 2 {:.3e}, bias {:+.3e}), tracer {:.7e} ± {:.1e}: z {z:+.2}",
        s.effects.scattering_orders,
        s.medium.albedo,
        s.estimator.radius,
        s.lights.len(),
        m.mean.value,
        m.mean.error,
        m.beyond_first.value,
        m.bias.value,
        t.value,
        t.se
    );
    // Var L is not modelled with a beam: said, naming the light.
    assert!(m.variance.is_none(), "{m:?}");
    let why = m.variance_missing.as_deref().unwrap_or_default();
    assert!(why.contains("kind = \"beam\""), "{why}");
    (z, t.se / t.value)
}

/// The tracer's mean agrees with the exact mean of every order of a beam,
/// alone and beside a point light: `"all"` at albedo 0.8, R 0.2, q 0.5,
/// N_F 20, N_B 2; order 5 at albedo 0.95, R 0.05 with a point light
/// beside the beam, q 1, N_F 200; order 2 at albedo 0.5, R 0.2, N_F 1;
/// `"all"` with a beam of radius 0.3 running beside the camera ray, 1
/// from it (far down it most of the light comes from the disk, not from
/// the beam's nearest part: the shells' cut must reach past the disk;
/// before it did, the bar was e^{700}): |z| ≤ 4, no allowance, each at a
/// standard error below 1 %.
#[test]
fn the_tracer_agrees_with_a_beams_exact_mean_of_every_order() {
    use ScatteringOrders::{All, Limited};
    let alone = beam_scene(All, 0.8, 0.2, (0.5, 20, 2));
    let mut beside = beam_scene(Limited(5), 0.95, 0.05, (1.0, 200, 1));
    beside.lights.push(Light::Point { position: DVec3::new(1.0, 0.0, 1.0), flux: 1.0 });
    let low = beam_scene(Limited(2), 0.5, 0.2, (1.0, 1, 1));
    let mut parallel = beam_scene(All, 0.8, 0.2, (1.0, 20, 1));
    parallel.lights = vec![Light::Beam {
        center: DVec3::new(1.0, 0.0, -0.5),
        direction: DVec3::new(0.0, 0.0, 1.0),
        radius: 0.3,
        flux: 1.0,
    }];
    let points = [(alone, 51, 300_000), (beside, 52, 100_000), (low, 53, 1_000_000), (parallel, 54, 1_000_000)];
    for (s, seed, trials) in points {
        let (z, rel_se) = tracer_z(&s, seed, trials);
        assert!(rel_se < 0.01, "the tracer's se {rel_se:e} is too wide to test anything");
        assert!(z.abs() <= 4.0, "{:?}: z = {z}", s.effects.scattering_orders);
    }
}

/// Var L of a beam's every order is not modelled: `predict` refuses the
/// scene before any integral, naming the light and the fields, and
/// `optimize` does not search it with the standard method's exact model.
#[test]
fn a_beams_var_l_of_every_order_is_refused_naming_the_light() {
    let mut s = beam_scene(ScatteringOrders::All, 0.8, 0.2, (1.0, 20, 1));
    s.lights.insert(0, Light::Point { position: DVec3::new(1.0, 0.0, 1.0), flux: 1.0 });
    let started = std::time::Instant::now();
    let err = mcrt_noise::predict(&s).unwrap_err().to_string();
    println!("{err}");
    assert!(err.contains("lights[1] (kind = \"beam\")") && err.contains("scattering_orders"), "{err}");
    assert!(started.elapsed().as_secs_f64() < 5.0, "refused only after {:?}", started.elapsed());
    assert!(!mcrt_noise::oracle::finite_sphere_covers_the_standard_method(&s));
}

/// Hard cases of a beam's every order finish within the default budget,
/// with a result within its bars or an honest NOT CONVERGED: albedo 0.99
/// (the diffusion mode decays over ~6 free paths, so the shells run ~300
/// of them; a result), a beam 300 free paths from the camera ray (its
/// light reaches the ray through the orders ≥ 2 alone at "all"; a result,
/// ~10⁻⁹⁸), and R = 10 (the sphere holds the camera and the beam's start:
/// G′'s bracket about d = R leaves its volume integrals' samples a bar of
/// 1.3·10⁻¹⁰ against their goal of 1.25·10⁻¹⁰, so NOT CONVERGED, said, in
/// ~40 s). Ignored in CI (~100 s): `cargo test --release --test
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
        let budget = mcrt_noise::quad::Budget::new(mcrt_noise::quad::DEFAULT_EVALUATIONS);
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
            &beam_scene(ScatteringOrders::Limited(2), 0.8, r, (1.0, 1, 1)),
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
