//! The periodic trapezoidal rule for ∫₀^{2π} of an even periodic function,
//! after a Möbius map of the circle that moves its two known singularities
//! as far from the real axis as they can both be (the check pass's rule for
//! Λ(ϑ), `docs/quadrature.md`).

use crate::quad::{Estimate, Options, Rule};
use crate::real::Real;

/// Smallest strip half-width (in the mapped variable) for which the check
/// pass tries the periodic trapezoidal rule: N = 512 nodes on the circle
/// reach e^{−512·0.05} ≈ 10⁻¹¹ relative. Below it (ϑ within ~10⁻³ of ψ_u)
/// the adaptive rule with graded cuts takes over, as it does when the
/// trapezoidal rule has not converged by N = 512.
pub(crate) const MIN_STRIP: f64 = 0.05;

/// The Möbius map of the circle φ = 2 arctan(ε tan(τ/2)), which crowds the
/// nodes of a uniform τ-grid towards φ = 0 (ε < 1) or φ = π (ε > 1),
/// dφ/dτ = ε/(cos²(τ/2) + ε² sin²(τ/2)). It is conformal, so an integrand
/// periodic and analytic in a strip stays so in τ: singularities at
/// φ = ±2i·artanh(a) and φ = π ± 2i·artanh(b) move to τ = ±2i·artanh(a/ε)
/// and τ = π ± 2i·artanh(εb). With ε = √(a/b) both lie at
/// 2 artanh(√(ab)), against 2 artanh(min(a, b)) without the map.
pub(crate) struct CircleMap<T> {
    eps: T,
    /// Half-width of the strip of analyticity in τ, 2 artanh(√(ab)).
    pub strip: T,
}

impl<T: Real> CircleMap<T> {
    /// The balanced map for singularities at tan(φ/2) = ±i·a and
    /// cot(φ/2) = ∓i·b (0 < a, b < 1).
    pub fn balanced(a: &T, b: &T) -> Self {
        let one = a.lit(1.0);
        if !(*a > a.lit(0.0) && *b > a.lit(0.0)) {
            return CircleMap { eps: one, strip: a.lit(0.0) };
        }
        let g = (a.clone() * b.clone()).sqrt();
        // 2 artanh(g) = ln((1 + g)/(1 − g)).
        let strip = ((one.clone() + g.clone()) / (one - g)).ln();
        CircleMap { eps: (a.clone() / b.clone()).sqrt(), strip }
    }

    /// (φ, π − φ, dφ/dτ) at τ, given τ and π − τ (each angle from its own
    /// half-angle tangent, so that both are accurate near 0).
    pub fn at(&self, tau: &T, tau_c: &T) -> (T, T, T) {
        let two = tau.lit(2.0);
        // cos(τ/2) = sin((π − τ)/2): accurate near τ = π.
        let (hs, hc) = ((tau.clone() / two.clone()).sin(), (tau_c.clone() / two.clone()).sin());
        // tan(φ/2) = ε·tan(τ/2), tan((π − φ)/2) = tan((π − τ)/2)/ε.
        let atan = |y: T, x: T| -> T {
            // 2·atan(y/x) for y, x ≥ 0, via asin of the normalised sine.
            let r = (y.clone() * y.clone() + x.clone() * x).sqrt();
            two.clone() * (y / r).asin()
        };
        let (y, x) = (self.eps.clone() * hs.clone(), hc.clone());
        let (yc, xc) = (hc.clone(), self.eps.clone() * hs.clone());
        let phi = if y <= x { atan(y.clone(), x.clone()) } else { tau.pi() - atan(yc.clone(), xc.clone()) };
        let phi_c = if yc <= xc { atan(yc, xc) } else { tau.pi() - atan(y, x) };
        let jac = self.eps.clone() / (hc.clone() * hc + self.eps.clone() * self.eps.clone() * hs.clone() * hs);
        (phi, phi_c, jac)
    }
}

