//! The check API on the reference tracer (release mode): calibrated false
//! alarms where the model is exact, the stated power against planted
//! errors of the detectable size, and the failures it owes.
//!
//! The calibration runs the tracer `RUNS` times on disjoint trial ranges of
//! one seed (independent runs), checks each at a family-wise false-alarm
//! rate of 5 % against the finite-sphere model (exact: no model bar), and
//! requires the number of failures to lie within the binomial 99 % interval
//! of 5 % of `RUNS`. The same runs, each shifted by its own detectable error
//! (L scaled by 1 + δ for the mean, by √(1 + δ) for Var L), must fail at
//! least as often as the stated power, within the binomial 99 % interval.

use mcrt_noise::reference::{HitMethod, Tracer};
use mcrt_noise::{check, predict, CheckOptions, Model, Samples, Scene, Verdict};
use rayon::prelude::*;
use statrs::distribution::{Binomial, DiscreteCDF};

/// Independent runs (the issue asks for ≥ 400).
const RUNS: u64 = 400;
/// Trials per run.
const TRIALS: u64 = 20_000;
const SEED: u64 = 2024;

/// Where the finite-sphere model is exact: the README's scene.
fn scene() -> Scene {
    Scene::builder()
        .medium(1.0, 0.8)
        .point_light([1.0, 0.0, 1.0], 1.0)
        .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        .estimator(0.2, 0.5, 20, 4)
        .build()
        .unwrap()
}

/// The 99 % two-sided binomial interval [lo, hi] of failures for `n` runs at rate `p`.
fn binomial_99(n: u64, p: f64) -> (u64, u64) {
    let b = Binomial::new(p, n).unwrap();
    (b.inverse_cdf(0.005), b.inverse_cdf(0.995))
}

/// Every run's values (run k: trials k·TRIALS … (k+1)·TRIALS − 1).
fn runs(scene: &Scene) -> Vec<Vec<f64>> {
    let tracer = Tracer::new(scene).unwrap();
    (0..RUNS)
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
    let options = CheckOptions::new(0.05).unwrap();
    let values = runs(&scene);
    let verdicts: Vec<Verdict> =
        values.par_iter().map(|v| check(&prediction, &samples(v.iter().copied()), &options)).collect();
    let false_alarms = verdicts.iter().filter(|v| !v.pass).count() as u64;
    let (lo, hi) = binomial_99(RUNS, 0.05);
    let z = |k: usize| verdicts.iter().map(|v| v.checks[k].z.unwrap()).collect::<Vec<_>>();
    let moments = |x: &[f64]| {
        let m = x.iter().sum::<f64>() / x.len() as f64;
        (m, (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64).sqrt())
    };
    println!(
        "false alarms {false_alarms}/{RUNS} (99 % interval [{lo}, {hi}]); mean z {:?}, Var z {:?} (mean, sd)",
        moments(&z(0)),
        moments(&z(1))
    );
    assert!((lo..=hi).contains(&false_alarms), "false alarms {false_alarms} outside [{lo}, {hi}]");

    // Power: each run moved by its own detectable error must fail with
    // probability ≥ the power (0.9); its 99 % interval's lower end bounds
    // the count from below.
    let power = options.power();
    let (lo_power, _) = binomial_99(RUNS, power);
    let shifted: Vec<(bool, bool)> = values
        .par_iter()
        .zip(&verdicts)
        .map(|(v, verdict)| {
            let dm = verdict.checks[0].detectable_relative_error.unwrap();
            let mean_off = check(&prediction, &samples(v.iter().map(|l| l * (1.0 + dm))), &options);
            let scale = (1.0 + verdict.checks[1].detectable_relative_error.unwrap()).sqrt();
            let variance_off = check(&prediction, &samples(v.iter().map(|l| l * scale)), &options);
            (mean_off.checks[0].pass, variance_off.checks[1].pass)
        })
        .collect();
    let caught_mean = shifted.iter().filter(|(m, _)| !m).count() as u64;
    let caught_var = shifted.iter().filter(|(_, v)| !v).count() as u64;
    println!("planted errors of the detectable size caught: mean {caught_mean}/{RUNS}, Var L {caught_var}/{RUNS} (need ≥ {lo_power})");
    assert!(caught_mean >= lo_power && caught_var >= lo_power);
}

