//! Where a ray-centric integrand has its kinks: the angles ϑ ∈ (0, π) at
//! which A sin ϑ + B cos ϑ = C, returned as (ϑ, π − ϑ), each accurate where
//! it is small, so that a kink near either pole lands on the right side of
//! `crate::model::angular::Halves`.

use crate::real::Real;

/// The roots ϑ ∈ (0, π) of A sin ϑ + B cos ϑ = C, as (ϑ, π − ϑ).
///
/// With t = tan(ϑ/2) the equation is (B + C)t² − 2At + (C − B) = 0, whose
/// roots are taken in the stable form t₁ = q/(B + C), t₂ = (C − B)/q,
/// q = A + sgn(A)√D, and their reciprocals likewise (1/t₁ = (B + C)/q,
/// 1/t₂ = q/(C − B)), so that ϑ = 2 arctan t and π − ϑ = 2 arctan(1/t) are
/// both accurate. The caller passes B + C, C − B and the discriminant
/// D = A² + B² − C², each formed without cancellation from its geometry
/// (a difference of squares computed as a product). Roots with t ≤ 0 (ϑ
/// outside (0, π)) and the degenerate double root at D = A = 0 are dropped.
pub fn roots<T: Real>(a: &T, b_plus_c: &T, c_minus_b: &T, disc: &T) -> Vec<(T, T)> {
    let zero = a.lit(0.0);
    if disc.clone() < zero || !disc.is_finite() {
        return Vec::new();
    }
    let root = disc.sqrt();
    let q = if a.clone() < zero { a.clone() - root } else { a.clone() + root };
    if q.is_zero() {
        return Vec::new();
    }
    let two = a.lit(2.0);
    // (t, 1/t) for both roots.
    let pairs = [
        (q.clone() / b_plus_c.clone(), b_plus_c.clone() / q.clone()),
        (c_minus_b.clone() / q.clone(), q / c_minus_b.clone()),
    ];
    pairs
        .into_iter()
        .filter(|(t, inv)| *t > zero && *inv > zero && t.is_finite() && inv.is_finite())
        .map(|(t, inv)| (two.clone() * t.atan(), two.clone() * inv.atan()))
        .collect()
}

/// (x + y, x − y) for x² − y² = `diff_sq` given without cancellation: the
/// larger in magnitude directly, the other as `diff_sq` over it.
pub fn sum_and_difference<T: Real>(x: &T, y: &T, diff_sq: &T) -> (T, T) {
    let (sum, diff) = (x.clone() + y.clone(), x.clone() - y.clone());
    if sum.abs() >= diff.abs() {
        let d = if sum.is_zero() { diff } else { diff_sq.clone() / sum.clone() };
        (sum, d)
    } else {
        (diff_sq.clone() / diff.clone(), diff)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(a: f64, b: f64, c: f64) {
        let found = roots(&a, &(b + c), &(c - b), &(a * a + b * b - c * c));
        for (t, tc) in &found {
            assert!((t + tc - std::f64::consts::PI).abs() < 1e-15);
            assert!((a * t.sin() + b * t.cos() - c).abs() < 1e-14, "{a} {b} {c}: ϑ = {t}");
        }
        // Every sign change on a fine grid is one of the roots.
        let n = 100_000;
        let g = |t: f64| a * t.sin() + b * t.cos() - c;
        let mut changes = 0;
        for i in 1..n {
            let (t0, t1) =
                (std::f64::consts::PI * (i - 1) as f64 / n as f64, std::f64::consts::PI * i as f64 / n as f64);
            if i > 1 && g(t0).signum() != g(t1).signum() {
                changes += 1;
            }
        }
        assert_eq!(changes, found.len(), "{a} {b} {c}: {found:?}");
    }

    #[test]
    fn roots_of_sinusoids() {
        for (a, b, c) in
            [(1.0, 0.5, 0.3), (1.0, 0.5, -0.3), (-0.7, 0.2, 0.1), (0.0, 1.0, 0.4), (2.0, -1.0, 0.0), (0.3, 0.1, 5.0)]
        {
            check(a, b, c);
        }
    }

    #[test]
    fn a_root_near_the_pole_keeps_its_distance_from_it() {
        // sin ϑ·1 + cos ϑ·(−1) = −1 + 2·10⁻⁹·…: the root near π, given
        // exactly through B + C and C − B.
        let (a, b) = (1.0f64, 1e-6f64);
        // ϑ with A sin ϑ + B cos ϑ = C = −B + δ, δ = 10⁻¹²: near ϑ = π,
        // π − ϑ ≈ δ/A... and a second root near ϑ = 0 at ϑ ≈ (C − B)/A.
        let delta = 1e-12;
        let found = roots(&a, &delta, &(-2.0 * b + delta), &(a * a + b * b - (delta - b) * (delta - b)));
        let near_pi = found.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        // tan((π − ϑ)/2)·… : 2 arctan(1/t) with 1/t = (B + C)/q = δ/(2A).
        assert!((near_pi - delta).abs() < 1e-24, "{near_pi:e}");
    }
}