/// ∫₀^{2π} f dφ of an even periodic f given on [0, π] as f(φ, π − φ), by the
/// trapezoidal rule with N = 16, 32, … 512 nodes on the circle (nested), its
/// bar |T_N − T_{N/2}| (the error of T_{N/2} when it converges
/// geometrically, so a bound on T_N's), accepted when that is below a
/// quarter of the goal; `None` if it is not by N = 512 (the caller then
/// uses the adaptive rule).
pub(crate) fn periodic_trapezoid<T: Real>(like: &T, f: &dyn Fn(&T, &T) -> T, opts: &Options) -> Option<Estimate<T>> {
    let pi = like.pi();
    // Sum over the nodes φ_j = 2πj/N on [0, π] with half weights at 0 and π.
    let mut n = 8usize; // half the circle's node count
    let node = |j: usize, n: usize| {
        let phi = pi.clone() * like.lit(j as f64) / like.lit(n as f64);
        let phi_c = pi.clone() * like.lit((n - j) as f64) / like.lit(n as f64);
        f(&phi, &phi_c)
    };
    let mut sum = (node(0, n) + node(n, n)) / like.lit(2.0);
    for j in 1..n {
        sum = sum + node(j, n);
    }
    let mut evaluations = (n + 1) as u64;
    let mut value = sum.clone() * like.lit(2.0) * pi.clone() / like.lit(n as f64);
    while n < 256 {
        // Doubling: the new nodes are the odd ones of the finer grid.
        let fine = 2 * n;
        for j in (1..fine).step_by(2) {
            sum = sum + node(j, fine);
        }
        evaluations += n as u64;
        n = fine;
        let next = sum.clone() * like.lit(2.0) * pi.clone() / like.lit(n as f64);
        let diff = (next.clone() - value.clone()).abs();
        value = next;
        let goal = (value.abs() * like.lit(opts.rel_tol)).max_of(like.lit(opts.abs_tol)) / like.lit(4.0);
        if diff <= goal && diff.is_finite() {
            return Some(Estimate::known(value, diff, evaluations, Rule::Check));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫₀^{2π} [1/(1 − r cos φ) + 1/(1 + r′ cos φ)] dφ = 2π/√(1 − r²) + 2π/√(1 − r′²):
    /// poles at tan(φ/2) = ±i√((1 − r)/(1 + r)) and cot(φ/2) = ±i√((1 − r′)/(1 + r′)),
    /// the structure of Λ's integrand near w₀ and its antipode.
    fn two_poles(r: f64, r_far: f64) -> (f64, f64, f64, impl Fn(&f64, &f64) -> f64) {
        // 1 − r² as (1 − r)(1 + r): 1 − r is exact in f64.
        let exact = 2.0
            * std::f64::consts::PI
            * (1.0 / ((1.0 - r) * (1.0 + r)).sqrt() + 1.0 / ((1.0 - r_far) * (1.0 + r_far)).sqrt());
        let a = ((1.0 - r) / (1.0 + r)).sqrt();
        let b = ((1.0 - r_far) / (1.0 + r_far)).sqrt();
        // 1 − r cos φ = (1 − r) + 2r sin²(φ/2) and 1 + r′ cos φ = (1 − r′) +
        // 2r′ sin²((π − φ)/2), each without cancellation near its pole.
        let f = move |phi: &f64, phi_c: &f64| {
            let near = (1.0 - r) + 2.0 * r * (phi / 2.0).sin().powi(2);
            let far = (1.0 - r_far) + 2.0 * r_far * (phi_c / 2.0).sin().powi(2);
            1.0 / near + 1.0 / far
        };
        (exact, a, b, f)
    }

    #[test]
    fn circle_map_moves_both_poles_to_the_balanced_strip() {
        let (exact, a, b, f) = two_poles(0.9999, 0.5);
        let map = CircleMap::balanced(&a, &b);
        let predicted = 2.0 * ((a * b).sqrt()).atanh();
        assert!((map.strip - predicted).abs() <= 1e-15 * predicted);
        let mapped = |tau: &f64, tau_c: &f64| {
            let (phi, phi_c, jac) = map.at(tau, tau_c);
            assert!((phi + phi_c - std::f64::consts::PI).abs() <= 4.0 * f64::EPSILON);
            f(&phi, &phi_c) * jac
        };
        let opts = Options::rel(1e-12);
        let e = periodic_trapezoid(&1.0, &mapped, &opts).expect("mapped rule converges by N = 512");
        assert!((e.value - exact).abs() <= e.error + 1e-14 * exact, "{} vs {exact} ± {}", e.value, e.error);
        assert!(e.error <= 1e-12 * exact / 4.0);
        // Without the map the poles sit 2 artanh(a) ≈ 0.014 from the axis:
        // the plain rule has not converged by N = 512 and says so.
        assert!(periodic_trapezoid(&1.0, &f, &opts).is_none());
    }

    #[test]
    fn circle_map_is_the_identity_when_the_poles_are_equally_far() {
        let map = CircleMap::balanced(&0.3, &0.3);
        let (phi, phi_c, jac) = map.at(&1.0, &(std::f64::consts::PI - 1.0));
        assert!((phi - 1.0).abs() <= 4.0 * f64::EPSILON && (jac - 1.0).abs() <= 4.0 * f64::EPSILON);
        assert!((phi_c - (std::f64::consts::PI - 1.0)).abs() <= 4.0 * f64::EPSILON);
    }
}
