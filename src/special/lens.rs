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

/// The angle Θ ∈ [0, 2π] of the circle of radius ρ about a point `dist`
/// from the centre of a disc of radius a that lies inside that disc:
/// ρΘ(ρ) dρ is the disc's area between the circles of radii ρ and ρ + dρ
/// (so ∫₀^R ρΘ dρ = [`disc_overlap`](R, a, dist)). Domain: ρ ≥ 0, a > 0,
/// dist ≥ 0 (NaN otherwise).
///
/// Θ = 2π where the circle lies inside (ρ + dist ≤ a), 0 where it lies
/// outside or encloses the disc, else 2α with cos α = (ρ² + dist² − a²)/(2ρ·dist),
/// formed as α = 2 atan(√((1 − cos α)/(1 + cos α))) from the products
/// (a − ρ + dist)(a + ρ − dist) and (ρ + dist − a)(ρ + dist + a), so that the
/// √-kinks at ρ = |a − dist| and a + dist keep their relative accuracy.
pub fn arc_in_disc<T: Real>(rho: &T, a: &T, dist: &T) -> T {
    // ρ − (a − dist) or ρ − (dist − a).
    let to_near = if a >= dist { sum_less(rho, dist, a) } else { sum_less(rho, a, dist) };
    arc_in_disc_gaps(rho, a, dist, &to_near, &sum_less(a, dist, rho))
}

/// [`arc_in_disc`] with the circle's distances to its kinks given:
/// `to_near` = ρ − |a − dist| and `to_far` = a + dist − ρ, formed by a
/// caller that knows them better than ρ's rounding (the shells of
/// `model::beam_source`, where ρ = d√(1 − c²) is itself rounded). Domain as
/// [`arc_in_disc`].
pub fn arc_in_disc_gaps<T: Real>(rho: &T, a: &T, dist: &T, to_near: &T, to_far: &T) -> T {
    let zero = rho.lit(0.0);
    if !(rho.clone() >= zero && a.clone() > zero && dist.clone() >= zero) {
        return rho.lit(f64::NAN);
    }
    // The factors of 1 ∓ cos α: a + dist − ρ, a + ρ − dist, ρ + dist − a;
    // the second or the third is ρ − |a − dist|, the other ρ + |a − dist|.
    let near = (a.clone() - dist.clone()).abs();
    let (f2, f3) =
        if dist >= a { (to_near.clone(), rho.clone() + near) } else { (rho.clone() + near, to_near.clone()) };
    if f3 <= zero {
        return rho.lit(2.0) * rho.pi();
    }
    let inner = to_far.clone() * f2;
    if !(inner > zero) {
        return zero;
    }
    let outer = f3 * (rho.clone() + dist.clone() + a.clone());
    let (y, x) = (inner.sqrt(), outer.sqrt());
    // atan2(y, x) for x, y > 0, through the smaller ratio.
    let half = if y <= x { (y / x).atan() } else { rho.pi() / rho.lit(2.0) - (x / y).atan() };
    rho.lit(4.0) * half
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

    /// Against 2R²A(l/2R) evaluated at 256 bits from the same f64 inputs
    /// (in f64 that reference itself loses digits near tangency).
    #[test]
    #[cfg(feature = "mpfr")]
    fn equal_radii_give_the_papers_overlap() {
        use crate::special::overlap_a;
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
