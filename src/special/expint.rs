//! Exponential integrals E₁ and E₂, after the series / continued-fraction
//! split of Numerical Recipes §6.3 (modified Lentz for the fraction).

use crate::real::Real;

/// Switch from the power series to the continued fraction (x ≥ this). Chosen
/// by the ulp sweep (`docs/accuracy.md`): the series' head −γ − ln x cancels
/// near x = e^{−γ} ≈ 0.56, the fraction loses accuracy as x falls.
const E1_CF_FROM: f64 = 0.5;
/// For E₂ = e^{−x} − x E₁(x) the subtraction cancels by ~1.9 at x = 0.45;
/// below this the difference is used, above it E₂'s own fraction.
const E2_CF_FROM: f64 = 0.45;

/// E₁(x) = ∫₁^∞ e^{−xt}/t dt (the appendix's Ei(1, x)). Domain x > 0
/// (+∞ at 0, NaN below). Underflows to 0 past x ≈ 745 in f64.
pub fn exp_int_e1<T: Real>(x: &T) -> T {
    if let Some(edge) = domain_edge(x) {
        return edge;
    }
    if x.clone() >= x.lit(E1_CF_FROM) {
        return en_continued_fraction(1, x);
    }
    // E₁(x) = −γ − ln x + Σ_{k≥1} (−1)^{k+1} x^k / (k k!)
    let eps = x.eps();
    let mut fact = x.lit(1.0);
    let mut sum = x.lit(0.0);
    for k in 1..100_000 {
        let kf = k as f64;
        fact = -(fact * x.clone()) / x.lit(kf);
        let term = -fact.clone() / x.lit(kf);
        sum = sum + term.clone();
        if term.abs() <= eps.clone() * sum.abs() * x.lit(0.25) {
            break;
        }
    }
    let head = -x.euler_gamma() - x.ln();
    head + sum
}

/// e^{x}E₁(x), the scaled exponential integral: ≈ 1/x for large x, where
/// E₁ itself underflows (past x ≈ 745 in f64). Domain x > 0 (+∞ at 0, NaN
/// below). Same split as [`exp_int_e1`]: the continued fraction without its
/// factor e^{−x} for x ≥ 0.5, e^{x} times the series below.
pub fn exp_int_e1_scaled<T: Real>(x: &T) -> T {
    if let Some(edge) = domain_edge(x) {
        return edge;
    }
    if x.clone() >= x.lit(E1_CF_FROM) {
        return en_continued_fraction_scaled(1, x);
    }
    x.exp() * exp_int_e1(x)
}

/// X⁻¹(e^{−X} − X E₁(X)) = E₂(X)/X = ∫_X^∞ u⁻² e^{−u} du (appendix, the
/// inequality bounding I₂ₐ). Domain X > 0 (+∞ at 0). For large X the
/// difference e^{−X} − X E₁(X) cancels; there E₂ comes from its own continued
/// fraction.
pub fn exp_int_tail2<T: Real>(x: &T) -> T {
    if let Some(edge) = domain_edge(x) {
        return edge;
    }
    let e2 = if x.clone() >= x.lit(E2_CF_FROM) {
        en_continued_fraction(2, x)
    } else {
        (-x.clone()).exp() - x.clone() * exp_int_e1(x)
    };
    e2 / x.clone()
}

/// E_n(x) = e^{−x} / (b₀ + a₁/(b₁ + a₂/(b₂ + …))), b_k = x + n + 2k,
/// a_k = −k(n − 1 + k). A forward modified-Lentz pass finds the depth at which
/// the fraction has converged; the fraction is then evaluated *backward* from
/// that depth, which does not accumulate a rounding error per level the way
/// the forward product does (that costs ~100 ulps near x = 1).
fn en_continued_fraction<T: Real>(n: u32, x: &T) -> T {
    (-x.clone()).exp() / en_denominator(n, x)
}

/// e^{x}E_n(x) = 1/(b₀ + a₁/(b₁ + …)), the fraction of [`en_continued_fraction`]
/// without its factor e^{−x}.
fn en_continued_fraction_scaled<T: Real>(n: u32, x: &T) -> T {
    x.lit(1.0) / en_denominator(n, x)
}

/// b₀ + a₁/(b₁ + a₂/(b₂ + …)) of [`en_continued_fraction`], evaluated backward.
fn en_denominator<T: Real>(n: u32, x: &T) -> T {
    let depth = lentz_depth(n, x);
    let a = |k: usize| x.lit(-((k as f64) * ((n - 1) as f64 + k as f64)));
    let b = |k: usize| x.clone() + x.lit(n as f64 + 2.0 * k as f64);
    let mut f = b(depth);
    for k in (0..depth).rev() {
        f = b(k) + a(k + 1) / f;
    }
    f
}

/// The value at the edge of the domain x > 0 shared by E₁, e^{x}E₁ and
/// E₂/x: NaN below 0 (and for NaN), +∞ at 0; `None` inside.
fn domain_edge<T: Real>(x: &T) -> Option<T> {
    if !(x.clone() >= x.lit(0.0)) {
        return Some(x.lit(f64::NAN));
    }
    if x.is_zero() {
        return Some(x.lit(f64::INFINITY));
    }
    None
}

/// Depth at which the forward (Lentz) evaluation of the E_n fraction has
/// converged to the working precision, plus a safety margin.
fn lentz_depth<T: Real>(n: u32, x: &T) -> usize {
    let eps = x.eps();
    let tiny = x.eps() * x.eps() * x.eps();
    let one = x.lit(1.0);
    let mut b = x.clone() + x.lit(n as f64);
    let mut c = one.clone() / tiny;
    let mut d = one.clone() / b.clone();
    for i in 1..1_000_000usize {
        let an = x.lit(-((i as f64) * ((n - 1) as f64 + i as f64)));
        b = b + x.lit(2.0);
        d = one.clone() / (an.clone() * d + b.clone());
        c = b.clone() + an / c;
        let del = c.clone() * d.clone();
        if (del - one.clone()).abs() <= eps.clone() * x.lit(0.25) {
            // Lentz's own test stops a little early; half as deep again makes
            // the truncation error invisible in f64 (measured by the sweep).
            return i + i / 2 + 4;
        }
    }
    1_000_000
}
