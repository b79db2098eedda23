//! Every scattering order (`docs/model.md` §10): the exact mean at any R of
//! scenes with `scattering_orders` ≥ 2 or `"all"` (isotropic media, point
//! lights), against the reference tracer with no allowance, and the
//! small-sphere mean of every order against an independent route.

use mcrt_noise::oracle::{every_order_mean, EveryOrderMean};
use mcrt_noise::{ScatteringOrders, Scene};
use mcrt_reference::{trace, HitMethod, Tracer};
use std::path::Path;

/// The README scene (`point-isotropic`: σ = 1, light (1, 0, 1), camera at
/// the origin along z) with the given orders, albedo and R.
fn scene(orders: ScatteringOrders, albedo: f64, radius: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.effects.scattering_orders = orders;
    s.medium.albedo = albedo;
    s.estimator.radius = radius;
    s.estimator.forward_rays = 20;
    s.estimator.camera_rays = 2;
    s
}

fn mean(s: &Scene) -> EveryOrderMean {
    every_order_mean(s, None, &mcrt_noise::quad::Budget::new(2_000_000_000)).unwrap()
}

/// (z of the tracer against the exact mean, z against the small-sphere
/// mean, the tracer's relative se); where the oracle has Var L (q = 1,
/// N_B = 1) its z against the tracer's too, asserted within 4 (no
/// allowance).
fn tracer_z(s: &Scene, seed: u64, trials: u64) -> (f64, f64, f64) {
    let m = mean(s);
    let summary = trace(&Tracer::new(s).unwrap(), seed, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let t = summary.mean;
    let z = (t.value - m.mean.value) / (t.se * t.se + m.mean.error * m.mean.error).sqrt();
    let z_small = (t.value - m.small_sphere_mean.value) / (t.se * t.se + m.small_sphere_mean.error.powi(2)).sqrt();
    println!(
        "{:?} albedo {} R {}: exact {:.7e} ± {:.1e} (bias {:+.3e}), tracer {:.7e} ± {:.1e}: z {z:+.2}, small-sphere z {z_small:+.1}",
        s.effects.scattering_orders, s.medium.albedo, s.estimator.radius, m.mean.value, m.mean.error, m.bias.value, t.value, t.se
    );
    let modelled = s.estimator.q == 1.0 && s.estimator.camera_rays == 1;
    assert_eq!(m.variance.is_some(), modelled, "Var L at q = 1, N_B = 1 only: {:?}", m.variance_missing);
    if let Some(v) = m.variance {
        let tv = summary.variance;
        let z_var = (tv.value - v.value) / (tv.se * tv.se + v.error * v.error).sqrt();
        println!(
            "  Var L exact {:.7e} ± {:.1e}, tracer {:.7e} ± {:.1e}: z {z_var:+.2}",
            v.value, v.error, tv.value, tv.se
        );
        assert!(z_var.abs() <= 4.0, "{:?}: Var L z = {z_var}", s.effects.scattering_orders);
    }
    (z, z_small, t.se / t.value)
}

/// One point of the grid: orders, albedo, R, q, N_F, N_B, the lights'
/// positions (flux 1 each), trials, seed, and whether the small-sphere
/// mean must be rejected there.
struct Point {
    orders: ScatteringOrders,
    albedo: f64,
    radius: f64,
    q: f64,
    forward: u64,
    camera: u64,
    lights: &'static [[f64; 3]],
    trials: u64,
    seed: u64,
    /// Whether the tracer must reject the small-sphere mean here.
    rejects_small_sphere: bool,
}

impl Point {
    fn scene(&self) -> Scene {
        let mut s = scene(self.orders, self.albedo, self.radius);
        s.estimator.q = self.q;
        s.estimator.forward_rays = self.forward;
        s.estimator.camera_rays = self.camera;
        s.lights = self
            .lights
            .iter()
            .map(|&[x, y, z]| mcrt_scene::Light::Point { position: mcrt_scene::DVec3::new(x, y, z), flux: 1.0 })
            .collect();
        s
    }
}

/// The tracer's mean agrees with the exact mean of every order at each
/// point of a grid covering orders 2, 3, 5 and "all", albedo 0.5, 0.8,
/// 0.95 and 1 (order 3), R 0.2 and 0.05, q 1 and 0.5, N_F and N_B from 1
/// to 200, one and two lights, a light 0.1 from the camera line: |z| ≤ 4,
/// no allowance; at the four points with q = 1 and N_B = 1 (`"all"`,
/// orders 5, 2 and 3) Var L too. (The points are independent, a point's
/// mean and Var L from the same run: by chance any one of the thirteen z
/// has |z| > 4 with probability at most about 8·10⁻⁴.)
#[test]
fn the_tracer_agrees_with_the_exact_mean_of_every_order() {
    use ScatteringOrders::{All, Limited};
    const README: &[[f64; 3]] = &[[1.0, 0.0, 1.0]];
    let points = [
        Point {
            orders: All,
            albedo: 0.8,
            radius: 0.2,
            q: 0.5,
            forward: 20,
            camera: 2,
            lights: README,
            trials: 400_000,
            seed: 21,
            rejects_small_sphere: false,
        },
        Point {
            orders: All,
            albedo: 0.8,
            radius: 0.05,
            q: 1.0,
            forward: 200,
            camera: 1,
            lights: README,
            trials: 100_000,
            seed: 22,
            rejects_small_sphere: false,
        },
        Point {
            orders: Limited(2),
            albedo: 0.5,
            radius: 0.2,
            q: 0.5,
            forward: 200,
            camera: 8,
            lights: README,
            trials: 300_000,
            seed: 23,
            rejects_small_sphere: true,
        },
        Point {
            orders: Limited(5),
            albedo: 0.95,
            radius: 0.05,
            q: 1.0,
            forward: 200,
            camera: 1,
            lights: README,
            trials: 100_000,
            seed: 24,
            rejects_small_sphere: false,
        },
        Point {
            orders: All,
            albedo: 0.95,
            radius: 0.2,
            q: 0.5,
            forward: 50,
            camera: 200,
            lights: README,
            trials: 40_000,
            seed: 25,
            rejects_small_sphere: false,
        },
        Point {
            orders: Limited(5),
            albedo: 0.8,
            radius: 0.2,
            q: 1.0,
            forward: 20,
            camera: 4,
            lights: &[[1.0, 0.0, 1.0], [-0.5, 0.4, 2.0]],
            trials: 200_000,
            seed: 26,
            rejects_small_sphere: false,
        },
        Point {
            orders: All,
            albedo: 0.5,
            radius: 0.05,
            q: 0.5,
            forward: 20,
            camera: 2,
            lights: &[[0.1, 0.0, 1.0]],
            trials: 400_000,
            seed: 27,
            rejects_small_sphere: false,
        },
        Point {
            orders: Limited(2),
            albedo: 0.8,
            radius: 0.2,
            q: 1.0,
            forward: 1,
            camera: 1,
            lights: README,
            trials: 2_000_000,
            seed: 28,
            rejects_small_sphere: false,
        },
        // Albedo 1: a finite order ends every path after its last
        // scattering (only "all" needs albedo < 1), and optimize searches
        // such scenes.
        Point {
            orders: Limited(3),
            albedo: 1.0,
            radius: 0.2,
            q: 1.0,
            forward: 1,
            camera: 1,
            lights: README,
            trials: 2_000_000,
            seed: 29,
            rejects_small_sphere: false,
        },
    ];
    for p in &points {
        let (z, z_small, rel_se) = tracer_z(&p.scene(), p.seed, p.trials);
        assert!(rel_se < 0.01, "{:?}: the tracer's se {rel_se:e} is too wide to test anything", p.orders);
        assert!(z.abs() <= 4.0, "{:?} albedo {} R {}: z = {z}", p.orders, p.albedo, p.radius);
        // At orders ≤ 2, albedo 0.5, R = 0.2 the bias (1.2 %) is 11 standard
        // errors: the small-sphere mean must be rejected there.
        if p.rejects_small_sphere {
            assert!(z_small > 6.0, "the small-sphere mean is not rejected: z = {z_small}");
        }
    }
}

/// The small-sphere mean of every order, by the cut and pole of
/// `start_density` (docs/model.md §10.1), against two independent routes:
/// orders ≤ 1 against the small-sphere model of §3a (L₁ integrated over
/// directions, `model::moments`), and every order against
/// `scripts/all-orders-mean.py` (mpmath's inverse sine transforms of the
/// resummed (aĉ₁)²/(1 − aĉ₁), 6 December 2026: 4.663214054·10⁻³, ten
/// digits, no bar, so 2·10⁻¹⁰ relative is allowed beside ours).
#[test]
fn the_small_sphere_mean_of_every_order_agrees_with_independent_routes() {
    use mcrt_noise::model::field::Field;
    use mcrt_noise::model::finite::FiniteField;
    use mcrt_noise::model::moments::mean_luminance;
    use mcrt_noise::quad::Options;
    let o = Options::rel(1e-9).declared();
    let s1 = scene(ScatteringOrders::Limited(1), 0.8, 0.01);
    let field = Field::from_scene(&s1, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(&s1, &field);
    let ours = ff.small_sphere_mean_every_order(ScatteringOrders::Limited(1), &o).unwrap();
    let theirs = mean_luminance(&field, &Options::rel(1e-9)).unwrap();
    let k = (-ff.shift).exp();
    let (a, b) = (ours.value * k, theirs.value * (-field.shift).exp());
    let bar = ours.error * k + theirs.error * (-field.shift).exp();
    println!("orders <= 1: cut {a:.12e}, L1 route {b:.12e} (± {bar:.1e})");
    assert!((a - b).abs() <= bar + 1e-14 * a, "orders <= 1: {a:e} vs {b:e}");
    let all = ff.small_sphere_mean_every_order(ScatteringOrders::All, &o).unwrap();
    let (v, e) = (all.value * k, all.error * k);
    println!("every order: {v:.12e} ± {e:.1e} (mpmath prototype 4.663214054e-3)");
    assert!((v - 4.663214054e-3).abs() <= e + 2e-10 * v + 0.5e-12, "every order: {v:e}");
}

/// Orders n → ∞ converge to "all": the exact means of orders 2..=9 at
/// R = 0.2 rise towards every order's, each gap below the flux the orders
/// beyond n carry times the largest per-flux mean an order has had
/// (a^{n+1}/(1 − a) · max_j μ_j/a^j, a bound the data justify, not a
/// theorem), and order 9's within 3·10⁻⁴ of every order's at albedo 0.5.
#[test]
fn finite_orders_converge_to_every_order() {
    let a = 0.5;
    let all = mean(&scene(ScatteringOrders::All, a, 0.2));
    let mut previous = mean(&scene(ScatteringOrders::Limited(2), a, 0.2)).mean.value;
    let mut worst_share = 0.0f64;
    for n in 3..=9u32 {
        let m = mean(&scene(ScatteringOrders::Limited(n), a, 0.2));
        let order_n = m.mean.value - previous;
        worst_share = worst_share.max(order_n / a.powi(n as i32));
        let gap = all.mean.value - m.mean.value;
        let bound = a.powi(n as i32 + 1) / (1.0 - a) * worst_share;
        println!("order {n}: {:.10e} ± {:.1e}, gap to all {gap:.3e}, bound {bound:.3e}", m.mean.value, m.mean.error);
        assert!(m.mean.value > previous, "order {n} adds nothing");
        assert!(gap > -(all.mean.error + m.mean.error) && gap <= bound, "order {n}: gap {gap:e}, bound {bound:e}");
        previous = m.mean.value;
    }
    assert!((all.mean.value - previous) / all.mean.value < 3e-4);
}

/// σ-scaling: with σ multiplied by 3 and every length divided by 3 (the
/// light's position and R) the geometry in free paths is the same, and the
/// mean, which carries 1/(πR²), is 9 times the original, within the bars.
#[test]
fn the_mean_scales_with_the_medium() {
    for orders in [ScatteringOrders::All, ScatteringOrders::Limited(3)] {
        let base = scene(orders, 0.8, 0.2);
        let mut scaled = base.clone();
        scaled.medium.sigma_ext = 3.0;
        scaled.estimator.radius = 0.2 / 3.0;
        scaled.lights =
            vec![mcrt_scene::Light::Point { position: mcrt_scene::DVec3::new(1.0 / 3.0, 0.0, 1.0 / 3.0), flux: 1.0 }];
        let (m, k) = (mean(&base), mean(&scaled));
        for (what, a, b) in [
            ("mean", m.mean, k.mean),
            ("small-sphere", m.small_sphere_mean, k.small_sphere_mean),
            ("beyond", m.beyond_first, k.beyond_first),
        ] {
            let off = (b.value - 9.0 * a.value).abs();
            println!("{orders:?} {what}: {:.12e} vs 9 × {:.12e}, off {off:.1e}", b.value, a.value);
            assert!(off <= b.error + 9.0 * a.error + 1e-14 * b.value, "{orders:?} {what}: {b:?} vs 9 × {a:?}");
        }
    }
}

/// Hard cases finish with a result within their bars: albedo 0.999 (the
/// diffusion mode decays over 18 free paths), R = 10 (the sphere holds the
/// light and the camera), R = 10⁻⁶ at order 9, and a light 500 free paths
/// away (σ·distance 500; the mean ~10⁻¹⁵⁹, all of it from segments ≥ 2).
#[test]
fn hard_cases_of_every_order_finish() {
    use ScatteringOrders::{All, Limited};
    let mut far = scene(All, 0.8, 0.2);
    far.lights = vec![mcrt_scene::Light::Point { position: mcrt_scene::DVec3::new(300.0, 0.0, 400.0), flux: 1.0 }];
    for (s, what) in [
        (scene(All, 0.999, 0.2), "albedo 0.999"),
        (scene(All, 0.8, 10.0), "R 10"),
        (scene(Limited(9), 0.9, 1e-6), "R 1e-6, order 9"),
        (far, "σ·distance 500"),
    ] {
        let m = mean(&s);
        println!("{what}: {:.6e} ± {:.1e}, bias {:+.3e}", m.mean.value, m.mean.error, m.bias.value);
        assert!(m.mean.value > 0.0 && m.mean.error <= 1e-6 * m.mean.value, "{what}: {m:?}");
        assert!(m.small_sphere_mean.error <= 1e-6 * m.small_sphere_mean.value, "{what}: {m:?}");
    }
}

/// The README scene with every order at R = 0.2 (N_F 200, N_B 8), two
/// tracer runs of 10⁶ trials (seeds 41, 42; ~2 minutes): each agrees with
/// the exact mean (|z| ≤ 4) at a standard error of ~0.05 % and rejects the
/// small-sphere mean (z > 6; the bias is +0.61 %).
#[test]
#[ignore]
fn the_tracer_resolves_the_bias_of_every_order() {
    for seed in [41, 42] {
        let mut s = scene(ScatteringOrders::All, 0.8, 0.2);
        s.estimator.forward_rays = 200;
        s.estimator.camera_rays = 8;
        let (z, z_small, _) = tracer_z(&s, seed, 1_000_000);
        assert!(z.abs() <= 4.0 && z_small > 6.0, "seed {seed}: z {z}, small-sphere z {z_small}");
    }
}
