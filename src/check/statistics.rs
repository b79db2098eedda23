//! The two z-scores of the verdict and what follows from them, as pure
//! functions of the samples' shape and the prediction (the null
//! hypothesis):
//!
//! - the mean's z, scaled by the *predicted* Var L (null-scaled: no value
//!   of the samples widens its own yardstick), its skewness removed by
//!   Hall's cubic transformation with the samples' skewness of L;
//! - Var L's z, the studentised s² (the t-statistic of the squared
//!   deviations, whose mean s² is), its skewness removed by Hall's
//!   transformation with the samples' skewness of the squared deviations
//!   (from the sixth moment);
//! - the detectable errors and the sample counts that meet a target;
//! - the tail test: the largest value against the Markov and Cantelli
//!   bounds, which hold for any distribution.
//!
//! Derivations and the calibration: `docs/library.md`, "The statistics".

use super::shape::Shape;
use serde::Serialize;

/// The null hypothesis: the prediction, with the bars (quadrature, model
/// and the samples' rounding) a correct renderer's true moments may lie
/// within.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Null {
    /// Predicted ⟨L⟩.
    pub mean: f64,
    /// Bound on the distance of the true mean from it.
    pub mean_bar: f64,
    /// Predicted Var L.
    pub variance: f64,
    /// Bound on the distance of the true Var L from it (below `variance`).
    pub variance_bar: f64,
}

impl Null {
    /// The prediction as a null hypothesis, its bars widened by the
    /// samples' rounding bars (mean, s²; 0 for exact sums).
    pub fn new(prediction: &super::Prediction, (round_mean, round_var): (f64, f64)) -> Null {
        Null {
            mean: prediction.mean.value,
            mean_bar: prediction.mean.total_bar() + round_mean,
            variance: prediction.variance.value,
            variance_bar: prediction.variance.total_bar() + round_var,
        }
    }

    /// The mean's standard error for a correct renderer, √((Var L + bar)/M):
    /// the largest Var L the bars allow, so that the bars never make the
    /// test stricter.
    pub fn mean_se(&self, count: u64) -> f64 {
        ((self.variance + self.variance_bar) / count as f64).sqrt()
    }

    /// The bar of Var L relative to it, β = bar/Var L.
    fn variance_bar_relative(&self) -> f64 {
        self.variance_bar / self.variance
    }
}

/// Hall's (1992) monotone cubic transformation that removes the first-order
/// skewness of an asymptotically normal statistic:
/// H(x) = x(1 + kx + k²x²/3) + b = ((1 + kx)³ − 1)/(3k) + b, increasing for
/// every x (its derivative is (1 + kx)² ≥ 0), with its exact inverse. For a
/// statistic whose Edgeworth expansion is
/// P(X ≤ x) = Φ(x) − (p₀ + p₂x²)φ(x)/√n + O(1/n), H(X) is normal to
/// O(1/n) with k = p₂/√n and b = p₀/√n, as the two constructors below
/// give.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normaliser {
    k: f64,
    b: f64,
}

impl Normaliser {
    /// For the standardised mean (known variance) of M values of skewness
    /// γ: P(Z ≤ x) = Φ(x) − g(x² − 1)φ(x)/6, g = γ/√M, removed by
    /// H(Z) = Z − gZ²/6 + g²Z³/108 + g/6 (k = −g/6, b = g/6).
    pub fn standardised_mean(skewness: f64, count: u64) -> Normaliser {
        let g = skewness / (count as f64).sqrt();
        Normaliser { k: -g / 6.0, b: g / 6.0 }
    }

    /// For the studentised mean of M values of skewness γ (the
    /// t-statistic): P(T ≤ x) = Φ(x) + g(2x² + 1)φ(x)/6, g = γ/√M,
    /// removed by H(T) = T + gT²/3 + g²T³/27 + g/6 (k = g/3, b = g/6;
    /// Hall 1992, after Johnson 1978).
    pub fn studentised_mean(skewness: f64, count: u64) -> Normaliser {
        let g = skewness / (count as f64).sqrt();
        Normaliser { k: g / 3.0, b: g / 6.0 }
    }

