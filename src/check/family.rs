//! The family-wise limit of the two z-tests: their z-scores are correlated
//! (a renderer's mean and Var L move together: both grow with the number of
//! hits), so Šidák's split, exact for independent tests, would spend less
//! than the stated rate. The limit here spends it exactly for bivariate
//! normal z-scores with the samples' estimated correlation.

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
/// P(|Z₁| > c or |Z₂| > c) = 2Φ̄(c) + 2∫₀^c φ(x)[Φ̄((c − ρx)/s) + Φ̄((c + ρx)/s)] dx,
/// s = √(1 − ρ²) (Z₂ given Z₁ = x is normal with mean ρx and standard
/// deviation s; every term is a positive tail, so tiny rates keep their
/// digits). The integral by the crate's engine at 10⁻⁹ relative; `None`
/// if it does not converge.
pub fn family_rate(c: f64, rho: f64) -> Option<f64> {
    use crate::quad::{integrate, Domain, Options};
    let rho = rho.abs().min(MAX_CORRELATION);
    let s = (1.0 - rho * rho).sqrt();
    let density = |x: f64| (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let f = |x: &f64| density(*x) * (normal_upper((c - rho * x) / s) + normal_upper((c + rho * x) / s));
    let inner = integrate(f, &Domain::finite(0.0, c), &Options::rel(1e-9)).ok()?;
    Some(2.0 * normal_upper(c) + 2.0 * inner.value)
}

/// The |z| limit at which the two z-tests, correlated by `rho`, fail a
/// correct renderer with probability `rate` together: the root of
/// [`family_rate`] between the limit of one test alone (ρ = ±1) and
/// Šidák's (ρ = 0, the largest: Šidák's inequality), by bisection on the
/// log of the rate. Šidák's limit when the rate's integral does not
/// converge (conservative).
pub fn z_limit_for(rate: f64, rho: f64) -> f64 {
    let single = -normal_quantile(rate / 2.0);
    let sidak = -normal_quantile(-((-rate).ln_1p() / 2.0).exp_m1() / 2.0);
    let (mut lo, mut hi) = (single, sidak);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        match family_rate(mid, rho) {
            Some(r) if r > rate => lo = mid,
            Some(_) => hi = mid,
            None => return sidak,
        }
    }
    hi
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
    fn the_family_limit_lies_between_one_test_and_sidak() {
        // ρ = 0: Šidák exactly; larger |ρ|: smaller limits, down towards one test's.
        let sidak = z_limit_for(0.05, 0.0);
        assert!((family_rate(sidak, 0.0).unwrap() - 0.05).abs() < 1e-9);
        assert!((sidak - 2.2364).abs() < 1e-3, "{sidak}");
        let correlated = z_limit_for(0.05, 0.9);
        assert!(correlated < sidak && correlated > 1.96, "{correlated}");
        assert_eq!(z_limit_for(0.05, -0.9), correlated);
        // Tiny rates keep their digits.
        let far = z_limit_for(1e-300, 0.5);
        assert!(far.is_finite() && (family_rate(far, 0.5).unwrap() / 1e-300 - 1.0).abs() < 1e-6, "{far}");
    }
}
