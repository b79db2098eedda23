//! The family-wise rate of the two z-tests. Their limit is Šidák's, exact
//! for independent z-scores and the largest any correlation gives, and
//! fixed by the stated rate alone (a limit that moved with the samples'
//! correlation would move when a value is added, and a narrow failure could
//! pass by it). A renderer's z-scores are correlated (its mean and Var L
//! both grow with its hits), so the two tests spend less than the stated
//! rate: the verdict says how much, from the samples' correlation.

use super::shape::Shape;

/// The upper tail of the standard normal, Φ̄(x) = erfc(x/√2)/2 (accurate
/// far into the tail: no cancellation).
fn normal_upper(x: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(x / std::f64::consts::SQRT_2)
}

/// Correlations closer to ±1 are taken as ±this (the limit then lies a
/// hair above the exact one: conservative).
const MAX_CORRELATION: f64 = 0.999;

/// The family-wise rate of the two two-sided z-tests at limit `c` when the
/// z-scores are bivariate normal with correlation `rho`:
/// P(|Z₁| > c or |Z₂| > c) = 4Φ̄(c) − P(|Z₁| > c, |Z₂| > c), and by symmetry
/// P(|Z₁| > c, |Z₂| > c) = 2∫_c^∞ φ(x)[Φ̄((c − ρx)/s) + Φ̄((c + ρx)/s)] dx,
/// s = √(1 − ρ²) (Z₂ given Z₁ = x is normal with mean ρx and standard
/// deviation s). With x = c + t the integrand is φ(c)·e^{−ct − t²/2}·[…], so
/// the integral is taken of numbers of order 1 over t ∈ [0, 40] (beyond,
/// e^{−t²/2} < 10⁻³⁴⁷) and scaled by φ(c) after: tiny rates keep their
/// digits, and the subtraction loses at most one bit (P(both) ≤ 2Φ̄(c) for
/// |ρ| ≤ 0.999). The integral by the crate's engine at 10⁻¹⁰ relative;
/// `None` if it does not converge.
pub fn family_rate(c: f64, rho: f64) -> Option<f64> {
    use crate::quad::{integrate, Domain, Options};
    let rho = rho.abs().min(MAX_CORRELATION);
    let s = (1.0 - rho * rho).sqrt();
    let density_at_c = (-0.5 * c * c).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let f = |t: &f64| {
        let x = c + t;
        (-c * t - 0.5 * t * t).exp() * (normal_upper((c - rho * x) / s) + normal_upper((c + rho * x) / s))
    };
    let scaled = integrate(f, &Domain::finite(0.0, 40.0), &Options::rel(1e-10)).ok()?;
    Some(4.0 * normal_upper(c) - 2.0 * density_at_c * scaled.value)
}

/// The |z| limit of [`CHECKS`](super::CHECKS) independent two-sided tests
/// that together fail with probability `rate`: the two-sided normal
/// quantile of 1 − (1 − rate)^{1/CHECKS} (Šidák), from the lower tail.
pub fn sidak_limit(rate: f64) -> f64 {
    -normal_quantile(sidak_split(rate) / 2.0)
}

/// 1 − (1 − rate)^{1/CHECKS}: each test's share of `rate` (Šidák).
pub fn sidak_split(rate: f64) -> f64 {
    -((-rate).ln_1p() / super::CHECKS as f64).exp_m1()
}

/// Φ⁻¹(p), from the lower tail (finite for every p > 0).
fn normal_quantile(p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    Normal::standard().inverse_cdf(p)
}

/// The correlation of the two z-scores under the null hypothesis,
/// corr(mean, s²) = μ₃/√(μ₂(μ₄ − μ₂²)) = γ/√(κ − 1), from the samples'
/// skewness and kurtosis (|ρ| ≤ 1 by Pearson's inequality κ ≥ γ² + 1).
pub fn z_correlation(shape: &Shape) -> f64 {
    let rho = shape.skewness / (shape.kurtosis - 1.0).sqrt();
    if rho.is_finite() {
        rho.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_family_rate_lies_between_one_test_and_independent_ones() {
        let sidak = sidak_limit(0.05);
        assert!((family_rate(sidak, 0.0).unwrap() - 0.05).abs() < 1e-9);
        assert!((sidak - 2.2364).abs() < 1e-3, "{sidak}");
        assert!(
            family_rate(sidak, 0.9).unwrap() < 0.05 && family_rate(sidak, 0.9).unwrap() > 2.0 * normal_upper(sidak)
        );
        assert_eq!(family_rate(sidak, -0.9), family_rate(sidak, 0.9));
        // ρ = 0: independent, 1 − (1 − 2Φ̄(c))²; ρ → 1: one test, 2Φ̄(c) (ρ is
        // capped at 0.999, and far in the tail even that leaves the two apart:
        // between one test's rate and twice it).
        for c in [1.0, 3.5, 20.0, 37.0] {
            let tail = normal_upper(c);
            let independent = 4.0 * tail - 4.0 * tail * tail;
            assert!((family_rate(c, 0.0).unwrap() / independent - 1.0).abs() < 1e-8, "{c}");
            let one = family_rate(c, 1.0).unwrap() / (2.0 * tail);
            assert!(one > 1.0 && one < if c < 4.0 { 1.1 } else { 2.0 }, "{c}: {one}");
            // Šidák's inequality: any correlation lowers the rate.
            for rho in [0.3, 0.6, 0.9] {
                assert!(family_rate(c, rho).unwrap() <= independent * (1.0 + 1e-9), "{c} {rho}");
            }
        }
        // Tiny rates keep their digits.
        let far = sidak_limit(1e-300);
        assert!(far.is_finite() && (family_rate(far, 0.0).unwrap() / 1e-300 - 1.0).abs() < 1e-6, "{far}");
    }
}