    /// H(x) = x(1 + kx + k²x²/3) + b (no division by k, so no switch at
    /// k = 0).
    pub fn apply(&self, x: f64) -> f64 {
        let kx = self.k * x;
        x * (1.0 + kx + kx * kx / 3.0) + self.b
    }

    /// H⁻¹(h): with c = ∛(1 + 3k(h − b)), x = (c − 1)/k = 3(h − b)/(c² + c + 1)
    /// (the second form has no cancellation as k → 0).
    pub fn invert(&self, h: f64) -> f64 {
        let c = (1.0 + 3.0 * self.k * (h - self.b)).cbrt();
        3.0 * (h - self.b) / (c * c + c + 1.0)
    }
}

/// sign(d)·max(0, |d| − bar): a distance with the bars taken off.
fn beyond_bars(d: f64, bar: f64) -> f64 {
    (d.abs() - bar).max(0.0).copysign(d)
}

/// The mean's z: Z = (mean − ⟨L⟩ ∓ bar)/√((Var L + bar)/M), the standard
/// error a correct renderer's mean has (null-scaled: the samples' own
/// spread does not enter), then H(Z) with the samples' skewness of L
/// ([`Normaliser::standardised_mean`]).
pub fn z_mean(shape: &Shape, null: &Null) -> f64 {
    let z = beyond_bars(shape.mean - null.mean, null.mean_bar) / null.mean_se(shape.count);
    Normaliser::standardised_mean(shape.skewness, shape.count).apply(z)
}

/// Var L's z: the t-statistic of the squared deviations,
/// T = (s² − Var L ∓ bar)/(s²·a), a the relative standard error of s² from
/// the samples' kurtosis ([`Shape::variance_relative_se`]), then H(T) with
/// their skewness ([`Shape::skewness_of_squares`],
/// [`Normaliser::studentised_mean`]). Studentised, because Var L's own
/// scale needs the fourth moment, which the prediction does not give; the
/// skewness of s² (a renderer's d² are very skewed) and the correlation of
/// s² with its estimated error are what Hall's transformation removes to
/// first order (the plain t rejects a correct renderer's low s² several
/// times too often: `docs/library.md`).
pub fn z_variance(shape: &Shape, null: &Null) -> f64 {
    let r = shape.variance_over(null.variance);
    let a = shape.variance_relative_se();
    let t = beyond_bars(r - 1.0, null.variance_bar_relative()) / (r * a);
    Normaliser::studentised_mean(shape.skewness_of_squares(), shape.count).apply(t)
}

/// The smallest relative error δ of the mean, either way, that fails the
/// mean's z-test with probability ≥ the power, for a bug that scales L by
/// 1 ± δ (the samples scaled: Z → (1 ± δ)Z ± δ⟨L⟩/se₀, the shape kept).
/// With H the mean's normaliser, c' = H⁻¹(z_limit), d' = H⁻¹(−z_limit),
/// x = H⁻¹(−z_power), y = H⁻¹(z_power), p = ⟨L⟩/se₀ and β = bar/se₀:
/// up, δ = (c' − x + β)/(p + x); down, δ = (y − d' + β)/(p + y); the
/// larger. `None` when no error is certain to be caught.
pub fn detectable_mean(shape: &Shape, null: &Null, z_limit: f64, z_power: f64) -> Option<f64> {
    let h = Normaliser::standardised_mean(shape.skewness, shape.count);
    let se = null.mean_se(shape.count);
    let (p, beta) = (null.mean.abs() / se, null.mean_bar / se);
    let (x, y) = (h.invert(-z_power), h.invert(z_power));
    let up = (p + x > 0.0).then(|| (h.invert(z_limit) - x + beta) / (p + x));
    let down = (p + y > 0.0).then(|| (y - h.invert(-z_limit) + beta) / (p + y));
    up.zip(down).map(|(u, d)| u.max(d)).filter(|d| d.is_finite() && *d >= 0.0)
}

