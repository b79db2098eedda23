//! Same-path double hits: one forward path whose first segment passes a
//! sphere, scatters near it, and whose second segment passes the *same*
//! sphere. The paper's ⟨𝒞²⟩ (20) counts one segment per hit; with
//! scattered light the cross term 2𝒞₁𝒞₂ of the two segments adds, in the
//! small-sphere limit (`docs/model.md` §3b),
//!
//!   ⟨𝒞²⟩ₓ(s) = (8 albedo³ 𝓕 σ/(3π²R)) Σ_uncollided f(−μ) W K(μ),
//!   K(μ) = ∫ p(v₁·v₂) f(−u·v₂) cot(θ/2) dω₂,  cos θ = −v₁·v₂,
//!
//! μ = u·v₁ the first segment's direction. (4/3)R³cot(θ/2) is the volume of
//! the collision points from which both segments hit: the intersection of
//! the half-cylinder of radius R ahead of the sphere's centre along v₁ with
//! the one behind it along v₂ ((1 + cos θ)/4 of the Steinmetz solid
//! 16R³/(3 sin θ) of the two full cylinders). It is
//! O(1/R) against the O(1/R²) of (20), the order of (25) that the paper
//! keeps; the tracer confirms it (`tests/errata_evidence.rs`, E9 of
//! `docs/errata.md`; the kernel's checks: `tests/same_path.rs`).
//!
//! In the polar frame about −v₁ (θ the polar angle), cot(θ/2) sin θ =
//! 1 + cos θ cancels the backscatter singularity:
//! K = ∫₀^π (1 + cos θ) p(−cos θ) Φ(θ) dθ, Φ the ring integral of f(−u·v₂)
//! in closed form ([`crate::special::hg_ring`]); K = 1/8 for isotropic media.

use super::field::{graded_about, Field};
use crate::quad::{integrate, CheckRule, Domain, Estimate, Options, Outcome};
use crate::real::Real;
use crate::special::hg_ring;
use mcrt_scene::Phase;

/// K(μ) = ∫ p(v₁·v₂) f(−u·v₂) cot(θ/2) dω₂ (1/sr): the angular factor of
/// the same-path double hit for a first segment along v₁ with u·v₁ = μ,
/// sin ϑ = `sin` ≥ 0 (module docs). Domain: μ² + sin² = 1; |g| < 1.
/// Isotropic: 1/8 exactly. Henyey–Greenstein: a 1-D quadrature in the polar
/// angle about −v₁ with the peaks of p (at θ = π for g > 0, 0 for g < 0)
/// and of f (at θ = γ, cos γ = sgn(g) μ) declared with decades of width
/// 1 − |g|. Not in the paper (E9).
pub fn kernel<T: CheckRule>(phase: &Phase, mu: &T, sin: &T, opts: &Options) -> Outcome<T> {
    let g = match *phase {
        Phase::HenyeyGreenstein { g } if g != 0.0 => g,
        _ => return Ok(Estimate::known(mu.lit(0.125), mu.lit(0.0), 1, opts.rule)),
    };
    let pi = mu.pi();
    let zero = mu.lit(0.0);
    // γ: angle between −v₁ and f's peak direction −sgn(g)u.
    let gamma = if g > 0.0 { angle(mu, sin) } else { angle(&-mu.clone(), sin) };
    let width = mu.lit(1.0 - g.abs());
    let mut cuts = graded_about(&gamma, &width, &pi);
    let peak = if g > 0.0 { pi.clone() } else { zero.clone() };
    cuts.extend(graded_about(&peak, &width, &pi));
    cuts.retain(|c| *c > zero && *c < pi);
    cuts.push(gamma.clone());
    let integrand = |theta: &T| {
        let half = theta.clone() / theta.lit(2.0);
        let (c, s) = (half.cos(), half.sin());
        // 1 + cos θ and 1 − cos θ from half angles.
        let (one_plus, one_minus) = (theta.lit(2.0) * c.clone() * c, theta.lit(2.0) * s.clone() * s);
        one_plus.clone() * scattering_phase(g, &one_plus, &one_minus) * hg_ring(g, theta, &gamma, sin, 1)
    };
    let domain = Domain::finite(zero, pi.clone()).with_breakpoints(cuts.into_iter().filter(|c| *c < pi));
    integrate(integrand, &domain, opts)
}

/// The angle in [0, π] with cosine `cos` and sine `sin` ≥ 0, from the
/// arctangent of the smaller ratio (accurate at both poles).
pub(crate) fn angle<T: Real>(cos: &T, sin: &T) -> T {
    let half_pi = cos.pi() / cos.lit(2.0);
    if cos.abs() >= *sin {
        let a = (sin.clone() / cos.abs()).atan();
        if *cos >= cos.lit(0.0) {
            a
        } else {
            cos.pi() - a
        }
    } else {
        half_pi - (cos.clone() / sin.clone()).atan()
    }
}

/// The medium's Henyey–Greenstein p at the scattering cosine v₁·v₂ = −cos θ,
/// from 1 ± cos θ so that a peak of width 1 − |g| keeps its digits.
pub(crate) fn scattering_phase<T: Real>(g: f64, one_plus: &T, one_minus: &T) -> T {
    let (gl, one) = (one_plus.lit(g), one_plus.lit(1.0));
    // 1 + g² − 2g(−cos θ) = (1 − g)² + 2g(1 + cos θ) = (1 + g)² − 2g(1 − cos θ).
    let denom = if g >= 0.0 {
        (one.clone() - gl.clone()) * (one.clone() - gl.clone()) + one_plus.lit(2.0) * gl.clone() * one_plus.clone()
    } else {
        (one.clone() + gl.clone()) * (one.clone() + gl.clone()) - one_plus.lit(2.0) * gl.clone() * one_minus.clone()
    };
    (one.clone() - gl.clone()) * (one + gl) / (one_plus.pi() * one_plus.lit(4.0) * denom.clone() * denom.sqrt())
}

/// ⟨𝒞²⟩ₓ at s = field.center + x with its bar: the same-path double hits of
/// the field's uncollided (first) segments, which scatter when the scene
/// simulates order 1 (zero for an uncollided field). Domain: any x; R > 0.
/// Small-sphere limit, as (20): first order in R against it.
pub fn second_moment_term<T: CheckRule>(field: &Field<T>, x: &T, r: &T, opts: &Options) -> Outcome<T> {
    let zero = x.lit(0.0);
    if !field.is_smooth() {
        return Ok(Estimate::known(zero.clone(), zero, 0, opts.rule));
    }
    let a = field.albedo.clone();
    let pi = x.pi();
    let front = x.lit(8.0) * a.clone() * a.clone() * a * field.total_flux.clone() * field.sigma_ext.clone()
        / (x.lit(3.0) * pi.clone() * pi * r.clone());
    let mut total = Estimate::known(zero.clone(), zero, 0, opts.rule);
    let share = opts.abs_tol / field.components.len().max(1) as f64;
    for c in &field.components {
        if let Some(l) = c.at(x, &field.sigma_ext) {
            let weight = front.clone() * field.phase_at(&l.mu) * l.w.clone();
            if weight.is_zero() {
                continue;
            }
            let o = Options { abs_tol: (share / weight.to_f64()).min(f64::MAX), ..opts.clone() };
            total = total.plus(kernel(&field.phase, &l.mu, &l.sin, &o)?.scaled(&weight));
        }
    }
    Ok(total)
}
