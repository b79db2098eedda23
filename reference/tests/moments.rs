//! The run statistics: exact, order-independent sums; the standard errors of
//! the mean and of the variance (from the fourth moment) checked against a
//! distribution whose moments are known.

use mcrt_reference::moments::PowerSums;
use mcrt_reference::rng::{Draw, Stream};
use mcrt_reference::sampling::exponential;

fn sums(values: &[f64]) -> PowerSums {
    let mut s = PowerSums::default();
    values.iter().for_each(|v| s.push(*v));
    s
}

#[test]
fn small_sample_is_exact() {
    let s = sums(&[1.0, 2.0, 3.0, 4.0]).summary().unwrap();
    assert_eq!(s.mean.value, 2.5);
    assert_eq!(s.variance.value, 5.0 / 3.0);
    assert_eq!(s.mean.se, (5.0f64 / 12.0).sqrt());
}

#[test]
fn sums_do_not_depend_on_the_order_of_addition() {
    // Values over 40 decades: any rounded summation would depend on order.
    let values: Vec<f64> = (0..1000).map(|i| 10f64.powi(i % 40 - 20) * (1.0 + i as f64 / 7.0)).collect();
    let forward = sums(&values);
    let mut reversed: Vec<f64> = values.clone();
    reversed.reverse();
    let halves = sums(&values[..333]).merge(&sums(&values[333..]));
    assert_eq!(forward, sums(&reversed));
    assert_eq!(forward, halves);
    let back = PowerSums::from_hex(forward.count, &forward.to_hex()).unwrap();
    assert_eq!(back, forward);
}

/// For Exp(1): σ² = 1 and μ₄ = 9, so se(s²) → √(8/M) and se(mean) → √(1/M).
#[test]
fn standard_errors_match_the_exponential_distribution() {
    let m = 200_000;
    let mut stream = Stream::new(42, 0);
    let values: Vec<f64> = (0..m).map(|_| exponential(&mut stream, 1.0, Draw::FreePath)).collect();
    let s = sums(&values).summary().unwrap();
    let m = m as f64;
    // The estimates are themselves random. se(mean) ∝ s, with relative sd
    // √((μ₄ − σ⁴)/(4σ⁴M)) = √(2/M) = 0.3 %; se(s²) ≈ √((μ₄ − σ⁴)/M), whose
    // relative sd is ≈ √Var(m̂₄)/(2·8) with Var(m̂₄) ≈ (μ₈ − μ₄²)/M, μ₈ = 14 833
    // for Exp(1) (central): 1.7 %. Bounds: 4 sigma.
    assert!((s.mean.se / (1.0 / m).sqrt() - 1.0).abs() < 0.012, "se(mean) {}", s.mean.se);
    assert!((s.variance.se / (8.0 / m).sqrt() - 1.0).abs() < 0.07, "se(var) {}", s.variance.se);
}

/// Coverage: over 400 independent runs of 2 000 samples, z = (s² − 1)/se(s²)
/// has standard deviation 1 and mean 0 within what 400 runs resolve.
#[test]
fn variance_error_bars_cover_the_truth() {
    let runs = 400;
    let mut zs = Vec::new();
    for r in 0..runs {
        let mut stream = Stream::new(7, r);
        let values: Vec<f64> = (0..2000).map(|_| exponential(&mut stream, 1.0, Draw::FreePath)).collect();
        let s = sums(&values).summary().unwrap();
        zs.push((s.variance.value - 1.0) / s.variance.se);
    }
    let n = zs.len() as f64;
    let mean = zs.iter().sum::<f64>() / n;
    let sd = (zs.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // One sigma of the sample sd is ~1/√(2·400) = 0.035 for normal z; the
    // bounds are ~4 sigma (z is skewed for an exponential's s²).
    assert!((sd - 1.0).abs() < 0.15, "sd of z = {sd}");
    assert!(mean.abs() < 0.2, "mean of z = {mean}");
    let outside = zs.iter().filter(|z| z.abs() > 2.0).count() as f64 / n;
    assert!(outside < 0.1, "{outside} of the runs beyond 2 se");
}

/// Equal values have s² = 0 exactly and no standard error (the powers used
/// to be rounded to doubles before the exact sums: 1000 copies of
/// 1.111498698e−3 gave s² = −3.3e−23 and a NaN standard error).
#[test]
fn equal_values_have_zero_variance_exactly() {
    for l in [1.111498698e-3, 0.1, 1.0 / 3.0, 3.0e-5] {
        let mut sums = mcrt_reference::moments::PowerSums::default();
        for _ in 0..1000 {
            sums.push(l);
        }
        let e = sums.estimates();
        assert!(e.mean.is_err(), "{l}: mean {:?}", e.mean);
        assert!(e.variance.is_err(), "{l}: variance {:?}", e.variance);
        // One different value: s² > 0 with finite standard errors.
        sums.push(l * 2.0);
        let s = sums.estimates().summary().unwrap_or_else(|why| panic!("{l}: {why}"));
        assert!(s.variance.value > 0.0 && s.variance.se.is_finite() && s.mean.se > 0.0, "{l}: {s:?}");
    }
}
