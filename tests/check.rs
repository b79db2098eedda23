//! The check API on the reference tracer (release mode): calibrated false
//! alarms where the model is exact, the stated power against planted
//! errors of the detectable size, and the failures it owes.
//!
//! The calibration runs the tracer `RUNS` times on disjoint trial ranges of
//! one seed (independent runs), checks each at a family-wise false-alarm
//! rate of 5 % against the finite-sphere model (exact: no model bar), and
//! requires the number of failures to lie within the binomial 99 % interval
//! of 5 % of `RUNS` (the CI-sized calibration; the documented one, at
//! α = 10⁻³ and 10⁻² over 10 000 and 2 000 runs, is `mcrt-noise
//! check-calibration`). The same runs, each shifted by its own detectable
//! error either way (L scaled by 1 ± δ for the mean, by √(1 ± δ) for
//! Var L), must fail at least as often as the stated power, within the
//! binomial 99 % interval.

use mcrt_noise::check::Status;
use mcrt_noise::reference::{HitMethod, Tracer};
use mcrt_noise::{check, predict, CheckOptions, Model, Prediction, Samples, Scene, Verdict};
use rayon::prelude::*;

/// Independent runs (the issue asks for ≥ 400).
const RUNS: u64 = 400;
/// Trials per run.
const TRIALS: u64 = 20_000;
const SEED: u64 = 2024;

/// Where the finite-sphere model is exact: the README's scene.
fn scene() -> Scene {
    mcrt_noise::reports::check_calibration::readme_geometry(mcrt_noise::Phase::Isotropic, (0.2, 0.5, 20, 4))
}

use mcrt_noise::reports::check_calibration::binomial_99;

/// Every run's values (run k: trials k·TRIALS … (k+1)·TRIALS − 1).
fn traced_runs(scene: &Scene, runs: u64) -> Vec<Vec<f64>> {
    let tracer = Tracer::new(scene).unwrap();
    (0..runs)
        .into_par_iter()
        .map(|k| (k * TRIALS..(k + 1) * TRIALS).map(|i| tracer.trial(SEED, i, HitMethod::Sorted).0).collect())
        .collect()
}

fn samples(values: impl IntoIterator<Item = f64>) -> Samples {
    let mut s = Samples::new();
    s.extend(values).unwrap();
    s
}

#[test]
fn check_is_calibrated_and_has_its_stated_power() {
    let scene = scene();
    let prediction = predict(&scene).unwrap();
    assert_eq!(prediction.model, Model::FiniteSphere);
    calibrated_with_stated_power(&scene, &prediction, RUNS);
}

/// Every scattering order (`"all"`, albedo 0.8, at q = 1 and one camera
/// ray, where the finite-sphere model of every order has Var L exactly,
/// `docs/model.md` §10.3): the prediction is exact (model bars 0, the bias
/// predicted), and the check on the tracer's values is calibrated and has
/// its stated power, as for uncollided light. Half the runs (the tracer's
/// paths are ~5 segments long here): the binomial interval is wider, the
/// test the same.
#[test]
fn check_of_every_order_is_calibrated_and_has_its_stated_power() {
    let mut scene = scene();
    scene.effects.scattering_orders = mcrt_noise::ScatteringOrders::All;
    (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
    let prediction = predict(&scene).unwrap();
    assert_eq!(prediction.model, Model::FiniteSphere);
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0));
    let report = prediction.report.every_order().expect("the report of every order");
    assert!(prediction.bias.is_some() && report.same_path_pairs.is_some(), "{report:?}");
    // Var L's bar is the quadrature's at the goal 1e-4 of its integrals.
    assert!(prediction.variance.quadrature_bar <= 1e-4 * prediction.variance.value, "{:?}", prediction.variance);
    assert!(prediction.model_bar_basis.contains("every scattering order"), "{}", prediction.model_bar_basis);
    calibrated_with_stated_power(&scene, &prediction, RUNS / 2);
}

