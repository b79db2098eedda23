//! The azimuthal integral of a Henyey–Greenstein phase function (or its
//! square) over a circle of directions: the closed forms behind the
//! finite-sphere caps (`docs/model.md` §9.2) and the same-path kernel of
//! §3b.

use super::complete_elliptic_e;
use crate::real::Real;

/// ∫₀^{2π} f^k dχ of a Henyey–Greenstein phase function over the circle
/// at polar angle ψ about w, whose peak direction lies at γ from w with
/// sin γ = `sin_g` (closed forms in
/// `model::finite::point::PointLight::moment_cap`). Domain: ψ, γ ∈ [0, π],
/// |g| < 1, k ∈ {1, 2}; exact (no quadrature).
pub fn hg_ring<T: Real>(g: f64, psi: &T, gamma: &T, sin_g: &T, power: i32) -> T {
    assert!(power == 1 || power == 2, "hg_ring: power {power}, must be 1 or 2");
    let (two, ga, one) = (psi.lit(2.0), psi.lit(g.abs()), psi.lit(1.0));
    let floor = (one.clone() - ga.clone()) * (one.clone() - ga.clone());
    let norm = (one.clone() - ga.clone() * ga.clone()) / (psi.pi() * psi.lit(4.0));
    let sq = |a: T| {
        let s = (a / two.clone()).sin();
        s.clone() * s
    };
    let lo = floor.clone() + psi.lit(4.0) * ga.clone() * sq(psi.clone() - gamma.clone());
    let hi = floor + psi.lit(4.0) * ga.clone() * sq(psi.clone() + gamma.clone());
    if power == 1 {
        let kp = (lo.clone() / hi.clone()).sqrt();
        norm * psi.lit(4.0) * complete_elliptic_e(&kp) / (lo * hi.sqrt())
    } else {
        let b = two.clone() * ga * psi.sin() * sin_g.clone();
        let a = (lo.clone() + hi.clone()) / two.clone();
        let prod = lo * hi;
        norm.clone() * norm * psi.pi() * (two * a.clone() * a + b.clone() * b)
            / (prod.clone() * prod.clone() * prod.sqrt())
    }
}
