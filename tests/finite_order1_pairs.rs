//! The finite-sphere model of single-scattered light with two spheres per
//! camera ray (`model::finite::order1::order1_integrals`, `docs/model.md`
//! §9.7): C₂₃ and C₂₄ with the scattered segment meeting both spheres
//! and the two segments of one path meeting one each, against the tracer
//! with no allowance, where q < 1 and N_B > 1 bring them into (7)–(9).

use mcrt_noise::model::field::Field;
use mcrt_noise::model::finite::FiniteField;
use mcrt_noise::quad::{Budget, Options, Rule};
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light, Scene};
use std::path::Path;

mod common;
use common::order1::{against_tracer, costly_part_spends_the_budget, finite_prediction, z, Barred};

/// One tracer point: `point-isotropic-order1` with these settings.
#[derive(Debug, Clone, Copy)]
struct Point {
    radius: f64,
    q: f64,
    n_f: u64,
    n_b: u64,
    albedo: f64,
    /// The light's distance from the camera line (the scene's: 1).
    light_b: f64,
    trials: u64,
}

impl Point {
    fn scene(&self) -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic-order1.toml");
        let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        s.estimator.radius = self.radius;
        s.estimator.q = self.q;
        s.estimator.forward_rays = self.n_f;
        s.estimator.camera_rays = self.n_b;
        s.medium.albedo = self.albedo;
        let Light::Point { flux, .. } = s.lights[0] else { panic!("the scene has a point light") };
        s.lights[0] = Light::Point { position: DVec3::new(self.light_b, 0.0, 1.0), flux };
        s
    }
}

/// Traces the point and returns (z of the mean, z of Var L, the model's
/// Var L, the tracer's).
fn check(p: &Point, goal: f64) -> (f64, f64, Barred, Barred) {
    against_tracer(&format!("{p:?}"), &p.scene(), goal, p.trials, 77)
}

/// What the two segments of one path add to Var L through C₂₃ and C₂₄
/// (erratum E10), with its bar.
fn two_segment_share(s: &Scene, goal: f64) -> Barred {
    use mcrt_noise::model::finite::cross_segments::CrossPair;
    let field = Field::from_scene(s, &1.0f64).unwrap();
    let ff = FiniteField::of_first_segments(s, &field);
    // The rules `order1_pair_added` runs this share with at such goals.
    let o = Options { rule: Rule::Kronrod, ..Options::rel(goal).declared().with_budget(Budget::new(20_000_000_000)) };
    let k = (-ff.shift).exp();
    let x23 = ff.order1_cross(CrossPair::C23, &o).unwrap();
    let x24 = ff.order1_cross(CrossPair::C24, &o).unwrap();
    let (q, nf, nb) = (s.estimator.q, s.estimator.forward_rays as f64, s.estimator.camera_rays as f64);
    let (w23, w24) = (2.0 * (1.0 - q) / (nf * nb), (1.0 - 1.0 / nb) / nf);
    Barred((w23 * x23.value + w24 * x24.value) * k, (w23 * x23.error + w24 * x24.error) * k)
}

/// The first point of `docs/model.md` §9.7: R = 0.2, q = 0.5, N_F = 20,
/// N_B = 8, albedo 0.8, the light at (1, 0, 1).
const BASE: Point = Point { radius: 0.2, q: 0.5, n_f: 20, n_b: 8, albedo: 0.8, light_b: 1.0, trials: 2_000_000 };

/// Traces `p` and asserts |z| ≤ 4 for the mean and Var L against the
/// finite model at the quadrature goal 10⁻³ (its bars are below 10⁻⁴ of
/// each integral).
fn agrees(p: &Point) -> (Barred, Barred) {
    let (zm, zv, var, tracer) = check(p, 1e-3);
    assert!(zm.abs() <= 4.0 && zv.abs() <= 4.0, "{p:?}: mean z {zm:+.2}, Var L z {zv:+.2}");
    (var, tracer)
}

