//! One forward ray's functionals: what a single uncollided forward ray
//! contributes, averaged over its free path ℓ ~ Exp(σ) and over the
//! integration spheres of one camera ray, to each moment of the model
//! (`docs/model.md` §9).
//!
//! A ray from p along v hits the sphere at x(s) when the closest point of
//! its line to x(s), at τ(s) = (x(s) − p)·v along the ray, lies within R
//! and within the segment: 0 ≤ τ(s) ≤ ℓ. For a given ray the centres s ≥ 0
//! with τ(s) ≥ 0 and distance ≤ R form one interval J = [a, a + L] of the
//! camera line, the *hit interval*; τ is linear on it, τ(s) = τ(a) + μ(s − a)
//! (μ = u·v), and the segment reaches the sphere at s with probability
//! e^{−στ(s)}. Spheres lie at density (σ/q)e^{−σs} with weight q, pairs at
//! (1 − q)σ²e^{−σs′}/q² for s < s′ (`docs/model.md` §2), so with
//! P = a + τ(a), the path from the light to the first sphere's closest
//! point and on to the camera:
//!
//! - G₁  = ∫_J σe^{−σs}e^{−στ(s)} ds = σ e^{−σP} F₁(σ(1+μ), L)                (13), (15), (16)
//! - G₂₃ = ∫∫_{s<s′∈J} σ²e^{−σs′}e^{−σ max τ} = σ² e^{−σP} F₂(r, r′, L)        (16)
//! - G₂₄ = ∫∫_{J²} σ²e^{−σ(s+s′)}e^{−σ max τ} = 2σ² e^{−σ(P + a)} F₂(r, r′, L) (18)
//!
//! with F₁ = [`exp_segment`], F₂ = [`exp_triangle`], and the rates (r, r′)
//! = (σ(1+μ), σ(1+μ)) (G₂₃, μ ≥ 0: the farther sphere is reached last),
//! (σ, σ(1+μ)) (G₂₃, μ < 0: the nearer one), (σ(1+μ), σ(2+μ)) (G₂₄, μ ≥ 0),
//! (σ, σ(2+μ)) (G₂₄, μ < 0). Every rate is ≥ 0, so nothing grows.

use crate::model::angular::Direction;
use crate::real::Real;
use crate::special::{exp_segment, exp_triangle};

/// Which moment a ray-centric integral computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Functional {
    /// ⟨⟨Ĉ⟩⟩ (13): weight f, G₁.
    Mean,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩ (16): weight f², G₁.
    Second,
    /// C₂₃ = ∫∫_{s<s′}⟨𝒞(s)𝒞(s′)⟩σ²e^{−σs′} (16), (23): weight f², G₂₃.
    Pair23,
    /// C₂₄ = ∫∫⟨𝒞(s)𝒞(s′)⟩σ²e^{−σ(s+s′)} (18), (24): weight f², G₂₄.
    Pair24,
}

impl Functional {
    /// The power of f(−μ) and of the per-hit 𝒞 in the functional.
    pub fn power(self) -> i32 {
        match self {
            Functional::Mean => 1,
            _ => 2,
        }
    }

    /// The name of the quantity, for failures.
    pub fn name(self) -> &'static str {
        match self {
            Functional::Mean => "finite-sphere mean luminance",
            Functional::Second => "finite-sphere ∫⟨𝒞²⟩",
            Functional::Pair23 => "finite-sphere correlation integral (23)",
            Functional::Pair24 => "finite-sphere correlation integral (24)",
        }
    }
}

/// A ray's hit interval J = [start, start + len] on the camera line
/// (absolute s; `len` may be +∞), with `path` = start + τ(start).
#[derive(Debug, Clone)]
pub struct Hit<T> {
    /// a, the lower end of J (absolute s ≥ 0).
    pub start: T,
    /// L > 0, the length of J (+∞ when unbounded).
    pub len: T,
    /// P = a + τ(a): the path from the ray's start to its closest point to x(a), then to the camera.
    pub path: T,
}

