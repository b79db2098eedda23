//! The circle-overlap function A(x) of §4.3 and its two integrals.
//!
//! Two discs of radius R whose centres are l apart overlap in the area
//! 2R² A(l / 2R), with A(x) = arccos x − x√(1−x²) for 0 ≤ x ≤ 1 and 0 beyond.
//! A'(x) = −2√(1−x²), so A(x) = 2∫ₓ¹ √(1−t²) dt; with u = 1 − x this is
//! A = 2√2 u^{3/2} Σ_k C(1/2,k)(−1/2)^k u^k / (k + 3/2), which we use near
//! x = 1, where the two terms of the closed form cancel (both ~ √(2u)).

use super::series::{sqrt_half_series, y_minus_sin};
use crate::real::Real;

/// Below this x the closed forms are used, above it the series in u = 1 − x.
/// From x = 0.5 on, u = 1 − x is exact in f64 (Sterbenz), which matters:
/// A is 1.4 times as sensitive to u as to x near there. At x = 0.5 the closed
/// form of A cancels by a factor 1.7 and the series ratio is u/2 = 0.25.
const SERIES_FROM: f64 = 0.5;
/// For ∫₀ˣ A y dy the tail π/16 − ∫ₓ¹ A y dy cancels (factor 1.7 at x = 0.5),
/// while the closed form stays well conditioned (factor 1.4 at 0.75); so the
/// series takes over only from x = 0.75 (u = 1/4, still exact).
const MOMENT_SERIES_FROM: f64 = 0.75;

/// A(x) = arccos x − x√(1−x²) for 0 ≤ x < 1, 0 for x ≥ 1 (paper §4.3; the
/// argument is l/(2R), see `docs/errata.md` for the paper's A(t sin ϑ/R)).
///
/// Domain: x ≥ 0 (NaN for x < 0 or NaN). A(0) = π/2, A(1⁻) ~ (8/3)((1−x)/2)^{3/2}.
pub fn overlap_a<T: Real>(x: &T) -> T {
    if !(x.clone() >= x.lit(0.0)) {
        return x.lit(f64::NAN);
    }
    if x.clone() >= x.lit(1.0) {
        return x.lit(0.0);
    }
    if x.clone() < x.lit(SERIES_FROM) {
        return overlap_a_closed(x);
    }
    a_near_one(&(x.lit(1.0) - x.clone())) // u = 1 − x exact (Sterbenz), u ≤ 0.5
}

/// A(1 − u) for 0 ≤ u ≤ 1/2, from the gap u itself.
fn a_near_one<T: Real>(u: &T) -> T {
    if T::CAN_RAISE_PRECISION {
        // MPFR: the closed form with guard bits for the ~log₂(1/u) bits its
        // cancellation loses is 4× faster than the series at 128 bits.
        let lost = (-u.to_f64().log2()).max(0.0).ceil() as u32;
        let raised = u.raised(lost + 16);
        return overlap_a_closed(&(raised.lit(1.0) - raised)).rounded_to(u.prec());
    }
    // √(8u³) rounds once less than 2√2·u·√u.
    (u.lit(8.0) * u.clone() * u.clone() * u.clone()).sqrt() * sqrt_half_series(u, 1.5, false)
}

/// A(1 − u) = arccos(1 − u) − (1 − u)√(u(2 − u)) for 0 ≤ u ≤ 2: the area of
/// the segment of height u cut from a unit disc (π at u = 2), computed from
/// the height itself, so that a segment thinner than ulp(1) keeps its
/// relative accuracy (`lens::disc_overlap`). Domain: [0, 2] (NaN outside).
pub fn overlap_a_gap<T: Real>(u: &T) -> T {
    if !(u.clone() >= u.lit(0.0) && u.clone() <= u.lit(2.0)) {
        return u.lit(f64::NAN);
    }
    if u.clone() <= u.lit(SERIES_FROM) {
        return a_near_one(u);
    }
    if u.clone() < u.lit(1.5) {
        // 1 − u ∈ (−1/2, 1/2], exact (Sterbenz); the closed form holds for
        // negative arguments too and is well conditioned here.
        return overlap_a_closed(&(u.lit(1.0) - u.clone()));
    }
    // A(−x) = π − A(x); 2 − u ∈ [0, 1/2] is exact.
    u.pi() - a_near_one(&(u.lit(2.0) - u.clone()))
}