/// The first two points of `docs/model.md` §9.7 with the light at (1, 0, 1)
/// (q < 1 and N_B > 1 throughout; R 0.2, 0.5; q 0.5, 0.2; N_F 20, 1; N_B
/// 8, 2), ~30–50 s of quadrature each on two cores with the Gauss–Kronrod
/// pair (`docs/quadrature.md`); at the first, the prediction without the
/// two-segment pairs is rejected (erratum E10). The third point (R 0.1,
/// N_F 200, albedo 0.3) is ignored in CI for its ~1.5 minutes, below.
#[test]
fn order1_correlations_agree_with_the_tracer() {
    let points = [BASE, Point { radius: 0.5, q: 0.2, n_f: 1, n_b: 2, trials: 6_000_000, ..BASE }];
    for p in &points {
        let (var, tracer) = agrees(p);
        if p.radius == BASE.radius {
            // E10: the same model without the two-segment pairs is rejected.
            let x = two_segment_share(&p.scene(), 1e-3);
            let without = Barred(var.0 - x.0, var.1 + x.1);
            let z_without = z(tracer, without);
            println!("without the two-segment pairs: Var L {:.6e}, z {z_without:+.1}", without.0);
            assert!(z_without > 6.0, "E10: the prediction without the pairs is not rejected (z {z_without:+.2})");
        }
    }
}

/// The third point of `docs/model.md` §9.7: R = 0.1, N_F = 200, albedo
/// 0.3 (q = 0.5, N_B = 8), ignored in CI for its ~1.5 minutes.
#[test]
#[ignore]
fn order1_correlations_agree_with_the_tracer_at_low_albedo() {
    agrees(&Point { radius: 0.1, n_f: 200, albedo: 0.3, trials: 700_000, ..BASE });
}

/// The fourth point of `docs/model.md` §9.7: the light 0.1 from the camera
/// line, inside the spheres' cylinder (R = 0.2, N_B = 2), where the
/// quadrature takes ~2.5 minutes on two cores (`cargo test --release
/// --test finite_order1_pairs -- --ignored --nocapture`).
#[test]
#[ignore]
fn order1_correlations_agree_with_the_tracer_next_to_the_line() {
    agrees(&Point { n_b: 2, light_b: 0.1, ..BASE });
}

/// Spheres larger than the light's distance from the camera line (R = 2,
/// N_B = 2; the hard case of `docs/model.md` §9.7): the cross-segment
/// share's m-integrals converge since the inner integrals of a nested
/// level get a sixteenth of its absolute goal (`quad::integrate_within_pass`;
/// with a quarter, the inner bars alone filled what the G7–K15 rule aims
/// at and it bisected to its panel limit), and the model agrees with 10⁷
/// trials (Var L to ~0.07 %), where the small-sphere model (the oracle's,
/// §3a with E9; E10's R → 0 terms are not added at σR = 2) is rejected.
/// ~3–5 minutes on two cores (`cargo test --release --test
/// finite_order1_pairs -- --ignored --nocapture`).
#[test]
#[ignore]
fn order1_correlations_agree_with_the_tracer_at_r2() {
    let p = Point { radius: 2.0, n_b: 2, trials: 10_000_000, ..BASE };
    let (_, tracer) = agrees(&p);
    let small = mcrt_noise::oracle::run(&p.scene(), mcrt_noise::oracle::Precision::F64, Some(1e-4)).unwrap();
    let z_small =
        z(tracer, Barred(small.variance.as_ref().unwrap().exact.value, small.variance.as_ref().unwrap().exact.error));
    println!("small-sphere Var L {:.6e}: z {z_small:+.1}", small.variance.as_ref().unwrap().exact.value);
    assert!(z_small.abs() > 6.0, "the small-sphere Var L is not rejected (z {z_small:+.2})");
}