/// The smallest relative error δ of Var L, either way, that fails Var L's
/// z-test with probability ≥ the power, for a bug that scales Var L by
/// 1 ± δ (the samples scaled: s² → (1 ± δ)s², the shape kept, so that
/// T = (1 − 1/r)/a maps one-to-one between the correct and the scaled
/// samples). With H Var L's normaliser, c' = H⁻¹(z_limit),
/// d' = H⁻¹(−z_limit), x = H⁻¹(−z_power), y = H⁻¹(z_power) and the band
/// [1 − β, 1 + β] of the bars: up, 1 + δ = (1 + β)(1 − ax)/(1 − ac');
/// down, 1 − δ = (1 − β)(1 − ay)/(1 − ad'); the larger. `None` when an
/// error of any size upward is not certain to be caught (ac' ≥ 1).
pub fn detectable_variance(shape: &Shape, null: &Null, z_limit: f64, z_power: f64) -> Option<f64> {
    detectable_variance_at(
        shape.variance_relative_se(),
        shape.skewness_of_squares(),
        shape.count,
        null,
        z_limit,
        z_power,
    )
}

/// [`detectable_variance`] for relative standard error `a` of s² and
/// skewness `skew_squares` of the squared deviations, at `count` samples.
fn detectable_variance_at(
    a: f64,
    skew_squares: f64,
    count: u64,
    null: &Null,
    z_limit: f64,
    z_power: f64,
) -> Option<f64> {
    let h = Normaliser::studentised_mean(skew_squares, count);
    let beta = null.variance_bar_relative();
    let (c, d) = (h.invert(z_limit), h.invert(-z_limit));
    let (x, y) = (h.invert(-z_power), h.invert(z_power));
    if !(a * c < 1.0 && a * x < 1.0) {
        return None;
    }
    let up = (1.0 + beta) * (1.0 - a * x) / (1.0 - a * c) - 1.0;
    let down = 1.0 - (1.0 - beta) * (1.0 - a * y) / (1.0 - a * d);
    Some(up.max(down.min(1.0))).filter(|d| d.is_finite() && *d >= 0.0)
}

/// The number of samples, at least the shape's own count, at which the
/// mean's detectable error is `target` (bisection in log M; the skewness of
/// L held at the samples'). `None` when the bars alone exceed the target.
pub fn samples_for_mean(target: f64, shape: &Shape, null: &Null, z_limit: f64, z_power: f64) -> Option<f64> {
    smallest_count(target, shape.count, |m| detectable_mean(&Shape { count: m, ..*shape }, null, z_limit, z_power))
}

/// The number of samples, at least the shape's own count, at which Var L's
/// detectable error is `target`, for values of this shape (the kurtosis and
/// the skewness of the squared deviations held at the samples'). `None`
/// when the bars alone exceed the target.
pub fn samples_for_variance(target: f64, shape: &Shape, null: &Null, z_limit: f64, z_power: f64) -> Option<f64> {
    smallest_count(target, shape.count, |m| {
        let at = Shape { count: m, ..*shape };
        detectable_variance_at(at.variance_relative_se(), at.skewness_of_squares(), m, null, z_limit, z_power)
    })
}