/// The closed form arccos x − x√((1−x)(1+x)), well conditioned for x ≤ 1/2.
fn overlap_a_closed<T: Real>(x: &T) -> T {
    let w = (x.lit(1.0) - x.clone()) * (x.lit(1.0) + x.clone());
    x.acos() - x.clone() * w.sqrt()
}

/// ∫₀ˣ A(y) dy (appendix, I₁: ∫₀¹ A = 2/3). Domain x ≥ 0; 2/3 for x ≥ 1.
///
/// Small x: x arccos x + x⁴ (2 + √w) / (3 (1 + √w)²), w = 1 − x², which is the
/// closed form x arccos x − √w + w^{3/2}/3 + 2/3 with its O(1) terms cancelled
/// analytically. Near 1: 2/3 − 2√2 u^{5/2} Σ_k b_k u^k / (k + 5/2), u = 1 − x.
pub fn overlap_a_integral<T: Real>(x: &T) -> T {
    if !(x.clone() >= x.lit(0.0)) {
        return x.lit(f64::NAN);
    }
    if x.clone() >= x.lit(1.0) {
        return x.lit(2.0) / x.lit(3.0);
    }
    if x.clone() < x.lit(SERIES_FROM) {
        let w = (x.lit(1.0) - x.clone()) * (x.lit(1.0) + x.clone());
        let sw = w.sqrt();
        let x2 = x.clone() * x.clone();
        let one_plus = x.lit(1.0) + sw.clone();
        return x.clone() * x.acos() + x2.clone() * x2 * (x.lit(2.0) + sw) / (x.lit(3.0) * one_plus.clone() * one_plus);
    }
    let u = x.lit(1.0) - x.clone();
    x.lit(2.0) / x.lit(3.0) - two_sqrt2(x) * u.clone() * u.clone() * u.sqrt() * sqrt_half_series(&u, 2.5, true)
}

/// ∫₀ˣ A(y) y dy (appendix, before the bound on I₂ₐ). Domain x ≥ 0; π/16 for x ≥ 1.
///
/// The appendix's closed form [π/2 − (1 − 4X²) arccos X − X(1 + 2X²)√(1 − X²)]/8
/// is exact (checked by differentiation, `docs/model.md`) but cancels as X → 0
/// (π/2 − arccos X − X√(1−X²) = O(X³)). We use, with φ = arcsin X,
/// [ (2φ − sin 2φ)/2 + 4X² arccos X − 2X³√(1−X²) ] / 8 for small X, and
/// π/16 − 2√2 Σ_k b_k [u^{k+5/2}/(k+5/2) − u^{k+7/2}/(k+7/2)] near X = 1.
pub fn overlap_a_moment<T: Real>(x: &T) -> T {
    if !(x.clone() >= x.lit(0.0)) {
        return x.lit(f64::NAN);
    }
    let pi16 = x.pi() / x.lit(16.0);
    if x.clone() >= x.lit(1.0) {
        return pi16;
    }
    if x.clone() < x.lit(MOMENT_SERIES_FROM) {
        let w = (x.lit(1.0) - x.clone()) * (x.lit(1.0) + x.clone());
        let x2 = x.clone() * x.clone();
        let phi2 = x.lit(2.0) * x.asin();
        let n = y_minus_sin(&phi2) / x.lit(2.0) + x.lit(4.0) * x2.clone() * x.acos()
            - x.lit(2.0) * x2 * x.clone() * w.sqrt();
        return n / x.lit(8.0);
    }
    let u = x.lit(1.0) - x.clone();
    let u52 = u.clone() * u.clone() * u.sqrt();
    let inner = sqrt_half_series(&u, 2.5, true) - u.clone() * sqrt_half_series(&u, 3.5, true);
    pi16 - two_sqrt2(x) * u52 * inner
}