#[test]
fn predict_validates_a_hand_assembled_scene_and_refuses_what_it_cannot_vouch_for() {
    let mut scene = scene();
    scene.estimator.q = 2.0;
    let err = predict(&scene).unwrap_err().to_string();
    assert!(err.contains("estimator.q = 2: must be in (0, 1]"), "{err}");
    let mut scattered = self::scene();
    scattered.effects.scattering_orders = mcrt_noise::ScatteringOrders::Limited(1);
    let err = predict(&scattered).unwrap_err().to_string();
    assert!(err.contains("estimator.radius = 0.2") && err.contains("R ≤ 0.1"), "{err}");
}

#[test]
fn scattered_light_is_predicted_with_the_measured_model_bar() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml")).unwrap();
    let scene = Scene::from_toml_str(&text).unwrap();
    let p = mcrt_noise::check::predict_with(&scene, mcrt_noise::oracle::Precision::F64, Some(1e-4)).unwrap();
    assert_eq!(p.model, Model::SmallSphere);
    let (m, v) = mcrt_noise::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE;
    let scale = mcrt_noise::prec::model_error_scale(scene.estimator.radius);
    assert_eq!(p.mean.model_bar, m * scale * p.mean.value);
    assert_eq!(p.variance.model_bar, v * scale * p.variance.value);
    assert!(p.model_bar_basis.contains("measured with the reference tracer"));
    // The bars are subtracted before z: two-point samples a ± d with mean
    // inside the model bar give z = 0; outside it, z counts the excess only.
    let two_point = |mean: f64| {
        let d = p.variance.value.sqrt();
        samples((0..1000).map(|i| if i % 2 == 0 { mean + d } else { mean - d }))
    };
    let bar = p.mean.total_bar();
    let inside = check(&p, &two_point(p.mean.value + 0.9 * bar), &CheckOptions::default());
    assert_eq!(inside.checks[0].z, Some(0.0), "{inside}");
    let outside = check(&p, &two_point(p.mean.value + 1.5 * bar), &CheckOptions::default());
    let se = outside.checks[0].measured.unwrap().standard_error;
    let z = outside.checks[0].z.unwrap();
    assert!((z - 0.5 * bar / se).abs() < 1e-6 * z, "{outside}");
    // The ratio carries the model bar: m/P ± (|m|·b/|P|)/(|P| − b).
    let ratio = outside.checks[0].ratio.unwrap();
    let (m, pm) = (outside.checks[0].measured.unwrap().value, p.mean.value);
    assert_eq!(ratio.value, m / pm);
    assert_eq!(ratio.standard_error, se / pm);
    assert!((ratio.bar - m * bar / pm / (pm - bar)).abs() < 1e-12 * ratio.bar, "{ratio:?}");
    assert!(ratio.bar > 0.01 * mcrt_noise::prec::model_error_scale(scene.estimator.radius), "{ratio:?}");
}

