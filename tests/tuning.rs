//! Choosing parameters (issue 12), the deterministic parts: the cost
//! model's expected counts against the tracer's counters, the objective's
//! Var L against the oracle's, the search against brute force, the
//! comparisons and the small-sphere fallback. (Time itself, the costs and
//! the measured RMSE after a budget are machine-dependent: they are
//! measured in docs/choosing-parameters.md, not here.)

use mcrt_noise::oracle::{run, Precision};
use mcrt_noise::reference::{trace, HitMethod, Tracer};
use mcrt_noise::tuning::cost::{CostTable, IterationCounts, Parameters};
use mcrt_noise::tuning::objective::ModelAtRadius;
use mcrt_noise::tuning::rates::Rates;
use mcrt_noise::tuning::search::{Constraints, Radius};
use mcrt_noise::tuning::{optimize, sensitivity, Options};
use mcrt_noise::Scene;

fn scene(name: &str) -> Scene {
    let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn with(mut s: Scene, q: f64, r: f64, n_f: u64, n_b: u64) -> Scene {
    s.estimator.q = q;
    s.estimator.radius = r;
    s.estimator.forward_rays = n_f;
    s.estimator.camera_rays = n_b;
    s
}

/// Mean per trial of `pick(counters)` over 20 chunks of `per` trials, with
/// its standard error from the chunks' spread.
fn chunked(tracer: &Tracer, per: u64, pick: impl Fn(&mcrt_noise::reference::Counters) -> f64) -> (f64, f64) {
    let k = 20u64;
    let xs: Vec<f64> = (0..k)
        .map(|i| {
            let run = trace(tracer, 5, i * per..(i + 1) * per, HitMethod::Sorted, &|_| {});
            pick(&run.counters) / per as f64
        })
        .collect();
    let m = xs.iter().sum::<f64>() / k as f64;
    let var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (k - 1) as f64;
    (m, (var / k as f64).sqrt())
}

/// The cost model's expected counts of one iteration — segments, spheres,
/// searching segments and hits — against the tracer's counters (the rates
/// from an independent pilot walk with another seed): |z| ≤ 4 on every
/// count, over point lights and a beam, isotropic and Henyey–Greenstein,
/// orders 0 and 1, q from 1 to 0.05, R from 0.01 to 0.3.
#[test]
fn expected_counts_match_the_tracers_counters() {
    let cases = [
        with(scene("point-isotropic"), 0.5, 0.05, 200, 8),
        with(scene("point-isotropic"), 1.0, 0.3, 100, 4),
        with(scene("point-hg-forward"), 0.1, 0.1, 50, 16),
        with(scene("point-isotropic-order1"), 0.2, 0.05, 100, 4),
        with(scene("beam-isotropic"), 0.05, 0.02, 60, 8),
        // every order: ~5 segments a ray at albedo 0.8
        with(scene("point-isotropic-all"), 1.0, 0.2, 20, 1),
    ];
    for s in cases {
        let tracer = Tracer::new(&s).unwrap();
        let rates = Rates::estimate(&s, 200_000).unwrap();
        let e = s.estimator;
        let predicted = IterationCounts::predict(&s, &rates, e.q, e.forward_rays as f64, e.camera_rays as f64);
        let per = 2000;
        let log2s = (1.0 + e.camera_rays as f64 / e.q).log2();
        let checks: [(&str, f64, f64, (f64, f64)); 4] = [
            ("segments", predicted.segments, 0.0, chunked(&tracer, per, |c| c.forward_segments as f64)),
            ("spheres", predicted.spheres, 0.0, chunked(&tracer, per, |c| c.sphere_placements as f64)),
            (
                "searching segments",
                predicted.search_work / log2s,
                predicted.segments * rates.candidate_fraction.error,
                chunked(&tracer, per, |c| c.candidate_tests as f64),
            ),
            (
                "hits",
                predicted.hits,
                predicted.hits * rates.hit_measure.error / rates.hit_measure.value,
                chunked(&tracer, per, |c| c.hits as f64),
            ),
        ];
        for (what, want, want_se, (got, got_se)) in checks {
            // Order 0 has exactly N_F segments per iteration: no spread, no error.
            let z = if want_se.hypot(got_se) == 0.0 {
                (got - want) * f64::INFINITY
            } else {
                (got - want) / want_se.hypot(got_se)
            };
            let z = if z.is_nan() { 0.0 } else { z };
            assert!(
                z.abs() <= 4.0,
                "{} q={} R={}: {what} predicted {want:.5e} ± {want_se:.1e}, traced {got:.5e} ± {got_se:.1e}, z {z:.2}",
                s.lights.len(),
                e.q,
                e.radius
            );
        }
    }
}

/// The objective's Var L (explicit in q, N_F, N_B) is the oracle's at the
/// scene's own parameters, within the bars, for both models: the
/// finite-sphere one (bias predicted) and, from the same report without
/// it, the small-sphere one (bias not predicted).
#[test]
fn the_objectives_variance_is_the_oracles() {
    for name in ["point-isotropic", "point-hg-forward", "beam-isotropic"] {
        let s = scene(name);
        let report = run(&s, Precision::F64, None).unwrap();
        let mut small = report.clone();
        small.finite = None;
        for (r, model, want) in [
            (&report, "finite-sphere", report.prediction.variance),
            (&small, "small-sphere", report.variance.as_ref().unwrap().exact),
        ] {
            let m = ModelAtRadius::from_report(r).unwrap();
            let e = s.estimator;
            let v = m.variance(e.q, e.forward_rays as f64, e.camera_rays as f64).unwrap();
            assert!(
                (v.value - want.value).abs() <= v.error + want.error + 1e-13 * want.value,
                "{name}, {model}: {} ± {:e} vs {} ± {:e}",
                v.value,
                v.error,
                want.value,
                want.error
            );
            assert_eq!(m.model, model);
            assert_eq!(m.bias.is_some(), model == "finite-sphere");
        }
    }
}

/// Every scattering order (`"all"`): `optimize` searches R and N_F at the
/// standard method (q = 1, N_B = 1), where the finite-sphere model of every
/// order has Var L; the model a radius gets is the prediction's (its Var L
/// within the bars of both), with the bias, without pair integrals (Var L
/// at q < 1 or N_B > 1 is `None`, never read as 0), and its small-sphere M₂
/// (the asymptotic rule's, ∝ 1/R²) is c f μ(0) with c = albedo·Φ/(πR²) and
/// f = 1/4π from the scene's numbers, below M₂ by the same-path pairs and
/// the bias. (~25 s: the prediction and one radius.)
#[test]
fn every_order_is_searched_at_the_standard_method_with_the_predictions_model() {
    use mcrt_noise::tuning::{radii::RadiusCache, Searched};
    let s = with(scene("point-isotropic-all"), 1.0, 0.2, 20, 1);
    assert_eq!(Searched::of(&s), Searched::StandardMethod);
    let mut own = s.clone();
    (own.estimator.q, own.estimator.camera_rays) = (0.5, 8);
    assert_eq!(Searched::of(&own), Searched::StandardMethod);
    own.effects.scattering_orders = mcrt_noise::ScatteringOrders::Limited(3);
    assert_eq!(Searched::of(&own), Searched::StandardMethod);
    own.medium.phase = mcrt_noise::Phase::HenyeyGreenstein { g: 0.5 };
    assert_eq!(Searched::of(&own), Searched::HeldRadius);
    let mut cache = RadiusCache::new(&own, mcrt_noise::quad::Budget::new(1), None);
    let err = cache.at(0.2).unwrap_err().to_string();
    assert!(err.contains("medium.phase") && err.contains("isotropic media only"), "refused before any integral: {err}");

    let prediction = mcrt_noise::predict(&s).unwrap();
    let mut cache = RadiusCache::new(&s, mcrt_noise::quad::Budget::new(1_000_000_000), None);
    let m = cache.at(0.2).unwrap().model;
    assert_eq!((m.model, m.radius), ("finite-sphere", 0.2));
    let v = m.variance(1.0, 20.0, 1.0).unwrap();
    let want = prediction.variance;
    assert!((v.value - want.value).abs() <= v.error + want.quadrature_bar, "{v:?} against the prediction's {want:?}");
    assert!(m.variance(0.5, 20.0, 1.0).is_none() && m.variance(1.0, 20.0, 2.0).is_none());
    let bias = m.bias.unwrap();
    let exact = prediction.bias.unwrap();
    assert!((bias.value - exact.value).abs() <= bias.error + exact.error, "{bias:?} against {exact:?}");
    let report = prediction.report.every_order().unwrap();
    let pairs = report.same_path_pairs.unwrap().value;
    let cf_mu = m.m2.value - pairs;
    assert!(m.small_sphere_m2.value < cf_mu && cf_mu < m.m2.value, "{m:?}");
    // c f μ(0) from the scene's own numbers: c = albedo·Φ/(πR²), f = 1/4π.
    let pi = std::f64::consts::PI;
    let want_small = s.medium.albedo * 1.0 / (pi * 0.2 * 0.2) / (4.0 * pi) * m.mean_at_zero.value;
    let bar = m.small_sphere_m2.error + want_small * m.mean_at_zero.error / m.mean_at_zero.value;
    assert!((m.small_sphere_m2.value - want_small).abs() <= bar, "{m:?} against c f μ(0) = {want_small:e} ± {bar:e}");
}

/// The whole search for every order on the README scene (`"all"`, R = 0.2,
/// N_F = 20, q = 1, N_B = 1) with a 10 s budget at the reference costs:
/// q = 1 and N_B = 1 held, R searched and not the scene's, the bias
/// predicted, no radius evaluated better, the small-sphere comparison and
/// q < 1 said not to be scored, the asymptotic rule scored. Minutes (~30
/// radii at ~10 s): `cargo test --release --test tuning -- --ignored`.
#[test]
#[ignore = "every order: ~30 radii at ~10 s each, ~15 min in release mode"]
fn every_order_is_searched_over_r() {
    use mcrt_noise::tuning::Searched;
    let s = with(scene("point-isotropic-all"), 1.0, 0.2, 20, 1);
    let o = optimize(&s, &Options::new(10.0, CostTable::reference_machine())).unwrap();
    assert_eq!((o.searched, o.model, o.bias_predicted), (Searched::StandardMethod, "finite-sphere", true));
    assert_eq!(o.scattering_orders, "all");
    let b = o.best;
    let p = b.parameters;
    println!("best {p:?}: {:?}", b.rmse);
    assert_eq!((p.q, p.camera_rays), (1.0, 1), "{p:?}");
    assert!(o.radius_range.0 <= p.radius && p.radius <= o.radius_range.1 && p.radius != s.estimator.radius);
    assert!(b.rmse.relative_bias.is_some_and(|x| x > 0.0));
    let standard = Constraints { q: Some(1.0), camera_rays: Some(1), ..Constraints::free(10.0, None) };
    for r in &o.radii {
        if let Some(x) = r.best(&s, &CostTable::reference_machine(), &standard) {
            assert!(x.rmse.relative >= b.rmse.relative * (1.0 - 1e-12), "R = {}: {x:?}", r.model.radius);
        }
    }
    let named = |n: &str| o.alternatives.iter().find(|a| a.name.starts_with(n)).unwrap();
    assert!(named("q, N_F, N_B free at the scene's R").scored.is_err());
    assert!(named("q < 1 or N_B > 1").scored.as_ref().is_err_and(|e| e.contains("§10.4")));
    assert!(named("R of the asymptotic rule").scored.is_ok(), "{:?}", named("R of the asymptotic rule"));
    let text = mcrt_noise::reports::optimum::text("all", &o);
    assert!(text.contains("for every scattering order") && !text.contains("single-scattered"), "{text}");
}

/// Costs that make the search's structure visible: every count costs.
fn costs() -> CostTable {
    CostTable::from_array([1500.0, 50.0, 400.0, 45.0, 12.0, 2.0, 3.0, 6.0, 10.0], [0.0; 9], "test".into())
}

/// At one radius the search (closed-form N_F*, grid in q and N_B, then
/// refinement) finds an RMSE no worse than a brute-force scan of a fine
/// grid, and within 0.1 % of the scan's best.
#[test]
fn the_search_at_one_radius_matches_brute_force() {
    let s = with(scene("point-isotropic"), 0.5, 0.05, 200, 8);
    let report = run(&s, Precision::F64, None).unwrap();
    let at =
        Radius { model: ModelAtRadius::from_report(&report).unwrap(), rates: Rates::estimate(&s, 50_000).unwrap() };
    let c = Constraints::free(0.1, None);
    let best = at.best(&s, &costs(), &c).unwrap();
    let mut brute = f64::INFINITY;
    for i in 0..=60 {
        let q = 10f64.powf(-3.0 * f64::from(i) / 60.0);
        for j in 0..=40 {
            let n_b = 10f64.powf(3.0 * f64::from(j) / 40.0).round() as u64;
            for k in 0..=60 {
                let n_f = 10f64.powf(5.0 * f64::from(k) / 60.0).round() as u64;
                let p = Parameters { q, radius: 0.05, forward_rays: n_f, camera_rays: n_b };
                if let Some(x) = at.scored_at(&s, &costs(), &c, &p) {
                    brute = brute.min(x.rmse.relative);
                }
            }
        }
    }
    assert!(best.rmse.relative <= brute * 1.001, "search {:e} vs brute force {brute:e}", best.rmse.relative);
    // And its own RMSE is what scoring its parameters gives.
    let again = at.scored_at(&s, &costs(), &c, &best.parameters).unwrap();
    assert_eq!(again.rmse.relative, best.rmse.relative);
}

/// The whole optimisation on the bundled isotropic scene: the optimum is no
/// worse than any alternative of the sphere method (the cylinder limit is
/// another integration volume, with a cost model of its own, and may be
/// better), the bias/noise split adds up, the
/// sensitivity ranges contain the optimum, and M τ = T.
#[test]
fn the_optimum_beats_its_alternatives_and_its_parts_add_up() {
    let s = scene("point-isotropic");
    let o = optimize(&s, &Options::new(0.1, costs())).unwrap();
    assert!(o.bias_predicted && o.model == "finite-sphere");
    let b = o.best;
    for a in o.alternatives.iter().filter(|a| !a.name.starts_with("q → 0")) {
        if let Ok(x) = &a.scored {
            assert!(
                x.rmse.relative >= b.rmse.relative * (1.0 - 1e-12),
                "{}: {:e} < {:e}",
                a.name,
                x.rmse.relative,
                b.rmse.relative
            );
        }
    }
    let r = b.rmse;
    let bias = r.relative_bias.unwrap();
    assert!((r.relative.powi(2) - bias.powi(2) - r.relative_noise.powi(2)).abs() <= 1e-12 * r.relative.powi(2));
    // M whole iterations fit in T, M + 1 do not.
    let m = r.iterations as f64;
    assert!(m >= 1.0 && m * r.seconds_per_iteration <= 0.1 && (m + 1.0) * r.seconds_per_iteration > 0.1, "{r:?}");
    // Each sensitivity range: its ends within 10 % of the best, and the
    // scan's next step beyond an end that is not a bound, outside.
    let sens = o.sensitivity;
    let p = b.parameters;
    let at = o.radii.iter().find(|x| x.model.radius == p.radius).unwrap();
    let c = Constraints::free(0.1, None);
    let score = |p: Parameters| at.scored_at(&s, &costs(), &c, &p).map_or(f64::INFINITY, |x| x.rmse.relative);
    let limit = 1.1 * r.relative;
    let q = sens.q.unwrap();
    assert!(score(Parameters { q: q.lo, ..p }) <= limit && score(Parameters { q: q.hi, ..p }) <= limit, "{q:?}");
    if !q.lo_at_bound {
        assert!(score(Parameters { q: q.lo / sensitivity::q_step(), ..p }) > limit, "{q:?}");
    }
    let with_n_f = |p: Parameters, v: f64| Parameters { forward_rays: v as u64, ..p };
    let with_n_b = |p: Parameters, v: f64| Parameters { camera_rays: v as u64, ..p };
    for (range, set) in [
        (sens.forward_rays, &with_n_f as &dyn Fn(Parameters, f64) -> Parameters),
        (sens.camera_rays.unwrap(), &with_n_b),
    ] {
        assert!(score(set(p, range.lo)) <= limit && score(set(p, range.hi)) <= limit, "{range:?}");
        if !range.hi_at_bound {
            assert!(score(set(p, sensitivity::count_up(range.hi))) > limit, "{range:?}");
        }
        if !range.lo_at_bound {
            assert!(score(set(p, sensitivity::count_down(range.lo))) > limit, "{range:?}");
        }
    }
    let rr = sens.radius.unwrap();
    assert!(rr.lo <= p.radius && p.radius <= rr.hi);
    // The scene's own parameters are among the alternatives, at its R.
    let own = o.alternatives.iter().find(|a| a.name.contains("own")).unwrap().scored.as_ref().unwrap();
    assert_eq!(own.parameters, Parameters::of(&s));
}

/// A memory limit holds, and a tighter one cannot do better.
#[test]
fn a_memory_limit_is_respected() {
    let s = scene("point-isotropic");
    let free = optimize(&s, &Options::new(0.1, costs())).unwrap();
    let mut opts = Options::new(0.1, costs());
    opts.max_spheres = Some(16.0);
    let tight = optimize(&s, &opts).unwrap();
    let p = tight.best.parameters;
    assert!(p.camera_rays as f64 / p.q <= 16.0 * (1.0 + 1e-12), "{p:?}");
    assert!(tight.best.rmse.relative >= free.best.rmse.relative * (1.0 - 1e-12));
}

/// Single scattering in an isotropic medium: the finite-sphere model gives
/// Var L at q = 1, N_B = 1 only (its pair integrals take minutes, and
/// the oracle computes them only when asked: `Scope::FinitePairs`), so `optimize` searches R and N_F there, the bias b(R) predicted.
/// Checked: what was searched; the best's Var L is the oracle's own
/// finite-sphere Var L at those parameters (the absent pair integrals
/// weigh exactly 0 there, and the model refuses other q and N_B instead of
/// reading them as 0); no radius evaluated does better at q = 1, N_B = 1;
/// the small-sphere comparison at the scene's R carries the finite-sphere
/// bias; q < 1 and N_B > 1 are said not to be scored.
#[test]
fn single_scattered_light_is_searched_over_r_at_the_standard_method() {
    use mcrt_noise::oracle::{run_scoped, Scope};
    use mcrt_noise::tuning::Searched;
    let s = scene("point-isotropic-order1");
    let o = optimize(&s, &Options::new(0.1, costs())).unwrap();
    assert_eq!((o.searched, o.model, o.bias_predicted), (Searched::StandardMethod, "finite-sphere", true));
    let b = o.best;
    let p = b.parameters;
    assert_eq!((p.q, p.camera_rays), (1.0, 1), "{p:?}");
    assert!(o.radius_range.0 <= p.radius && p.radius <= o.radius_range.1 && p.radius != s.estimator.radius);
    assert!(b.rmse.relative_bias.is_some_and(|x| x > 0.0));
    assert!(o.sensitivity.q.is_none() && o.sensitivity.camera_rays.is_none() && o.sensitivity.radius.is_some());
    // The objective's Var L at the best against the oracle's prediction there.
    let at = o.radii.iter().find(|x| x.model.radius == p.radius).unwrap();
    let var = at.model.variance(1.0, p.forward_rays as f64, 1.0).unwrap();
    let report =
        run_scoped(&with(s.clone(), 1.0, p.radius, p.forward_rays, 1), Precision::F64, Some(1e-4), Scope::Prediction)
            .unwrap();
    let exact = report.finite.unwrap().variance;
    assert!((var.value - exact.value).abs() <= var.error + exact.error, "{var:?} against {exact:?}");
    assert!(at.model.variance(0.5, p.forward_rays as f64, 1.0).is_none());
    assert!(at.model.variance(1.0, p.forward_rays as f64, 2.0).is_none());
    // The best over every radius evaluated.
    let standard = Constraints { q: Some(1.0), camera_rays: Some(1), ..Constraints::free(0.1, None) };
    for r in &o.radii {
        if let Some(x) = r.best(&s, &costs(), &standard) {
            assert!(x.rmse.relative >= b.rmse.relative * (1.0 - 1e-12), "R = {}: {x:?}", r.model.radius);
        }
    }
    let named = |n: &str| o.alternatives.iter().find(|a| a.name.starts_with(n)).unwrap();
    let small = named("q, N_F, N_B free at the scene's R").scored.as_ref().unwrap();
    assert_eq!(small.parameters.radius, s.estimator.radius);
    assert!(small.rmse.relative_bias.is_some(), "{small:?}");
    assert!(named("q < 1 or N_B > 1").scored.as_ref().is_err_and(|e| e.contains("§9.7")));
    // The bias of single-scattered light is resolved at some radius: the rule has its b₂.
    assert!(named("R of the asymptotic rule").scored.is_ok(), "{:?}", named("R of the asymptotic rule"));
    // What `optimize --json` carries: what was searched, the held
    // parameters and the absent pair integrals as null, not 0.
    let v = serde_json::to_value(&o).unwrap();
    assert_eq!(v["searched"], "StandardMethod");
    assert!(v["sensitivity"]["q"].is_null() && v["sensitivity"]["camera_rays"].is_null());
    assert!(v["radii"].as_array().unwrap().iter().all(|r| r["model"]["c23"].is_null() && r["model"]["c24"].is_null()));
}

/// The small-sphere comparison is the small-sphere model whatever the
/// report holds: on an order-1 scene at q = 1, N_B = 1 the oracle's
/// prediction is the finite-sphere model, and `from_report` takes it (no
/// pair integrals), while `small_sphere_from_report` takes the paper's
/// model with its pair integrals and the finite-sphere bias.
#[test]
fn the_small_sphere_model_is_taken_from_any_report() {
    let s = with(scene("point-isotropic-order1"), 1.0, 0.1, 20, 1);
    let report = run(&s, Precision::F64, Some(1e-4)).unwrap();
    let exact = ModelAtRadius::from_report(&report).unwrap();
    assert_eq!(exact.model, "finite-sphere");
    assert!(!exact.has_pairs() && exact.bias.is_some());
    let small = ModelAtRadius::small_sphere_from_report(&report).unwrap();
    assert_eq!(small.model, "small-sphere");
    assert!(small.has_pairs() && small.variance(0.5, 20.0, 8.0).is_some());
    assert_eq!(small.bias.map(|b| b.value), exact.bias.map(|b| b.value));
    assert_eq!(small.m2.value, report.integral_m2.value);
}

/// Scattered light whose Var L the finite-sphere model does not cover
/// (here single scattering in a Henyey–Greenstein medium): the
/// small-sphere model, R held at the scene's (a smaller RMSE from another R
/// would rest on a Var L whose error is measured at R ≤ 0.1 only), the
/// bias not predicted over R — but known at the scene's R from the exact
/// mean (`docs/model.md` §9.9), and in the RMSE there.
#[test]
fn with_scattered_light_it_does_not_cover_the_radius_is_held_and_the_bias_not_predicted() {
    let mut s = scene("point-isotropic-order1");
    s.medium.phase = mcrt_noise::scene::Phase::HenyeyGreenstein { g: 0.5 };
    let opts = Options::new(0.1, costs());
    let mut cache =
        mcrt_noise::tuning::radii::RadiusCache::new(&s, mcrt_noise::quad::Budget::new(opts.evaluations), None);
    let o = mcrt_noise::tuning::optimize_with(&s, &opts, &mut cache).unwrap();
    assert!(!o.bias_predicted && o.model == "small-sphere");
    assert_eq!(o.searched, mcrt_noise::tuning::Searched::HeldRadius);
    assert_eq!(o.best.parameters.radius, s.estimator.radius);
    // The model it optimised with (cached, not recomputed) has the exact
    // mean's bias, and the RMSE carries it.
    let model = cache.at(s.estimator.radius).unwrap().model;
    let exact = model.bias.expect("the exact mean's bias");
    let relative = o.best.rmse.relative_bias.expect("the bias at the held R");
    let want = exact.value.abs() / model.mean_at_zero.value;
    assert!((relative - want).abs() <= 1e-12 * want, "{relative} vs {want}");
    // Its bar is carried (at R = 0.01 b(R) is 5·10⁻⁵ of the mean, and the
    // Henyey–Greenstein mean is computed to 10⁻³: the bar may be a sizeable
    // part of it).
    let bar = o.best.rmse.relative_bias_error.expect("the bias's bar");
    assert!(bar >= exact.error / model.mean_at_zero.value, "{bar:e} vs {exact:?}");
    let text = mcrt_noise::reports::optimum::text("hg", &o);
    assert!(text.contains("the bias at its R") && !text.contains("NOT predicted"), "{text}");
    assert!(o.sensitivity.radius.is_none() && o.sensitivity.q.is_some());
    assert!(o.alternatives.iter().all(|a| !a.name.contains("asymptotic")));
}

/// A radius cache keeps one scene's models: `optimize_with` refuses a
/// cache built for another scene, before any oracle run, instead of
/// optimising with the other scene's integrals.
#[test]
fn a_cache_of_another_scene_is_refused() {
    let (a, b) = (scene("point-isotropic"), scene("point-hg-forward"));
    let mut cache = mcrt_noise::tuning::radii::RadiusCache::new(&a, mcrt_noise::quad::Budget::new(1), None);
    let err = mcrt_noise::tuning::optimize_with(&b, &Options::new(0.1, costs()), &mut cache).unwrap_err().to_string();
    assert!(err.contains("built for another scene"), "{err}");
    assert!(cache.all().is_empty());
}

/// A budget below one iteration is refused before any search, naming
/// `--budget` and the least budget that fits one iteration.
#[test]
fn a_budget_below_one_iteration_names_the_least_that_fits() {
    let err = optimize(&scene("point-isotropic"), &Options::new(1e-9, costs())).unwrap_err().to_string();
    assert!(err.contains("--budget 0.000000001") && err.contains("at least one iteration"), "{err}");
}
