//! The area common to two discs: the hit probability of a beam's rays at a
//! finite sphere (`model::finite`, `docs/model.md` §9).

use super::overlap::overlap_a_gap;
use crate::real::Real;

/// Area of the intersection of two discs of radii r₁, r₂ > 0 whose centres
/// are `dist` ≥ 0 apart. Domain: radii > 0, dist ≥ 0 (NaN otherwise).
///
/// The lens is the union of two circular segments cut by the common chord,
/// of heights h₁ = (r₁ + r₂ − D)(r₂ + D − r₁)/(2D) and
/// h₂ = (r₁ + r₂ − D)(r₁ + D − r₂)/(2D) (each from its own disc), so
/// area = r₁² A(1 − h₁/r₁) + r₂² A(1 − h₂/r₂) with A the unit segment area
/// ([`overlap_a_gap`]). Forming the heights from the products, not as
/// rᵢ − dᵢ, keeps a sliver (a disc of radius 10⁻⁸ at the edge of one of
/// radius 0.5, whose segment height is ~10⁻¹⁶) at full relative accuracy.
/// For r₁ = r₂ = R it is 2R² A(D/2R) (§4.3, `docs/errata.md` E2).
pub fn disc_overlap<T: Real>(r1: &T, r2: &T, dist: &T) -> T {
    let zero = r1.lit(0.0);
    if !(r1.clone() > zero && r2.clone() > zero && dist.clone() >= zero) {
        return r1.lit(f64::NAN);
    }
    let gap = sum_less(r1, r2, dist);
    if !(gap > zero) {
        return zero;
    }
    let small = r1.clone().min_of(r2.clone());
    if !(dist.clone() > (r1.clone() - r2.clone()).abs()) {
        return r1.pi() * small.clone() * small;
    }
    let two_d = dist.lit(2.0) * dist.clone();
    let h1 = gap.clone() * sum_less(r2, dist, r1) / two_d.clone();
    let h2 = gap * sum_less(r1, dist, r2) / two_d;
    let segment = |r: &T, h: &T| {
        let u = (h.clone() / r.clone()).min_of(r.lit(2.0)).max_of(r.lit(0.0));
        r.clone() * r.clone() * overlap_a_gap(&u)
    };
    segment(r1, &h1) + segment(r2, &h2)
}

/// a + b − c for a, b, c > 0, subtracting c from whichever of a, b is
/// nearer to it first (exact by Sterbenz when they are close): the heights
/// of the segments cancel there (equal radii at small D; a small disc at the
/// edge of a large one).
fn sum_less<T: Real>(a: &T, b: &T, c: &T) -> T {
    if (a.clone() - c.clone()).abs() <= (b.clone() - c.clone()).abs() {
        (a.clone() - c.clone()) + b.clone()
    } else {
        (b.clone() - c.clone()) + a.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::overlap_a;

    /// Against 2R²A(l/2R) evaluated at 256 bits from the same f64 inputs
    /// (in f64 that reference itself loses digits near tangency).
    #[test]
    fn equal_radii_give_the_papers_overlap() {
        let r = 0.3f64;
        for l in [0.0, 1e-9, 0.01, 0.2, 0.4, 0.59, 0.6 - 1e-12, 0.6, 0.7] {
            let big = |v: f64| rug::Float::with_val(256, v);
            let x = big(l) / (big(2.0) * big(r));
            let reference = if l >= 2.0 * r { 0.0 } else { (big(2.0) * big(r) * big(r) * overlap_a(&x)).to_f64() };
            let a = disc_overlap(&r, &r, &l);
            assert!((a - reference).abs() <= 4.0 * f64::EPSILON * reference, "l = {l}: {a} vs {reference}");
        }
    }

    #[test]
    fn containment_disjointness_and_symmetry() {
        let pi = std::f64::consts::PI;
        assert_eq!(disc_overlap(&0.1, &1.0, &0.5), pi * 0.01);
        assert_eq!(disc_overlap(&1.0, &0.1, &0.9), pi * 0.01);
        assert_eq!(disc_overlap(&0.1, &1.0, &1.1), 0.0);
        assert_eq!(disc_overlap(&0.2, &0.7, &0.6), disc_overlap(&0.7, &0.2, &0.6));
        assert!(disc_overlap(&-1.0, &1.0, &0.5).is_nan());
    }

    /// A tiny disc centred on the edge of a large one: half of it is inside
    /// the tangent line, less the sliver between tangent and arc,
    /// ∫₋ᵣʳ x²/(2·big) dx = r³/(3·big): area/half − 1 = −2r/(3π·big) + O(r²).
    #[test]
    fn sliver_at_the_edge_of_a_large_disc() {
        let (r, big) = (1e-8f64, 0.5f64);
        let half = std::f64::consts::PI * r * r / 2.0;
        let rel = disc_overlap(&r, &big, &big) / half - 1.0;
        let expected = -2.0 * r / (3.0 * std::f64::consts::PI * big);
        assert!((rel - expected).abs() < 1e-14, "{rel:e} vs {expected:e}");
    }
}