/// G₁, G₂₃ or G₂₄ of one ray (module doc), times e^{c₀} (`shift`), for a
/// ray of direction `dir` (μ and 1 + μ to full relative accuracy): the
/// ray's share of the mean (13), (15) and of M₂ (16) (G₁), of C₂₃ (16),
/// (23) (G₂₃) and of C₂₄ (18), (24) (G₂₄), without the per-hit factor
/// (albedo f 𝓕/(πR²))^k. Domain: a non-empty hit interval (L ∈ (0, ∞]),
/// σ > 0. Deviation: the paper has no per-ray form; its (21)–(24) take the
/// attenuation and f at the sphere's centre (§4.3), these are exact.
pub fn functional<T: Real>(which: Functional, hit: &Hit<T>, dir: &Direction<T>, sigma: &T, shift: &T) -> T {
    let len = hit.len.is_finite().then_some(&hit.len);
    let one_plus = dir.one_plus_mu.clone();
    let backward = dir.mu < dir.mu.lit(0.0);
    let attenuation = |extra: &T| (shift.clone() - sigma.clone() * (hit.path.clone() + extra.clone())).exp();
    let zero = sigma.lit(0.0);
    match which {
        Functional::Mean | Functional::Second => {
            sigma.clone() * attenuation(&zero) * exp_segment(&(sigma.clone() * one_plus), len)
        }
        Functional::Pair23 => {
            let r2 = sigma.clone() * one_plus;
            let r1 = if backward { sigma.clone() } else { r2.clone() };
            sigma.clone() * sigma.clone() * attenuation(&zero) * exp_triangle(&r1, &r2, len)
        }
        Functional::Pair24 => {
            let r2 = sigma.clone() * (one_plus.clone() + sigma.lit(1.0));
            let r1 = if backward { sigma.clone() } else { sigma.clone() * one_plus };
            sigma.lit(2.0) * sigma.clone() * sigma.clone() * attenuation(&hit.start) * exp_triangle(&r1, &r2, len)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::angular::view_direction;

    /// The functionals against their defining integrals over the hit
    /// interval, by midpoint sums (n² cells; a diagonal cell of the ordered
    /// pairs of G₂₃ counts half), for a ray leaving the camera, one coming
    /// towards it and one across it (μ = 0).
    #[test]
    fn functionals_match_their_definitions() {
        let sigma = 1.3f64;
        for theta in [0.4f64, 2.2, std::f64::consts::FRAC_PI_2] {
            let dir = view_direction(&theta, &(std::f64::consts::PI - theta));
            let mu = dir.mu;
            let (a, len, tau_a) = (0.7f64, 0.9f64, 0.5f64);
            let hit = Hit { start: a, len, path: a + tau_a };
            let tau = |s: f64| tau_a + mu * (s - a);
            let n = 2000;
            let h = len / n as f64;
            let mid = |i: usize| a + (i as f64 + 0.5) * h;
            let g1: f64 = (0..n).map(|i| sigma * (-sigma * mid(i)).exp() * (-sigma * tau(mid(i))).exp() * h).sum();
            let (mut g23, mut g24) = (0.0, 0.0);
            for i in 0..n {
                for j in 0..n {
                    let (s, t) = (mid(i), mid(j));
                    let reach = (-sigma * tau(s).max(tau(t))).exp();
                    let share = match i.cmp(&j) {
                        std::cmp::Ordering::Less => 1.0,
                        std::cmp::Ordering::Equal => 0.5,
                        std::cmp::Ordering::Greater => 0.0,
                    };
                    g23 += share * sigma * sigma * (-sigma * t).exp() * reach * h * h;
                    g24 += sigma * sigma * (-sigma * (s + t)).exp() * reach * h * h;
                }
            }
            let f = |w| functional(w, &hit, &dir, &sigma, &0.0);
            for (w, brute) in [(Functional::Mean, g1), (Functional::Pair23, g23), (Functional::Pair24, g24)] {
                let v = f(w);
                assert!((v - brute).abs() <= 1e-6 * brute, "ϑ = {theta} {w:?}: {v} vs {brute}");
            }
        }
    }

    /// An unbounded hit interval (a ray leaving along the camera line) is
    /// the limit of long ones.
    #[test]
    fn an_unbounded_interval_is_the_limit_of_long_ones() {
        let sigma = 0.8f64;
        let dir = view_direction(&0.3f64, &(std::f64::consts::PI - 0.3));
        for w in [Functional::Mean, Functional::Pair23, Functional::Pair24] {
            let at = |len: f64| functional(w, &Hit { start: 0.2, len, path: 0.6 }, &dir, &sigma, &0.0);
            let (inf, long) = (at(f64::INFINITY), at(100.0));
            assert!((inf - long).abs() <= 1e-15 * inf, "{w:?}: {inf} vs {long}");
        }
    }
}