/// `runs` independent runs of the tracer on `scene`, each checked at a
/// family-wise false-alarm rate of 5 % against `prediction` (which must be
/// exact: no model bar): the failures within the binomial 99 % interval of
/// 5 % of the runs; each run moved by its own detectable error, either way,
/// caught at least as often as the stated power allows.
fn calibrated_with_stated_power(scene: &Scene, prediction: &Prediction, runs: u64) {
    assert_eq!((prediction.mean.model_bar, prediction.variance.model_bar), (0.0, 0.0), "not exact");
    let options = CheckOptions::new(0.05).unwrap();
    let values = traced_runs(scene, runs);
    let verdicts: Vec<Verdict> =
        values.par_iter().map(|v| check(prediction, &samples(v.iter().copied()), &options)).collect();
    let false_alarms = verdicts.iter().filter(|v| v.status == Status::Fail).count() as u64;
    let unresolved = verdicts.iter().filter(|v| v.status == Status::NotResolved).count();
    let (lo, hi) = binomial_99(runs, 0.05);
    let z = |k: usize| verdicts.iter().filter_map(|v| v.checks[k].z).collect::<Vec<_>>();
    let moments = |x: &[f64]| {
        let m = x.iter().sum::<f64>() / x.len() as f64;
        (m, (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64).sqrt())
    };
    println!(
        "false alarms {false_alarms}/{runs} (99 % interval [{lo}, {hi}]), {unresolved} not resolved; mean z {:?}, \
         Var z {:?} (mean, sd)",
        moments(&z(0)),
        moments(&z(1))
    );
    assert!((lo..=hi).contains(&false_alarms), "false alarms {false_alarms} outside [{lo}, {hi}]");
    // NOT RESOLVED only where a pass would rest on one value: a band below
    // the limit as wide as one value's influence (~0.1–0.5 here), where the
    // normal density is φ(2.24) ≈ 0.03: ~1–2 % of runs per quantity.
    assert!(unresolved as u64 <= runs / 20, "{unresolved} not resolved");

    // Power: each run moved by its own detectable error, either way, must
    // fail with probability ≥ the power (0.9); its 99 % interval's lower
    // end bounds the count from below. Runs that failed as they were (the
    // false alarms) state no detectable error and are left out.
    let power = options.power();
    let caught = |k: usize, scale: &(dyn Fn(f64) -> f64 + Sync)| -> (u64, u64) {
        let planted: Vec<bool> = values
            .par_iter()
            .zip(&verdicts)
            .filter_map(|(v, verdict)| {
                let d = verdict.checks[k].detectable_relative_error?;
                let shifted = check(prediction, &samples(v.iter().map(|l| l * scale(d))), &options);
                Some(
                    shifted.status == Status::Fail
                        && shifted.failures.iter().any(|r| r.starts_with(verdict.checks[k].name)),
                )
            })
            .collect();
        (planted.iter().filter(|c| **c).count() as u64, planted.len() as u64)
    };
    for (what, k, scale) in [
        ("mean up", 0, &(|d: f64| 1.0 + d) as &(dyn Fn(f64) -> f64 + Sync)),
        ("mean down", 0, &|d: f64| 1.0 - d),
        ("Var L up", 1, &|d: f64| (1.0 + d).sqrt()),
        ("Var L down", 1, &|d: f64| (1.0 - d).sqrt()),
    ] {
        let (hits, n) = caught(k, scale);
        let (lo_power, _) = binomial_99(n, power);
        println!("planted errors of the detectable size, {what}: caught {hits}/{n} (need ≥ {lo_power})");
        assert!(hits >= lo_power, "{what}: {hits}/{n} < {lo_power}");
    }
}

#[test]
fn predict_validates_a_hand_assembled_scene_and_refuses_what_it_cannot_vouch_for() {
    let mut scene = scene();
    scene.estimator.q = 2.0;
    let err = predict(&scene).unwrap_err().to_string();
    assert!(err.contains("estimator.q = 2: must be in (0, 1]"), "{err}");
    // Single-scattered light in a Henyey–Greenstein medium at q < 1: the
    // small-sphere model, whose error is measured at R ≤ 0.1 only.
    let mut scattered = self::scene();
    scattered.effects.scattering_orders = mcrt_noise::ScatteringOrders::Limited(1);
    scattered.medium.phase = mcrt_noise::Phase::HenyeyGreenstein { g: 0.5 };
    let err = predict(&scattered).unwrap_err().to_string();
    assert!(err.contains("estimator.radius = 0.2") && err.contains("R ≤ 0.1"), "{err}");
    // Every order where its Var L is not modelled (q < 1, N_B > 1):
    // refused before any integral, naming the fields; in MPFR (f64 only),
    // naming the precision.
    let mut all = self::scene();
    all.effects.scattering_orders = mcrt_noise::ScatteringOrders::All;
    // (a budget of one evaluation: anything computed first would spend it)
    let one = mcrt_noise::quad::Budget::new(1);
    let err = mcrt_noise::check::predict_within(&all, mcrt_noise::oracle::Precision::F64, None, &one)
        .unwrap_err()
        .to_string();
    assert!(err.contains("effects.scattering_orders = \"all\", estimator.q = 0.5, estimator.camera_rays = 4"), "{err}");
    assert!(err.contains("correlations of two spheres of every order"), "{err}");
    all.effects.scattering_orders = mcrt_noise::ScatteringOrders::Limited(3);
    let refusal = |scene: &Scene, precision, rel_tol| {
        mcrt_noise::check::predict_within(scene, precision, rel_tol, &one).unwrap_err().to_string()
    };
    let f64_ = mcrt_noise::oracle::Precision::F64;
    let err = refusal(&all, f64_, None);
    assert!(err.contains("effects.scattering_orders = 3, estimator.q = 0.5, estimator.camera_rays = 4"), "{err}");
    (all.estimator.q, all.estimator.camera_rays) = (1.0, 1);
    all.effects.scattering_orders = mcrt_noise::ScatteringOrders::All;
    let err = refusal(&all, mcrt_noise::oracle::Precision::Bits(128), None);
    assert!(err.contains("precision = 128 bits") && err.contains("f64 only"), "{err}");
    let err = refusal(&all, f64_, Some(0.05));
    assert!(err.contains("rel_tol = 5e-2") && err.contains("[1e-8, 1e-2]"), "{err}");
    // What the model of every order does not cover is named first (not q).
    all.medium.phase = mcrt_noise::Phase::HenyeyGreenstein { g: 0.5 };
    all.estimator.q = 0.5;
    let err = refusal(&all, f64_, None);
    assert!(err.contains("medium.phase") && err.contains("isotropic media only"), "{err}");
}