/// `mcrt-noise oracle --finite-pairs` ([`Scope::FinitePairs`]) at the
/// second point of `docs/model.md` §9.7: the report's prediction is the
/// finite-sphere model with its pairs, and its mean and Var L are the ones
/// assembled above from the library's integrals, within their bars; the
/// small-sphere prediction of the same run stays beside it. ~6 minutes on
/// two cores (`cargo test --release --test finite_order1_pairs --
/// --ignored --nocapture`).
#[test]
#[ignore]
fn the_oracle_predicts_with_the_finite_pairs_when_asked() {
    use mcrt_noise::oracle::{run_within_scoped, Precision, Scope};
    let p = Point { radius: 0.5, q: 0.2, n_f: 1, n_b: 2, albedo: 0.8, light_b: 1.0, trials: 0 };
    let s = p.scene();
    let report =
        run_within_scoped(&s, Precision::F64, Some(1e-3), &Budget::new(40_000_000_000), Scope::FinitePairs).unwrap();
    assert_eq!(report.prediction.model, "finite-sphere", "{}", report.prediction.note);
    let finite = report.finite.as_ref().unwrap();
    assert!(finite.corr23.is_some() && finite.corr24.is_some() && finite.not_computed.is_none());
    assert_eq!(report.finite_not_used, None);
    let (mu, var) = finite_prediction(&s, 1e-3);
    let close = |what: &str, got: (f64, f64), want: Barred| {
        let gap = (got.0 - want.0).abs();
        println!("{what}: oracle {:.9e} ± {:.1e}, assembled {:.9e} ± {:.1e}", got.0, got.1, want.0, want.1);
        assert!(gap <= got.1 + want.1, "{what}: oracle {got:?}, assembled {want:?}");
    };
    close("mean", (report.prediction.mean.value, report.prediction.mean.error), mu);
    close("Var L", (report.prediction.variance.value, report.prediction.variance.error), var);
}

/// `Scope::FinitePairs` computes the pairs after everything else: when they
/// spend the budget, the report stands with the small-sphere prediction,
/// the exact finite-sphere mean, and the pairs' failure in
/// `finite_not_used` — the same prediction and mean as `Scope::Everything`
/// gives (the run is given what `Everything` used plus 2·10⁷ evaluations,
/// far below the pairs' billions).
#[test]
fn finite_pairs_that_spend_the_budget_leave_the_rest_of_the_report() {
    let p = Point { radius: 0.2, q: 0.5, n_f: 20, n_b: 8, albedo: 0.8, light_b: 1.0, trials: 0 };
    let (why, used) = costly_part_spends_the_budget(&p.scene(), 20_000_000);
    println!("Everything used {used} evaluations; the pairs' failure: {why}");
}

/// C₂₃ and C₂₄ of the order-1 finite model tend to the small-sphere (23),
/// (24) as R → 0 (both with every share: the scattered segment meeting
/// both spheres, and the two segments of one path meeting one each —
/// §3c's cross-segment terms on the small-sphere side), the relative gaps
/// and their fitted orders printed. Each gap must lie above three of its
/// bars (the two models' bars added) and shrink with R at a fitted order
/// of at least ½; the orders themselves are reported, not pinned (the
/// cross-segment share alone tends to its R → 0 form at order ~1, §3c).
/// 23 minutes on two cores (`cargo test --release --test
/// finite_order1_pairs -- --ignored --nocapture`); on 5 December 2026 the
/// gaps at R = 0.04, 0.02, 0.01 were 9.594·10⁻³, 4.586·10⁻³, 2.243·10⁻³
/// (C₂₃) and 7.310·10⁻³, 3.435·10⁻³, 1.666·10⁻³ (C₂₄): fitted orders
/// 1.065, 1.032 and 1.089, 1.044 (`docs/model.md` §9.7).
#[test]
#[ignore]
fn order1_correlations_tend_to_the_small_sphere_ones() {
    use mcrt_noise::model::correlations::{exact, Which};
    use mcrt_noise::model::cross_segment::cross_segment;
    use mcrt_noise::model::finite::Functional;
    let radii = [0.04, 0.02, 0.01];
    let mut gaps: Vec<[Barred; 2]> = Vec::new();
    let t0 = std::time::Instant::now();
    for &r in &radii {
        let s = Point { radius: r, ..BASE }.scene();
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        let (k, k_small) = ((-ff.shift).exp(), (-field.shift).exp());
        let fo = Options::rel(1e-3).declared().with_budget(Budget::new(40_000_000_000));
        let so = Options { max_evals: 4_000_000_000, ..Options::rel(1e-6).with_budget(Budget::new(40_000_000_000)) };
        let mut row = [Barred(0.0, 0.0); 2];
        for (i, (functional, which)) in
            [(Functional::Pair23, Which::Eq23), (Functional::Pair24, Which::Eq24)].into_iter().enumerate()
        {
            let finite = ff.ray_total(functional, &fo).unwrap().plus(ff.order1_pair_added(functional, &fo).unwrap());
            let small =
                exact(&field, &r, which, &so).unwrap().plus(cross_segment(&field, &r, which, &so).unwrap().unwrap());
            let (f, sm) =
                (Barred(finite.value * k, finite.error * k), Barred(small.value * k_small, small.error * k_small));
            let gap = f.0 / sm.0 - 1.0;
            row[i] = Barred(gap, (f.1 / f.0 + sm.1 / sm.0) * (1.0 + gap.abs()));
            println!(
                "[{:.0} s] R {r}: {which:?} finite {:.9e} ± {:.1e}, small-sphere {:.9e} ± {:.1e}, gap {gap:+.3e} ± {:.1e}",
                t0.elapsed().as_secs_f64(),
                f.0, f.1, sm.0, sm.1, row[i].1
            );
        }
        gaps.push(row);
    }
    for i in 0..2 {
        let orders: Vec<f64> = gaps.windows(2).map(|w| (w[0][i].0 / w[1][i].0).abs().log2()).collect();
        println!(
            "{}: relative gaps {:?} at R = {radii:?}; fitted orders {orders:.3?}",
            ["C23", "C24"][i],
            gaps.iter().map(|g| g[i].0).collect::<Vec<_>>()
        );
        for g in &gaps {
            assert!(
                g[i].0.abs() > 3.0 * g[i].1,
                "a gap {:e} within three of its bars {:e}: no order can be fitted",
                g[i].0,
                g[i].1
            );
        }
        for o in &orders {
            assert!(*o >= 0.5, "the gap shrinks at order {o} only");
        }
    }
}