#[test]
fn too_few_samples_and_unmet_targets_fail_with_their_reason() {
    let prediction = predict(&scene()).unwrap();
    let verdict = check(&prediction, &samples([1.0, 2.0, 3.0]), &CheckOptions::default());
    assert!(!verdict.pass && verdict.checks.is_empty() && verdict.reasons[0].contains("at least 4"), "{verdict}");
    // A target: the count the failure names does resolve it (standard errors
    // estimated from 20 000 samples, so within a few per cent).
    let tracer = Tracer::new(&scene()).unwrap();
    let run = |n: u64| samples((0..n).map(|i| tracer.trial(9, i, HitMethod::Sorted).0));
    let options = CheckOptions::default().with_mean_target(0.02).unwrap();
    let small = check(&prediction, &run(20_000), &options);
    assert!(!small.pass, "{small}");
    let reason = small.reasons.iter().find(|r| r.contains("too few samples")).expect("a target reason");
    let needed: f64 = reason.split("about ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    let enough = check(&prediction, &run(needed as u64), &options);
    let achieved = enough.checks[0].detectable_relative_error.unwrap();
    println!("{reason}\nwith {needed} samples: detects {achieved:.4}");
    assert!((achieved / 0.02 - 1.0).abs() < 0.05, "{enough}");
}

/// Power sums that no real numbers have are refused, naming the inequality;
/// sums of real numbers, rounded as f64 summation rounds them, are not.
#[test]
fn impossible_power_sums_are_refused_naming_the_inequality_they_break() {
    use mcrt_noise::{SampleError, SumsInequality as I};
    let refused = |count: u64, nonzero: Option<u64>, sums: [f64; 4], eps: f64| {
        let s = Samples::from_power_sums(count, sums, eps);
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
    let err = Samples::from_power_sums(10_000, [11.1, 0.8, 0.5, 1e10], 1e-12).unwrap_err().to_string();
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
        let sums = [1, 2, 3, 4].map(|k| values.iter().map(|x| x * x.powi(k - 1)).sum::<f64>());
        let nonzero = values.iter().filter(|x| **x != 0.0).count() as u64;
        let eps = (m as f64 + 2.0) * f64::EPSILON / 2.0;
        assert_eq!(refused(m as u64, Some(nonzero), sums, eps), None, "{m} values: {sums:?}");
        assert_eq!(refused(m as u64, None, sums, eps), None, "{m} values: {sums:?}");
    }
    // Exact sums on the boundaries: one nonzero value 0.5 of two; one value.
    assert_eq!(refused(2, Some(1), [0.5, 0.25, 0.125, 0.0625], 0.0), None);
    assert_eq!(refused(1, Some(1), [0.5, 0.25, 0.125, 0.0625], 0.0), None);
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
        assert!(!verdict.pass, "{text}");
        for q in &verdict.checks {
            assert!(q.measured.is_none() && q.z.is_none() && q.ratio.is_none(), "{text}");
            assert!(q.not_resolved.as_ref().is_some_and(|r| r.contains("zero spread")), "{text}");
        }
        assert!(!text.contains("± 0.0e0 (s.e.)") && !text.contains("too large"), "{text}");
        assert!(text.contains(&format!("mean L and Var L: not resolved: all {} values are equal", values.len())));
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
    assert!(text.contains("mean L and Var L: not resolved: only 99 of the 100000 values are nonzero (fewer than 100)"));
    assert!(text.contains("≈ 1/√99 (10 %)") && text.contains("fourth moment"), "{text}");
    let at = check(&prediction, &samples(padded(MIN_NONZERO as usize)), &CheckOptions::default());
    assert!(at.checks.iter().all(|q| q.z.is_some() && q.not_resolved.is_none()), "{at}");
    assert!(!at.statement.contains("sparsity"), "{at}");
    // Zeros of either sign are zero.
    assert_eq!(samples([0.0, -0.0, 1.0, -2.0]).nonzero(), Some(2));
    // Power sums: the count is unknown unless stated.
    let values = padded(MIN_NONZERO as usize - 1);
    let sums = [1, 2, 3, 4].map(|k| values.iter().map(|x| x.powi(k)).sum::<f64>());
    let eps = 1e-10;
    let unknown = Samples::from_power_sums(values.len() as u64, sums, eps).unwrap();
    let v = check(&prediction, &unknown, &CheckOptions::default());
    assert_eq!(v.nonzero, None);
    assert!(v.checks.iter().all(|q| q.z.is_some()), "{v}");
    assert!(v.statement.contains("sparsity could not be checked"), "{v}");
    let stated = unknown.with_nonzero(MIN_NONZERO - 1).unwrap();
    let v = check(&prediction, &stated, &CheckOptions::default());
    assert!(!v.pass && v.reasons.iter().any(|r| r.contains("only 99 of the 100000 values are nonzero")), "{v}");
}

/// Values far from the prediction's scale: no number is printed as 0, inf
/// or NaN, nor in fixed point with hundreds of digits; a z beyond the range
/// of a double fails with that reason.
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
        assert!(verdict.reasons[0].starts_with("mean L: measured"), "{text}");
        assert!(verdict.checks[1].not_resolved.as_ref().unwrap().contains("outside the range of a double"), "{text}");
        if value == 1e-303 {
            assert!(verdict.checks[0].z.is_none() && verdict.checks[0].ratio.is_none(), "{text}");
            assert!(verdict.reasons[0].contains("|z| beyond the range of a double"), "{text}");
            assert!(verdict.statement.starts_with("the renderer's mean L differs"), "{text}");
        } else {
            // In exponent notation: z ≈ −2.3·10¹⁶⁸, ratio ≈ 1.8·10⁻¹⁶⁷.
            assert!(text.contains("   z -2.2") && text.contains("e168   detects"), "{text}");
            assert!(text.contains("   ratio 1.7") && text.contains("e-167 ± "), "{text}");
        }
    }
}