/// Every order where Var L's integrals spend the budget: no fallback, the
/// prediction fails with the quadrature's error, its kind kept (a computed
/// failure, not a refusal). 1.5·10⁸ evaluations: the means charge the
/// budget 4.35·10⁷, Var L's integrals 1.24·10⁸ (so they finish on their
/// own budget, beside the means), the whole 1.67·10⁸ on the README scene at
/// R = 0.2 (measured 7 December 2026 once the scale passes read the primary
/// passes' tables, docs/model.md §10.6; before, 5.14·10⁷ + 1.68·10⁸ with a
/// budget of 2·10⁸) — the budget is spent only as the two are charged
/// together, as it would be were they run one after the other.
#[test]
fn a_prediction_of_every_order_that_spends_the_budget_fails_with_its_reason() {
    let mut all = scene();
    all.effects.scattering_orders = mcrt_noise::ScatteringOrders::All;
    (all.estimator.q, all.estimator.camera_rays) = (1.0, 1);
    let budget = mcrt_noise::quad::Budget::new(150_000_000);
    let err = mcrt_noise::check::predict_within(&all, mcrt_noise::oracle::Precision::F64, None, &budget).unwrap_err();
    let shown = err.to_string();
    assert!(
        matches!(err, mcrt_noise::PredictError::Oracle(mcrt_noise::model::OracleError::Quadrature { .. })),
        "{shown}"
    );
    assert!(shown.contains("NOT CONVERGED") && shown.contains("budget of 150000000"), "{shown}");
    assert!(shown.contains("run beside them") && !shown.contains("stopped there"), "{shown}");
}

/// Single-scattered light in an isotropic medium with point lights is
/// predicted by the finite-sphere model with the correlations of two
/// spheres that Var L weighs (model bar 0): here q < 1 and N_B = 1, so C₂₃
/// and not C₂₄ (~40 s).
#[test]
fn scattered_light_with_point_lights_is_predicted_exactly_at_any_q() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml")).unwrap();
    let mut scene = Scene::from_toml_str(&text).unwrap();
    (scene.estimator.radius, scene.estimator.forward_rays, scene.estimator.camera_rays) = (0.2, 20, 1);
    let p = predict(&scene).unwrap();
    assert_eq!(p.model, Model::FiniteSphere, "{}", p.model_bar_basis);
    assert_eq!((p.mean.model_bar, p.variance.model_bar), (0.0, 0.0));
    assert!(p.model_bar_basis.contains("correlations of two spheres included"), "{}", p.model_bar_basis);
    let finite = p.report.up_to_order_one().unwrap().finite.as_ref().unwrap();
    assert!(finite.corr23.is_some() && finite.integral_q.is_some() && finite.corr24.is_none(), "{finite:?}");
    let why = finite.not_computed.as_deref().unwrap();
    assert!(why.contains("C₂₄") && why.contains("N_B = 1"), "{why}");
    // The Var L bar is that of a goal of 1e-3 at the loosest.
    assert!(p.variance.quadrature_bar <= 1e-3 * p.variance.value, "{p:?}");
    assert_eq!(p.report.up_to_order_one().unwrap().prediction.model, "finite-sphere");
}

/// When the finite-sphere correlations spend the budget (they run last),
/// `predict` falls back to the small-sphere model with its allowance for
/// R ≤ 0.1 — here with the cross-segment terms of E10 in it, for Var L; the
/// mean is the exact one computed before them, with its bias — and returns the failure beyond
/// (~30 s).
#[test]
fn a_prediction_whose_finite_correlations_fail_falls_back_or_fails_loudly() {
    use mcrt_noise::check::{predict_within, PredictError};
    use mcrt_noise::oracle::{run_within_scoped, Precision, Scope};
    use mcrt_noise::quad::Budget;
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml")).unwrap();
    let mut scene = Scene::from_toml_str(&text).unwrap();
    (scene.estimator.forward_rays, scene.estimator.camera_rays) = (20, 1);
    let tol = Some(1e-4);
    // The budget of everything but the correlations, and a little more.
    let all_but_the_pairs = |scene: &Scene| {
        let first = Budget::new(1_000_000_000);
        run_within_scoped(scene, Precision::F64, tol, &first, Scope::Prediction).unwrap();
        Budget::new(first.used() + 20_000_000)
    };
    scene.estimator.radius = 0.1;
    let p = predict_within(&scene, Precision::F64, tol, &all_but_the_pairs(&scene)).unwrap();
    assert_eq!(p.model, Model::SmallSphere, "{}", p.model_bar_basis);
    let (_, v) = mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE;
    let scale = mcrt_noise::prec::model_error_scale(0.1);
    assert_eq!(p.variance.model_bar, v * scale * p.variance.value);
    let basis = &p.model_bar_basis;
    assert!(basis.contains("with the cross-segment terms") && basis.contains("its computation failed"), "{basis}");
    assert!(basis.contains("budget"), "{basis}");
    // The exact mean was computed before the correlations: it is the
    // prediction's mean (model bar 0), and its bias stays.
    let finite = p.report.up_to_order_one().unwrap().finite_mean.as_ref().expect("the finite-sphere mean");
    let (mean, exact) = (finite.mean.expect("its value"), finite.bias.expect("its bias"));
    assert_eq!((p.mean.value, p.mean.quadrature_bar, p.mean.model_bar), (mean.value, mean.error, 0.0));
    assert!(basis.contains("exact μ(R)"), "{basis}");
    assert_eq!(p.bias.map(|b| (b.value, b.error)), Some((exact.value, exact.error)));
    scene.estimator.radius = 0.2;
    let err = predict_within(&scene, Precision::F64, tol, &all_but_the_pairs(&scene)).unwrap_err();
    assert!(matches!(err, PredictError::Oracle(_)), "{err}");
    assert!(err.to_string().contains("budget"), "{err}");
}