/// A scene with a beam at scattering order 1, two spheres per camera ray.
#[derive(Debug, Clone, Copy)]
struct BeamPoint {
    name: &'static str,
    radius: f64,
    q: f64,
    n_f: u64,
    n_b: u64,
    albedo: f64,
    trials: u64,
}

impl BeamPoint {
    fn scene(&self) -> Scene {
        let mut s = match self.name {
            "across" => common::bundled("beam-isotropic"),
            "towards the camera" => common::beam_towards_camera(),
            "away from the camera" => common::beam_away_from_camera(),
            "slanted" => {
                let mut s = common::bundled("beam-isotropic");
                let Light::Beam { radius, flux, .. } = s.lights[0] else { panic!("a beam") };
                let (center, direction) = (DVec3::new(-1.5, -0.2, 0.0), DVec3::new(1.0, 0.3, 0.6).normalize());
                s.lights[0] = Light::Beam { center, direction, radius, flux };
                s
            }
            "point and beam" => {
                let mut s = common::bundled("beam-isotropic");
                s.lights.push(Light::Point { position: DVec3::new(1.0, 0.0, 1.0), flux: 1.0 });
                s
            }
            other => panic!("no beam scene {other}"),
        };
        s.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
        s.estimator.radius = self.radius;
        s.estimator.q = self.q;
        s.estimator.forward_rays = self.n_f;
        s.estimator.camera_rays = self.n_b;
        s.medium.albedo = self.albedo;
        s
    }
}

/// The beam points of `docs/model.md` §9.11.
const BEAM_POINTS: [BeamPoint; 5] = [
    BeamPoint { name: "across", radius: 0.2, q: 0.5, n_f: 20, n_b: 8, albedo: 0.8, trials: 4_000_000 },
    BeamPoint { name: "slanted", radius: 0.5, q: 0.2, n_f: 1, n_b: 2, albedo: 0.8, trials: 8_000_000 },
    BeamPoint { name: "towards the camera", radius: 0.1, q: 0.5, n_f: 200, n_b: 8, albedo: 0.3, trials: 1_000_000 },
    BeamPoint { name: "point and beam", radius: 0.2, q: 0.5, n_f: 20, n_b: 2, albedo: 1.0, trials: 4_000_000 },
    BeamPoint { name: "away from the camera", radius: 0.03, q: 0.2, n_f: 20, n_b: 8, albedo: 0.8, trials: 4_000_000 },
];

