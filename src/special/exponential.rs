//! Integrals of exponentials over a segment and over a triangle: the
//! closed forms of the finite-sphere model's per-ray functionals
//! (`model::finite`, `docs/model.md` §9).
//!
//! - [`exp_segment`]`(r, L)` = ∫₀^L e^{−r x} dx = L·e[0, −rL], the first
//!   divided difference of exp (scaled);
//! - [`exp_triangle`]`(r₁, r₂, L)` = ∫∫_{0<x<x′<L} e^{−(r₂−r₁)x − r₁x′} dx dx′
//!   = L²·e[0, −r₁L, −r₂L] (Hermite–Genocchi), the second divided
//!   difference, symmetric in r₁ ↔ r₂;
//!
//! for rates r ≥ 0 and L ∈ [0, ∞] (`None` for ∞). Both are evaluated
//! without cancellation: the second by its Taylor series in the nodes when
//! they span at most 1, and otherwise by the recursion
//! [F₁(p) − e^{−pL} F₁(q − p)]/q (p ≤ q the two rates), whose subtraction
//! loses at most a factor ≈ 3 (the two divided differences it subtracts are
//! means of eˣ over adjacent intervals of total length ≥ 1). Accuracy in f64
//! against MPFR: `tests/special_functions.rs`.

use crate::real::Real;

/// ∫₀^L e^{−r x} dx for r ≥ 0 and L ≥ 0 (`len` = `None`: L = ∞, then
/// 1/r; requires r > 0). Domain: r ≥ 0, L ≥ 0; NaN outside it.
pub fn exp_segment<T: Real>(rate: &T, len: Option<&T>) -> T {
    let zero = rate.lit(0.0);
    if !(rate.clone() >= zero) || len.is_some_and(|l| !(l.clone() >= zero)) {
        return rate.lit(f64::NAN);
    }
    let Some(len) = len.filter(|l| l.is_finite()) else {
        return rate.lit(1.0) / rate.clone();
    };
    let x = rate.clone() * len.clone();
    if x.is_zero() {
        return len.clone();
    }
    -(-x).exp_m1() / rate.clone()
}

/// ∫∫_{0<x<x′<L} e^{−(r₂−r₁)x − r₁x′} dx dx′ = (F₁(r₁) − F₁(r₂))/(r₂ − r₁)
/// with F₁ = [`exp_segment`], symmetric in the rates. Domain: r₁, r₂ ≥ 0,
/// L ≥ 0 (`None`: ∞, then 1/(r₁r₂), which requires both > 0); NaN outside.
pub fn exp_triangle<T: Real>(r1: &T, r2: &T, len: Option<&T>) -> T {
    let zero = r1.lit(0.0);
    if !(r1.clone() >= zero) || !(r2.clone() >= zero) || len.is_some_and(|l| !(l.clone() >= zero)) {
        return r1.lit(f64::NAN);
    }
    let (p, q) = if r1 <= r2 { (r1.clone(), r2.clone()) } else { (r2.clone(), r1.clone()) };
    let Some(len) = len.filter(|l| l.is_finite()) else {
        return r1.lit(1.0) / (p * q);
    };
    let big_q = q.clone() * len.clone();
    if big_q <= r1.lit(1.0) {
        let big_p = p * len.clone();
        return len.clone() * len.clone() * second_difference_series(&big_p, &big_q);
    }
    let head = exp_segment(&p, Some(len));
    let tail = (-(p.clone() * len.clone())).exp() * exp_segment(&(q.clone() - p), Some(len));
    (head - tail) / q
}

/// e[0, −P, −Q] = Σ_{k≥0} (−1)^k S_k/(k + 2)!, S_k = Σ_{i=0}^k P^i Q^{k−i},
/// for 0 ≤ P ≤ Q ≤ 1: the terms fall at least like (k + 1)/(k + 2)!, the
/// sum is ≥ e^{−1}/2 while the largest term is 1/2, so at most ~1.5 bits
/// cancel.
fn second_difference_series<T: Real>(big_p: &T, big_q: &T) -> T {
    let eps = big_p.eps();
    let mut s_k = big_p.lit(1.0); // S_0
    let mut p_pow = big_p.lit(1.0); // P^k
    let mut factorial = big_p.lit(2.0); // (k + 2)!
    let mut sum = big_p.lit(0.5);
    for k in 1..200u32 {
        p_pow = p_pow * big_p.clone();
        s_k = big_q.clone() * s_k + p_pow.clone();
        factorial = factorial * big_p.lit(f64::from(k + 2));
        let term = s_k.clone() / factorial.clone();
        sum = if k % 2 == 1 { sum - term.clone() } else { sum + term.clone() };
        if term <= eps.clone() * sum.abs() * big_p.lit(0.125) {
            break;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct definitions, for the well-conditioned cases.
    fn triangle_direct(r1: f64, r2: f64, l: f64) -> f64 {
        (exp_segment(&r1, Some(&l)) - exp_segment(&r2, Some(&l))) / (r2 - r1)
    }

    #[test]
    fn segment_limits() {
        assert_eq!(exp_segment(&0.0, Some(&3.0)), 3.0);
        assert!((exp_segment(&2.0, None) - 0.5).abs() < 1e-16);
        assert!((exp_segment(&1e-20, Some(&1.0)) - 1.0).abs() < 1e-16);
        assert!(exp_segment(&-1.0, Some(&1.0)).is_nan());
    }

    #[test]
    fn triangle_matches_the_direct_form_where_that_is_well_conditioned() {
        for (r1, r2, l) in [(1.0, 3.0, 2.0), (0.5, 7.0, 1.3), (2.0, 0.1, 5.0), (0.0, 4.0, 0.9)] {
            let (a, b) = (exp_triangle(&r1, &r2, Some(&l)), triangle_direct(r1, r2, l));
            assert!((a - b).abs() <= 1e-14 * b, "{r1} {r2} {l}: {a} vs {b}");
            assert_eq!(a, exp_triangle(&r2, &r1, Some(&l)));
        }
    }

    #[test]
    fn triangle_limits() {
        // Equal rates: ∫₀^L x e^{−r x} dx; zero rates: L²/2; L = ∞: 1/(r₁ r₂).
        let (r, l) = (0.7f64, 1.1f64);
        let exact = (1.0 - (1.0 + r * l) * (-r * l).exp()) / (r * r);
        assert!((exp_triangle(&r, &r, Some(&l)) - exact).abs() <= 1e-15 * exact);
        assert_eq!(exp_triangle(&0.0, &0.0, Some(&2.0)), 2.0);
        assert!((exp_triangle(&2.0, &5.0, None) - 0.1).abs() < 1e-16);
        assert!((exp_triangle(&2.0, &5.0, Some(&1e300)) - 0.1).abs() < 1e-16);
        let tiny = exp_triangle(&1.0, &2.0, Some(&1e-9));
        assert!((tiny - 0.5e-18).abs() <= 1e-8 * 0.5e-18, "{tiny}");
    }
}