/// What the finite-sphere model does not cover yet (Var L in
/// Henyey–Greenstein media at order 1 with q < 1 or N_B > 1, here q = 0.5,
/// N_B = 8; at q = 1 and N_B = 1 where its computation fails, below) is
/// predicted by the small-sphere
/// model with its measured allowance as the model bar; the mean is the
/// finite-sphere model's exact one (`docs/model.md` §9.9), model bar 0.
#[test]
fn scattered_light_is_predicted_with_the_measured_model_bar() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml")).unwrap();
    let scene = Scene::from_toml_str(&text).unwrap();
    let (_, v) = mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE;
    let scale = mcrt_noise::prec::model_error_scale(scene.estimator.radius);
    // In a Henyey–Greenstein medium the cross-segment terms are not derived:
    // the bar measured without them serves.
    let mut hg = scene.clone();
    hg.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.5 };
    let p = mcrt_noise::check::predict_with(&hg, mcrt_noise::oracle::Precision::F64, Some(1e-4)).unwrap();
    assert_eq!(p.model, Model::SmallSphere);
    let (m0, v0) = mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS;
    assert!(v0 > v);
    let exact = p.report.up_to_order_one().unwrap().finite_mean.as_ref().and_then(|f| f.mean).expect("the exact mean");
    assert_eq!((p.mean.value, p.mean.quadrature_bar, p.mean.model_bar), (exact.value, exact.error, 0.0));
    assert_eq!(p.variance.model_bar, v0 * scale * p.variance.value);
    assert!(p.model_bar_basis.contains("measured with the reference tracer"));
    assert!(p.model_bar_basis.contains("not added"), "{}", p.model_bar_basis);
    assert!(p.model_bar_basis.contains("exact μ(R)"), "{}", p.model_bar_basis);
    // The sign convention: μ(0) = mean − bias is the small-sphere mean.
    let bias = p.bias.expect("the bias");
    let small = p.report.up_to_order_one().unwrap().prediction.mean;
    assert!((p.mean.value - bias.value - small.value).abs() <= bias.error + exact.error + small.error, "{bias:?}");
    // With q = 1 and N_B = 1 the prediction is the finite-sphere model
    // (`oracle::finite_hg_moments_cover`; minutes, so checked against the
    // tracer in tests/finite_order1_hg.rs, ignored). Where its computation
    // fails (here its budget: what the rest of the prediction uses plus
    // 3·10⁸ evaluations, far below its billions; the exact mean, which has
    // a budget of its own of the run's size, needs ~2·10⁸) the small-sphere model serves
    // at R ≤ 0.1; (7)–(9) weigh (23), (24) 0 there, so the model is the same
    // with or without the cross-segment terms: the bar measured with them.
    use mcrt_noise::oracle::{prediction_scope, run_within_scoped, Precision::F64, Scope};
    let mut unpaired = hg.clone();
    (unpaired.estimator.q, unpaired.estimator.camera_rays) = (1.0, 1);
    assert_eq!(prediction_scope(&unpaired, F64).0, Scope::ExactPrediction);
    let rest = mcrt_noise::quad::Budget::new(1_000_000_000);
    run_within_scoped(&unpaired, F64, Some(1e-4), &rest, Scope::Prediction).unwrap();
    let budget = mcrt_noise::quad::Budget::new(rest.used() + 300_000_000);
    let p_un = mcrt_noise::check::predict_within(&unpaired, F64, Some(1e-4), &budget).unwrap();
    assert_eq!(p_un.model, Model::SmallSphere);
    assert!(
        p_un.report.up_to_order_one().unwrap().finite_mean.as_ref().and_then(|f| f.mean).is_some(),
        "the exact mean (its own budget, of the run's size) was lost: {:?}",
        p_un.report.up_to_order_one().unwrap().finite_mean
    );
    let why = p_un.report.up_to_order_one().unwrap().finite_not_used.as_deref().unwrap_or_default();
    assert!(why.contains("its computation failed") && why.contains("budget"), "{why}");
    assert_eq!(p_un.mean.model_bar, 0.0);
    assert_eq!(p_un.variance.model_bar, v * scale * p_un.variance.value);
    assert!(p_un.model_bar_basis.contains("here q = 1 and N_B = 1, where (7)–(9)"), "{}", p_un.model_bar_basis);
    // The bars are subtracted before z: two-point samples 0 and 2a (mean a)
    // with a inside the model bar give z = 0; outside it, z counts the
    // excess only, in units of the null-scaled standard error
    // √((Var L + its bar)/M). A mean with the small-sphere allowance as its
    // model bar (what a prediction without the exact mean has: in MPFR, or
    // where its computation failed) stands in for one.
    let mut p = p;
    p.mean = mcrt_noise::check::Predicted {
        value: p.report.up_to_order_one().unwrap().prediction.mean.value,
        quadrature_bar: p.report.up_to_order_one().unwrap().prediction.mean.error,
        model_bar: m0 * scale * p.report.up_to_order_one().unwrap().prediction.mean.value,
    };
    let two_point = |mean: f64| samples((0..1000).map(|i| if i % 2 == 0 { 0.0 } else { 2.0 * mean }));
    let bar = p.mean.total_bar();
    let inside = check(&p, &two_point(p.mean.value + 0.9 * bar), &CheckOptions::default());
    assert_eq!(inside.checks[0].z, Some(0.0), "{inside}");
    let outside = check(&p, &two_point(p.mean.value + 1.5 * bar), &CheckOptions::default());
    let se = outside.checks[0].measured.unwrap().standard_error;
    let null_se = ((p.variance.value + p.variance.total_bar()) / 1000.0).sqrt();
    let z = outside.checks[0].z.unwrap();
    assert!((z - 0.5 * bar / null_se).abs() < 1e-9 * z, "{outside}");
    // The ratio carries the model bar: m/P ± (|m|·b/|P|)/(|P| − b).
    let ratio = outside.checks[0].ratio.unwrap();
    let (m, pm) = (outside.checks[0].measured.unwrap().value, p.mean.value);
    assert_eq!(ratio.value, m / pm);
    assert_eq!(ratio.standard_error, se / pm);
    assert!((ratio.bar - m * bar / pm / (pm - bar)).abs() < 1e-12 * ratio.bar, "{ratio:?}");
    assert!(ratio.bar > 0.01 * mcrt_noise::prec::model_error_scale(scene.estimator.radius), "{ratio:?}");
}