/// The least M in [`from`, 10³⁰] at which `detectable(M)` ≤ `target`, by
/// bisection in log M (detectable errors fall as M grows from the samples'
/// own count; below it the skewness corrections, fitted at that count, are
/// not meant to be extrapolated).
fn smallest_count(target: f64, from: u64, detectable: impl Fn(u64) -> Option<f64>) -> Option<f64> {
    let meets = |ln_m: f64| detectable(ln_m.exp().ceil() as u64).is_some_and(|d| d <= target);
    let (mut lo, mut hi) = ((from.max(5) as f64).ln(), 1e30f64.ln());
    if !meets(hi) {
        return None;
    }
    if meets(lo) {
        return Some(from.max(5) as f64);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if meets(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi.exp().ceil())
}

/// A bound on the probability that a correct renderer's largest value of
/// `count` reaches `largest`, for any distribution with the predicted mean
/// and variance (each at the end of its bars that favours the renderer):
/// the union bound M·min(Markov, Cantelli), with Markov P(L ≥ x) ≤ ⟨L⟩/x
/// (L ≥ 0) and Cantelli P(L − ⟨L⟩ ≥ t) ≤ σ²/(σ² + t²). At most 1.
pub fn tail_probability(count: u64, largest: f64, null: &Null) -> f64 {
    let mean = null.mean + null.mean_bar;
    let variance = null.variance + null.variance_bar;
    if !(largest > mean) {
        return 1.0;
    }
    let markov = mean / largest;
    let t = largest - mean;
    let cantelli = variance / (variance + t * t);
    (count as f64 * markov.min(cantelli)).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(count: u64) -> Shape {
        Shape { count, mean: 1e-3, sd: 8e-3, skewness: 9.0, kurtosis: 100.0, fifth: 1.5e3, sixth: 2.5e4 }
    }

    #[test]
    fn the_normaliser_inverts_and_is_monotone() {
        for g in [-3.0, -0.1, 0.0, 0.05, 2.0] {
            for n in [Normaliser::standardised_mean(g, 100), Normaliser::studentised_mean(g, 100)] {
                let mut last = f64::NEG_INFINITY;
                for k in -80..=80 {
                    let x = k as f64 / 10.0;
                    let h = n.apply(x);
                    assert!(h >= last, "{n:?} not monotone at {x}");
                    last = h;
                    assert!((n.invert(h) - x).abs() < 1e-9 * x.abs().max(1.0), "{n:?}: {x} → {h}");
                }
            }
        }
    }

    #[test]
    fn the_tail_bound_is_markov_or_cantelli_times_the_count() {
        let null = Null { mean: 1.0, mean_bar: 0.0, variance: 4.0, variance_bar: 0.0 };
        assert_eq!(tail_probability(10, 0.5, &null), 1.0);
        // Cantelli at t = 99: 4/(4 + 99²); Markov 1/100 is larger.
        assert!((tail_probability(10, 100.0, &null) - 10.0 * 4.0 / (4.0 + 99.0 * 99.0)).abs() < 1e-15);
        let wide = Null { variance: 1e6, ..null };
        assert!((tail_probability(10, 100.0, &wide) - 10.0 / 100.0).abs() < 1e-15);
    }

    #[test]
    fn sample_counts_meet_their_targets() {
        let null = Null { mean: 1e-3, mean_bar: 1e-15, variance: 6.6e-5, variance_bar: 1e-16 };
        let (zl, zp) = (3.5, 1.28);
        let m = samples_for_mean(0.1, &shape(5), &null, zl, zp).unwrap();
        assert!(detectable_mean(&shape(m as u64), &null, zl, zp).unwrap() <= 0.1);
        assert!(detectable_mean(&shape(m as u64 - 2), &null, zl, zp).unwrap() > 0.1);
        let m = samples_for_variance(0.2, &shape(5), &null, zl, zp).unwrap();
        assert!(detectable_variance(&shape(m as u64), &null, zl, zp).unwrap() <= 0.2);
        assert!(detectable_variance(&shape(m as u64 - 2), &null, zl, zp).unwrap() > 0.2);
        let tight = Null { mean_bar: 0.2e-3, ..null };
        assert_eq!(samples_for_mean(0.1, &shape(5), &tight, zl, zp), None);
        // Never fewer than the samples have.
        assert_eq!(samples_for_mean(0.5, &shape(10_000_000), &null, zl, zp), Some(1e7));
    }
}