/// A beam's single-scattered light with two spheres per camera ray
/// (`docs/model.md` §9.11: the virtual-light and cross-segment shares with
/// the beam's interaction density and rays) against the tracer, no
/// allowance. `BEAM=k` runs the k-th point only; `TRIALS=0` the model only.
#[test]
#[ignore]
fn beam_correlations_agree_with_the_tracer() {
    let only: Option<usize> = std::env::var("BEAM").ok().and_then(|t| t.parse().ok());
    let trials: Option<u64> = std::env::var("TRIALS").ok().and_then(|t| t.parse().ok());
    for (i, p) in BEAM_POINTS.iter().enumerate() {
        if only.is_some_and(|k| k != i) {
            continue;
        }
        let s = p.scene();
        let n = trials.unwrap_or(p.trials);
        let t = std::time::Instant::now();
        if n == 0 {
            let (mu, var) = finite_prediction(&s, 1e-3);
            println!(
                "{p:?}: mean {:.7e} ± {:.1e}, Var L {:.7e} ± {:.1e} [{:.1?}]",
                mu.0,
                mu.1,
                var.0,
                var.1,
                t.elapsed()
            );
            continue;
        }
        let (zm, zv, _, _) = against_tracer(&format!("{p:?}"), &s, 1e-3, n, 77);
        println!("  [{:.1?}]", t.elapsed());
        assert!(zm.abs() <= 4.0 && zv.abs() <= 4.0);
    }
}

/// The first beam point in CI through the library's `predict` (10⁶
/// trials: Var L to ~0.25 %): the prediction is the finite-sphere model
/// with model bars 0 and no small-sphere Var L beside it (`predict` skips
/// that model's pair integrals for a beam, to which it never falls back), it agrees with
/// the tracer, and without the two-segment share of C₂₃, C₂₄ (§9.11's
/// second route) it is rejected, so the check can fail. ~1.5 minutes on
/// two cores.
#[test]
fn beam_correlations_agree_with_the_tracer_in_ci() {
    let p = BeamPoint { trials: 1_000_000, ..BEAM_POINTS[0] };
    let s = p.scene();
    let prediction = mcrt_noise::predict(&s).unwrap();
    assert_eq!(prediction.model, mcrt_noise::Model::FiniteSphere, "{}", prediction.model_bar_basis);
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0));
    let report = prediction.report.up_to_order_one().unwrap();
    assert!(report.variance.is_none() && report.corr23.is_none(), "predict skips the small-sphere pairs of a beam");
    let finite = report.finite.as_ref().unwrap();
    assert!(finite.corr23.is_some() && finite.corr24.is_some() && finite.variance_ratio.is_none());
    let json = serde_json::to_value(report).unwrap();
    assert!(json["variance"].is_null(), "{}", json["variance"]);
    // The order-1 `finite` object with its correlations of two spheres
    // (C₂₃, C₂₄, Q), pinned to 6 digits and the decades of their bars.
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("finite_beam-isotropic-order1-pairs", common::finite_text(report, 6));
    });
    let t = trace(&Tracer::new(&s).unwrap(), 77, 0..p.trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    let tracer = Barred(t.variance.value, t.variance.se);
    let var = Barred(prediction.variance.value, prediction.variance.quadrature_bar);
    let mu = Barred(prediction.mean.value, prediction.mean.quadrature_bar);
    let (zm, zv) = (z(Barred(t.mean.value, t.mean.se), mu), z(tracer, var));
    println!(
        "{p:?}: Var L {:.6e} ± {:.1e} vs {:.6e} ± {:.1e}: z {zv:+.2}; mean z {zm:+.2}",
        var.0, var.1, tracer.0, tracer.1
    );
    assert!(zm.abs() <= 4.0 && zv.abs() <= 4.0, "mean z {zm:+.2}, Var L z {zv:+.2}");
    let x = two_segment_share(&s, 1e-3);
    let z_without = z(tracer, Barred(var.0 - x.0, var.1 + x.1));
    println!("without the two-segment share ({:.3e}): z {z_without:+.1}", x.0);
    assert!(z_without > 6.0, "the prediction without the two-segment share is not rejected (z {z_without:+.2})");
}