#[test]
fn too_few_samples_and_unmet_targets_are_not_resolved_with_their_reason() {
    let prediction = predict(&scene()).unwrap();
    let verdict = check(&prediction, &samples([1.0, 2.0, 3.0]), &CheckOptions::default());
    assert_eq!(verdict.status, Status::NotResolved);
    assert!(verdict.checks.is_empty() && verdict.unresolved[0].contains("at least 4"), "{verdict}");
    // A target: the count the verdict names does resolve it (the mean's
    // detectable error depends on the prediction, M and the skewness of L).
    let tracer = Tracer::new(&scene()).unwrap();
    let run = |n: u64| samples((0..n).map(|i| tracer.trial(9, i, HitMethod::Sorted).0));
    let options = CheckOptions::default().with_mean_target(0.02).unwrap();
    let small = check(&prediction, &run(20_000), &options);
    assert_eq!(small.status, Status::NotResolved, "{small}");
    let reason = small.unresolved.iter().find(|r| r.contains("too few samples")).expect("a target reason");
    let needed: f64 = reason.split("about ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    let enough = check(&prediction, &run(needed as u64), &options);
    let achieved = enough.checks[0].detectable_relative_error.unwrap();
    println!("{reason}\nwith {needed} samples: detects {achieved:.6}");
    // The count was computed with the first run's skewness of L, which enters
    // the mean's z at O(γ/√M): the longer run's own differs by its sampling
    // error, so the target is met to within ~1 %.
    assert!((achieved / 0.02 - 1.0).abs() < 0.01, "{enough}");
}

/// Σ L⁵ and Σ L⁶ for test sums that must fail on one of the first four
/// sums' inequalities: large enough to pass the higher ones.
fn with_higher([s1, s2, s3, s4]: [f64; 4]) -> [f64; 6] {
    let s6 = (10.0 * s4 * s4 / s2.max(1e-300) + 1.0).min(1e307);
    [s1, s2, s3, s4, 0.5 * s4.sqrt() * s6.sqrt(), s6]
}

/// Power sums that no real numbers have are refused, naming the inequality;
/// sums of real numbers, rounded as f64 summation rounds them, are not.
#[test]
fn impossible_power_sums_are_refused_naming_the_inequality_they_break() {
    use mcrt_noise::{SampleError, SumsInequality as I};
    let refused = |count: u64, nonzero: Option<u64>, sums: [f64; 4], eps: f64| {
        let s = Samples::from_power_sums(count, with_higher(sums), eps);
        let s = match nonzero {
            Some(k) => s.and_then(|s| s.with_nonzero(k)),
            None => s,
        };
        match s {
            Err(SampleError::Unrealisable { violated, .. }) => Some(violated),
            Err(e) => panic!("{sums:?}: {e}"),
            Ok(_) => None,
        }
    };
    // Each case breaks one inequality and none checked before it (the
    // adversarial probe's two first: Σ L⁴ far above (Σ L²)²).
    let cases = [
        (10_000, None, [11.1, 0.8, 0.5, 1e10], 1e-12, I::FourthSumAtMostSquareOfSecond),
        (100, None, [0.1, 0.01, 0.001, 1e300], 0.0, I::FourthSumAtMostSquareOfSecond),
        (4, None, [10.0, 1.0, 100.0, 354.0], 0.0, I::SquareOfSumAtMostNTimesSumOfSquares),
        (4, None, [0.0, 4.0, 0.0, 1.0], 0.0, I::SquareOfSumOfSquaresAtMostNTimesFourthSum),
        (4, None, [0.0, 4.0, 5.0, 5.0], 0.0, I::SquareOfThirdSumAtMostSecondTimesFourth),
        // 1.1, 1.1, 0.9, 0.9 with Σ L⁴ lowered by 10⁻³: μ₄ < μ₂².
        (4, None, [4.0, 4.04, 4.12, 4.2394], 0.0, I::CentralFourthAtLeastSquareOfSecond),
        // The same with Σ L³ raised by δ = 10⁻³ and Σ L⁴ by 4δ + 10⁻⁵: μ₄ > μ₂², but μ₃ ≠ 0 is too large.
        (4, None, [4.0, 4.04, 4.121, 4.24441], 0.0, I::Pearson),
        // 10, 10, 10, 14 with Σ L⁴ raised by 100: kurtosis above M − 1.
        (4, None, [44.0, 496.0, 5744.0, 68516.0], 0.0, I::CentralFourthAtMostMMinusOneTimesSquare),
        // Negative values: −1, 1, −1 (Σ L < 0); −1, 1 (Σ L = 0, yet Σ L² > 0 needs Σ L·Σ L³ > 0).
        (3, None, [-1.0, 3.0, -1.0, 3.0], 0.0, I::OddSumsNonNegative),
        (2, None, [0.0, 2.0, 0.0, 2.0], 0.0, I::SquareOfSecondAtMostFirstTimesThird),
        // A single value x has Σ L² = x² and Σ L⁴ = x⁴: 2, 4.0000001, 8, 16 are not.
        (1, None, [2.0, 4.0000001, 8.0, 16.0], 0.0, I::SquareOfSumOfSquaresAtMostNTimesFourthSum),
        // Three ones among ten values are not two nonzero values.
        (10, Some(2), [3.0, 3.0, 3.0, 3.0], 0.0, I::SquareOfSumAtMostNTimesSumOfSquares),
        (10, Some(0), [1.0, 1.0, 1.0, 1.0], 0.0, I::SquareOfSumAtMostNTimesSumOfSquares),
        (10, Some(1), [0.0, 0.0, 0.0, 0.0], 0.0, I::NonzeroValuesNeedPositiveSquares),
    ];
    for (count, nonzero, sums, eps, which) in cases {
        assert_eq!(refused(count, nonzero, sums, eps), Some(which), "{count} {nonzero:?} {sums:?}");
    }
    // The message names the inequality, its sides and the allowance.
    let err = Samples::from_power_sums(10_000, with_higher([11.1, 0.8, 0.5, 1e10]), 1e-12).unwrap_err().to_string();
    assert!(
        err.contains("Σ L⁴ ≤ (Σ L²)² must hold, but its left side is 1.00000e10 and its right side 6.40000e-1"),
        "{err}"
    );
    assert!(err.contains("relative error 1e-12"), "{err}");
    // Sums of real numbers in plain f64 summation, with the CLI's default
    // bound (M + 2)·2⁻⁵³, are accepted, including where the inequalities are
    // tight: one nonzero value (Σ L⁴ = (Σ L²)²), two values (μ₄ = μ₂² =
    // μ₄/(M − 1)), one value, equal values, and the tracer's skewed L.
    let tracer = Tracer::new(&scene()).unwrap();
    let traced: Vec<f64> = (0..20_000).map(|i| tracer.trial(5, i, HitMethod::Sorted).0).collect();
    let mut one_hit = vec![0.0; 999];
    one_hit.push(0.123456789);
    let sets: [Vec<f64>; 6] =
        [traced, one_hit, vec![0.3, 0.7], vec![0.1], vec![0.1; 1000], vec![1e-3, 1e-3, 2e-3, 7e-3, 1e-3]];
    for values in sets {
        let m = values.len();
        let sums = [1, 2, 3, 4, 5, 6].map(|k| values.iter().map(|x| x * x.powi(k - 1)).sum::<f64>());
        let nonzero = values.iter().filter(|x| **x != 0.0).count() as u64;
        let eps = (m as f64 + 2.0) * f64::EPSILON / 2.0;
        for k in [Some(nonzero), None] {
            let s = Samples::from_power_sums(m as u64, sums, eps).and_then(|s| match k {
                Some(k) => s.with_nonzero(k),
                None => Ok(s),
            });
            assert!(s.is_ok(), "{m} values: {sums:?}: {:?}", s.err());
        }
    }
    // Exact sums on the boundaries: one nonzero value 0.5 of two; one value.
    let half = [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625];
    assert!(Samples::from_power_sums(2, half, 0.0).and_then(|s| s.with_nonzero(1)).is_ok());
    assert!(Samples::from_power_sums(1, half, 0.0).and_then(|s| s.with_nonzero(1)).is_ok());
    // The fifth and sixth sums: negative, or beyond Cauchy–Schwarz.
    let bad_higher = [
        ([10.0, 30.0, 100.0, 354.0, -1.0, 4890.0], I::HigherSumsNonNegative),
        ([10.0, 30.0, 100.0, 354.0, 1300.0, 4000.0], I::SquareOfFourthAtMostSecondTimesSixth),
        ([10.0, 30.0, 100.0, 354.0, 1400.0, 4890.0], I::SquareOfFifthAtMostFourthTimesSixth),
    ];
    for (sums, which) in bad_higher {
        match Samples::from_power_sums(4, sums, 0.0) {
            Err(SampleError::Unrealisable { violated, .. }) => assert_eq!(violated, which, "{sums:?}"),
            other => panic!("{sums:?}: {other:?}"),
        }
    }
}

/// Values with no spread have no standard error: the verdict fails as not
/// resolved, says why (zero spread, not a large error), and prints no
/// measured number with a 0 bar, in text or JSON.
#[test]
fn values_without_spread_are_not_resolved_and_have_no_zero_bar() {
    let prediction = predict(&scene()).unwrap();
    for values in [vec![0.0; 5], vec![prediction.mean.value; 1000]] {
        let verdict = check(&prediction, &samples(values.iter().copied()), &CheckOptions::default());
        let text = verdict.to_string();
        assert_eq!(verdict.status, Status::NotResolved, "{text}");
        for q in &verdict.checks {
            assert!(q.measured.is_none() && q.z.is_none() && q.ratio.is_none(), "{text}");
            assert!(q.not_resolved.as_ref().is_some_and(|r| r.contains("zero spread")), "{text}");
        }
        assert!(!text.contains("± 0.0e0 (s.e.)") && !text.contains("too large"), "{text}");
        assert!(text.contains(&format!("not resolved: mean L and Var L: all {} values are equal", values.len())));
        let json = serde_json::to_value(&verdict).unwrap();
        for k in 0..2 {
            assert!(json["checks"][k]["measured"].is_null() && json["checks"][k]["ratio"].is_null(), "{json}");
            assert!(json["checks"][k]["not_resolved"].as_str().unwrap().contains("zero spread"), "{json}");
        }
    }
}

/// The ratio measured/predicted is printed with its standard error and its
/// bar, in text and JSON, and a disagreement states the prediction's bars.
#[test]
fn the_ratio_has_its_standard_error_and_bar() {
    let prediction = predict(&scene()).unwrap();
    let tracer = Tracer::new(&scene()).unwrap();
    let bright = samples((0..20_000).map(|i| 1.5 * tracer.trial(21, i, HitMethod::Sorted).0));
    let verdict = check(&prediction, &bright, &CheckOptions::default());
    let text = verdict.to_string();
    for q in &verdict.checks {
        let (m, r) = (q.measured.unwrap(), q.ratio.unwrap());
        let p = q.predicted.value;
        assert_eq!(r.standard_error, m.standard_error / p);
        let b = q.predicted.total_bar();
        assert!(r.bar > 0.0 && (r.bar - m.value * b / p / (p - b)).abs() <= 1e-12 * r.bar, "{r:?}");
        assert!(text.contains(&format!("ratio {r}")), "{text}");
        assert!(text.contains(&format!("{:.5} ± {:.1e} (s.e.) ± {:.1e} (bars)", r.value, r.standard_error, r.bar)));
    }
    assert!(text.contains("fails: mean L") && text.contains("(bars) (ratio 1."), "{text}");
    let json = serde_json::to_value(&verdict).unwrap();
    for k in 0..2 {
        let r = &json["checks"][k]["ratio"];
        assert!(r["value"].is_f64() && r["standard_error"].is_f64() && r["bar"].is_f64(), "{json}");
    }
}

/// Mostly-zero values: below `MIN_NONZERO` nonzero values nothing is
/// resolved, however many zeros; at it the z-tests run. Power sums without
/// a nonzero count say that sparsity was not checked.
#[test]
fn sparse_values_are_not_resolved_below_the_nonzero_threshold() {
    use mcrt_noise::check::MIN_NONZERO;
    let prediction = predict(&scene()).unwrap();
    let tracer = Tracer::new(&scene()).unwrap();
    let hits: Vec<f64> = (0..)
        .map(|i| tracer.trial(33, i, HitMethod::Sorted).0)
        .filter(|l| *l != 0.0)
        .take(MIN_NONZERO as usize)
        .collect();
    // k nonzero values among 10⁵, spread evenly.
    let padded = |k: usize| {
        let mut v = vec![0.0; 100_000];
        for (j, l) in hits[..k].iter().enumerate() {
            v[j * 997] = *l;
        }
        v
    };
    let below = samples(padded(MIN_NONZERO as usize - 1));
    assert_eq!(below.nonzero(), Some(MIN_NONZERO - 1));
    let verdict = check(&prediction, &below, &CheckOptions::default());
    let text = verdict.to_string();
    assert!(!verdict.pass, "{text}");
    for q in &verdict.checks {
        assert!(q.z.is_none() && q.detectable_relative_error.is_none(), "{text}");
        assert!(q.measured.is_some() && q.ratio.is_some(), "{text}");
    }
    assert!(text.contains("not resolved: mean L and Var L: only 99 of the 100000 values are nonzero (fewer than 100)"));
    assert!(text.contains("≈ 1/√99 (10 %)") && text.contains("fourth moment"), "{text}");
    let at = check(&prediction, &samples(padded(MIN_NONZERO as usize)), &CheckOptions::default());
    assert!(at.checks.iter().all(|q| q.z.is_some() && q.not_resolved.is_none()), "{at}");
    assert!(!at.statement.contains("sparsity"), "{at}");
    // Zeros of either sign are zero.
    assert_eq!(samples([0.0, -0.0, 1.0, 2.0]).nonzero(), Some(2));
    // Power sums: the count is unknown unless stated.
    let values = padded(MIN_NONZERO as usize - 1);
    let sums = [1, 2, 3, 4, 5, 6].map(|k| values.iter().map(|x| x.powi(k)).sum::<f64>());
    let eps = 1e-10;
    let unknown = Samples::from_power_sums(values.len() as u64, sums, eps).unwrap();
    let v = check(&prediction, &unknown, &CheckOptions::default());
    assert_eq!(v.nonzero, None);
    assert_eq!(v.status, Status::NotResolved, "{v}");
    assert!(v.unresolved[0].contains("smallest and largest were not given"), "{v}");
    let ranged = unknown.clone().with_range(0.0, hits.iter().copied().fold(0.0, f64::max)).unwrap();
    let v = check(&prediction, &ranged, &CheckOptions::default());
    assert!(v.checks.iter().all(|q| q.z.is_some()), "{v}");
    assert!(v.statement.contains("sparsity could not be checked"), "{v}");
    let stated = unknown.with_nonzero(MIN_NONZERO - 1).unwrap();
    let v = check(&prediction, &stated, &CheckOptions::default());
    assert!(!v.pass && v.unresolved.iter().any(|r| r.contains("only 99 of the 100000 values are nonzero")), "{v}");
}

/// Values far from the prediction's scale: no number is printed as 0, inf
/// or NaN, nor in fixed point with hundreds of digits; a ratio beyond the
/// range of a double is said in words.
#[test]
fn extreme_values_print_no_zero_infinite_or_unreadable_stand_ins() {
    let bright_scene = Scene::builder()
        .medium(1.0, 0.8)
        .point_light([1.0, 0.0, 1.0], 1e10)
        .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        .estimator(0.2, 0.5, 20, 4)
        .build()
        .unwrap();
    for (scene, value) in [(scene(), 1e-170), (bright_scene, 1e-303)] {
        let prediction = predict(&scene).unwrap();
        let values = (0..200).flat_map(|_| [value, 3.0 * value]);
        let verdict = check(&prediction, &samples(values), &CheckOptions::default());
        let text = verdict.to_string();
        assert!(!verdict.pass, "{text}");
        for bad in ["inf", "NaN", " 0.00000 ", "0.000 %", "0.0e0"] {
            assert!(!text.contains(bad), "{bad:?} in\n{text}");
        }
        assert!(text.lines().all(|l| l.len() < 1200), "{text}");
        assert_eq!(verdict.status, Status::Fail, "{text}");
        assert!(verdict.failures[0].starts_with("mean L: measured"), "{text}");
        assert!(verdict.checks[1].not_resolved.as_ref().unwrap().contains("outside the range of a double"), "{text}");
        // The mean's z is scaled by the predicted Var L: finite, ≈ −√400/√(Var L/⟨L⟩²) = −7.7.
        let z = verdict.checks[0].z.unwrap();
        assert!((z + 7.7).abs() < 0.05, "{text}");
        if value == 1e-303 {
            assert!(verdict.checks[0].ratio.is_none(), "{text}");
            assert!(text.contains("ratio beyond the range of a double: 2.000e-303/1.131e7"), "{text}");
        } else {
            // In exponent notation: ratio ≈ 1.8·10⁻¹⁶⁷.
            assert!(text.contains("   ratio 1.7") && text.contains("e-167 ± "), "{text}");
        }
    }
}