fn two_sqrt2<T: Real>(x: &T) -> T {
    x.lit(8.0).sqrt()
}

/// ∫₀¹ A(x) e^{−βx} dx by its power series in β, with a bound on the
/// truncation and rounding error: Σₙ (−β)ⁿ/n! Mₙ, Mₙ = ∫₀¹ A xⁿ dx =
/// B(n/2 + 1, 3/2)/(n + 1), B(1, 3/2) = 2/3, B(3/2, 3/2) = π/8,
/// B(a + 1, b) = B(a, b)·a/(a + b). (The inner separation integral of (23),
/// (24): ∫₀^T A(t/T) e^{−rt} dt = T·this at β = rT.)
///
/// Domain: any β for which the alternating terms do not cancel beyond what
/// the precision affords; `None` when |β| exceeds 2 in f64 (≤ 3 bits lost)
/// — MPFR carries ⌈β/ln 2⌉ + 16 guard bits instead and accepts |β| ≤ 64.
pub fn overlap_a_laplace<T: Real>(beta: &T) -> Option<(T, T)> {
    let b = beta.to_f64();
    let limit = if T::CAN_RAISE_PRECISION { 64.0 } else { 2.0 };
    if !(b.abs() <= limit) {
        return None;
    }
    let prec = beta.prec();
    let guard = if T::CAN_RAISE_PRECISION && b > 0.0 { (b / std::f64::consts::LN_2).ceil() as u32 + 16 } else { 0 };
    let x = beta.raised(guard);
    let eps = x.eps();
    let (sum, abs_sum, last) = laplace_sum(&x);
    // Truncation: the terms decrease past n > |β| (alternating for β > 0,
    // and bounded by a geometric tail for β < 0): ≤ 2·last. Rounding: a few
    // eps of Σ|terms| at the working precision.
    let bound = last * x.lit(2.0) + abs_sum * eps * x.lit(8.0);
    let out_eps = beta.eps();
    let value = sum.rounded_to(prec);
    let bound = bound.rounded_to(prec) + value.abs() * out_eps;
    Some((value, bound))
}

/// Σₙ (−β)ⁿ/n! Mₙ at the precision of `beta` (the caller supplies the guard
/// bits the alternating terms cancel): (sum, Σ|terms|, |last term|). Stops
/// past n > |β| once a term falls below eps·|sum|. Shared by
/// [`overlap_a_laplace`] and the quadrature-free kernel reference.
pub(crate) fn laplace_sum<T: Real>(beta: &T) -> (T, T, T) {
    let x = beta;
    let b = x.to_f64().abs();
    let eps = x.eps();
    // Mₙ·(n + 1) = B(n/2 + 1, 3/2) for the last even and odd n.
    let mut moments = [x.lit(2.0) / x.lit(3.0), x.pi() / x.lit(8.0)];
    let mut power = x.lit(1.0); // (−β)ⁿ/n!
    let mut sum = x.lit(0.0);
    let mut abs_sum = x.lit(0.0);
    let mut last = x.lit(0.0);
    for n in 0u32..1_000_000 {
        let parity = (n % 2) as usize;
        if n >= 2 {
            // B(a + 1, 3/2) = B(a, 3/2)·a/(a + 3/2), a = n/2.
            let a = x.lit(f64::from(n) / 2.0);
            moments[parity] = moments[parity].clone() * a.clone() / (a + x.lit(1.5));
        }
        let term = power.clone() * moments[parity].clone() / x.lit(f64::from(n + 1));
        sum = sum + term.clone();
        abs_sum = abs_sum + term.abs();
        last = term.abs();
        if f64::from(n) > b && last <= eps.clone() * sum.abs() {
            break;
        }
        power = -(power * x.clone()) / x.lit(f64::from(n + 1));
    }
    (sum, abs_sum, last)
}
