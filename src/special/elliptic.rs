//! The complete elliptic integral of the second kind, for the azimuthal
//! integral of a Henyey–Greenstein phase function over a circle of
//! directions (`model::finite::point`, `docs/model.md` §9.2):
//!
//!   ∫₀^{2π} (A − B cos χ)^{−3/2} dχ = 4 E(m) / ((A − |B|)√(A + |B|)),
//!   m = 2|B|/(A + |B|),  1 − m = (A − |B|)/(A + |B|).

use crate::real::Real;

/// Below this k′ f64 uses the expansion at m → 1 ([`near_one`]), whose
/// next term, (15/128)k′⁶ ln(4/k′), is then below 10⁻¹⁸ (the AGM's bracket
/// would cancel by up to 30 ulps there).
const NEAR_ONE: f64 = 1e-3;

/// E(m) = 1 + (k′²/2)(L − 1/2) + (3k′⁴/16)(L − 13/12) + O(k′⁶L),
/// L = ln(4/k′) (DLMF 19.12.2; Abramowitz & Stegun 17.3.36).
fn near_one<T: Real>(kp: &T) -> T {
    let l = kp.lit(4.0).ln() - kp.ln();
    let k2 = kp.clone() * kp.clone();
    let second = k2.clone() * k2.clone() * kp.lit(3.0) / kp.lit(16.0) * (l.clone() - kp.lit(13.0) / kp.lit(12.0));
    kp.lit(1.0) + (k2 / kp.lit(2.0) * (l - kp.lit(0.5)) + second)
}

/// E(m) = ∫₀^{π/2} √(1 − m sin²θ) dθ, given the complementary modulus
/// k′ = √(1 − m) ∈ (0, 1] (so that m → 1 keeps its accuracy: 1 − m is
/// what the caller knows exactly). Domain: 0 < k′ ≤ 1 (NaN otherwise).
///
/// Gauss's arithmetic–geometric mean: a₀ = 1, b₀ = k′, c₀² = m;
/// aₙ₊₁ = (aₙ + bₙ)/2, bₙ₊₁ = √(aₙbₙ), cₙ₊₁ = cₙ²/(4aₙ₊₁) (= (aₙ − bₙ)/2,
/// formed without the cancellation); K = π/(2a_∞) and
/// E = K (1 − Σₙ 2^{n−1} cₙ²). The bracket (≈ E/K ≥ 1/ln(4/k′)) is
/// summed from a₁² = 1 − m/2 − c₁², so its partial sums stay within a
/// factor ≈ 8 of it; MPFR carries 16 guard bits for what still cancels, and
/// f64 switches to the expansion at m → 1 below k′ = 10⁻³. f64 stays within
/// 8 ulps over k′ ∈ [10⁻¹², 1] (measured: 5.7; `docs/accuracy.md`).
pub fn complete_elliptic_e<T: Real>(k_prime: &T) -> T {
    if !(k_prime.clone() > k_prime.lit(0.0) && k_prime.clone() <= k_prime.lit(1.0)) {
        return k_prime.lit(f64::NAN);
    }
    if !T::CAN_RAISE_PRECISION && k_prime.clone() < k_prime.lit(NEAR_ONE) {
        return near_one(k_prime);
    }
    let prec = k_prime.prec();
    let kp = k_prime.raised(16);
    let two = kp.lit(2.0);
    let eps = kp.eps();
    // The first step in closed form: 1 − m/2 − c₁² = ((1 + k′)/2)² = a₁²,
    // so the bracket starts at a₁² (≥ 1/4) rather than at 1: its partial
    // sums stay near the result, which is what keeps the rounding small
    // when the bracket ≈ E/K is small (k′ → 0).
    let mut a = (kp.lit(1.0) + kp.clone()) / two.clone();
    let mut b = kp.sqrt();
    let mut c2 = {
        let c1 = (kp.lit(1.0) - kp.clone()) / two.clone();
        c1.clone() * c1
    };
    let mut bracket = a.clone() * a.clone();
    let mut weight = kp.lit(1.0); // 2^{n−1} at n = 1
    for _ in 0..64 {
        let next_a = (a.clone() + b.clone()) / two.clone();
        b = (a * b).sqrt();
        a = next_a;
        c2 = c2.clone() * c2 / (kp.lit(16.0) * a.clone() * a.clone());
        weight = weight * two.clone();
        let term = weight.clone() * c2.clone();
        bracket = bracket - term.clone();
        if term <= eps.clone() * eps.clone() {
            break;
        }
    }
    let k = kp.pi() / (two * a);
    (k * bracket).rounded_to(prec)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f64 against the same algorithm at 256 bits, in ulps, over
    /// k′ ∈ [1e-12, 1] log-spaced.
    #[test]
    #[cfg(feature = "mpfr")]
    fn f64_within_a_few_ulps_of_mpfr() {
        let mut worst = 0.0f64;
        for i in 0..=2000 {
            let kp = 10f64.powf(-12.0 * i as f64 / 2000.0);
            let exact = complete_elliptic_e(&rug::Float::with_val(256, kp)).to_f64();
            let ulp = f64::EPSILON * exact;
            worst = worst.max((complete_elliptic_e(&kp) - exact).abs() / ulp);
        }
        assert!(worst <= 8.0, "{worst} ulp");
    }

    #[test]
    fn known_values() {
        let pi = std::f64::consts::PI;
        assert!((complete_elliptic_e(&1.0f64) - pi / 2.0).abs() < 4e-16);
        // E(1/2) = 1.3506438810476755025…; m → 1: E → 1.
        let kp = 0.5f64.sqrt();
        assert!((complete_elliptic_e(&kp) - 1.3506438810476755).abs() < 4e-16);
        assert!((complete_elliptic_e(&1e-12f64) - 1.0).abs() < 4e-16);
        assert!(complete_elliptic_e(&0.0f64).is_nan());
    }

    /// The azimuthal identity it is used for, against a fine trapezoidal
    /// rule (exponentially accurate for a periodic analytic integrand).
    #[test]
    fn azimuthal_integral_of_a_three_halves_power() {
        for (a, b) in [(1.81f64, 1.8), (2.0, 0.5), (1.0, 0.0), (1.5, -1.2)] {
            let n = 4000;
            let h = 2.0 * std::f64::consts::PI / n as f64;
            let trap: f64 = (0..n).map(|i| (a - b * (i as f64 * h).cos()).powf(-1.5) * h).sum();
            let kp = ((a - b.abs()) / (a + b.abs())).sqrt();
            let closed = 4.0 * complete_elliptic_e(&kp) / ((a - b.abs()) * (a + b.abs()).sqrt());
            assert!((trap - closed).abs() <= 1e-12 * closed, "A = {a}, B = {b}: {trap} vs {closed}");
        }
    }
}
